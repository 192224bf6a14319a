/* SPDX-License-Identifier: MIT */
/*
 * The nozzle curve in the Q15 runtime (pf_nozzle_q15.c; the table,
 * pf_nozzle_q15 in pf_controller.h, is built by pf_nozzle_q15_design.c).
 */
#ifndef PF_NOZZLE_Q15_H
#define PF_NOZZLE_Q15_H

#include <stdint.h>
#include "pneufrac/pf_controller.h"

#define PF_NZ_R 27 /* fraction bits of the position r within a piece */
#define PF_NZ_AB 24 /* fraction bits of the shape coefficients a, b */

/* h(x) for any x of the node (|x| <= 2^30: within the knots), in x's
 * scale times 2^h_sh. */
int32_t pf_nz_h(const pf_nozzle_q15 *nz, int32_t x);

/* The x with W(x) = t, and *h = h(x). Beyond the knots' W the solution is
 * the end of the node's range. */
int32_t pf_nz_solve(const pf_nozzle_q15 *nz, int64_t t, int32_t *h);

#endif /* PF_NOZZLE_Q15_H */
