/* SPDX-License-Identifier: MIT */
/*
 * pneufracd's accuracy against the exact step response, as a client sees
 * it: one instance running the daemon's own exchange (pfd_sample_run: the
 * first controller step, the output, then the remaining substeps with the
 * input held), e = 1 from exchange 0, and the output taken at every
 * exchange instant t = n/fs, against the host library's exact reference
 * (tools/host, pfh_accuracy.h). The library pneufracd_accuracy, shared by
 * test_pfd_rate and bench_rate, so that the test and the benchmark
 * measure the same thing.
 */
#ifndef PFD_ACCURACY_H
#define PFD_ACCURACY_H

#include "pfh_accuracy.h"

typedef struct pfd_acc_result {
    double err;     /**< max |p_c - exact| over the window / the peak */
    double t_worst; /**< where it is largest, s */
    unsigned k;     /**< substeps the instance ran */
} pfd_acc_result;

/** The error of an instance of r->p exchanging at r->fs, in @p arith
 *  (PFD_ARITH_FLOAT or PFD_ARITH_Q15; Q15 with in_fs = 2, so the step is
 *  half scale, and out_fs = 1.25 x the peak, as pfh_acc_error), with
 *  @p substeps (0: the daemon's rule). @return 0, or -1 if the daemon
 *  refuses the instance or memory runs out. */
int pfd_acc_error(const pfh_acc_ref *r, int arith, unsigned substeps, pfd_acc_result *out);

#endif
