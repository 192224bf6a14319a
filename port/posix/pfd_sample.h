/* SPDX-License-Identifier: MIT */
/*
 * One sample of one instance, as the real-time loop runs it: the Modbus
 * side's commands, the controller step (switching in a committed set
 * bumplessly), the watchdog, the choice of output, the statistics, and
 * the snapshot for the readers. No locks, no allocation, no libm.
 */
#ifndef PFD_SAMPLE_H
#define PFD_SAMPLE_H

#include "pfd_state.h"

/** Run one exchange (one sample at fs) of @p in: its first controller
 *  step, the output and snapshot, then the remaining substeps with the
 *  input held (pfd_rate.h). @p missed: periods skipped before it (they
 *  count for the watchdog and as overruns, and are not integrated);
 *  @p jitter_ns < 0: none to record in @p jit. */
void pfd_sample_run(pfd_inst *in, pfd_jitter *jit, uint32_t missed, int64_t jitter_ns);

/** The jitter below which a fraction @p q of the samples in @p jit lie, us. */
uint32_t pfd_jitter_percentile(const pfd_jitter *jit, double q);

#endif
