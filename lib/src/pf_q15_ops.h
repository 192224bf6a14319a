/* SPDX-License-Identifier: MIT */
/*
 * Q15 operator kernels, shared by the operator and controller runtimes.
 * Same two-phase split as the float kernels (pf_float_ops.h):
 *   S = pf_q_op_state(op, &sf);   y = pf_q_op_update(op, u, sf).
 * Integer only: this is the code the Cortex-M0+ build must keep free of
 * floating-point helpers. Every product is pf_q_mul16 (two 32-bit
 * multiplies on an M0+) except one pf_mulw per operator and sample.
 *
 * Leaky section: s <- s + lam (u - s), lam = lam_m 2^-lam_sh with a 15-bit
 * mantissa (2^-16 relative: a pole moves by far less than the
 * approximation's own error). The state is s 2^32 in two words
 * (pf_q15_sec), so the integer part needs no shift and increments far
 * below one LSB accumulate. One sample of a slow section (lam < 1/8) is,
 * exactly:
 *   p  = floor(lam_m ((u >> 1) - (hi >> 1)) / 2^16)        |p| < 2^30
 *   s <- s + p 2^(49 - lam_sh)                 (hi:lo, 49 - lam_sh <= 31)
 * i.e. lam (u - s) with d = u - s halved (so it fits 32 bits whatever the
 * states) and the product floored: a state settles within 11 units (of
 * 2^28 for a node's design peak) of the exact recursion's: the floor of
 * the product biases it by less than 2^17/lam_m <= 8 units, the halving
 * and the dropped fraction in d by 3 more. A slow section is a convex
 * combination of its state and input, so it needs no clamp; the few near
 * Nyquist (lam up to 2) can overshoot their input and are clamped.
 *
 * Output: S = sum_k G_m[k] hi_k 2^-G_sh with exact 64-bit products, summed
 * and rounded once: for a differentiating fractional part S nearly cancels
 * the feedthrough d u, so the gains keep 26 bits. The sum is formed for the
 * next sample in the update loop, from the new states (sv).
 */
#ifndef PF_Q15_OPS_H
#define PF_Q15_OPS_H

#include "pf_qmath.h"

/* A fast section's state stays within +-2^31 - 1: its halved difference
 * to the input then fits 31 bits. */
#define PF_Q_SEC_MAX INT32_MAX

/* *sf keeps the fractional part's sum unsaturated: for a differentiating
 * operator it nearly cancels the feedthrough d*u, and clamping either term
 * alone before the sum would be wrong. */
static inline int32_t pf_q_op_state(const pf_fracop_q15 *S, int64_t *sf)
{
    const pf_fracop_coeffs_q15 *c = S->c;
    int64_t wide;
    int k, n = c->n_int < 0 ? -c->n_int : c->n_int;
    *sf = pf_round_shift(S->sv, c->G_sh);
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
    int32_t y = pf_q_sat(pf_round_shift(pf_q_mul64(c->d.m, u), c->d.sh) + sf);
    int32_t u2 = u >> 1;
    int64_t sv = 0;
    int k, n = c->n_int < 0 ? -c->n_int : c->n_int, n_slow = c->n_slow, n_sec = c->n_sec;
    for (k = 0; k < n_slow; k++) {
        uint32_t lo = S->s[k].lo;
        int32_t hi = S->s[k].hi;
        unsigned v = 49u - c->lam_sh[k]; /* in [5, 31] */
        int32_t p = pf_q_mul16(c->lam_m[k], u2 - (hi >> 1));
        /* the sum fits (a convex combination); the words may wrap on the
         * way. The carry written two ways that GCC compiles best on each
         * kind of core (measured): the same integer. */
#if PF_Q15_NARROW_MUL
        uint32_t inc = (uint32_t)p << v, carry;
        lo += inc;
        carry = lo < inc;
#else
        uint64_t t = (uint64_t)lo + ((uint32_t)p << v);
        uint32_t carry = (uint32_t)(t >> 32);
        lo = (uint32_t)t;
#endif
        hi = (int32_t)((uint32_t)hi + (uint32_t)(p >> (32u - v)) + carry);
        S->s[k].lo = lo;
        S->s[k].hi = hi;
        sv += pf_q_mul64(c->G_m[k], hi);
    }
    for (; k < n_sec; k++) {
        int32_t hi = S->s[k].hi;
        int32_t p = pf_q_mul16(c->lam_m[k], u2 - (hi >> 1));
        /* lam_sh in [14, 17]: the increment is p 2^(17 - lam_sh) units */
        int64_t h = (int64_t)hi + (int64_t)p * ((int32_t)1 << (17u - c->lam_sh[k]));
        hi = h > PF_Q_SEC_MAX ? PF_Q_SEC_MAX : (h < -PF_Q_SEC_MAX ? -PF_Q_SEC_MAX : (int32_t)h);
        S->s[k].hi = hi;
        sv += pf_q_mul64(c->G_m[k], hi);
    }
    S->sv = sv;
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
