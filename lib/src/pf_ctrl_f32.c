/* SPDX-License-Identifier: MIT */
/* Float controller runtime. The kernels are the float/double template
 * (pf_ctrl_float.inc); the exported functions are written out here. */
#include "pneufrac/pf_controller.h"

#define PF_T float
#define PF_SFX f32
#define PF_OPC pf_fracop_coeffs_f32
#define PF_OPI pf_fracop_f32
#define PF_CC pf_ctrl_coeffs_f32
#define PF_CI pf_ctrl_f32
#define PF_BIG 1e30f
#define PF_EPS 1.1920929e-07f /* FLT_EPSILON */
#define PF_SUM_LANES 1 /* one running sum: see pf_float_ops.h, op_update */
#define PF_LINEAR_FIRST 0 /* the loop solve on every sample: pf_ctrl_float.inc */
#include "pf_float_ops.h"
#include "pf_ctrl_float.inc"

pf_status pf_ctrl_init_f32(pf_ctrl_f32 *S, const pf_ctrl_coeffs_f32 *c,
                           float *dbuf, size_t dlen)
{
    return ctrl_init_f32(S, c, dbuf, dlen);
}

void pf_ctrl_reset_f32(pf_ctrl_f32 *S)
{
    ctrl_reset_f32(S);
}

float pf_ctrl_step_f32(pf_ctrl_f32 *S, float e)
{
    return ctrl_step_f32(S, e);
}

void pf_ctrl_run_f32(pf_ctrl_f32 *S, const float *e, float *pc, size_t n)
{
    ctrl_run_f32(S, e, pc, n);
}
