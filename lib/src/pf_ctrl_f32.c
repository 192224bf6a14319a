/* SPDX-License-Identifier: MIT */
/* Float controller runtime. */
#include "pneufrac/pf_controller.h"

#define PF_T float
#define PF_SFX f32
#define PF_OPC pf_fracop_coeffs_f32
#define PF_OPI pf_fracop_f32
#define PF_CC pf_ctrl_coeffs_f32
#define PF_CI pf_ctrl_f32
#define PF_BIG 1e30f
#include "pf_float_ops.h"
#include "pf_ctrl_float.inc"
