/* SPDX-License-Identifier: MIT */
/*
 * Q15 controller runtime: the same per-sample solution as the float
 * template (pf_ctrl_float.inc), in integers. Each pf_qc carries a physical
 * coefficient times the ratio of the scales of the nodes it connects
 * (pf_ctrl_q15_design.c), so this file never sees a physical unit.
 * Overflow: every node is a sum of unsaturated 64-bit products clamped
 * once to +-2^30 (4x its design peak); the output saturates to the int16
 * range.
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
        in->lag = pf_q_advance(in->lag, c->lag_m, pf_q_sat32((int64_t)pc - pf_q_state(in->lag)),
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
    int32_t e, sP, sQ = 0, sV = 0, sW = 0, x, pb, v, w, pc, rv = 0, rw = 0, m;
    int64_t fP, fQ = 0, fV = 0, fW = 0;

    e = pf_mulc(c->e_in, c->hold ? (int32_t)e_q15 + in->e1 : (int32_t)e_q15);
    in->e1 = e_q15;
    sP = pf_q_op_state(&in->P, &fP);
    if (c->has_q)
        sQ = pf_q_op_state(&in->Q, &fQ);
    if (c->has_v)
        sV = pf_q_op_state(&in->V, &fV);
    if (c->has_w)
        sW = pf_q_op_state(&in->W, &fW);

    /* x straight from the states (pf_controller.h): one wide sum, one
     * saturation, however small x is against the terms that form it. */
    x = pf_q_sat(pf_mulw(c->x_e, e) - pf_mulw(c->x_q, sQ) - pf_mulw(c->x_v, sV) +
                 pf_mulw(c->x_w, sW) - pf_mulw(c->x_p, sP));
    if (c->saturate) {
        /* Saturation is the only in-loop effect here, and it is monotone:
         * if the linear solution's p_c is beyond a limit, the true one sits
         * on that limit, and x follows from it directly. */
        int32_t pc_lin = pf_q_sat(pf_mulw(c->pc_x, x) + pf_mulw(c->pc_p, sP));
        int32_t pc_c = clamp_pc(c, pc_lin);
        if (pc_c != pc_lin)
            x = pf_q_sat(pf_mulw(c->ce, e) - pf_mulw(c->x_pc, pc_c) - pf_mulw(c->t_q, sQ) -
                         pf_mulw(c->t_v, sV) + pf_mulw(c->t_w, sW));
    }
    pb = pf_mulc(c->k1, x);
    v = pf_q_sat(pf_mulw(c->relay_v_pb, pb) + pf_mulw(c->relay_v_s, sP));
    w = pf_q_op_update(&in->P, v, fP);
    pc = clamp_pc(c, pf_q_sat(pf_mulw(c->relay_z_pb, pb) + pf_mulw(c->relay_z_w, w)));
    if (c->has_v) {
        rv = pf_q_sat(pf_mulw(c->v_a, pc) + pf_mulw(c->v_b, sV));
        (void)pf_q_op_update(&in->V,
                             pf_q_sat(pf_mulw(c->dv_pc, pc) - pf_mulw(c->dv_r, rv)), fV);
    }
    if (c->has_w) {
        rw = pf_q_sat(pf_mulw(c->w_a, pc) + pf_mulw(c->w_b, sW));
        (void)pf_q_op_update(&in->W,
                             pf_q_sat(pf_mulw(c->dw_pc, pc) - pf_mulw(c->dw_r, rw)), fW);
    }
    m = pf_q_sat((c->has_v ? pf_mulw(c->m_v, rv) : pf_mulw(c->m_pc, pc)) -
                 (c->has_w ? pf_mulw(c->m_w, rw) : 0));
    in->x = x;
    in->pb = pb;
    in->y = c->has_q ? pf_q_op_update(&in->Q, m, fQ) : pf_mulc(c->kA_m, m);
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
        *pc = pf_q_to_q15(c->pc_out, in->pc);
}
