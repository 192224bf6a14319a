/* SPDX-License-Identifier: MIT */
/*
 * One fractional operator as a cascade of second-order sections (biquads)
 * in the coefficient conventions of CMSIS-DSP's arm_biquad_cascade_df1_*:
 * the form "pneufrac design --format cmsis-f32|cmsis-q15" exports, and the
 * "obvious alternative" the benchmarks run against the library's parallel
 * leaky form. Host code (design time): double and libm.
 */
#ifndef PFH_SOS_H
#define PFH_SOS_H

#include <complex.h>
#include <stdint.h>

#include "pneufrac/pneufrac.h"

/* First-order factors: the approximant's poles, plus up to PF_MAX_INT
 * integer-part roots, one held-input zero and one zero at z = -1 of the
 * refined variant's extra pole; two per stage. */
#define PFH_SOS_MAX ((PF_MAX_SEC + PF_MAX_INT + 3) / 2)

/** A biquad cascade in double. Stage k computes
 *      y[n] = b0 x[n] + b1 x[n-1] + b2 x[n-2] + a1 y[n-1] + a2 y[n-2],
 *  i.e. H_k(z) = (b0 + b1 z^-1 + b2 z^-2) / (1 - a1 z^-1 - a2 z^-2): the
 *  feedback coefficients carry CMSIS-DSP's sign (the negated denominator). */
typedef struct pfh_sos {
    int n;                    /**< number of stages, 1..PFH_SOS_MAX */
    double fs;                /**< sample rate, Hz */
    double b[PFH_SOS_MAX][3]; /**< b0, b1, b2 of each stage */
    double a[PFH_SOS_MAX][2]; /**< a1, a2 of each stage (CMSIS sign) */
} pfh_sos;

/** The operator @p op (designed with the resolved options @p opt) times
 *  @p scale as a cascade, including the held-input mean (1 + z^-1)/2 when
 *  op->hold is set, so that it reproduces pf_fracop_step_f64 sample for
 *  sample. Zeros and poles come from pf_fracop_zpk, mapped by Tustin with
 *  the design's constant op->c. Pairing, see pfh_sos.c: each pole with its
 *  rank-matched zero into first-order sections, then the slowest section
 *  with the fastest into one biquad, so no biquad holds two poles near
 *  z = 1 (whose roots a rounded a1, a2 would scatter). The gain is spread
 *  evenly over the stages at the band's geometric centre.
 *  @return PF_OK, or the status of pf_fracop_zpk. */
pf_status pfh_sos_from_op(pfh_sos *s, const pf_fracop_design *op,
                          const pf_design_opts *opt, double scale);

/** Frequency response of the cascade at omega rad/s (z = exp(j omega/fs)). */
double complex pfh_sos_resp(const pfh_sos *s, double omega);

/** Frequency response of what pf_fracop_step_f64 computes: the design's
 *  response times the held-input mean when op->hold is set. */
double complex pfh_sos_op_resp(const pf_fracop_design *op, double omega);

/** The cascade rounded for arm_biquad_cascade_df1_f32: 5 floats per stage,
 *  {b0, b1, b2, a1, a2}. @p c holds 5 * s->n values. */
void pfh_sos_f32(const pfh_sos *s, float *c);

/** The cascade quantised for arm_biquad_cascade_df1_q15. */
typedef struct pfh_sos_q15 {
    int n;                          /**< number of stages */
    int post_shift;                 /**< postShift, 0..15 */
    int16_t c[6 * PFH_SOS_MAX];     /**< {b0, 0, b1, b2, a1, a2} per stage */
} pfh_sos_q15;

/** Quantise: each coefficient v becomes round(v * 2^(15 - postShift)),
 *  with the smallest postShift that keeps all of them in [-32768, 32767].
 *  @return PF_OK, or PF_E_SCALE if a coefficient reaches 2^15. */
pf_status pfh_sos_q15_make(const pfh_sos *s, pfh_sos_q15 *q);

/** The value a quantised coefficient stands for: c * 2^(postShift - 15). */
double pfh_sos_q15_value(const pfh_sos_q15 *q, int16_t c);

#endif
