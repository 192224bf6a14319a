/* SPDX-License-Identifier: MIT */
/**
 * @file pfh_lti.h
 * @brief The realised discrete controller of a design as a linear
 *        time-invariant system in scipy's conventions (sample time 1/fs),
 *        for `pneufrac design --format ss|zpk|sos`:
 *  - state space x[n+1] = A x[n] + B e[n], p_c[n] = C x[n] + D e[n], in
 *    the double runtime's own coordinates: one state per parallel leaky
 *    section and per integer stage of each operator, the held input, the
 *    output lag. A is a diagonal of the leaks (1 - lam_k) plus the few
 *    rank-one couplings of the loops, so nothing is expanded into
 *    polynomials and the response keeps every digit (the expanded
 *    transfer function of a controller whose poles sit within 1e-7 of
 *    z = 1 keeps none);
 *  - zeros, poles and gain: H(z) = k prod(z - z_i) / prod(z - p_i), roots
 *    as roots (not corner frequencies), from the eigenvalues of A and of
 *    A - B C / D (LAPACK dgeev, with balancing);
 *  - second-order sections [b0 b1 b2 1 a1 a2], H = prod (b0 + b1 z^-1 +
 *    b2 z^-2) / (1 + a1 z^-1 + a2 z^-2): scipy's sos layout, a0 = 1.
 *
 * The state space is read off the runtime itself (pf_ctrl_state_space:
 * pf_ctrl_step_f64 from each unit state and from a unit input), so it is
 * the controller that runs, not a second derivation of it. Linear designs only: backlash, the
 * nozzle curve and saturation have no transfer function, and a dead time
 * of D samples would add D states (append z^-D instead).
 */
#ifndef PFH_LTI_H
#define PFH_LTI_H

#include <complex.h>

#include "pneufrac/pneufrac.h"

/** Errors of the pfh_lti_* functions (0 is success). */
enum {
    PFH_LTI_OK = 0,
    PFH_LTI_NONLINEAR = 1, /**< backlash, nozzle curve or saturation is on */
    PFH_LTI_DEADTIME = 2,  /**< a dead time is on */
    PFH_LTI_NOMEM = 3,     /**< out of memory */
    PFH_LTI_NUMERIC = 4,   /**< LAPACK failed, or D = 0 (no zeros from A - BC/D) */
};

/** One line for an error code. */
const char *pfh_lti_strerror(int err);

/** State space; A is n x n, row-major. */
typedef struct pfh_lti_ss {
    int n;
    double fs;       /**< sample rate, Hz: dt = 1/fs */
    double *A, *B, *C;
    double D;
} pfh_lti_ss;

/** The state space of design @p d (its double runtime). Free with
 *  pfh_lti_ss_free. @return PFH_LTI_OK or an error. */
int pfh_lti_ss_make(pfh_lti_ss *ss, const pf_ctrl_design *d);
void pfh_lti_ss_free(pfh_lti_ss *ss);
/** C (zI - A)^-1 B + D at z = exp(j omega/fs) (LAPACK zgesv). */
double complex pfh_lti_ss_resp(const pfh_lti_ss *ss, double omega);

/** Zeros, poles, gain; complex roots come in conjugate pairs, the one with
 *  positive imaginary part first. */
typedef struct pfh_lti_zpk {
    int nz, np;
    double fs;
    double complex *z, *p;
    double k;
} pfh_lti_zpk;

/** From a state space (D != 0: n zeros and n poles, k = D). */
int pfh_lti_zpk_make(pfh_lti_zpk *zpk, const pfh_lti_ss *ss);
void pfh_lti_zpk_free(pfh_lti_zpk *zpk);
double complex pfh_lti_zpk_resp(const pfh_lti_zpk *zpk, double omega);

/** Second-order sections, 6 coefficients each: b0 b1 b2 1 a1 a2. */
typedef struct pfh_lti_sos {
    int n;
    double fs;
    double (*s)[6];
} pfh_lti_sos;

/** From zeros and poles: each conjugate pair in one section; the real
 *  roots nearest z = 1 share a section with the farthest, as in
 *  pfh_sos.c, so no section holds two poles that a rounded coefficient
 *  would scatter; zero sections follow the pole sections' order; the gain
 *  goes into the first section (as scipy's zpk2sos does). */
int pfh_lti_sos_make(pfh_lti_sos *sos, const pfh_lti_zpk *zpk);
void pfh_lti_sos_free(pfh_lti_sos *sos);
double complex pfh_lti_sos_resp(const pfh_lti_sos *sos, double omega);

#endif /* PFH_LTI_H */
