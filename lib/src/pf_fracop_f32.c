/* SPDX-License-Identifier: MIT */
/* Float operator runtime and the conversion of a design to float. */
#include "pneufrac/pf_fracop.h"

#define PF_T float
#define PF_SFX f32
#define PF_OPC pf_fracop_coeffs_f32
#define PF_OPI pf_fracop_f32
#define PF_BIG 1e30f
#define PF_SUM_LANES 1 /* one running sum: see pf_float_ops.h, op_update */
#include "pf_float_ops.h"
#include "pf_fracop_float.inc"

pf_status pf_fracop_init_f32(pf_fracop_f32 *S, const pf_fracop_coeffs_f32 *c)
{
    return fracop_init_f32(S, c);
}

void pf_fracop_reset_f32(pf_fracop_f32 *S)
{
    fracop_reset_f32(S);
}

float pf_fracop_step_f32(pf_fracop_f32 *S, float u)
{
    return fracop_step_f32(S, u);
}

void pf_fracop_coeffs_f32_make(pf_fracop_coeffs_f32 *cf, const pf_fracop_design *op)
{
    int k;
    if (cf == NULL || op == NULL)
        return;
    memset(cf, 0, sizeof *cf);
    cf->n_int = (int8_t)op->n_int;
    cf->int_rho = (int8_t)op->int_rho;
    cf->n_sec = (uint8_t)op->n_sec;
    cf->hold = (uint8_t)op->hold;
    cf->d = (float)op->d;
    cf->D = (float)op->D;
    cf->int_d = (float)op->int_d;
    cf->int_k = (float)op->int_k;
    for (k = 0; k < op->n_sec; k++) {
        cf->lam[k] = (float)op->lam[k];
        cf->G[k] = (float)op->G[k];
    }
}
