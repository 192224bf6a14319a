/* SPDX-License-Identifier: MIT */
/*
 * Effect kernels shared by the float and double controller runtimes and by
 * pf_effects.c (pf_play, pf_nozzle), so each curve is written once.
 * Template: define PF_T (float or double) and PF_SFX (f32 or f64) before
 * including; static kernels only.
 */
#include "pf_tmpl.h"

static PF_T PF_FN(play_)(PF_T prev, PF_T x, PF_T r)
{
    if (x - r > prev)
        return x - r;
    if (x + r < prev)
        return x + r;
    return prev;
}

/* See pf_nozzle_biased() in pf_effects.h, with F(u) = 1/(1+u^2): u0 the
 * gap at the operating point, f0 = F(u0), g = x_1/2/|F'(u0)| and xh_inv =
 * 1/x_1/2 precomputed (pf_nozzle_shape_make). The gap cannot close below
 * 0, where p_b reaches supply.
 * F(u0) - F(u) is formed as (u - u0)(u + u0) F(u0) F(u), without the
 * subtraction of two nearly equal values: with x far below x_1/2 (a nearly
 * linear nozzle, as a fit passes on its way to none) that difference kept
 * a few digits only, g times the rounding of F was far above the loop
 * equation's tolerance, and the loop solve ran to its iteration limit on
 * every sample (up to 20x the cost of a simulation; analysis-bench.md). */
static PF_T PF_FN(nozzle_)(PF_T x, PF_T xh_inv, PF_T u0, PF_T f0, PF_T g)
{
    PF_T d = x * xh_inv, u = u0 + d;
    if (u < 0) {
        u = 0;
        d = -u0;
    }

    /* Far open, F(u) < 1e-16 against f0 >= 1/(1+u0^2) (u0 <= 11): the
     * limit is within about 1e-14 relative of the curve, and u * u stays
     * finite. */
    if (u > (PF_T)1e8)
        return g * f0;
    return (g * f0) * d * (u + u0) / (1 + u * u);
}
