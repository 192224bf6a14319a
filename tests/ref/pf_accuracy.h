/* SPDX-License-Identifier: MIT */
/*
 * Accuracy of a designed controller against the exact fractional step
 * response (pf_ref_step), sampled at t = n/fs: shared by the accuracy test
 * and the accuracy benchmark so both measure the same thing.
 */
#ifndef PF_ACCURACY_H
#define PF_ACCURACY_H

#include "pneufrac/pneufrac.h"

typedef enum pf_acc_arith { PF_ACC_F64, PF_ACC_F32, PF_ACC_Q15 } pf_acc_arith;

/** The exact unit-step response at t = n/fs for n0 <= n <= n1. */
typedef struct pf_acc_ref {
    pf_params p;
    double fs;
    long n0, n1;
    double *y;    /**< y[n - n0] */
    double peak;  /**< max |y| over the window */
} pf_acc_ref;

/** Sample the exact response of @p p over [t0, t1] at rate fs (malloc'd;
 *  release with pf_acc_ref_free). @return 0, or -1 if out of memory. */
int pf_acc_ref_make(pf_acc_ref *r, const pf_params *p, double fs, double t0,
                    double t1);
void pf_acc_ref_free(pf_acc_ref *r);

/** Receives every output sample of a run (physical units). */
typedef void (*pf_acc_sink)(void *ctx, long n, double y);

/** The unit-step response of @p p designed with @p o, samples 0..n_last,
 *  in the given arithmetic, each passed to @p fn. Q15 runs a half-scale
 *  step (in_fs = 2: Q15 16384) and converts back with @p out_fs.
 *  @return 0, or -1 if the design or the Q15 coefficients are refused. */
int pf_acc_run(const pf_params *p, const pf_design_opts *o, pf_acc_arith arith,
               double out_fs, long n_last, pf_acc_sink fn, void *ctx);

/** Max |y - exact| over the window relative to the peak, for the design
 *  options @p o (o->fs must equal r->fs) in the given arithmetic. Q15 runs
 *  a half-scale step (in_fs = 2) with out_fs = 1.25 x peak. Returns a
 *  negative value if the design or the Q15 coefficients are refused;
 *  *t_worst (if not NULL) receives where the error peaks. */
double pf_acc_error(const pf_acc_ref *r, const pf_design_opts *o,
                    pf_acc_arith arith, double *t_worst);

#endif
