/* SPDX-License-Identifier: MIT */
/*
 * Integer arithmetic of the Q15 runtime. Internal signals are int32 kept
 * within +-2^30 (one guard bit), so a product with a 31-bit mantissa stays
 * below 2^61.
 *
 * Rules: round half up, saturate, never wrap, no undefined behaviour.
 * C99 leaves >> of a negative value implementation-defined (not undefined);
 * every compiler pneufrac targets (GCC, Clang, and the Arm and IAR
 * compilers) shifts arithmetically, and the check below stops the build on
 * one that does not. Left shifts of negative values, which are undefined,
 * are written as multiplications by a power of two.
 */
#ifndef PF_QMATH_H
#define PF_QMATH_H

#include <stdint.h>
#include "pneufrac/pf_fracop.h"

typedef char pf_qmath_needs_arithmetic_shift[((int64_t)-8 >> 1) == -4 ? 1 : -1];

#define PF_Q_MAX ((int32_t)1 << 30)
/* Fractional bits of a state: it is held as s * 2^30 in an int64. */
#define PF_Q_FRAC 30
#define PF_Q_STATE_MAX ((int64_t)PF_Q_MAX << PF_Q_FRAC)

/* Clamp to the internal range +-2^30. */
static inline int32_t pf_q_sat(int64_t v)
{
    if (v > PF_Q_MAX)
        return PF_Q_MAX;
    if (v < -PF_Q_MAX)
        return -PF_Q_MAX;
    return (int32_t)v;
}

/* round-half-up(p / 2^sh), |p| < 2^62, 0 <= sh <= 62. */
static inline int64_t pf_round_shift(int64_t p, unsigned sh)
{
    return sh == 0 ? p : (p + ((int64_t)1 << (sh - 1))) >> sh;
}

/* c * x rounded half up, NOT saturated: one term of a node formed as a
 * sum and saturated once, so that a small difference of large terms keeps
 * its precision. |c.m| < 2^31 and |x| <= 2^31 keep the product below 2^62;
 * the term is clamped to +-2^60 so that a sum of eight cannot wrap. */
static inline int64_t pf_mulw(pf_qc c, int64_t x)
{
    const int64_t lim = (int64_t)1 << 60;
    int64_t v = pf_round_shift((int64_t)c.m * x, c.sh);
    return v > lim ? lim : (v < -lim ? -lim : v);
}

/* pf_mulw for an operand beyond +-2^31 (a wide intermediate): the operand
 * gives up low bits and the shift as many, so the product stays in range;
 * it loses only bits far below the operand's own magnitude. */
static inline int64_t pf_mulw_wide(pf_qc c, int64_t x)
{
    const int64_t lim = (int64_t)1 << 31;
    while ((x > lim || x < -lim) && c.sh > 0) {
        x >>= 1;
        c.sh--;
    }
    return pf_mulw(c, x > lim ? lim : (x < -lim ? -lim : x));
}

/* c * x, rounded half up and saturated to the internal range. */
static inline int32_t pf_mulc(pf_qc c, int64_t x)
{
    return pf_q_sat(pf_mulw(c, x));
}

/* The integer part of a state (floor), in the internal range. */
static inline int32_t pf_q_state(int64_t S)
{
    return (int32_t)(S >> PF_Q_FRAC);
}

/* A state S = s * 2^30 advanced by k * 2^-sh * x, with 30 fractional bits
 * kept: increments far below one LSB still accumulate (what error feedback
 * does for a 32-bit state), so a slow pole decays at its designed rate.
 * |k| < 2^31 and sh >= 30 (a gain below 2: the leak format, checked at
 * design), |x| <= 2^31: the increment stays below 2^62 and the sum, with
 * S within +-2^60, cannot wrap before it is clamped. */
static inline int64_t pf_q_advance(int64_t S, int32_t k, int64_t x, unsigned sh)
{
    S += ((int64_t)k * x) >> (sh - PF_Q_FRAC);
    if (S > PF_Q_STATE_MAX)
        return PF_Q_STATE_MAX;
    if (S < -PF_Q_STATE_MAX)
        return -PF_Q_STATE_MAX;
    return S;
}

/* Round an internal value to Q15 with the output coefficient, saturating
 * to the int16 range (not to +-2^30). */
static inline int16_t pf_q_to_q15(pf_qc c, int64_t x)
{
    int64_t v = pf_round_shift((int64_t)c.m * x, c.sh);
    if (v > 32767)
        return 32767;
    if (v < -32768)
        return -32768;
    return (int16_t)v;
}

#endif /* PF_QMATH_H */
