/* SPDX-License-Identifier: MIT */
/*
 * The real-time loop: one thread steps every instance at its own sample
 * rate (earliest deadline first, clock_nanosleep on absolute
 * CLOCK_MONOTONIC times), or, with --clock external, exactly as many
 * samples as the tick register asks for.
 */
#ifndef PFD_LOOP_H
#define PFD_LOOP_H

#include "pfd_state.h"

/** Start the loop thread (SCHED_FIFO and mlockall when permitted; logs
 *  which). @return 0, or -1 after logging why. */
int pfd_loop_start(pfd_daemon *d);

/** Ask the loop to stop and join it. */
void pfd_loop_stop(pfd_daemon *d);

/** Log the period-jitter distribution (p50/p99/max over every sample of
 *  every instance) and the overruns: one line, msg=loop-stats. */
void pfd_loop_log_stats(const pfd_daemon *d);

/** Lockstep: add @p n ticks to @p in and wait until the loop has run them
 *  (or the daemon stops). @return 0, or -1 if stopping. */
int pfd_loop_tick(pfd_daemon *d, pfd_inst *in, unsigned n);

#endif
