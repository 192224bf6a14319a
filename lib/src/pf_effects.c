/* SPDX-License-Identifier: MIT */
/* Effect primitives: play operator, nozzle curve, validation. */
#include "pneufrac/pf_effects.h"

#include <stddef.h>

#include "pneufrac/pf_param_info.h"

#define PF_T double
#define PF_SFX f64
#include "pf_effect_ops.h"
#include "pf_nozzle_shape.h"

pf_status pf_effects_validate(const pf_effects *fx)
{
    pf_status st;
    if (fx == NULL)
        return PF_E_NULL;
    st = pf_param_check(PF_P_BACKLASH, fx->backlash);
    if (st == PF_OK)
        st = pf_param_check(PF_P_NOZZLE_XH, fx->nozzle_xh);
    if (st == PF_OK)
        st = pf_param_check(PF_P_SATURATE, (double)fx->saturate);
    if (st == PF_OK && fx->saturate) {
        st = pf_param_check(PF_P_SAT_LO, fx->sat_lo);
        if (st == PF_OK)
            st = pf_param_check(PF_P_SAT_HI, fx->sat_hi);
        if (st == PF_OK && !(fx->sat_hi > fx->sat_lo))
            st = PF_E_PARAM(PF_P_SAT_HI);
    }
    if (st == PF_OK)
        st = pf_param_check(PF_P_DEAD_TIME, fx->dead_time);
    if (st == PF_OK)
        st = pf_param_check(PF_P_LAG, fx->lag);
    if (st == PF_OK)
        st = pf_param_check(PF_P_NOZZLE_BIAS, fx->nozzle_bias);
    return st;
}

int pf_effects_any(const pf_effects *fx)
{
    return fx != NULL && (fx->backlash > 0.0 || fx->nozzle_xh > 0.0 ||
                          fx->saturate || fx->dead_time > 0.0 || fx->lag > 0.0);
}

/* The double instances of the kernels the runtimes use (pf_effect_ops.h),
 * so each curve exists once. */
double pf_play(double prev, double x, double r)
{
    return play_f64(prev, x, r);
}

double pf_nozzle(double x, double xh)
{
    return pf_nozzle_biased(x, xh, 0.0);
}

double pf_nozzle_biased(double x, double xh, double bias)
{
    pf_nozzle_shape n;
    pf_nozzle_shape_make(&n, xh, bias);
    return nozzle_f64(x, 1.0 / xh, n.u0, n.f0, n.g);
}
