/* SPDX-License-Identifier: MIT */
/*
 * Q15 controller design: choose a scale for every internal node, then fold
 * the scales into integer coefficients.
 *
 * Scaling: each node's peak gain from e is estimated from the closed-loop
 * discrete frequency response (same block algebra as the runtime, in
 * complex double) over a log grid up to Nyquist. A full-scale input e =
 * in_fs then maps the node's peak to 2^28: a factor 4 of headroom below the
 * +-2^30 clamp covers step overshoot beyond the sinusoidal peak, and the
 * resolution left is 2^-28 of the node's own range, so a small error signal
 * x in a high-gain loop is not starved of bits.
 */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "pf_ctrl_internal.h"

#define PF_PI 3.14159265358979323846

/* With a nozzle curve, the linear peaks are not the whole story. Where the
 * curve compresses, the loop's gain falls and x grows towards the open
 * lever's ce e - cy y: x's scale covers that. And the curve bounds p_b,
 * whatever x does, at pb_max = k1 times its reach within x's range; every
 * node after p_b but the bellows (an integrator in the open loop, held by
 * the loop) is a linear response to p_b, so at most its peak gain from p_b
 * times pb_max: where that is below the linear peak it sets the scale, and
 * a strongly compressing nozzle does not leave those nodes coarse. */
static void nozzle_peaks(const pf_ctrl_coeffs_f64 *c, double in_fs, double peak[PF_N_COUNT],
                         const double per_pb[PF_N_COUNT])
{
    double pb_max;
    int n;
    peak[PF_N_X] = fmax(peak[PF_N_X], fabs(c->ce) + fabs(c->cy) * peak[PF_N_Y]);
    /* x's range: its peak maps to 2^28 of the 2^30 it holds */
    pb_max = c->k1 * pf_nozzle_q15_reach(c, 4.0 * peak[PF_N_X] * in_fs) / in_fs;
    for (n = PF_N_PB; n < PF_N_COUNT; n++)
        if (n != PF_N_Y && n != PF_N_FQ && per_pb[n] * pb_max < peak[n])
            peak[n] = per_pb[n] * pb_max;
}

static void node_scales(const pf_ctrl_design *d, double in_fs,
                        double s[PF_N_COUNT])
{
    double peak[PF_N_COUNT] = {0}, per_pb[PF_N_COUNT] = {0};
    int i, n;
    for (i = 0; i < PF_GRID; i++) {
        double complex g[PF_N_COUNT];
        pf_ctrl_node_resp(&d->rt, pf_grid_omega(&d->rt.P, d->opt.wb, i), g);
        for (n = 0; n < PF_N_COUNT; n++) {
            if (cabs(g[n]) > peak[n])
                peak[n] = cabs(g[n]);
            /* nodes after p_b: their gain from p_b */
            if (cabs(g[PF_N_PB]) > 0.0 && cabs(g[n]) / cabs(g[PF_N_PB]) > per_pb[n])
                per_pb[n] = cabs(g[n]) / cabs(g[PF_N_PB]);
        }
    }
    if (d->rt.nozzle_xh > 0.0)
        nozzle_peaks(&d->rt, in_fs, peak, per_pb);
    /* A node the configuration does not use (peak 0) borrows p_c's scale,
     * so the coefficients that touch it stay finite (they multiply 0). */
    for (n = 0; n < PF_N_COUNT; n++)
        s[n] = peak[n] > 0.0 && isfinite(peak[n]) ? PF_Q_TARGET / (peak[n] * in_fs)
                                                   : 0.0;
    for (n = 0; n < PF_N_COUNT; n++)
        if (s[n] == 0.0)
            s[n] = s[PF_N_PC];
    /* The supply limits must be representable in p_c's scale, or they
     * would clamp to the node's range and collapse onto each other. */
    if (d->rt.saturate) {
        double lim = fmax(fabs(d->rt.sat_lo), fabs(d->rt.sat_hi));
        if (lim * s[PF_N_PC] > PF_Q_TARGET)
            s[PF_N_PC] = PF_Q_TARGET / lim;
    }
}

/* q = v * s[to] / s[from]: a physical coefficient between two nodes. */
#define QC(field, v, to, from)                                                 \
    do {                                                                       \
        if (st == PF_OK)                                                       \
            st = pf_qc_make(&cq->field, (v) * s[to] / s[from]);                \
    } while (0)

static int32_t q_limit(double v)
{
    if (v > PF_Q_TARGET * 4.0)
        return (int32_t)1 << 30;
    if (v < -PF_Q_TARGET * 4.0)
        return -((int32_t)1 << 30);
    return (int32_t)llround(v);
}

pf_status pf_ctrl_coeffs_q15_make(pf_ctrl_coeffs_q15 *cq,
                                  const pf_ctrl_design *d, double in_fs,
                                  double out_fs)
{
    return pf_ctrl_coeffs_q15_make_nz(cq, NULL, d, in_fs, out_fs);
}

pf_status pf_ctrl_coeffs_q15_make_nz(pf_ctrl_coeffs_q15 *cq, pf_nozzle_q15 *nz,
                                     const pf_ctrl_design *d, double in_fs,
                                     double out_fs)
{
    const pf_ctrl_coeffs_f64 *c;
    double s[PF_N_COUNT], hs = 1.0;
    pf_status st = PF_OK;
    if (cq == NULL || d == NULL)
        return PF_E_NULL;
    st = pf_q15_scales_check(in_fs, out_fs);
    if (st != PF_OK)
        return st;
    c = &d->rt;
    /* The refined approximant's extra pole has a branch gain 1e6..1e13
     * times the others, more than one shared branch shift can hold. */
    if (d->opt.approx == PF_APPROX_REFINED)
        return PF_E_UNSUPPORTED;
    /* A relay whose memory winds on at a limit (PF_SAT_WIND) takes its
     * state far beyond the linear loop's peaks, by the time it is held
     * there ((t/tau)^beta): no fixed node scale holds it. */
    if (c->saturate == PF_SAT_WIND)
        return PF_E_UNSUPPORTED;
    if (c->nozzle_xh > 0.0 && PF_Q15_NOZZLE_SEG == 0)
        return PF_E_UNSUPPORTED; /* left out of this build (pf_config.h) */
    if (c->nozzle_xh > 0.0 && nz == NULL)
        return PF_E_BUFFER;
    node_scales(d, in_fs, s);
    memset(cq, 0, sizeof *cq);
    if (c->nozzle_xh > 0.0) {
        st = pf_nozzle_q15_make(nz, c, s[PF_N_X]);
        cq->nz = nz;
        /* the nozzle's output h, in x's scale times 2^h_sh, feeds p_b
         * and p_c in place of x */
        hs = ldexp(1.0, -nz->h_sh);
    }
    cq->has_q = c->has_q;
    cq->has_v = c->has_v;
    cq->has_w = c->has_w;
    cq->saturate = c->saturate;
    cq->hold = c->hold;
    cq->delay_len = c->delay_len;

    if (st == PF_OK)
        st = pf_q15_op_make(&cq->P, &c->P, s[PF_N_V], s[PF_N_FP], s[PF_N_W]);
    if (st == PF_OK && c->has_q)
        st = pf_q15_op_make(&cq->Q, &c->Q, s[PF_N_M], s[PF_N_FQ], s[PF_N_Y]);
    if (st == PF_OK && c->has_v)
        st = pf_q15_op_make(&cq->V, &c->V, s[PF_N_DV], s[PF_N_FV], s[PF_N_RV]);
    if (st == PF_OK && c->has_w)
        st = pf_q15_op_make(&cq->W, &c->W, s[PF_N_DW], s[PF_N_FW], s[PF_N_RW]);

    /* Q15 e (one LSB = in_fs/32768) into the e node; the held-input mean's
     * 1/2 is folded in here, so the sum of two samples is exact. */
    if (st == PF_OK)
        st = pf_qc_make(&cq->e_in, s[PF_N_E] * in_fs / 32768.0 * (c->hold ? 0.5 : 1.0));
    QC(v_b, c->v_den_inv, PF_N_RV, PF_N_RV);
    QC(w_b, c->w_den_inv, PF_N_RW, PF_N_RW);
    {
        /* The loop solution (pf_controller.h), expanded down to the state
         * contributions: sigma_y = Dq (S_V/(1+D_V) - S_W/(1+D_W)) + S_Q,
         * sigma_pc = k2 relay_sz S_P, with Dq the bellows feedthrough. */
        double Dq = c->has_q ? c->Q.D : c->kA, li = c->loop_inv, cy = c->cy;
        QC(x_e, li * c->ce, PF_N_X, PF_N_E);
        QC(x_q, li * cy, PF_N_X, PF_N_Y);
        QC(x_v, li * cy * Dq * c->v_den_inv, PF_N_X, PF_N_RV);
        QC(x_w, li * cy * Dq * c->w_den_inv, PF_N_X, PF_N_RW);
        QC(x_p, li * cy * c->alpha_y * c->k2 * c->relay_sz, PF_N_X, PF_N_W);
        QC(ce, c->ce, PF_N_X, PF_N_E);
        QC(x_pc, cy * c->alpha_y, PF_N_X, PF_N_PC);
        QC(t_q, cy, PF_N_X, PF_N_Y);
        QC(t_v, cy * Dq * c->v_den_inv, PF_N_X, PF_N_RV);
        QC(t_w, cy * Dq * c->w_den_inv, PF_N_X, PF_N_RW);
        QC(pc_x, c->k2 * c->alpha_z * c->k1 * hs, PF_N_PC, PF_N_X);
        QC(pc_p, c->k2 * c->relay_sz, PF_N_PC, PF_N_W);
    }
    QC(k1, c->k1 * hs, PF_N_PB, PF_N_X);
    QC(relay_v_pb, c->relay_den_inv, PF_N_V, PF_N_PB);
    QC(relay_v_s, -c->pmin * c->relay_den_inv, PF_N_V, PF_N_W);
    QC(relay_z_pb, c->k2 * c->relay_d0, PF_N_PC, PF_N_PB);
    QC(relay_z_w, c->k2 * c->relay_w, PF_N_PC, PF_N_W);
    if (c->saturate == PF_SAT_STOP) {
        /* v = (p_c/k2 - S_P)/(1 + D_P) on the seat (pf_effects.h) */
        double seat = 1.0 / (1.0 + c->P.D);
        QC(stop_v_pc, c->k2_inv * seat, PF_N_V, PF_N_PC);
        QC(stop_v_s, -seat, PF_N_V, PF_N_W);
    }
    QC(v_a, c->v_a, PF_N_RV, PF_N_PC);
    QC(w_a, c->w_a, PF_N_RW, PF_N_PC);
    QC(dv_pc, 1.0, PF_N_DV, PF_N_PC);
    QC(dv_r, 1.0, PF_N_DV, PF_N_RV);
    QC(dw_pc, 1.0, PF_N_DW, PF_N_PC);
    QC(dw_r, 1.0, PF_N_DW, PF_N_RW);
    QC(m_v, 1.0, PF_N_M, PF_N_RV);
    QC(m_pc, 1.0, PF_N_M, PF_N_PC);
    QC(m_w, 1.0, PF_N_M, PF_N_RW);
    QC(kA_m, c->kA, PF_N_Y, PF_N_M);
    if (st == PF_OK)
        st = pf_qc_make(&cq->pc_out, 32768.0 / (out_fs * s[PF_N_PC]));
    if (st == PF_OK && c->lag_lam > 0.0)
        st = pf_qc_leak(&cq->lag_m, &cq->lag_sh, c->lag_lam);
    /* A play wider than the x node's range never moves: clamped there. */
    cq->play_r = q_limit(c->play_r * s[PF_N_X]);
    cq->play_ri = q_limit(c->play_r * c->loop_inv * s[PF_N_X]);
    /* the play's half-width in the loop map W (pf_nozzle_q15) */
    if (c->nozzle_xh > 0.0)
        nz->t_r = c->loop_inv <= 1.0 ? cq->play_ri : cq->play_r;
    cq->sat_lo = q_limit(c->sat_lo * s[PF_N_PC]);
    cq->sat_hi = q_limit(c->sat_hi * s[PF_N_PC]);
    /* Monitoring: x and y in Q15 of in_fs, p_b of k1*in_fs, p_c of out_fs. */
    if (st == PF_OK)
        st = pf_qc_make(&cq->mon_x, 32768.0 / (in_fs * s[PF_N_X]));
    if (st == PF_OK)
        st = pf_qc_make(&cq->mon_y, 32768.0 / (in_fs * s[PF_N_Y]));
    if (st == PF_OK)
        st = pf_qc_make(&cq->mon_pb, 32768.0 / (c->k1 * in_fs * s[PF_N_PB]));
    return st;
}
