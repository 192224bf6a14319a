/* SPDX-License-Identifier: MIT */
/* The nozzle curve's constants at its bias point (pf_nozzle_biased), for
 * the design and for pf_effects.c: written once. */
#ifndef PF_NOZZLE_SHAPE_H
#define PF_NOZZLE_SHAPE_H

#include <math.h>

/* With F(u) = 1/(1+u^2), |F'(u)| = 2u/(1+u^2)^2 is steepest at the
 * inflection u = 1/sqrt(3). */
#define PF_NOZZLE_INFLECTION 0.57735026918962576

typedef struct pf_nozzle_shape {
    double u0; /* gap at the operating point, units of x_1/2 */
    double f0; /* F(u0) */
    double g;  /* x_1/2 / |F'(u0)|: unit slope at x = 0 */
    double steepest; /* |F'| at the inflection over |F'(u0)|: the curve's
                        largest slope, >= 1 (1 at the inflection) */
} pf_nozzle_shape;

static inline void pf_nozzle_shape_make(pf_nozzle_shape *n, double xh, double bias)
{
    double u0 = PF_NOZZLE_INFLECTION + bias, s = 1.0 + u0 * u0;
    n->u0 = u0;
    n->f0 = 1.0 / s;
    n->g = xh * s * s / (2.0 * u0);
    /* |F'(1/sqrt(3))| = (2/sqrt(3)) / (4/3)^2 = 3 sqrt(3)/8 */
    n->steepest = fmax(1.0, 0.64951905283832898 * n->g / xh); /* 1 + rounding at u0 = 1/sqrt(3) */
}

#endif
