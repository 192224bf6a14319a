/* SPDX-License-Identifier: MIT */
/* Design-side internals of the controller (never on a per-sample path). */
#ifndef PF_CTRL_INTERNAL_H
#define PF_CTRL_INTERNAL_H

#include "pf_design_internal.h"
#include "pneufrac/pf_controller.h"

/* Response of every internal node (enum pf_ctrl_node) to e at omega. */
void pf_ctrl_node_resp(const pf_ctrl_coeffs_f64 *c, double omega,
                       double complex g[PF_N_COUNT]);

/* The nozzle curve's Q15 table for an x node of sx internal units per
 * physical unit (pf_nozzle_q15_design.c): PF_OK, PF_E_SCALE when a
 * coefficient does not fit, or PF_E_UNSUPPORTED when the loop map is not
 * monotone (1 + L0 h' <= 0 somewhere). t_r is left to the caller. */
pf_status pf_nozzle_q15_make(pf_nozzle_q15 *nz, const pf_ctrl_coeffs_f64 *c, double sx);

/* The largest |h(x)| for |x| <= x_range (physical units). */
double pf_nozzle_q15_reach(const pf_ctrl_coeffs_f64 *c, double x_range);

#endif
