/* SPDX-License-Identifier: MIT */
/* Design-side helpers shared between the double and Q15 designs (host or
 * MCU init code; never on a per-sample path). */
#ifndef PF_DESIGN_INTERNAL_H
#define PF_DESIGN_INTERNAL_H

#include <complex.h>
#include "pneufrac/pf_fracop.h"
#include "pneufrac/pf_param_info.h"

/* Return from the calling function with the status of the first check
 * that fails: PF_E_PARAM(id) when v is out of parameter id's range. */
#define PF_RETURN_IF_OUT(id, v)                                                \
    do {                                                                       \
        pf_status pf_st_ = pf_param_check((id), (v));                          \
        if (pf_st_ != PF_OK)                                                   \
            return pf_st_;                                                     \
    } while (0)

/* The Q15 full scales of a coefficient set, each within its range. */
static inline pf_status pf_q15_scales_check(double in_fs, double out_fs)
{
    pf_status st = pf_param_check(PF_P_IN_FS, in_fs);
    return st != PF_OK ? st : pf_param_check(PF_P_OUT_FS, out_fs);
}

/* Discrete response of an operator at omega rad/s; *frac (if not NULL)
 * receives the fractional part alone (before the integer stages). */
double complex pf_op_resp(const pf_fracop_design *op, double omega,
                          double complex *frac);

/* Quantise v to m * 2^-sh with |m| in [2^30, 2^31). PF_E_SCALE if
 * |v| >= 2^28 (pf_mulw's terms must stay below 2^59). The leak format (pf_qc_leak) is a gain below 2 with shift
 * >= 30, as pf_q_advance needs. */
pf_status pf_qc_make(pf_qc *q, double v);
pf_status pf_qc_leak(int32_t *m, uint8_t *sh, double lam);
/* A signed gain in the leak format (|v| < 2, shift >= 30). */
pf_status pf_qc_leak_signed(pf_qc *q, double v);

/* Q15 coefficients of one operator whose input, fractional-part output
 * and output are held in the internal scales s_in, s_frac and s_out
 * (internal units per physical unit). */
pf_status pf_q15_op_make(pf_fracop_coeffs_q15 *cq, const pf_fracop_design *op,
                         double s_in, double s_frac, double s_out);

/* Log-spaced frequency grid for peak-gain estimates: PF_GRID points from
 * wb/100 to just below Nyquist. */
#define PF_GRID 240
double pf_grid_omega(const pf_fracop_design *op, double wb, int i);

/* Internal full-scale target: a node's estimated peak maps to 2^28, which
 * leaves a factor 4 of headroom below the +-2^30 clamp. */
#define PF_Q_TARGET 268435456.0

#endif
