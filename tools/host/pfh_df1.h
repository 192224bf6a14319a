/* SPDX-License-Identifier: MIT */
/*
 * Direct-form-I biquad cascades with the documented semantics of CMSIS-DSP's
 * arm_biquad_cascade_df1_f32 and arm_biquad_cascade_df1_q15, written here
 * from the documentation (no CMSIS source is used): the test of the CMSIS
 * export runs the exported arrays through them, and the benchmarks use
 * them as the obvious alternative to the library's parallel leaky form.
 *
 * Stage k, in both: y[n] = b0 x[n] + b1 x[n-1] + b2 x[n-2] + a1 y[n-1]
 * + a2 y[n-2]; its output is the next stage's input; state per stage
 * {x[n-1], x[n-2], y[n-1], y[n-2]}.
 */
#ifndef PFH_DF1_H
#define PFH_DF1_H

#include <stddef.h>
#include <stdint.h>

/** Float cascade: coefficients {b0, b1, b2, a1, a2} per stage. */
typedef struct pfh_df1_f32 {
    int n;
    const float *c;   /**< 5 * n coefficients */
    float *st;        /**< 4 * n states, zero at start */
} pfh_df1_f32;

/** Q15 cascade: coefficients {b0, 0, b1, b2, a1, a2} per stage, scaled by
 *  2^-postShift. Products 1.15 x 1.15 = 2.30 summed exactly in a 64-bit
 *  accumulator, shifted right by 15 - postShift (truncating, i.e. toward
 *  minus infinity) and saturated to 1.15: every stage's output, and so the
 *  state, is 16-bit. */
typedef struct pfh_df1_q15 {
    int n;
    int post_shift;
    const int16_t *c; /**< 6 * n coefficients */
    int16_t *st;      /**< 4 * n states, zero at start */
} pfh_df1_q15;

void pfh_df1_run_f32(pfh_df1_f32 *f, const float *x, float *y, size_t len);
void pfh_df1_run_q15(pfh_df1_q15 *f, const int16_t *x, int16_t *y, size_t len);

#endif
