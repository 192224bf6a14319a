/* SPDX-License-Identifier: MIT */
/*
 * The nozzle curve's Q15 table (pf_nozzle_q15, pf_controller.h), from the
 * double curve pf_nozzle() and the in-sample loop gain L0.
 *
 * With the normalised gap u = u0 + x/x_1/2 the curve is h = g (F(u0) -
 * F(u)), F(u) = 1/(1+u^2), g = x_1/2/|F'(u0)| its span, flat where the
 * gap is closed (u <= 0). Each piece is the cubic through the curve at
 * both knots and at 1/3 and 2/3 of the way; the inverse x(W) likewise,
 * its inner points found by bisection on the exact W.
 *
 * Placement. A cubic piece of width du errs by about du^4 |F''''|/1950
 * of the span (the largest |r (r - 1/3)(r - 2/3)(r - 1)| is 0.0123, over
 * 4!). The knots equidistribute the density that makes this error equal
 * in every piece (de Boor's rule), relative to |h| rather than to the
 * span: a controller works mostly near its operating point, where a small
 * signal's gain must be right to a small fraction of itself. So pieces
 * shrink towards x = 0 (a knot: the curve is exact there), and one flat
 * piece reaches from the node's end to the closed gap. The inverse adds
 * its own need for a large L0 (see nz_density).
 */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "pf_ctrl_internal.h"
#include "pf_nozzle_q15.h"

#define NZ_XMAX 1073741824.0 /* 2^30: the x node's range */
#define NZ_SEG PF_Q15_NOZZLE_SEG
#define NZ_GRID 512          /* quadrature points per side of u0 */

/* a flat piece and one on each side of x = 0 at least; n fits a byte */
typedef char pf_nozzle_seg_in_range[NZ_SEG == 0 || (NZ_SEG >= 4 && NZ_SEG <= 250) ? 1 : -1];

/* The operating point's gap, in units of x_1/2: the inflection of F,
 * where pf_nozzle() is biased (pf_effects.h). */
static double nz_u0(void)
{
    return 1.0 / sqrt(3.0);
}

/* The curve in internal units of x (scale sx per physical unit). */
static double nz_curve(const pf_ctrl_coeffs_f64 *c, double sx, double x)
{
    return pf_nozzle(x / sx, c->nozzle_xh) * sx;
}

double pf_nozzle_q15_reach(const pf_ctrl_coeffs_f64 *c, double x_range)
{
    /* monotone: its extremes are at the ends */
    return fmax(fabs(pf_nozzle(-x_range, c->nozzle_xh)), fabs(pf_nozzle(x_range, c->nozzle_xh)));
}

/* The density of knots at gap u, for the loop gain L0 and the curve's
 * unit slope at u0 (sg = 1/|F'(u0)|), relative to |h| = |F(u0) - F(u)|
 * of the span: the curve's cubic term, plus the inverse's. For x(W) the
 * quadratic term h' |x'''(W)| W'^3 (x_1/2)^2/span, which is
 *   -F' sg |3 L0^2 sg F''^2/(1 + L0 h')^2 + L0 F'''/(1 + L0 h')|
 * with h' = -sg F', serves as the measure of how far x(W) is from
 * straight: nothing for a small L0; for a large one it crowds the knots
 * towards the closed gap, where h' -> 0 and x(W) turns into a root. */
static double nz_density(double u, double u0, double L0, double sg)
{
    double s = 1.0 + u * u, f1 = -2.0 * u / (s * s), f2 = (6.0 * u * u - 2.0) / (s * s * s);
    double f3 = 24.0 * u * (1.0 - u * u) / (s * s * s * s);
    double f4 = 24.0 * (5.0 * u * u * u * u - 10.0 * u * u + 1.0) / (s * s * s * s * s);
    double l = 1.0 - L0 * sg * f1, rel = fabs(1.0 / (1.0 + u0 * u0) - 1.0 / s);
    double inv = -f1 * sg * fabs(3.0 * L0 * L0 * sg * f2 * f2 / (l * l) + L0 * f3 / l);
    return pow(fabs(f4) / (1950.0 * rel), 0.25) + cbrt(inv / (72.0 * rel));
}

/* Knots from u = a to u = b (n pieces) equidistributing nz_density,
 * appended to x[] as internal x = (u - u0) xh_i rounded, the ends as the
 * given xa, xb; a knot that does not exceed the last one is dropped.
 * Returns the new count. */
static int nz_side(int32_t *x, int cnt, double a, double b, int32_t xa, int32_t xb, int n,
                   double u0, double xh_i, double L0, double sg)
{
    double cum[NZ_GRID + 1], u[NZ_GRID + 1], va = asinh(a), dv = (asinh(b) - va) / NZ_GRID;
    int i, j = 1, k;
    /* du = cosh(v) dv on a grid uniform in v = asinh(u), fine near the
     * knee and u0, sparse on the tail; midpoints, as the density is
     * infinite (integrably) at u0 */
    cum[0] = 0.0;
    u[0] = a;
    for (i = 1; i <= NZ_GRID; i++) {
        double vm = va + dv * (i - 0.5);
        u[i] = sinh(va + dv * i);
        cum[i] = cum[i - 1] + nz_density(sinh(vm), u0, L0, sg) * cosh(vm) * dv;
    }
    for (k = 0; k <= n; k++) {
        double level = cum[NZ_GRID] * k / n, uk;
        int32_t xk;
        while (j < NZ_GRID && cum[j] < level)
            j++;
        uk = cum[j] > cum[j - 1]
                 ? u[j - 1] + (u[j] - u[j - 1]) * (level - cum[j - 1]) / (cum[j] - cum[j - 1])
                 : u[j];
        xk = k == 0 ? xa
                    : (k == n ? xb : (int32_t)fmax(xa, fmin(xb, round((uk - u0) * xh_i))));
        if (cnt == 0 || xk > x[cnt - 1])
            x[cnt++] = xk;
    }
    return cnt;
}

/* Integral of the density over [a, b] (for the split between sides). */
static double nz_mass(double a, double b, double u0, double L0, double sg)
{
    double va = asinh(a), dv = (asinh(b) - va) / NZ_GRID, m = 0.0;
    int i;
    for (i = 0; i < NZ_GRID; i++) {
        double vm = va + dv * (i + 0.5);
        m += nz_density(sinh(vm), u0, L0, sg) * cosh(vm);
    }
    return m * dv;
}

/* The loop map W(x) of the exact curve: (x + L0 h(x))/max(1, 1 + L0),
 * h in units of x. */
static double nz_map(const pf_ctrl_coeffs_f64 *c, double sx, double L0, double x)
{
    return (x + L0 * nz_curve(c, sx, x)) / fmax(1.0, 1.0 + L0);
}

/* The x in [lo, hi] where the exact W(x) = w (bisection: W increases). */
static double nz_inverse(const pf_ctrl_coeffs_f64 *c, double sx, double L0, double w, double lo,
                         double hi)
{
    int i;
    for (i = 0; i < 80 && hi - lo > 1e-6; i++) {
        double mid = 0.5 * (lo + hi);
        if (nz_map(c, sx, L0, mid) < w)
            lo = mid;
        else
            hi = mid;
    }
    return 0.5 * (lo + hi);
}

/* Whether the in-sample loop moves the solution by less than half a unit
 * of x anywhere: |W(x) - x| <= 1/2 at the knots and within each piece
 * (W - x = (L0 (h - x) - min(0, L0) x)/max(1, 1 + L0) is smooth between
 * the knots, and is checked at 1/3 and 2/3 of each piece too). Then the
 * solution is W's target itself, and the runtime skips the inverse. */
static int nz_direct(const pf_ctrl_coeffs_f64 *c, double sx, double L0, const pf_nozzle_q15 *nz)
{
    int k, i;
    for (k = 0; k + 1 < nz->n; k++)
        for (i = 0; i < 3; i++) {
            double x = nz->x[k] + ((double)nz->x[k + 1] - nz->x[k]) * i / 3.0;
            if (fabs(nz_map(c, sx, L0, x) - x) > 0.5)
                return 0;
        }
    return fabs(nz_map(c, sx, L0, nz->x[nz->n - 1]) - nz->x[nz->n - 1]) <= 0.5;
}

/* The shape (a, b) of P(r) = r + r (1 - r)(a + b r) through y at r = 1/3
 * and 2/3 (y1, y2) on the piece from y0 to y3, in Q24. */
static void nz_shape(double y0, double y1, double y2, double y3, int32_t *a, int32_t *b)
{
    double d = y3 - y0, p1, p2, ga, gb;
    if (d == 0.0) {
        *a = *b = 0;
        return;
    }
    /* P(1/3) - 1/3 = (2/9)(a + b/3), P(2/3) - 2/3 = (2/9)(a + 2b/3) */
    p1 = 4.5 * ((y1 - y0) / d - 1.0 / 3.0);
    p2 = 4.5 * ((y2 - y0) / d - 2.0 / 3.0);
    gb = 3.0 * (p2 - p1);
    ga = p1 - gb / 3.0;
    /* a monotone piece keeps |a|, |b| below 27; the clamp only guards */
    *a = (int32_t)fmax(-4.0e8, fmin(4.0e8, round(ldexp(ga, PF_NZ_AB))));
    *b = (int32_t)fmax(-4.0e8, fmin(4.0e8, round(ldexp(gb, PF_NZ_AB))));
}

/* 2^27 over a piece's width, in (m, sh). */
static pf_status nz_per_width(double width, int32_t *m, uint8_t *sh)
{
    pf_qc q;
    pf_status st = pf_qc_make(&q, width > 0.0 ? ldexp(1.0, PF_NZ_R) / width : 0.0);
    *m = q.m;
    *sh = q.sh;
    return st;
}

pf_status pf_nozzle_q15_make(pf_nozzle_q15 *nz, const pf_ctrl_coeffs_f64 *c, double sx)
{
    double L0 = 1.0 / c->loop_inv - 1.0, div = fmax(1.0, 1.0 + L0);
    double u0 = nz_u0(), xh_i = c->nozzle_xh * sx;
    double sg = (1.0 + u0 * u0) * (1.0 + u0 * u0) / (2.0 * u0); /* 1/|F'(u0)| */
    double ulo = u0 - NZ_XMAX / xh_i, uhi = u0 + NZ_XMAX / xh_i, uc = fmax(0.0, ulo);
    double ml, mr, hs;
    int n = 0, k, free_pieces = NZ_SEG - (ulo < 0.0 ? 1 : 0), left;
    pf_status st = PF_OK;

    memset(nz, 0, sizeof *nz);
    if (NZ_SEG == 0)
        return PF_E_UNSUPPORTED;
    if (!(xh_i > 0.0) || !isfinite(xh_i) || !isfinite(L0))
        return PF_E_SCALE;
    /* pieces on each side of x = 0 in proportion to the density's mass */
    ml = nz_mass(uc, u0, u0, L0, sg);
    mr = nz_mass(u0, uhi, u0, L0, sg);
    left = (int)lround(free_pieces * ml / (ml + mr));
    left = left < 1 ? 1 : (left > free_pieces - 1 ? free_pieces - 1 : left);
    /* the node's end, the closed gap (the knee) if within the node, the
     * operating point x = 0, the other end */
    nz->x[n++] = -(int32_t)NZ_XMAX;
    n = nz_side(nz->x, n, uc, u0, (int32_t)fmax(-NZ_XMAX, round(-u0 * xh_i)), 0, left, u0, xh_i,
                L0, sg);
    n = nz_side(nz->x, n, u0, uhi, 0, (int32_t)NZ_XMAX, free_pieces - left, u0, xh_i, L0, sg);
    nz->n = (uint8_t)n;

    /* h in units of x times 2^h_sh: its reach within the node fills 2^30,
     * however small the curve's span is against x's range */
    while (nz->h_sh < 30 &&
           ldexp(pf_nozzle_q15_reach(c, NZ_XMAX / sx) * sx, nz->h_sh + 1) <= NZ_XMAX)
        nz->h_sh++;
    hs = ldexp(1.0, nz->h_sh);
    for (k = 0; k < n; k++) {
        double h = fmax(-NZ_XMAX, fmin(NZ_XMAX, round(nz_curve(c, sx, nz->x[k]) * hs)));
        double w;
        nz->h[k] = (int32_t)h;
        if (k > 0 && nz->h[k] < nz->h[k - 1]) /* rounding must not undo monotony */
            nz->h[k] = nz->h[k - 1];
        w = round((nz->x[k] + L0 * nz->h[k] / hs) / div);
        if (!(fabs(w) < 2147483647.0))
            return PF_E_SCALE;
        nz->w[k] = (int32_t)w;
        /* W decreasing: 1 + L0 h' < 0 somewhere, the loop not monotone */
        if (k > 0 && nz->w[k] < nz->w[k - 1])
            return PF_E_UNSUPPORTED;
    }
    for (k = 0; k + 1 < n && st == PF_OK; k++) {
        double x0 = nz->x[k], dx = (double)nz->x[k + 1] - x0;
        double w0 = nz->w[k], dw = (double)nz->w[k + 1] - w0;
        nz_shape(nz->h[k], nz_curve(c, sx, x0 + dx / 3.0) * hs,
                 nz_curve(c, sx, x0 + 2.0 * dx / 3.0) * hs, nz->h[k + 1], &nz->ha[k], &nz->hb[k]);
        st = nz_per_width(dx, &nz->rx_m[k], &nz->rx_sh[k]);
        if (st == PF_OK && dw > 0.0) {
            nz_shape(x0, nz_inverse(c, sx, L0, w0 + dw / 3.0, x0, x0 + dx),
                     nz_inverse(c, sx, L0, w0 + 2.0 * dw / 3.0, x0, x0 + dx), x0 + dx,
                     &nz->xa[k], &nz->xb[k]);
            st = nz_per_width(dw, &nz->rw_m[k], &nz->rw_sh[k]);
        }
    }
    if (st == PF_OK)
        st = pf_qc_make(&nz->t_x, (1.0 + L0) / div);
    nz->direct = st == PF_OK && nz_direct(c, sx, L0, nz);
    return st;
}
