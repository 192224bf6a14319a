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
 * 0, where p_b reaches supply. */
static PF_T PF_FN(nozzle_)(PF_T x, PF_T xh_inv, PF_T u0, PF_T f0, PF_T g)
{
    PF_T u = u0 + x * xh_inv;
    if (u < 0)
        u = 0;
    return g * (f0 - 1 / (1 + u * u));
}
