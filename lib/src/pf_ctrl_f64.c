/* SPDX-License-Identifier: MIT */
/* Double-precision controller runtime, and the double effect primitives. */
#include "pneufrac/pf_controller.h"

#define PF_T double
#define PF_SFX f64
#define PF_OPC pf_fracop_design
#define PF_OPI pf_fracop_f64
#define PF_CC pf_ctrl_coeffs_f64
#define PF_CI pf_ctrl_f64
#define PF_BIG 1e300
#include "pf_float_ops.h"
#include "pf_ctrl_float.inc"

double pf_play(double prev, double x, double r) { return play_f64(prev, x, r); }
double pf_nozzle(double x, double xh) { return nozzle_f64(x, xh, 1.0 / xh); }
