/* SPDX-License-Identifier: MIT */
/* Effect primitives: play operator, nozzle curve, validation. */
#include "pneufrac/pf_effects.h"

#include <math.h>
#include <stddef.h>

#define PF_T double
#define PF_SFX f64
#include "pf_effect_ops.h"

#define PF_FX_MAX 1e9

static int nonneg(double v) { return isfinite(v) && v >= 0.0 && v <= PF_FX_MAX; }

pf_status pf_effects_validate(const pf_effects *fx)
{
    if (fx == NULL)
        return PF_E_NULL;
    if (!nonneg(fx->backlash))
        return PF_E_PARAM(PF_P_BACKLASH);
    if (!nonneg(fx->nozzle_xh))
        return PF_E_PARAM(PF_P_NOZZLE_XH);
    if (fx->saturate) {
        if (!isfinite(fx->sat_lo) || fabs(fx->sat_lo) > PF_FX_MAX)
            return PF_E_PARAM(PF_P_SAT_LO);
        if (!isfinite(fx->sat_hi) || fabs(fx->sat_hi) > PF_FX_MAX ||
            !(fx->sat_hi > fx->sat_lo))
            return PF_E_PARAM(PF_P_SAT_HI);
    }
    if (!nonneg(fx->dead_time) || fx->dead_time > 3600.0)
        return PF_E_PARAM(PF_P_DEAD_TIME);
    if (!nonneg(fx->lag))
        return PF_E_PARAM(PF_P_LAG);
    return PF_OK;
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
    return nozzle_f64(x, xh, 1.0 / xh);
}
