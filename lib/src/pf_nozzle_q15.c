/* SPDX-License-Identifier: MIT */
/*
 * The nozzle curve in the Q15 runtime. Integer only, no division: a search
 * among at most PF_Q15_NOZZLE_SEG + 1 knots, then one cubic piece (five
 * products). The curve is monotone, so the loop map W(x) = (x + L0 h(x))/
 * max(1, 1 + L0) increases and its knots bracket the solution: the loop is
 * solved without iteration, and has exactly one solution, whatever the
 * input. Functions, not inline: one copy of each on a small core.
 */
#include "pf_nozzle_q15.h"

#include "pf_qmath.h"

/* The piece of v among the knots key[0..n-1] (non-decreasing, n >= 2):
 * the k <= n - 2 with key[k] <= v < key[k + 1], or n - 2 past the end.
 * v >= key[0]. A piece of zero width is never returned but as the last. */
static int piece(const int32_t *key, int n, int32_t v)
{
    int lo = 0, hi = n - 1; /* key[lo] <= v; v < key[hi] or hi = n - 1 */
    while (hi - lo > 1) {
        int mid = (lo + hi) >> 1;
        if (key[mid] <= v)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

/* round-half-up(p / 2^sh) for a constant sh: pf_round_shift's integer,
 * with a shift the compiler writes out (no variable 64-bit shift, which
 * is a loop or a libgcc call on an M0+). |p| < 2^61. */
#define PF_NZ_ROUND(p, sh) (((p) + ((int64_t)1 << ((sh) - 1))) >> (sh))

/* y0 + (y1 - y0) P(r) for an offset d from the piece's start (0 <= d <
 * 2^31), the piece's 2^27/width (m, sh) and shape a, b. r is clamped to
 * [0, 1], so the result stays between the knots but for P's own bulge.
 * |y1 - y0| <= 2^30 (a knot at 0 splits the range), |a|, |b| < 2^29. */
static int64_t cubic(int32_t y0, int32_t y1, int32_t d, int32_t m, uint8_t sh, int32_t a,
                     int32_t b)
{
    const int32_t one = (int32_t)1 << PF_NZ_R;
    pf_qc rq;
    int64_t r64;
    int32_t r, c, rr, p;
    rq.m = m;
    rq.sh = sh;
    r64 = pf_mulw(rq, d);
    r = r64 > one ? one : (int32_t)r64;
    /* c = a + b r (Q24), rr = r (1 - r) (Q27), P = r + c rr (Q27) */
    c = pf_q_sat32(a + PF_NZ_ROUND(pf_q_mul64(b, r), PF_NZ_R));
    rr = (int32_t)PF_NZ_ROUND(pf_q_mul64(r, one - r), PF_NZ_R);
    p = pf_q_sat32(r + PF_NZ_ROUND(pf_q_mul64(c, rr), PF_NZ_AB));
    return y0 + PF_NZ_ROUND(pf_q_mul64(pf_q_sat32((int64_t)y1 - y0), p), PF_NZ_R);
}

/* h(x) on piece k, x in [x_k, x_{k+1}]. */
static int32_t curve(const pf_nozzle_q15 *nz, int k, int32_t x)
{
    return pf_q_sat(cubic(nz->h[k], nz->h[k + 1], x - nz->x[k], nz->rx_m[k], nz->rx_sh[k],
                          nz->ha[k], nz->hb[k]));
}

int32_t pf_nz_h(const pf_nozzle_q15 *nz, int32_t x)
{
    return curve(nz, piece(nz->x, nz->n, x), x);
}

int32_t pf_nz_solve(const pf_nozzle_q15 *nz, int64_t t, int32_t *h)
{
    int n = nz->n, k;
    int64_t x;
    if (nz->direct) {
        x = pf_q_sat(t);
        *h = pf_nz_h(nz, (int32_t)x);
        return (int32_t)x;
    }
    if (t <= nz->w[0]) {
        k = 0;
        x = nz->x[0];
    } else if (t >= nz->w[n - 1]) {
        k = n - 2;
        x = nz->x[n - 1];
    } else {
        k = piece(nz->w, n, (int32_t)t);
        x = cubic(nz->x[k], nz->x[k + 1], (int32_t)(t - nz->w[k]), nz->rw_m[k],
                        nz->rw_sh[k], nz->xa[k], nz->xb[k]);
        /* P may bulge past its ends; x stays on its piece */
        if (x < nz->x[k])
            x = nz->x[k];
        else if (x > nz->x[k + 1])
            x = nz->x[k + 1];
    }
    *h = curve(nz, k, (int32_t)x);
    return (int32_t)x;
}

