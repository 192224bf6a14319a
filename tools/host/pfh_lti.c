/* SPDX-License-Identifier: MIT */
/*
 * A design's realised controller as state space, zeros/poles/gain and
 * second-order sections (see pfh_lti.h).
 */
#include "pfh_lti.h"

#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

const char *pfh_lti_strerror(int err)
{
    switch (err) {
    case PFH_LTI_OK:
        return "no error";
    case PFH_LTI_NONLINEAR:
        return "backlash, the nozzle curve and saturation are nonlinear: no "
               "transfer function";
    case PFH_LTI_DEADTIME:
        return "a dead time of D samples adds D states: export without it and "
               "append z^-D";
    case PFH_LTI_NOMEM:
        return "out of memory";
    default:
        return "the eigenvalue computation failed";
    }
}

int pfh_lti_ss_make(pfh_lti_ss *ss, const pf_ctrl_design *d)
{
    const size_t max = PF_CTRL_MAX_STATES;

    memset(ss, 0, sizeof *ss);
    if (d->rt.in_loop_fx)
        return PFH_LTI_NONLINEAR;
    if (d->rt.delay_len > 0)
        return PFH_LTI_DEADTIME;
    ss->A = malloc(sizeof *ss->A * max * max);
    ss->B = malloc(sizeof *ss->B * max);
    ss->C = malloc(sizeof *ss->C * max);
    if (ss->A == NULL || ss->B == NULL || ss->C == NULL) {
        pfh_lti_ss_free(ss);
        return PFH_LTI_NOMEM;
    }
    /* The whole realised controller: the output lag included. */
    ss->n = pf_ctrl_state_space(d, 1, ss->A, ss->B, ss->C, &ss->D);
    ss->fs = d->opt.fs;
    return PFH_LTI_OK;
}

void pfh_lti_ss_free(pfh_lti_ss *ss)
{
    free(ss->A);
    free(ss->B);
    free(ss->C);
    memset(ss, 0, sizeof *ss);
}

double complex pfh_lti_ss_resp(const pfh_lti_ss *ss, double omega)
{
    const int n = ss->n;
    const double complex z = cexp(I * omega / ss->fs);
    lapack_complex_double *m = malloc(sizeof *m * (size_t)n * (size_t)n);
    lapack_complex_double *x = malloc(sizeof *x * (size_t)n);
    lapack_int *piv = malloc(sizeof *piv * (size_t)n);
    double complex h = NAN;
    int i, j;

    if (m != NULL && x != NULL && piv != NULL) {
        for (i = 0; i < n; i++) {
            for (j = 0; j < n; j++)
                m[(size_t)i * (size_t)n + (size_t)j] =
                    (i == j ? z : 0.0) - ss->A[(size_t)i * (size_t)n + (size_t)j];
            x[i] = ss->B[i];
        }
        if (LAPACKE_zgesv(LAPACK_ROW_MAJOR, n, 1, m, n, piv, x, 1) == 0) {
            h = ss->D;
            for (i = 0; i < n; i++)
                h += ss->C[i] * x[i];
        }
    }
    free(m);
    free(x);
    free(piv);
    return h;
}

/* Eigenvalues of the n x n row-major matrix a (overwritten) into ev. */
static int eigenvalues(double *a, int n, double complex *ev)
{
    double *wr = malloc(sizeof *wr * (size_t)n), *wi = malloc(sizeof *wi * (size_t)n);
    int i, rc = PFH_LTI_NOMEM;
    if (wr != NULL && wi != NULL) {
        rc = LAPACKE_dgeev(LAPACK_ROW_MAJOR, 'N', 'N', n, a, n, wr, wi, NULL, 1, NULL, 1)
                 == 0 ? PFH_LTI_OK : PFH_LTI_NUMERIC;
        for (i = 0; rc == PFH_LTI_OK && i < n; i++)
            ev[i] = wr[i] + I * wi[i];
    }
    free(wr);
    free(wi);
    return rc;
}

int pfh_lti_zpk_make(pfh_lti_zpk *zpk, const pfh_lti_ss *ss)
{
    const size_t n = (size_t)ss->n;
    double *a;
    size_t i, j;
    int rc;

    memset(zpk, 0, sizeof *zpk);
    if (ss->D == 0.0 || !isfinite(ss->D))
        return PFH_LTI_NUMERIC;
    a = malloc(sizeof *a * n * n);
    zpk->z = malloc(sizeof *zpk->z * n);
    zpk->p = malloc(sizeof *zpk->p * n);
    if (a == NULL || zpk->z == NULL || zpk->p == NULL) {
        free(a);
        pfh_lti_zpk_free(zpk);
        return PFH_LTI_NOMEM;
    }
    zpk->fs = ss->fs;
    zpk->k = ss->D;
    zpk->nz = zpk->np = ss->n;
    memcpy(a, ss->A, sizeof *a * n * n);
    rc = eigenvalues(a, ss->n, zpk->p);
    /* With D != 0 the zeros are the poles of the inverse system,
     * x[n+1] = (A - B C/D) x[n] + ...: n of them, and k = D. */
    for (i = 0; rc == PFH_LTI_OK && i < n; i++)
        for (j = 0; j < n; j++)
            a[i * n + j] = ss->A[i * n + j] - ss->B[i] * ss->C[j] / ss->D;
    if (rc == PFH_LTI_OK)
        rc = eigenvalues(a, ss->n, zpk->z);
    free(a);
    if (rc != PFH_LTI_OK)
        pfh_lti_zpk_free(zpk);
    return rc;
}

void pfh_lti_zpk_free(pfh_lti_zpk *zpk)
{
    free(zpk->z);
    free(zpk->p);
    memset(zpk, 0, sizeof *zpk);
}

double complex pfh_lti_zpk_resp(const pfh_lti_zpk *zpk, double omega)
{
    const double complex z = cexp(I * omega / zpk->fs);
    double complex h = zpk->k;
    int i;
    /* Ratio by ratio, so that a long product neither overflows nor
     * underflows on its way. */
    for (i = 0; i < zpk->nz || i < zpk->np; i++) {
        if (i < zpk->nz)
            h *= z - zpk->z[i];
        if (i < zpk->np)
            h /= z - zpk->p[i];
    }
    return h;
}

/* One quadratic factor 1 + c1 w + c2 w^2 (w = z^-1) and how near z = 1 its
 * nearest root lies. */
typedef struct quad {
    double c1, c2, key;
} quad;

static int by_key(const void *x, const void *y)
{
    double a = ((const quad *)x)->key, b = ((const quad *)y)->key;
    return (a > b) - (a < b);
}

static int by_distance_to_one(const void *x, const void *y)
{
    double a = fabs(1.0 - *(const double *)x), b = fabs(1.0 - *(const double *)y);
    return (a > b) - (a < b);
}

/* The roots r[0..n) as quadratics sorted by nearness to z = 1. */
static int quads_of(const double complex *r, int n, quad *q)
{
    double *re = malloc(sizeof *re * (size_t)(n > 0 ? n : 1));
    int nr = 0, nq = 0, i;
    if (re == NULL)
        return -1;
    for (i = 0; i < n; i++) {
        if (cimag(r[i]) > 0.0) {
            /* A conjugate pair: (1 - p w)(1 - conj(p) w). */
            q[nq].c1 = -2.0 * creal(r[i]);
            q[nq].c2 = creal(r[i]) * creal(r[i]) + cimag(r[i]) * cimag(r[i]);
            q[nq].key = cabs(1.0 - r[i]);
            nq++;
        } else if (cimag(r[i]) == 0.0) {
            re[nr++] = creal(r[i]);
        }
    }
    qsort(re, (size_t)nr, sizeof *re, by_distance_to_one);
    for (i = 0; i < (nr + 1) / 2; i++) {
        double r1 = re[i], r2 = (nr - 1 - i != i) ? re[nr - 1 - i] : 0.0;
        q[nq].c1 = -(r1 + r2);
        q[nq].c2 = r1 * r2;
        q[nq].key = fabs(1.0 - r1);
        nq++;
    }
    free(re);
    qsort(q, (size_t)nq, sizeof *q, by_key);
    return nq;
}

int pfh_lti_sos_make(pfh_lti_sos *sos, const pfh_lti_zpk *zpk)
{
    quad *qz = malloc(sizeof *qz * (size_t)(zpk->nz + 1));
    quad *qp = malloc(sizeof *qp * (size_t)(zpk->np + 1));
    int nqz, nqp, k;

    memset(sos, 0, sizeof *sos);
    if (zpk->nz != zpk->np) {
        free(qz);
        free(qp);
        return PFH_LTI_NUMERIC;
    }
    nqz = qz != NULL ? quads_of(zpk->z, zpk->nz, qz) : -1;
    nqp = qp != NULL ? quads_of(zpk->p, zpk->np, qp) : -1;
    if (nqz < 0 || nqp < 0) {
        free(qz);
        free(qp);
        return PFH_LTI_NOMEM;
    }
    sos->n = nqz > nqp ? nqz : nqp;
    if (sos->n == 0)
        sos->n = 1;
    sos->s = calloc((size_t)sos->n, sizeof *sos->s);
    if (sos->s == NULL) {
        free(qz);
        free(qp);
        return PFH_LTI_NOMEM;
    }
    sos->fs = zpk->fs;
    for (k = 0; k < sos->n; k++) {
        sos->s[k][0] = 1.0;
        sos->s[k][3] = 1.0;
        if (k < nqz) {
            sos->s[k][1] = qz[k].c1;
            sos->s[k][2] = qz[k].c2;
        }
        if (k < nqp) {
            sos->s[k][4] = qp[k].c1;
            sos->s[k][5] = qp[k].c2;
        }
    }
    /* H(z) = k prod(z - z_i)/prod(z - p_i) = k prod(1 - z_i w)/prod(1 -
     * p_i w) when there are as many zeros as poles. */
    for (k = 0; k < 3; k++)
        sos->s[0][k] *= zpk->k;
    free(qz);
    free(qp);
    return PFH_LTI_OK;
}

void pfh_lti_sos_free(pfh_lti_sos *sos)
{
    free(sos->s);
    memset(sos, 0, sizeof *sos);
}

double complex pfh_lti_sos_resp(const pfh_lti_sos *sos, double omega)
{
    const double complex w = cexp(-I * omega / sos->fs);
    double complex h = 1.0;
    int k;
    for (k = 0; k < sos->n; k++) {
        const double *c = sos->s[k];
        h *= (c[0] + w * (c[1] + w * c[2])) / (c[3] + w * (c[4] + w * c[5]));
    }
    return h;
}
