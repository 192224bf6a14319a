/* SPDX-License-Identifier: MIT */
/*
 * The linear runtime of a controller as a state space, and the stability
 * of its sampled loop.
 *
 * The runtime solves its loops exactly within each sample, so without
 * backlash, the nozzle curve and saturation it is a linear state-space
 * system x' = A x + B e, p_c = C x + D e, with the operator states (and the
 * held input and the output lag) as x. pf_ctrl_state_space reads it off the
 * double runtime itself, column by column: one step with zero input from
 * each unit state gives a column of A and an entry of C, one step from rest
 * with e = 1 gives B and D. So it is the controller that runs, not a second
 * derivation of it.
 *
 * rho(A) = lim ||A^k||^(1/k) (Gelfand's formula) is then evaluated by
 * repeated squaring, k = 2^PF_CHECK_SQUARINGS, rescaling at each step so
 * nothing overflows. Since ||A^k|| >= rho^k, the estimate approaches rho
 * from above; its excess, log(||A^k||/rho^k)/k, is below 1e-12 for any
 * constant up to 1e100. A diagonal similarity (balancing, powers of two,
 * so exact) first evens out the rows and columns: the states span many
 * decades when the gains are extreme.
 */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "pneufrac/pf_controller.h"

#define PF_CHECK_SQUARINGS 48

/* The operators the linear runtime uses, in a fixed order. @return their
 * number. */
static int operators(pf_ctrl_f64 *r, pf_fracop_f64 **ops)
{
    int k = 0;
    ops[k++] = &r->P;
    if (r->c->has_q)
        ops[k++] = &r->Q;
    if (r->c->has_v)
        ops[k++] = &r->V;
    if (r->c->has_w)
        ops[k++] = &r->W;
    return k;
}

/* Pointers to every state the linear runtime has, in a fixed order: each
 * operator's sections and integer stages, the held input, the output lag.
 * @return their number. */
static int states(pf_ctrl_f64 *r, double **s)
{
    pf_fracop_f64 *ops[4];
    int k = 0, o, j, n_int, n_ops = operators(r, ops);

    if (r->c->hold)
        s[k++] = &r->e1;
    for (o = 0; o < n_ops; o++) {
        const pf_fracop_design *c = ops[o]->c;
        for (j = 0; j < c->n_sec; j++)
            s[k++] = &ops[o]->s[j];
        n_int = c->n_int < 0 ? -c->n_int : c->n_int;
        for (j = 0; j < n_int; j++)
            s[k++] = &ops[o]->si[j];
    }
    if (r->c->lag_lam > 0.0)
        s[k++] = &r->lag;
    return k;
}

/* The runtime keeps each operator's branch sum sum_k G_k s_k from its last
 * update (pf_fracop_f64.sum); after states are written directly it must be
 * formed again, in the runtime's order, or the step would use stale sums. */
static void resum(pf_ctrl_f64 *r)
{
    pf_fracop_f64 *ops[4];
    int o, k, n_ops = operators(r, ops);

    for (o = 0; o < n_ops; o++) {
        double sum = 0.0;
        for (k = 0; k < ops[o]->c->n_sec; k++)
            sum += ops[o]->c->G[k] * ops[o]->s[k];
        ops[o]->sum = sum;
    }
}

/* Binds @p r to @p lin, a copy of @p c without the dead time (not a
 * state: the line's output is z^-delay_len of the rest), and lists its
 * states. @return their number. */
static int bind(const pf_ctrl_coeffs_f64 *c, pf_ctrl_coeffs_f64 *lin, pf_ctrl_f64 *r,
                double **s)
{
    *lin = *c;
    lin->delay_len = 0;
    (void)pf_ctrl_init_f64(r, lin, NULL, 0);
    return states(r, s);
}

/* The state space of the linear runtime of @p c (see the head of the
 * file); B, C and D may be NULL. @return the number of states. */
static int read_off(const pf_ctrl_coeffs_f64 *c, double *A, double *B, double *C,
                    double *D)
{
    pf_ctrl_coeffs_f64 lin;
    pf_ctrl_f64 r;
    double *s[PF_CTRL_MAX_STATES], y;
    int n = bind(c, &lin, &r, s), i, j;

    for (j = 0; j < n; j++) {
        pf_ctrl_reset_f64(&r);
        *s[j] = 1.0;
        resum(&r);
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
    if (B != NULL)
        for (i = 0; i < n; i++)
            B[i] = *s[i];
    return n;
}

pf_status pf_ctrl_state_space(const pf_ctrl_coeffs_f64 *c, double *A, double *B,
                              double *C, double *D, int *n)
{
    pf_ctrl_coeffs_f64 lin;
    pf_ctrl_f64 r;
    double *s[PF_CTRL_MAX_STATES];
    if (c == NULL || n == NULL)
        return PF_E_NULL;
    if (c->in_loop_fx)
        return PF_E_UNSUPPORTED;
    if (A == NULL) { /* ask for the size, then place */
        *n = bind(c, &lin, &r, s);
        return PF_OK;
    }
    if (B == NULL || C == NULL || D == NULL)
        return PF_E_NULL;
    *n = read_off(c, A, B, C, D);
    return PF_OK;
}

/* C = A B, n x n, row major; C may not alias A or B. */
static void matmul(const double *a, const double *b, double *c, int n)
{
    int i, j, k;
    for (i = 0; i < n; i++) {
        double *ci = c + (size_t)i * n;
        for (j = 0; j < n; j++)
            ci[j] = 0.0;
        for (k = 0; k < n; k++) {
            const double aik = a[(size_t)i * n + k];
            const double *bk = b + (size_t)k * n;
            if (aik == 0.0)
                continue;
            for (j = 0; j < n; j++)
                ci[j] += aik * bk[j];
        }
    }
}

static double frobenius(const double *a, int n)
{
    double m = 0.0, s = 0.0;
    int i;
    for (i = 0; i < n * n; i++)
        if (fabs(a[i]) > m)
            m = fabs(a[i]);
    if (m == 0.0 || !(m < HUGE_VAL))
        return m;
    for (i = 0; i < n * n; i++)
        s += (a[i] / m) * (a[i] / m);
    return m * sqrt(s);
}

/* Balance @p a in place by powers of two (Parlett and Reinsch, 1969), so
 * that each state's row and column have similar norms. */
static void balance(double *a, int n)
{
    int sweep, i, j, changed = 1;
    for (sweep = 0; sweep < 50 && changed; sweep++) {
        changed = 0;
        for (i = 0; i < n; i++) {
            double c = 0.0, r = 0.0, f = 1.0;
            for (j = 0; j < n; j++)
                if (j != i) {
                    c += fabs(a[(size_t)j * n + i]);
                    r += fabs(a[(size_t)i * n + j]);
                }
            if (c == 0.0 || r == 0.0)
                continue;
            while (c * f * f < r / 4.0) /* scale column by f, row by 1/f */
                f *= 2.0;
            while (c * f * f > r * 4.0)
                f /= 2.0;
            if (f != 1.0) {
                changed = 1;
                for (j = 0; j < n; j++) {
                    a[(size_t)j * n + i] *= f;
                    a[(size_t)i * n + j] /= f;
                }
            }
        }
    }
}

pf_status pf_ctrl_spectral_radius(const pf_ctrl_design *d, pf_ctrl_check_work *w,
                                  double *rho)
{
    pf_ctrl_coeffs_f64 lin;
    double *a, *b, log_norm = 0.0, nrm;
    int n, i, m;

    if (d == NULL || w == NULL || rho == NULL)
        return PF_E_NULL;
    /* The linear loop: the effects are nonlinear or outside the loop. */
    lin = d->rt;
    lin.in_loop_fx = 0;
    lin.play_r = 0.0;
    lin.nozzle_xh = 0.0;
    lin.saturate = 0;
    lin.lag_lam = 0.0;
    a = w->a;
    b = w->b;
    n = read_off(&lin, a, NULL, NULL, NULL);
    balance(a, n);
    for (m = 0; m <= PF_CHECK_SQUARINGS; m++) {
        /* a = A^(2^m) / exp(log_norm), log_norm over 2^m so far. */
        nrm = frobenius(a, n);
        if (nrm == 0.0) {
            *rho = 0.0; /* nilpotent: every pole at z = 0 */
            return PF_OK;
        }
        if (!(nrm < HUGE_VAL)) {
            *rho = HUGE_VAL; /* saturated states: clearly unstable */
            return PF_OK;
        }
        for (i = 0; i < n * n; i++)
            a[i] /= nrm;
        log_norm += log(nrm) / ldexp(1.0, m);
        if (m == PF_CHECK_SQUARINGS)
            break;
        matmul(a, a, b, n);
        memcpy(a, b, sizeof(double) * (size_t)n * (size_t)n);
    }
    *rho = exp(log_norm);
    return PF_OK;
}
