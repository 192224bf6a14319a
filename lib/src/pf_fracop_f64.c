/* SPDX-License-Identifier: MIT */
/* Double-precision operator runtime: the design itself is its coefficient set. */
#include "pneufrac/pf_fracop.h"

#define PF_T double
#define PF_SFX f64
#define PF_OPC pf_fracop_design
#define PF_OPI pf_fracop_f64
#define PF_BIG 1e300
#define PF_SUM_LANES 2 /* two partial sums: see pf_float_ops.h, op_update */
#include "pf_float_ops.h"
#include "pf_fracop_float.inc"

pf_status pf_fracop_init_f64(pf_fracop_f64 *S, const pf_fracop_design *c)
{
    return fracop_init_f64(S, c);
}

void pf_fracop_reset_f64(pf_fracop_f64 *S)
{
    fracop_reset_f64(S);
}

double pf_fracop_step_f64(pf_fracop_f64 *S, double u)
{
    return fracop_step_f64(S, u);
}
