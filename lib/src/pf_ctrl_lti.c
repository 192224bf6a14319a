/* SPDX-License-Identifier: MIT */
/*
 * A design's linear runtime as a discrete state space (pf_controller.h,
 * pf_ctrl_state_space): the one place that reads the double runtime's
 * states, for the stability check (pf_ctrl_check.c) and the host's
 * ss/zpk/sos exports (tools/host/pfh_lti.c).
 *
 * The runtime solves its loops exactly within each sample, so without the
 * nonlinear effects it is x[k+1] = A x[k] + B e[k], p_c[k] = C x[k] +
 * D e[k] with its own states as x. One step from each unit state with
 * e = 0 gives a column of A and an entry of C; one step from rest with
 * e = 1 gives B and D: exactly the arithmetic that runs, not a second
 * derivation of it.
 */
#include <stddef.h>
#include <string.h>

#include "pneufrac/pf_controller.h"

/* Pointers to every state of the linear runtime, in a fixed order.
 * @return their number. */
static int states(pf_ctrl_f64 *r, int with_lag, double **s)
{
    pf_fracop_f64 *ops[4];
    int used[4], k = 0, o, j, n_int;

    ops[0] = &r->P;
    ops[1] = &r->Q;
    ops[2] = &r->V;
    ops[3] = &r->W;
    used[0] = 1;
    used[1] = r->c->has_q;
    used[2] = r->c->has_v;
    used[3] = r->c->has_w;
    if (r->c->hold)
        s[k++] = &r->e1;
    for (o = 0; o < 4; o++) {
        const pf_fracop_design *c = ops[o]->c;
        if (!used[o])
            continue;
        for (j = 0; j < c->n_sec; j++)
            s[k++] = &ops[o]->s[j];
        n_int = c->n_int < 0 ? -c->n_int : c->n_int;
        for (j = 0; j < n_int; j++)
            s[k++] = &ops[o]->si[j];
    }
    if (with_lag && r->c->lag_lam > 0)
        s[k++] = &r->lag;
    return k;
}

/* What the runtime derives from the states (pf_fracop.h: sum = sum_k G_k
 * s_k), after a state was set by hand. */
static void resync(pf_ctrl_f64 *r)
{
    pf_fracop_f64 *ops[4];
    int o, j;
    ops[0] = &r->P;
    ops[1] = &r->Q;
    ops[2] = &r->V;
    ops[3] = &r->W;
    for (o = 0; o < 4; o++) {
        const pf_fracop_design *c = ops[o]->c;
        double sum = 0.0;
        for (j = 0; j < c->n_sec; j++)
            sum += c->G[j] * ops[o]->s[j];
        ops[o]->sum = sum;
    }
}

int pf_ctrl_state_space(const pf_ctrl_design *d, int with_lag, double *A, double *B,
                        double *C, double *D)
{
    pf_ctrl_coeffs_f64 lin;
    pf_ctrl_f64 r;
    double *s[PF_CTRL_MAX_STATES], y;
    int n, i, j;

    if (d == NULL || A == NULL)
        return -1;
    /* The linear model: the effects are nonlinear or outside the loop. */
    lin = d->rt;
    lin.in_loop_fx = 0;
    lin.play_r = 0.0;
    lin.nozzle_xh = 0.0;
    lin.saturate = 0;
    if (!with_lag)
        lin.lag_lam = 0.0;
    lin.delay_len = 0;
    if (pf_ctrl_init_f64(&r, &lin, NULL, 0) != PF_OK)
        return -1;
    n = states(&r, with_lag, s);
    for (j = 0; j < n; j++) {
        pf_ctrl_reset_f64(&r);
        *s[j] = 1.0;
        resync(&r);
        y = pf_ctrl_step_f64(&r, 0.0);
        if (C != NULL)
            C[j] = y;
        for (i = 0; i < n; i++)
            A[(size_t)i * (size_t)n + (size_t)j] = *s[i];
    }
    pf_ctrl_reset_f64(&r);
    y = pf_ctrl_step_f64(&r, 1.0);
    if (D != NULL)
        *D = y;
    for (i = 0; B != NULL && i < n; i++)
        B[i] = *s[i];
    return n;
}
