/* SPDX-License-Identifier: MIT */
/*
 * Per-sample operator kernels shared by the float and double runtimes.
 * Template: define PF_T (float or double), PF_SFX (f32 or f64), PF_OPC (the
 * operator coefficient type), PF_OPI (its instance type), PF_BIG (the
 * saturation level of integrator states) and PF_SUM_LANES (1 or 2: partial
 * sums of the branch sum, see op_update) before including.
 *
 * A sample is split in two so that loops can be solved in between:
 *   S = op_state(op, &sf)      what the state contributes (u unknown yet);
 *   y = op_update(op, u, sf)   y = D*u + S, and the state advances with u.
 * The branch sum sum_k G_k s_k is formed by op_update for the next sample
 * (same terms in the same order as summing at op_state: same results).
 */
#include "pf_tmpl.h"

#if !defined(PF_SUM_LANES) || (PF_SUM_LANES != 1 && PF_SUM_LANES != 2)
#error "define PF_SUM_LANES (1 or 2) before including pf_float_ops.h"
#endif

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

/* One leaky section: the state moves toward u by lam of the distance, so a
 * pole at 1 - 1e-7 costs no precision in lam itself; returns its term of
 * the branch sum. */
static inline PF_T PF_FN(op_section_)(PF_OPI *S, const PF_OPC *c, int k, PF_T u)
{
    PF_T sk = S->s[k] + c->lam[k] * (u - S->s[k]);
    S->s[k] = sk;
    return c->G[k] * sk;
}

static inline PF_T PF_FN(op_update_)(PF_OPI *S, PF_T u, PF_T sf)
{
    const PF_OPC *c = S->c;
    PF_T y = c->d * u + sf, sum0 = 0, sum1 = 0;
    int k = 0;
    /* The branch sum the next sample needs is formed here, while each new
     * state is at hand. With PF_SUM_LANES 2 (the double runtime, which the
     * host's fits run) the even and odd branches go to two partial sums, so
     * that the adds do not wait on one another: one running sum is a chain
     * of n_sec dependent adds, and cutting it made a step 10-17 % faster on
     * x86-64. The float runtime (firmware, in-order cores) keeps one sum:
     * there the lanes only add instructions (callgrind: +7 to +18 %). */
#if PF_SUM_LANES == 2
    for (; k + 1 < c->n_sec; k += 2) {
        sum0 += PF_FN(op_section_)(S, c, k, u);
        sum1 += PF_FN(op_section_)(S, c, k + 1, u);
    }
#endif
    for (; k < c->n_sec; k++)
        sum0 += PF_FN(op_section_)(S, c, k, u);
    S->sum = PF_SUM_LANES == 2 ? sum0 + sum1 : sum0;
    for (k = 0; k < (c->n_int < 0 ? -c->n_int : c->n_int); k++) {
        PF_T yk = c->int_d * y + S->si[k];
        PF_T si = (c->int_rho > 0 ? S->si[k] : -S->si[k]) + c->int_k * y;
        /* an integrator saturates rather than overflow (see PF_BIG) */
        S->si[k] = si < PF_BIG ? (si > -PF_BIG ? si : -PF_BIG) : PF_BIG;
        y = yk;
    }
    return y;
}
