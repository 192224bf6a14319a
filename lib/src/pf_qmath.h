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
 * are written as multiplications by a power of two or done on unsigned
 * values.
 *
 * Cores without a 32 x 32 -> 64 multiplier (ARMv6-M: Cortex-M0/M0+/M1,
 * and ARMv8-M Baseline) would call libgcc for every int64 product and
 * variable int64 shift; PF_Q15_NARROW_MUL selects, for the few primitives
 * below, a form built from 32-bit multiplies and shifts instead. Both forms
 * compute the same integers, so every build gives bit-identical outputs
 * (tests/unit/test_qmath.c compares them; tests/target runs them on the
 * cores).
 */
#ifndef PF_QMATH_H
#define PF_QMATH_H

#include <stdint.h>
#include "pneufrac/pf_fracop.h"

typedef char pf_qmath_needs_arithmetic_shift[((int64_t)-8 >> 1) == -4 ? 1 : -1];
/* An unsigned value converted back to a signed type keeps its bits. */
typedef char pf_qmath_needs_twos_complement[(int32_t)(uint32_t)0xFFFFFFFFu == -1 ? 1 : -1];

#ifndef PF_Q15_NARROW_MUL
#if defined(__ARM_ARCH_6M__) || defined(__ARM_ARCH_8M_BASE__)
#define PF_Q15_NARROW_MUL 1
#else
#define PF_Q15_NARROW_MUL 0
#endif
#endif

#define PF_Q_MAX ((int32_t)1 << 30)
/* Fractional bits of an integer-stage or lag state: s * 2^30 in an int64. */
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

/* Clamp to the int32 range: the operand of a 32 x 32 product. */
static inline int32_t pf_q_sat32(int64_t v)
{
    return v > INT32_MAX ? INT32_MAX : (v < -INT32_MAX ? -INT32_MAX : (int32_t)v);
}

/* a * b, exact. */
static inline int64_t pf_q_mul64(int32_t a, int32_t b)
{
#if PF_Q15_NARROW_MUL
    /* Four 16 x 16 products; the two cross terms are below 2^31 each. */
    uint32_t al = (uint32_t)a & 0xFFFFu, bl = (uint32_t)b & 0xFFFFu;
    int32_t ah = a >> 16, bh = b >> 16;
    uint64_t r = (uint64_t)(int64_t)(ah * bh) << 32;
    r += (uint64_t)((int64_t)(ah * (int32_t)bl) + (int64_t)((int32_t)al * bh)) << 16;
    return (int64_t)(r + al * bl);
#else
    return (int64_t)a * b;
#endif
}

/* floor(c * x / 2^16) for |c| < 2^15: the product of the section kernel
 * (a leak or a branch gain times a state or an input), exact, |result| <
 * 2^30. */
static inline int32_t pf_q_mul16(int32_t c, int32_t x)
{
#if PF_Q15_NARROW_MUL
    /* c (x_hi 2^16 + x_lo) / 2^16: both products stay below 2^31. */
    return c * (x >> 16) + ((c * (int32_t)((uint32_t)x & 0xFFFFu)) >> 16);
#else
    return (int32_t)(((int64_t)c * x) >> 16);
#endif
}

/* v >> sh (arithmetic), 0 <= sh <= 63. */
static inline int64_t pf_q_asr64(int64_t v, unsigned sh)
{
#if PF_Q15_NARROW_MUL
    uint32_t lo = (uint32_t)(uint64_t)v;
    int32_t hi = (int32_t)(v >> 32);
    /* Arithmetic shifts of negative values: required, and checked, above. */
    if (sh >= 32) {
        lo = (uint32_t)(hi >> (sh - 32));
        hi = hi < 0 ? -1 : 0;
    } else if (sh > 0) {
        lo = (lo >> sh) | ((uint32_t)hi << (32 - sh));
        /* cppcheck-suppress shiftTooManyBitsSigned */
        hi >>= sh;
    }
    return (int64_t)(((uint64_t)(uint32_t)hi << 32) | lo);
#else
    return v >> sh;
#endif
}

/* round-half-up(p / 2^sh), |p| < 2^62, 0 <= sh <= 62, as
 * floor((floor(p / 2^(sh-1)) + 1) / 2): the same integer (the bits below
 * 2^(sh-1) cannot carry past the half), without a 64-bit constant. */
static inline int64_t pf_round_shift(int64_t p, unsigned sh)
{
    return sh == 0 ? p : (pf_q_asr64(p, sh - 1) + 1) >> 1;
}

/* c * x rounded half up, NOT saturated: one term of a node formed as a
 * sum and saturated once, so that a small difference of large terms keeps
 * its precision. |c| < 2^28 (pf_qc_make) and |x| < 2^31 keep the term
 * below 2^59, so a sum of eight cannot wrap. */
static inline int64_t pf_mulw(pf_qc c, int32_t x)
{
    return pf_round_shift(pf_q_mul64(c.m, x), c.sh);
}

/* pf_mulw for an operand beyond the int32 range (a wide intermediate): the
 * operand gives up low bits and the shift as many, so the product stays in
 * range; it loses only bits far below the operand's own magnitude. */
static inline int64_t pf_mulw_wide(pf_qc c, int64_t x)
{
    while ((x > INT32_MAX || x < -INT32_MAX) && c.sh > 0) {
        x >>= 1;
        c.sh--;
    }
    return pf_mulw(c, pf_q_sat32(x));
}

/* c * x, rounded half up and saturated to the internal range. */
static inline int32_t pf_mulc(pf_qc c, int32_t x)
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
 * design), |x| < 2^31: the increment stays below 2^62 and the sum, with
 * S within +-2^60, cannot wrap before it is clamped. */
static inline int64_t pf_q_advance(int64_t S, int32_t k, int32_t x, unsigned sh)
{
    S += pf_q_asr64(pf_q_mul64(k, x), sh - PF_Q_FRAC);
    if (S > PF_Q_STATE_MAX)
        return PF_Q_STATE_MAX;
    if (S < -PF_Q_STATE_MAX)
        return -PF_Q_STATE_MAX;
    return S;
}

/* Round an internal value to Q15 with the output coefficient, saturating
 * to the int16 range (not to +-2^30). */
static inline int16_t pf_q_to_q15(pf_qc c, int32_t x)
{
    int64_t v = pf_round_shift(pf_q_mul64(c.m, x), c.sh);
    if (v > 32767)
        return 32767;
    if (v < -32768)
        return -32768;
    return (int16_t)v;
}

#endif /* PF_QMATH_H */
