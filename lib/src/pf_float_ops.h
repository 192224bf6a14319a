/* SPDX-License-Identifier: MIT */
/*
 * Per-sample operator kernels shared by the float and double runtimes.
 * Template: define PF_T (float or double), PF_SFX (f32 or f64), PF_OPC (the
 * operator coefficient type), PF_OPI (its instance type) and PF_BIG (the
 * saturation level of integrator states) before including.
 *
 * A sample is split in two so that loops can be solved in between:
 *   S = op_state(op, &sf)      what the state contributes (u unknown yet);
 *   y = op_update(op, u, sf)   y = D*u + S, and the state advances with u.
 * The branch sum sum_k G_k s_k is formed by op_update for the next sample
 * (same terms in the same order as summing at op_state: same results).
 */
#include "pf_tmpl.h"

static inline PF_T PF_FN(op_state_)(const PF_OPI *S, PF_T *sf)
{
    const PF_OPC *c = S->c;
    PF_T s = S->sum;
    int k;
    *sf = s;
    for (k = 0; k < (c->n_int < 0 ? -c->n_int : c->n_int); k++)
        s = c->int_d * s + S->si[k];
    return s;
}

static inline PF_T PF_FN(op_update_)(PF_OPI *S, PF_T u, PF_T sf)
{
    const PF_OPC *c = S->c;
    PF_T y = c->d * u + sf, sum0 = 0, sum1 = 0;
    int k;
    /* Leaky form: the state moves toward u by lam of the distance, so a pole
     * at 1 - 1e-7 costs no precision in lam itself. The branch sum the next
     * sample needs is formed here, while each new state is at hand, in two
     * interleaved partial sums (even and odd branches) so that the adds do
     * not wait on one another: the sum's chain of dependent adds was the
     * longest path of a step (bench/bench_speed.c). */
    for (k = 0; k + 1 < c->n_sec; k += 2) {
        PF_T s0 = S->s[k] + c->lam[k] * (u - S->s[k]);
        PF_T s1 = S->s[k + 1] + c->lam[k + 1] * (u - S->s[k + 1]);
        S->s[k] = s0;
        S->s[k + 1] = s1;
        sum0 += c->G[k] * s0;
        sum1 += c->G[k + 1] * s1;
    }
    if (k < c->n_sec) {
        PF_T s0 = S->s[k] + c->lam[k] * (u - S->s[k]);
        S->s[k] = s0;
        sum0 += c->G[k] * s0;
    }
    S->sum = sum0 + sum1;
    for (k = 0; k < (c->n_int < 0 ? -c->n_int : c->n_int); k++) {
        PF_T yk = c->int_d * y + S->si[k];
        PF_T si = (c->int_rho > 0 ? S->si[k] : -S->si[k]) + c->int_k * y;
        /* an integrator saturates rather than overflow (see PF_BIG) */
        S->si[k] = si < PF_BIG ? (si > -PF_BIG ? si : -PF_BIG) : PF_BIG;
        y = yk;
    }
    return y;
}
