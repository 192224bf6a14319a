/* SPDX-License-Identifier: MIT */
/*
 * Integer arithmetic of the Q15 runtime. Internal signals are int32 kept
 * within +-2^30 (one guard bit), so a difference of two fits int32's range
 * in int64 and a product with a 31-bit mantissa stays below 2^62.
 *
 * Rules: round half up, saturate, never wrap. Right shifts of negative
 * numbers are implementation-defined in C99 and left shifts of them are
 * undefined, so shifts go through uint64 with a bias (pf_floor_shift).
 */
#ifndef PF_QMATH_H
#define PF_QMATH_H

#include <stdint.h>
#include "pneufrac/pf_fracop.h"

#define PF_Q_MAX ((int32_t)1 << 30)
#define PF_Q_BIAS ((uint64_t)1 << 62)

/* Clamp to the internal range +-2^30. */
static inline int32_t pf_q_sat(int64_t v)
{
    if (v > PF_Q_MAX)
        return PF_Q_MAX;
    if (v < -PF_Q_MAX)
        return -PF_Q_MAX;
    return (int32_t)v;
}

/* floor(p / 2^sh) for -2^62 <= p < 2^63 and 1 <= sh <= 62, without UB:
 * the bias makes the operand non-negative, and 2^62 is a multiple of 2^sh. */
static inline int64_t pf_floor_shift(int64_t p, unsigned sh)
{
    return (int64_t)(((uint64_t)p + PF_Q_BIAS) >> sh) -
           (int64_t)(PF_Q_BIAS >> sh);
}

/* round-half-up(p / 2^sh), |p| < 2^62, 0 <= sh <= 62. */
static inline int64_t pf_round_shift(int64_t p, unsigned sh)
{
    if (sh == 0)
        return p;
    return pf_floor_shift(p + ((int64_t)1 << (sh - 1)), sh);
}

/* c * x, rounded half up and saturated to the internal range.
 * |c.m| < 2^31 and |x| <= 2^31 keep the product below 2^62. */
static inline int32_t pf_mulc(pf_qc c, int64_t x)
{
    return pf_q_sat(pf_round_shift((int64_t)c.m * x, c.sh));
}

/* A state advanced by k * x / 2^sh with first-order error feedback: the
 * part of the increment below one LSB is kept in *r, as a 32-bit fraction
 * of an LSB, and carried in later, so a state that moves by 1e-9 LSB per
 * sample still moves and slow poles decay at their designed rate. Together
 * s and *r form a 32.32 fixed-point state in 8 bytes. Only what lies below
 * 2^-32 LSB is dropped (sh > 32): at most 0.4 LSB of drift per day at
 * 20 kHz. |k| < 2^31, |x| <= 2^31, 1 <= sh <= 62. Returns whole LSBs. */
static inline int64_t pf_q_accum(uint32_t *r, int32_t k, int64_t x, unsigned sh)
{
    int64_t acc = (int64_t)k * x;
    uint64_t rem = (uint64_t)acc & ((PF_Q_BIAS >> (62 - sh)) - 1u);
    uint64_t frac = (sh >= 32 ? rem >> (sh - 32) : rem << (32 - sh)) + *r;
    *r = (uint32_t)frac;
    return pf_floor_shift(acc, sh) + (int64_t)(frac >> 32);
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
