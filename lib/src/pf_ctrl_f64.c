/* SPDX-License-Identifier: MIT */
/* Double-precision controller runtime. The kernels are the float/double template
 * (pf_ctrl_float.inc); the exported functions are written out here. */
#include "pneufrac/pf_controller.h"

#define PF_T double
#define PF_SFX f64
#define PF_OPC pf_fracop_design
#define PF_OPI pf_fracop_f64
#define PF_CC pf_ctrl_coeffs_f64
#define PF_CI pf_ctrl_f64
#define PF_BIG 1e300
#define PF_EPS 2.220446049250313e-16 /* DBL_EPSILON */
#define PF_SUM_LANES 2 /* two partial sums: see pf_float_ops.h, op_update */
#define PF_LINEAR_FIRST 1 /* the loop solve skipped inside the limits: pf_ctrl_float.inc */
#include "pf_float_ops.h"
#include "pf_ctrl_float.inc"

pf_status pf_ctrl_init_f64(pf_ctrl_f64 *S, const pf_ctrl_coeffs_f64 *c,
                           double *dbuf, size_t dlen)
{
    return ctrl_init_f64(S, c, dbuf, dlen);
}

void pf_ctrl_reset_f64(pf_ctrl_f64 *S)
{
    ctrl_reset_f64(S);
}

double pf_ctrl_step_f64(pf_ctrl_f64 *S, double e)
{
    return ctrl_step_f64(S, e);
}

void pf_ctrl_run_f64(pf_ctrl_f64 *S, const double *e, double *pc, size_t n)
{
    ctrl_run_f64(S, e, pc, n);
}

uint32_t pf_ctrl_limited_f64(const pf_ctrl_f64 *S)
{
    return S != NULL ? S->limited : 0;
}
