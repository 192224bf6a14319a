/* SPDX-License-Identifier: MIT */
/* Design-side internals of the controller (never on a per-sample path). */
#ifndef PF_CTRL_INTERNAL_H
#define PF_CTRL_INTERNAL_H

#include "pf_design_internal.h"
#include "pneufrac/pf_controller.h"

/* Response of every internal node (enum pf_ctrl_node) to e at omega. */
void pf_ctrl_node_resp(const pf_ctrl_coeffs_f64 *c, double omega,
                       double complex g[PF_N_COUNT]);

#endif
