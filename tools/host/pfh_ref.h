/* SPDX-License-Identifier: MIT */
/**
 * @file pfh_ref.h
 * @brief Exact reference (host library): the irrational transfer
 *        functions of the paper (eq. 17, 18, 20 and the pid of Remark 3)
 *        and their unit-step responses by numerical inverse Laplace
 *        transform, for the tests, the accuracy benchmark and `pneufrac
 *        reproduce`. No Oustaloup approximation and no library call is
 *        used, so this code can check the library. Only the pf_params
 *        and pf_effects structs and the topology enum are taken from the
 *        library's headers.
 */
#ifndef PFH_REF_H
#define PFH_REF_H

#include <complex.h>
#include "pneufrac/pf_effects.h"
#include "pneufrac/pf_params.h"

/** Quadrature nodes used by pfh_ref_step (see pfh_ref.c for the choice). */
#define PFH_REF_TALBOT_N 32

/** Exact P_c(s)/E(s) for p->topology, principal branch of all powers.
 *  s must not lie on the closed negative real axis (branch cut). */
double complex pfh_ref_tf(const pf_params *p, double complex s);

/** Unit-step response p_c(t) = L^-1{H(s)/s}(t) for t > 0 (NaN otherwise). */
double pfh_ref_step(const pf_params *p, double t);

/** As pfh_ref_step with n quadrature nodes (n even, >= 2); for convergence
 *  studies. */
double pfh_ref_step_n(const pf_params *p, double t, int n);

/** The exact output line of the linear effects, e^{-s dead_time}/(1 + s
 *  lag) (1 for NULL or both 0): the ideal controller with effects is
 *  pfh_ref_tf(p, s) * pfh_ref_line(fx, s). */
double complex pfh_ref_line(const pf_effects *fx, double complex s);

/** Unit-step response of the controller with the output line of @p fx
 *  (lag and dead time; the other effects are not linear and are ignored),
 *  for t > dead_time (NaN otherwise). */
double pfh_ref_step_fx(const pf_params *p, const pf_effects *fx, double t);

#endif /* PFH_REF_H */
