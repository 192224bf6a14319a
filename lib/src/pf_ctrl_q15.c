/* SPDX-License-Identifier: MIT */
/*
 * Q15 controller runtime: the same per-sample solution as the float
 * template (pf_ctrl_float.inc), in integers. Each pf_qc carries a physical
 * coefficient times the ratio of the scales of the nodes it connects
 * (pf_ctrl_q15_design.c), so this file never sees a physical unit.
 * Overflow: every node is a sum of unsaturated 64-bit products clamped
 * once to +-2^30 (4x its design peak); the output saturates to the int16
 * range.
 *
 * In-loop effects. Backlash (a play of half-width r on x) and saturation
 * of p_c are monotone and piecewise linear, so the loop is solved exactly
 * piece by piece, with the same algebra as the linear case. With
 *   X(p_c) = ce e - x_pc p_c - (t_q S_Q + t_v S_V - t_w S_W)
 * the lever's x for a given p_c, and P(xe) = sat(pc_x xe + pc_p S_P) the
 * p_c a play output xe gives, the solution is x = X(P(play(x))), and
 * X(P(.)) is non-increasing: if the play stuck at its last output xb gives
 * an x more than r above xb, the play moves up (xe = x - r), more than r
 * below, down; otherwise it stays. Moving, xe follows from the linear
 * solution x_lin as x_lin -+ r/(1 + L0), unless that p_c is beyond a
 * supply limit, where p_c sits on the limit and x = X(limit).
 *
 * The nozzle curve h (pf_nozzle_q15.h) sits between the play and p_b: P
 * takes h(xe), and the moving play's xe solves W(xe) = W's target of
 * x_lin -+ r (the loop map, increasing because h is), in place of the
 * linear xe = x_lin -+ r/(1 + L0). X(P(h(.))) is still non-increasing, so
 * the cases above, and their order, stay as they are.
 */
#include <stddef.h>
#include <string.h>

#include "pf_nozzle_q15.h"
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

static int16_t output_line(pf_ctrl_q15 *S, int32_t pc)
{
    const pf_ctrl_coeffs_q15 *c = S->c;
    int16_t o;
    if (c->lag_m > 0) {
        S->lag = pf_q_advance(S->lag, c->lag_m, pf_q_sat32((int64_t)pc - pf_q_state(S->lag)),
                               c->lag_sh);
        pc = pf_q_state(S->lag);
    }
    o = pf_q_to_q15(c->pc_out, pc);
    if (c->delay_len > 0) {
        int16_t d = S->dbuf[S->didx];
        S->dbuf[S->didx] = o;
        if (++S->didx >= c->delay_len)
            S->didx = 0;
        o = d;
    }
    return o;
}

/* x for a given p_c (the loop closed through a known p_c) */
static int32_t x_of_pc(const pf_ctrl_coeffs_q15 *c, int32_t e, int32_t pc, int32_t sQ,
                       int32_t sV, int32_t sW)
{
    return pf_q_sat(pf_mulw(c->ce, e) - pf_mulw(c->x_pc, pc) - pf_mulw(c->t_q, sQ) -
                    pf_mulw(c->t_v, sV) + pf_mulw(c->t_w, sW));
}

/* v - dir r for dir in {-1, 0, 1}: the play's offset, without a 64-bit
 * multiply (a libgcc call on an M0+). */
static int64_t off(int64_t v, int dir, int32_t r)
{
    return dir > 0 ? v - r : (dir < 0 ? v + r : v);
}

/* p_c before the supply limits, for a nozzle output h */
static int32_t pc_of_h(const pf_ctrl_coeffs_q15 *c, int32_t h, int32_t sP)
{
    return pf_q_sat(pf_mulw(c->pc_x, h) + pf_mulw(c->pc_p, sP));
}

/* The nozzle's table; none in a build without the curve (pf_config.h:
 * init has refused a set that points to one), whose code then drops out. */
#if PF_Q15_NOZZLE_SEG > 0
#define NOZZLE(c) ((c)->nz)
#else
#define NOZZLE(c) ((void)(c), (const pf_nozzle_q15 *)NULL)
#endif

/* The nozzle's output for a play output xe: its curve, or xe (eq. 9). */
static int32_t nozzle(const pf_ctrl_coeffs_q15 *c, int32_t xe)
{
    return NOZZLE(c) != NULL ? pf_nz_h(NOZZLE(c), xe) : xe;
}

/* The loop's play output xe, and *h = nozzle(xe), from the linear
 * solution x_lin, with the play moving up (dir = 1), down (-1), or absent
 * (0): x = xe + dir r. */
static int32_t loop_solve(const pf_ctrl_coeffs_q15 *c, int32_t x_lin, int dir, int32_t *h)
{
    const pf_nozzle_q15 *nz = NOZZLE(c);
    if (nz != NULL)
        return pf_nz_solve(nz, off(pf_mulw(nz->t_x, x_lin), dir, nz->t_r), h);
    return *h = pf_q_sat(off(x_lin, dir, c->play_ri));
}

/* The play's new output and x, from the linear solution x_lin (see the
 * head of the file); *h the nozzle's output. */
static int32_t play_solve(const pf_ctrl_q15 *S, int32_t e, int32_t x_lin, int32_t sP,
                          int32_t sQ, int32_t sV, int32_t sW, int32_t *x, int32_t *h)
{
    const pf_ctrl_coeffs_q15 *c = S->c;
    int32_t xb = S->xb, r = c->play_r, xe, pc, hb = nozzle(c, xb);
    int32_t xs = x_of_pc(c, e, clamp_pc(c, pc_of_h(c, hb, sP)), sQ, sV, sW);
    int dir = (int64_t)xs - xb > r ? 1 : ((int64_t)xs - xb < -(int64_t)r ? -1 : 0);
    if (dir == 0) {
        *x = xs;
        *h = hb;
        return xb;
    }
    xe = loop_solve(c, x_lin, dir, h);
    pc = pc_of_h(c, *h, sP);
    if (clamp_pc(c, pc) != pc) { /* on a supply limit: x from it */
        *x = x_of_pc(c, e, clamp_pc(c, pc), sQ, sV, sW);
        xe = pf_q_sat(off(*x, dir, r));
        *h = nozzle(c, xe);
    } else {
        *x = pf_q_sat(off(xe, -dir, r));
    }
    return xe;
}

/* The relay operator's input v for a solved p_b (= k1 h): the free
 * diaphragm's, or on its seat (PF_SAT_STOP) the v that holds z = w + v at
 * the limit (pf_effects.h, pf_ctrl_float.inc). */
static int32_t relay_input(const pf_ctrl_coeffs_q15 *c, int32_t pb, int32_t h, int32_t sP)
{
    if (c->saturate == PF_SAT_STOP) {
        int32_t pc = pc_of_h(c, h, sP), lim = clamp_pc(c, pc);
        if (lim != pc)
            return pf_q_sat(pf_mulw(c->stop_v_pc, lim) + pf_mulw(c->stop_v_s, sP));
    }
    return pf_q_sat(pf_mulw(c->relay_v_pb, pb) + pf_mulw(c->relay_v_s, sP));
}

int16_t pf_ctrl_step_q15(pf_ctrl_q15 *S, int16_t e_q15)
{
    const pf_ctrl_coeffs_q15 *c = S->c;
    int32_t e, sP, sQ = 0, sV = 0, sW = 0, x, xe, h, pb, v, w, pc, rv = 0, rw = 0, m;
    int64_t fP, fQ = 0, fV = 0, fW = 0;

    e = pf_mulc(c->e_in, c->hold ? (int32_t)e_q15 + S->e1 : (int32_t)e_q15);
    S->e1 = e_q15;
    sP = pf_q_op_state(&S->P, &fP);
    if (c->has_q)
        sQ = pf_q_op_state(&S->Q, &fQ);
    if (c->has_v)
        sV = pf_q_op_state(&S->V, &fV);
    if (c->has_w)
        sW = pf_q_op_state(&S->W, &fW);

    /* x straight from the states (pf_controller.h): one wide sum, one
     * saturation, however small x is against the terms that form it. */
    x = pf_q_sat(pf_mulw(c->x_e, e) - pf_mulw(c->x_q, sQ) - pf_mulw(c->x_v, sV) +
                 pf_mulw(c->x_w, sW) - pf_mulw(c->x_p, sP));
    if (c->play_r > 0) {
        xe = play_solve(S, e, x, sP, sQ, sV, sW, &x, &h);
        S->xb = xe;
    } else {
        if (NOZZLE(c) != NULL)
            x = loop_solve(c, x, 0, &h);
        else
            h = x;
        xe = x;
        if (c->saturate) {
            /* Saturation is monotone too: if the unclipped solution's p_c
             * is beyond a limit, the true one sits on that limit, and x
             * follows from it directly. */
            int32_t pc_lin = pc_of_h(c, h, sP);
            int32_t pc_c = clamp_pc(c, pc_lin);
            if (pc_c != pc_lin) {
                x = xe = x_of_pc(c, e, pc_c, sQ, sV, sW);
                h = nozzle(c, xe);
            }
        }
    }
    pb = pf_mulc(c->k1, h);
    v = relay_input(c, pb, h, sP);
    w = pf_q_op_update(&S->P, v, fP);
    pc = clamp_pc(c, pf_q_sat(pf_mulw(c->relay_z_pb, pb) + pf_mulw(c->relay_z_w, w)));
    if (c->has_v) {
        rv = pf_q_sat(pf_mulw(c->v_a, pc) + pf_mulw(c->v_b, sV));
        (void)pf_q_op_update(&S->V,
                             pf_q_sat(pf_mulw(c->dv_pc, pc) - pf_mulw(c->dv_r, rv)), fV);
    }
    if (c->has_w) {
        rw = pf_q_sat(pf_mulw(c->w_a, pc) + pf_mulw(c->w_b, sW));
        (void)pf_q_op_update(&S->W,
                             pf_q_sat(pf_mulw(c->dw_pc, pc) - pf_mulw(c->dw_r, rw)), fW);
    }
    m = pf_q_sat((c->has_v ? pf_mulw(c->m_v, rv) : pf_mulw(c->m_pc, pc)) -
                 (c->has_w ? pf_mulw(c->m_w, rw) : 0));
    S->x = x;
    S->pb = pb;
    S->y = c->has_q ? pf_q_op_update(&S->Q, m, fQ) : pf_mulc(c->kA_m, m);
    S->pc = pc;
    return output_line(S, pc);
}

void pf_ctrl_run_q15(pf_ctrl_q15 *S, const int16_t *e, int16_t *pc, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++)
        pc[i] = pf_ctrl_step_q15(S, e[i]);
}

void pf_ctrl_reset_q15(pf_ctrl_q15 *S)
{
    if (S == NULL || S->c == NULL)
        return;
    pf_fracop_reset_q15(&S->P);
    pf_fracop_reset_q15(&S->Q);
    pf_fracop_reset_q15(&S->V);
    pf_fracop_reset_q15(&S->W);
    S->x = S->pb = S->y = S->pc = S->xb = 0;
    S->e1 = 0;
    S->lag = 0;
    S->didx = 0;
    if (S->dbuf != NULL)
        memset(S->dbuf, 0, sizeof(int16_t) * S->c->delay_len);
}

pf_status pf_ctrl_init_q15(pf_ctrl_q15 *S, const pf_ctrl_coeffs_q15 *c,
                           int16_t *dbuf, size_t dlen)
{
    if (S == NULL || c == NULL)
        return PF_E_NULL;
    if (c->delay_len > 0 && (dbuf == NULL || dlen < c->delay_len))
        return PF_E_BUFFER;
    /* the knots are searched up to n - 1: n must be within the table */
    if (c->nz != NULL && (c->nz->n < 3 || c->nz->n > PF_Q15_NOZZLE_SEG + 1))
        return PF_E_BUFFER;
    memset(S, 0, sizeof *S);
    S->c = c;
    S->dbuf = c->delay_len > 0 ? dbuf : NULL;
    (void)pf_fracop_init_q15(&S->P, &c->P);
    (void)pf_fracop_init_q15(&S->Q, &c->Q);
    (void)pf_fracop_init_q15(&S->V, &c->V);
    (void)pf_fracop_init_q15(&S->W, &c->W);
    pf_ctrl_reset_q15(S);
    return PF_OK;
}

void pf_ctrl_monitor_q15(const pf_ctrl_q15 *S, int16_t *x, int16_t *pb,
                         int16_t *y, int16_t *pc)
{
    const pf_ctrl_coeffs_q15 *c = S->c;
    if (x != NULL)
        *x = pf_q_to_q15(c->mon_x, S->x);
    if (pb != NULL)
        *pb = pf_q_to_q15(c->mon_pb, S->pb);
    if (y != NULL)
        *y = pf_q_to_q15(c->mon_y, S->y);
    if (pc != NULL)
        *pc = pf_q_to_q15(c->pc_out, S->pc);
}
