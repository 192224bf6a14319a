/* SPDX-License-Identifier: MIT */
/*
 * Stability of a designed controller's sampled loop: the spectral radius
 * of its linear runtime's state-transition matrix, i.e. the largest |z|
 * of its discrete closed-loop poles.
 *
 * The runtime solves its loops exactly within each sample, so it is a
 * linear state-space system x' = A x + B e with the operator states as x;
 * pf_ctrl_state_space (pf_ctrl_lti.c) reads A off the double runtime.
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
    double *a, *b, log_norm = 0.0, nrm;
    int n, i, m;

    if (d == NULL || w == NULL || rho == NULL)
        return PF_E_NULL;
    a = w->a;
    b = w->b;
    /* The loop's own poles: without the effects and the output line. */
    n = pf_ctrl_state_space(d, 0, a, NULL, NULL, NULL);
    if (n < 0)
        return PF_E_NULL;
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
