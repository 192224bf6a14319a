/* SPDX-License-Identifier: MIT */
/**
 * @file pf_q15.h
 * @brief Physical values to and from Q15 numbers of a full scale: the one
 *        rule every tool uses at the edge of a Q15 runtime (the CLI's
 *        input, the daemon's int16 registers, the tagged runtime).
 */
#ifndef PNEUFRAC_PF_Q15_H
#define PNEUFRAC_PF_Q15_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Quantise @p v to Q15 of @p full_scale (v = full_scale is +1.0):
 *  x = v / full_scale * 32768, rounded half up (ties toward +infinity:
 *  0.5 -> 1, -0.5 -> 0), then saturated to [-32768, 32767], so it never
 *  wraps, whatever the ratio. NaN gives 0, as a NaN input counts as zero
 *  error in the float runtimes; +-infinity saturate. A @p full_scale that
 *  is not finite and > 0 gives 0. Uses no libm, so a real-time loop may
 *  call it. */
int16_t pf_q15_quantize(double v, double full_scale);

/** The physical value of Q15 number @p q of @p full_scale:
 *  q * full_scale / 32768. */
double pf_q15_value(int16_t q, double full_scale);

#ifdef __cplusplus
}
#endif
#endif /* PNEUFRAC_PF_Q15_H */
