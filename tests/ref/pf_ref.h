/* SPDX-License-Identifier: MIT */
/**
 * @file pf_ref.h
 * @brief Exact reference for the test suite: the irrational transfer
 *        functions of the paper (eq. 17, 18, 20 and the pid of Remark 3)
 *        and their unit-step responses by numerical inverse Laplace
 *        transform. No Oustaloup approximation and no library call is used,
 *        so this code can check the library. Only the pf_params struct and
 *        enum are taken from the library's headers.
 */
#ifndef PF_REF_H
#define PF_REF_H

#include <complex.h>
#include "pneufrac/pf_params.h"

/** Quadrature nodes used by pf_ref_step (see pf_ref.c for the choice). */
#define PF_REF_TALBOT_N 32

/** Exact P_c(s)/E(s) for p->config, principal branch of all powers.
 *  s must not lie on the closed negative real axis (branch cut). */
double complex pf_ref_tf(const pf_params *p, double complex s);

/** Unit-step response p_c(t) = L^-1{H(s)/s}(t) for t > 0 (NaN otherwise). */
double pf_ref_step(const pf_params *p, double t);

/** As pf_ref_step with n quadrature nodes (n even, >= 2); for convergence
 *  studies. */
double pf_ref_step_n(const pf_params *p, double t, int n);

#endif /* PF_REF_H */
