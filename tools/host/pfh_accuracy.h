/* SPDX-License-Identifier: MIT */
/*
 * Accuracy of a designed controller against the exact fractional step
 * response (pfh_ref_step), sampled at t = n/fs: shared by the accuracy test,
 * the accuracy benchmark and `pneufrac reproduce`, so all measure the same
 * thing.
 */
#ifndef PFH_ACCURACY_H
#define PFH_ACCURACY_H

#include "pneufrac/pneufrac.h"

/** The exact unit-step response at t = n/fs for n0 <= n <= n1. */
typedef struct pfh_acc_ref {
    pf_params p;
    double fs;
    long n0, n1;
    double *y;    /**< y[n - n0] */
    double peak;  /**< max |y| over the window */
} pfh_acc_ref;

/** Sample the exact response of @p p over [t0, t1] at rate fs (malloc'd;
 *  release with pfh_acc_ref_free). @return 0, or -1 if out of memory. */
int pfh_acc_ref_make(pfh_acc_ref *r, const pf_params *p, double fs, double t0,
                    double t1);
void pfh_acc_ref_free(pfh_acc_ref *r);

/** Receives every output sample of a run (physical units). */
typedef void (*pfh_acc_sink)(void *ctx, long n, double y);

/** The unit-step response of @p p designed with @p o, samples 0..n_last,
 *  in the given arithmetic, each passed to @p fn. Q15 runs a half-scale
 *  step (in_fs = 2: Q15 16384) and converts back with @p out_fs.
 *  @return 0, or -1 if the design or the Q15 coefficients are refused. */
int pfh_acc_run(const pf_params *p, const pf_design_opts *o, pf_arith arith,
               double out_fs, long n_last, pfh_acc_sink fn, void *ctx);

/** Max |y - exact| over the window relative to the peak, for the design
 *  options @p o (o->fs must equal r->fs) in the given arithmetic. Q15 runs
 *  a half-scale step (in_fs = 2) with out_fs = 1.25 x peak. Returns a
 *  negative value if the design or the Q15 coefficients are refused;
 *  *t_worst (if not NULL) receives where the error peaks. */
double pfh_acc_error(const pfh_acc_ref *r, const pf_design_opts *o,
                    pf_arith arith, double *t_worst);

#endif
