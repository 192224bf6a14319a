/* SPDX-License-Identifier: MIT */
/*
 * Q15 operator kernels, shared by the operator and controller runtimes.
 * Same two-phase split as the float kernels (pf_float_ops.h):
 *   S = pf_q_op_state(op, &sf);   y = pf_q_op_update(op, u, sf).
 * Integer only: this is the code the Cortex-M0+ build must keep free of
 * floating-point helpers.
 *
 * Leaky branch:  s <- s + lam*(u - s), lam = lam_m * 2^-lam_sh with
 * lam_sh >= 30 (the leak format, pf_q15_design.c): the pole's distance
 * from z = 1 keeps 30 bits of relative precision however small it is, and the state's 30 fractional bits let
 * increments far below one LSB accumulate.
 * The states are in the scale of the operator input; the G_m products are
 * summed in int64 and rounded once.
 */
#ifndef PF_Q15_OPS_H
#define PF_Q15_OPS_H

#include "pf_qmath.h"

/* *sf keeps the fractional part's sum unsaturated: for a differentiating
 * operator it nearly cancels the feedthrough d*u, and clamping either term
 * alone before the sum would be wrong. */
static inline int32_t pf_q_op_state(const pf_fracop_q15 *S, int64_t *sf)
{
    const pf_fracop_coeffs_q15 *c = S->c;
    int64_t acc = 0, wide;
    int k, n = c->n_int < 0 ? -c->n_int : c->n_int;
    for (k = 0; k < c->n_sec; k++)
        acc += (int64_t)c->G_m[k] * pf_q_state(S->s[k]);
    *sf = pf_round_shift(acc, c->G_sh);
    /* Through the integer stages wide as well: sf alone can exceed the
     * fractional output's range (it cancels against d*u), so it is
     * saturated only once, at the end. */
    wide = *sf;
    for (k = 0; k < n; k++)
        wide = pf_mulw_wide(c->int_d[k], wide) + pf_q_state(S->si[k]);
    return pf_q_sat(wide);
}

static inline int32_t pf_q_op_update(pf_fracop_q15 *S, int32_t u, int64_t sf)
{
    const pf_fracop_coeffs_q15 *c = S->c;
    int32_t y = pf_q_sat(pf_round_shift((int64_t)c->d.m * u, c->d.sh) + sf);
    int k, n = c->n_int < 0 ? -c->n_int : c->n_int;
    for (k = 0; k < c->n_sec; k++)
        S->s[k] = pf_q_advance(S->s[k], c->lam_m[k],
                                (int64_t)u - pf_q_state(S->s[k]), c->lam_sh[k]);
    for (k = 0; k < n; k++) {
        int32_t yk = pf_q_sat((int64_t)pf_mulc(c->int_d[k], y) + pf_q_state(S->si[k]));
        /* an integrator keeps its state; a differentiator's alternates */
        S->si[k] = pf_q_advance(c->int_rho > 0 ? S->si[k] : -S->si[k],
                                 c->int_k[k].m, y, c->int_k[k].sh);
        y = yk;
    }
    return y;
}

#endif /* PF_Q15_OPS_H */
