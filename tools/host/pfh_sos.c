/* SPDX-License-Identifier: MIT */
/*
 * Operator -> biquad cascade (see pfh_sos.h).
 *
 * Tustin, s = c (1 - z^-1)/(1 + z^-1), maps every real factor to a
 * first-order polynomial in z^-1:
 *     s + w  ->  (c + w) (1 - rho z^-1) / (1 + z^-1),   rho = (c - w)/(c + w)
 *     s      ->  c (1 - z^-1) / (1 + z^-1)
 * so s^m k prod(s + z_i)/prod(s + p_j) becomes a gain times monic factors
 * (1 - rho z^-1), with (1 + z^-1) to the power (np - nz) - m, and the
 * held-input mean adds one more (1 + z^-1)/2.
 */
#include "pfh_sos.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_ROOTS (2 * PFH_SOS_MAX)

typedef struct roots {
    int n;
    double r[MAX_ROOTS];
} roots;

static void push(roots *l, double r, int times)
{
    while (times-- > 0 && l->n < MAX_ROOTS)
        l->r[l->n++] = r;
}

static int descending(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return (a < b) - (a > b);
}

/* Monic (1 - r1 z^-1)(1 - r2 z^-1), or a first-order factor if only one
 * root is left (r2 absent): coefficients of 1, z^-1, z^-2. */
static void poly2(const roots *l, int i, int j, double out[3])
{
    double r1 = i < l->n ? l->r[i] : 0.0, r2 = (j < l->n && j != i) ? l->r[j] : 0.0;
    out[0] = 1.0;
    out[1] = -(r1 + r2);
    out[2] = r1 * r2;
}

static double complex stage_resp(const double b[3], const double a[2],
                                 double complex zi)
{
    return (b[0] + zi * (b[1] + zi * b[2])) / (1.0 - zi * (a[0] + zi * a[1]));
}

double complex pfh_sos_resp(const pfh_sos *s, double omega)
{
    double complex zi = cexp(-I * omega / s->fs), h = 1.0;
    int k;
    for (k = 0; k < s->n; k++)
        h *= stage_resp(s->b[k], s->a[k], zi);
    return h;
}

double complex pfh_sos_op_resp(const pf_fracop_design *op, double omega)
{
    double re, im;
    double complex h;
    pf_fracop_freqresp(op, omega, &re, &im);
    h = re + I * im;
    if (op->hold)
        h *= 0.5 * (1.0 + cexp(-I * omega / op->fs));
    return h;
}

pf_status pfh_sos_from_op(pfh_sos *s, const pf_fracop_design *op,
                          const pf_design_opts *opt, double scale)
{
    double z[PF_MAX_SEC], p[PF_MAX_SEC], K, c = op->c, g0, wref, mag;
    int m, nz, np, i, k, nsec, e;
    roots zr = {0, {0}}, pr = {0, {0}};
    pf_status st = pf_fracop_zpk(op->alpha, opt, &m, &K, z, &nz, p, &np);
    if (st != PF_OK)
        return st;

    g0 = scale * op->gain * K * (op->hold ? 0.5 : 1.0) * pow(c, m);
    for (i = 0; i < nz; i++) {
        g0 *= c + z[i];
        push(&zr, (c - z[i]) / (c + z[i]), 1);
    }
    for (i = 0; i < np; i++) {
        g0 /= c + p[i];
        push(&pr, (c - p[i]) / (c + p[i]), 1);
    }
    /* Roots at z = -1 from the degree difference, the integer part and
     * the held input; at z = +1 from the integer part. */
    e = (np - nz) - m + (op->hold ? 1 : 0);
    push(e > 0 ? &zr : &pr, -1.0, abs(e));
    push(m < 0 ? &pr : &zr, 1.0, abs(m));

    /* Rank-matched first-order sections (slowest pole with slowest zero:
     * Oustaloup's zeros and poles interlace, so each section is a bounded
     * lead or lag), then section k with section nsec-1-k in one biquad. */
    qsort(zr.r, (size_t)zr.n, sizeof zr.r[0], descending);
    qsort(pr.r, (size_t)pr.n, sizeof pr.r[0], descending);
    nsec = zr.n > pr.n ? zr.n : pr.n;
    memset(s, 0, sizeof *s);
    s->fs = op->fs;
    s->n = (nsec + 1) / 2;
    for (k = 0; k < s->n; k++) {
        double den[3];
        int j = nsec - 1 - k;
        /* Missing roots (one list shorter) are 0: a factor of 1. */
        poly2(&zr, k, j, s->b[k]);
        poly2(&pr, k, j, den);
        s->a[k][0] = -den[1];
        s->a[k][1] = -den[2];
    }

    /* Even gain at the band's geometric centre: in fixed point no stage
     * then amplifies much more than another there. */
    wref = sqrt(opt->wb * opt->wh);
    if (wref > 0.5 * M_PI * op->fs)
        wref = 0.5 * M_PI * op->fs;
    mag = fabs(g0) * cabs(pfh_sos_resp(s, wref));
    for (k = 0; k < s->n; k++) {
        double complex zi = cexp(-I * wref / op->fs);
        double gk = pow(mag, 1.0 / s->n) / cabs(stage_resp(s->b[k], s->a[k], zi));
        if (k == 0 && g0 < 0.0)
            gk = -gk;
        for (i = 0; i < 3; i++)
            s->b[k][i] *= gk;
    }
    return PF_OK;
}

void pfh_sos_f32(const pfh_sos *s, float *c)
{
    int k;
    for (k = 0; k < s->n; k++) {
        c[5 * k + 0] = (float)s->b[k][0];
        c[5 * k + 1] = (float)s->b[k][1];
        c[5 * k + 2] = (float)s->b[k][2];
        c[5 * k + 3] = (float)s->a[k][0];
        c[5 * k + 4] = (float)s->a[k][1];
    }
}

static int fits(const pfh_sos *s, int shift)
{
    double f = ldexp(1.0, 15 - shift);
    int k, i;
    for (k = 0; k < s->n; k++)
        for (i = 0; i < 5; i++) {
            double v = i < 3 ? s->b[k][i] : s->a[k][i - 3];
            double r = floor(v * f + 0.5);
            if (r < -32768.0 || r > 32767.0)
                return 0;
        }
    return 1;
}

pf_status pfh_sos_q15_make(const pfh_sos *s, pfh_sos_q15 *q)
{
    int shift, k;
    double f;
    for (shift = 0; shift <= 15 && !fits(s, shift); shift++)
        ;
    if (shift > 15)
        return PF_E_SCALE;
    memset(q, 0, sizeof *q);
    q->n = s->n;
    q->post_shift = shift;
    f = ldexp(1.0, 15 - shift);
    for (k = 0; k < s->n; k++) {
        /* CMSIS's q15 layout: a zero after b0 pads the pairs for its
         * dual 16-bit multiply-accumulate instructions. */
        q->c[6 * k + 0] = (int16_t)floor(s->b[k][0] * f + 0.5);
        q->c[6 * k + 1] = 0;
        q->c[6 * k + 2] = (int16_t)floor(s->b[k][1] * f + 0.5);
        q->c[6 * k + 3] = (int16_t)floor(s->b[k][2] * f + 0.5);
        q->c[6 * k + 4] = (int16_t)floor(s->a[k][0] * f + 0.5);
        q->c[6 * k + 5] = (int16_t)floor(s->a[k][1] * f + 0.5);
    }
    return PF_OK;
}

double pfh_sos_q15_value(const pfh_sos_q15 *q, int16_t c)
{
    return ldexp((double)c, q->post_shift - 15);
}
