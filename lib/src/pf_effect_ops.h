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

/* See pf_nozzle() in pf_effects.h: u0 = 1/sqrt(3), F(u0) = 3/4,
 * |F'(u0)| = 3 sqrt(3)/8; xh_inv = 1/xh is precomputed. */
static PF_T PF_FN(nozzle_)(PF_T x, PF_T xh, PF_T xh_inv)
{
    PF_T u = (PF_T)0.57735026918962576 + x * xh_inv;
    if (u < 0)
        u = 0;
    return xh * ((PF_T)0.75 - 1 / (1 + u * u)) * (PF_T)1.5396007178390020;
}
