/* SPDX-License-Identifier: MIT */
/*
 * Q15 controller runtime: the same per-sample solution as the float
 * template (pf_ctrl_float.inc), in integers. Each pf_qc carries a physical
 * coefficient times the ratio of the scales of the nodes it connects
 * (pf_ctrl_q15_design.c), so this file never sees a physical unit.
 * Overflow: every node is clamped to +-2^30 (4x its design peak); the
 * output saturates to the int16 range.
 */
#include <stddef.h>
#include <string.h>

#include "pf_q15_ops.h"
#include "pneufrac/pf_controller.h"

static int32_t clamp_pc(const pf_ctrl_coeffs_q15 *c, int32_t pc)
{
    if (c->saturate) {
        if (pc > c->sat_hi)
            return c->sat_hi;
        if (pc < c->sat_lo)
            return c->sat_lo;
    }
    return pc;
}

static int16_t output_line(pf_ctrl_q15 *in, int32_t pc)
{
    const pf_ctrl_coeffs_q15 *c = in->c;
    int16_t o;
    if (c->lag_m > 0) {
        in->lag = pf_q_advance(in->lag, c->lag_m, (int64_t)pc - pf_q_state(in->lag),
                               c->lag_sh);
        pc = pf_q_state(in->lag);
    }
    o = pf_q_to_q15(c->pc_out, pc);
    if (c->delay_len > 0) {
        int16_t d = in->dbuf[in->didx];
        in->dbuf[in->didx] = o;
        if (++in->didx >= c->delay_len)
            in->didx = 0;
        o = d;
    }
    return o;
}

int16_t pf_ctrl_step_q15(pf_ctrl_q15 *in, int16_t e_q15)
{
    const pf_ctrl_coeffs_q15 *c = in->c;
    int32_t n[PF_N_COUNT] = {0};
    int32_t e, sP, sQ = 0, sV, sW;
    int64_t fP, fQ = 0, fV = 0, fW = 0;
    int32_t bV = 0, bW = 0, sig_m, sig_y, sig_pc, x, pc, rv = 0, rw = 0;

    e = pf_mulc(c->e_in, c->hold ? (int32_t)e_q15 + in->e1 : (int32_t)e_q15);
    in->e1 = e_q15;
    sP = pf_q_op_state(&in->P, &fP);
    if (c->has_q)
        sQ = pf_q_op_state(&in->Q, &fQ);
    if (c->has_v) {
        sV = pf_q_op_state(&in->V, &fV);
        bV = pf_mulc(c->v_b, sV);
    }
    if (c->has_w) {
        sW = pf_q_op_state(&in->W, &fW);
        bW = pf_mulc(c->w_b, sW);
    }
    sig_m = pf_q_sat((int64_t)pf_mulc(c->sm_v, bV) - pf_mulc(c->sm_w, bW));
    sig_y = pf_mulc(c->sy_m, sig_m);
    if (c->has_q)
        sig_y = pf_q_sat((int64_t)sig_y + sQ);
    sig_pc = pf_mulc(c->sz_s, sP);

    x = pf_q_sat((int64_t)pf_mulc(c->loop_e, e) - pf_mulc(c->loop_sy, sig_y) -
                 pf_mulc(c->loop_sz, sig_pc));
    if (c->saturate) {
        /* Saturation is the only in-loop effect here, and it is monotone:
         * if the linear solution's p_c is beyond a limit, the true one sits
         * on that limit, and x follows from it directly. */
        int32_t pc_lin = pf_q_sat((int64_t)pf_mulc(c->pc_x, x) + sig_pc);
        int32_t pc_c = clamp_pc(c, pc_lin);
        if (pc_c != pc_lin)
            x = pf_q_sat((int64_t)pf_mulc(c->ce, e) - pf_mulc(c->x_pc, pc_c) -
                         pf_mulc(c->cy, sig_y));
    }
    n[PF_N_E] = e;
    n[PF_N_X] = x;
    n[PF_N_PB] = pf_mulc(c->k1, x);
    n[PF_N_V] = pf_q_sat((int64_t)pf_mulc(c->relay_v_pb, n[PF_N_PB]) +
                         pf_mulc(c->relay_v_s, sP));
    n[PF_N_W] = pf_q_op_update(&in->P, n[PF_N_V], fP);
    pc = clamp_pc(c, pf_q_sat((int64_t)pf_mulc(c->relay_z_pb, n[PF_N_PB]) +
                              pf_mulc(c->relay_z_w, n[PF_N_W])));
    n[PF_N_PC] = pc;
    if (c->has_v) {
        rv = pf_q_sat((int64_t)pf_mulc(c->v_a, pc) + bV);
        n[PF_N_DV] = pf_q_sat((int64_t)pf_mulc(c->dv_pc, pc) - pf_mulc(c->dv_r, rv));
        n[PF_N_RV] = pf_q_op_update(&in->V, n[PF_N_DV], fV);
    }
    if (c->has_w) {
        rw = pf_q_sat((int64_t)pf_mulc(c->w_a, pc) + bW);
        n[PF_N_DW] = pf_q_sat((int64_t)pf_mulc(c->dw_pc, pc) - pf_mulc(c->dw_r, rw));
        n[PF_N_RW] = pf_q_op_update(&in->W, n[PF_N_DW], fW);
    }
    n[PF_N_M] = pf_q_sat((int64_t)(c->has_v ? pf_mulc(c->m_v, rv) : pf_mulc(c->m_pc, pc)) -
                         (c->has_w ? pf_mulc(c->m_w, rw) : 0));
    n[PF_N_Y] = c->has_q ? pf_q_op_update(&in->Q, n[PF_N_M], fQ)
                         : pf_mulc(c->kA_m, n[PF_N_M]);
    in->x = n[PF_N_X];
    in->pb = n[PF_N_PB];
    in->y = n[PF_N_Y];
    in->pc = pc;
    return output_line(in, pc);
}

void pf_ctrl_run_q15(pf_ctrl_q15 *in, const int16_t *e, int16_t *pc, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++)
        pc[i] = pf_ctrl_step_q15(in, e[i]);
}

void pf_ctrl_reset_q15(pf_ctrl_q15 *in)
{
    if (in == NULL || in->c == NULL)
        return;
    pf_fracop_reset_q15(&in->P);
    pf_fracop_reset_q15(&in->Q);
    pf_fracop_reset_q15(&in->V);
    pf_fracop_reset_q15(&in->W);
    in->x = in->pb = in->y = in->pc = 0;
    in->e1 = 0;
    in->lag = 0;
    in->didx = 0;
    if (in->dbuf != NULL)
        memset(in->dbuf, 0, sizeof(int16_t) * in->c->delay_len);
}

pf_status pf_ctrl_init_q15(pf_ctrl_q15 *in, const pf_ctrl_coeffs_q15 *c,
                           int16_t *dbuf, size_t dlen)
{
    if (in == NULL || c == NULL)
        return PF_E_NULL;
    if (c->delay_len > 0 && (dbuf == NULL || dlen < c->delay_len))
        return PF_E_BUFFER;
    memset(in, 0, sizeof *in);
    in->c = c;
    in->dbuf = c->delay_len > 0 ? dbuf : NULL;
    (void)pf_fracop_init_q15(&in->P, &c->P);
    (void)pf_fracop_init_q15(&in->Q, &c->Q);
    (void)pf_fracop_init_q15(&in->V, &c->V);
    (void)pf_fracop_init_q15(&in->W, &c->W);
    pf_ctrl_reset_q15(in);
    return PF_OK;
}

void pf_ctrl_monitor_q15(const pf_ctrl_q15 *in, int16_t *x, int16_t *pb,
                         int16_t *y, int16_t *pc)
{
    const pf_ctrl_coeffs_q15 *c = in->c;
    if (x != NULL)
        *x = pf_q_to_q15(c->mon_x, in->x);
    if (pb != NULL)
        *pb = pf_q_to_q15(c->mon_pb, in->pb);
    if (y != NULL)
        *y = pf_q_to_q15(c->mon_y, in->y);
    if (pc != NULL)
        *pc = pf_q_to_q15(c->mon_pc, in->pc);
}
