/* SPDX-License-Identifier: MIT */
/*
 * The overrun report: one log line for every instance at once, at most
 * once per --overrun-report-s. The loop counts overruns per instance (in
 * its snapshots) and keeps each instance's worst lateness; the main
 * thread's housekeeping hands both over here every 200 ms. The first line
 * comes at the first overrun; later ones sum what happened since the line
 * before, with a count per instance and the worst lateness; the last comes
 * at stop. Every overrun is in exactly one line, so the lines add up to the
 * loop-stats total (a clear-statistics command aside). Before, 32 instances
 * at 10 kHz logged about 400 lines in 3 s, one per instance every round.
 */
#ifndef PFD_OVERRUN_H
#define PFD_OVERRUN_H

#include <stdint.h>

#include "pfd_state.h"

typedef struct pfd_overrun_report {
    int64_t interval_ns;
    int64_t last_line_ns;  /**< the last line, or the start */
    int lines;             /**< lines written so far */
    uint32_t seen[PFD_MAX_INSTANCES];    /**< each counter at the last look */
    uint64_t pending[PFD_MAX_INSTANCES]; /**< overruns not reported yet */
    int unit[PFD_MAX_INSTANCES];
    int64_t late_ns;       /**< the worst lateness since the last line */
    int late_unit;
} pfd_overrun_report;

/** Start a report at @p now_ns, a line at most every @p interval_s. */
void pfd_overrun_init(pfd_overrun_report *r, int interval_s, int64_t now_ns);

/** One look at instance @p i (unit @p unit): its overrun counter, and the
 *  worst lateness the loop saw since the last look, ns. A counter that
 *  went down was cleared (command 3): all of it is new. */
void pfd_overrun_look(pfd_overrun_report *r, int i, int unit, uint32_t overruns,
                      int64_t late_ns);

/** After a look at all @p n instances: log the line, if there are
 *  overruns to report and it is the first line or the interval has passed
 *  since the last, or @p final (at stop). */
void pfd_overrun_emit(pfd_overrun_report *r, int n, int64_t now_ns, int final);

/** Loop thread: note that an instance's sample started @p late_ns after
 *  its deadline, in @p worst, which the main thread takes and resets with
 *  pfd_overrun_take(). Lock-free, no system call. */
static inline void pfd_overrun_note(int64_t *worst, int64_t late_ns)
{
    int64_t cur = __atomic_load_n(worst, __ATOMIC_RELAXED);
    /* The main thread only ever sets it to 0: this retries only after
     * such a take, or a spurious failure of the weak exchange. */
    while (late_ns > cur &&
           !__atomic_compare_exchange_n(worst, &cur, late_ns, 1, __ATOMIC_RELAXED,
                                        __ATOMIC_RELAXED)) {
    }
}

/** Main thread: the worst lateness noted since the last take, ns. */
static inline int64_t pfd_overrun_take(int64_t *worst)
{
    return __atomic_exchange_n(worst, (int64_t)0, __ATOMIC_RELAXED);
}

#endif
