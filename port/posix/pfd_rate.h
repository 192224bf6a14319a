/* SPDX-License-Identifier: MIT */
/*
 * The model at its own rate: how many controller steps (substeps) an
 * exchange runs, and whether the loop can afford them.
 *
 * An exchange is one period of the loop at the instance's fs: it takes the
 * input the client wrote, runs the controller k times with that input held
 * (a PLC's output is a zero-order hold), and publishes the output of the
 * first of those steps, which is the model's response at the exchange
 * instant. The set is designed at the internal rate fs x k, so exchange n
 * equals sample n*k of `pneufrac simulate --fs <fs x k>` with each input
 * held for k samples. Rule, accuracy and budget: docs/pneufracd.md,
 * "Substeps".
 */
#ifndef PFD_RATE_H
#define PFD_RATE_H

#include <stdint.h>

#include "pfd_instance.h"
#include "pfd_state.h"

/** Internal rate the rule asks for, in steps per tau_fast. Over relays
 *  of every order and ratio (bench/bench_rate, docs/benchmarks-daemon.md)
 *  the part of the error that falls with the rate peaks at t = tau and
 *  halves as the rate doubles: at most 0.060 % of the peak at f tau = 10,
 *  0.029 % at 20. 0.1 % would be reached near f tau = 6; 20 leaves a
 *  factor of about 3. */
#define PFD_RATE_STEPS_PER_TAU 20.0

/** The design's fastest time constant, s: the smallest of the relay's tau,
 *  each restrictor's RC^(1/order), and 1/w_c where w_c is the highest
 *  frequency at which the flapper-bellows loop gain falls through 1.
 *  @p p must be valid (pf_params_validate). */
double pfd_rate_fastest(const pf_params *p);

/** The internal rate the rule asks for: 20 / tau_fast, Hz. */
double pfd_rate_wanted_fs(const pf_params *p);

/** The rule: the fewest substeps k >= 1 with fs x k >= 20 / tau_fast,
 *  within k <= PFD_SUBSTEPS_MAX and fs x k <= max(fs, PFD_INTERNAL_FS_MAX). */
unsigned pfd_rate_substeps(const pf_params *p, double fs);

/** Whether the rule asked for more than the limits give (r->wanted_fs
 *  above r->internal_fs): its accuracy aim cannot be met, and such a set
 *  is refused (pfd_plausible.h). Never for substeps given explicitly. */
int pfd_rate_capped(const pfd_rate *r);

/** Measure @p s's CPU time per controller step (this thread's CPU clock,
 *  the median of a few rounds with a mid-scale input) into
 *  s->rate.step_ns, and leave @p s at rest. About a millisecond of work;
 *  not for the real-time thread. */
void pfd_rate_measure(pfd_slot *s);

/** CPU ns the worst exchange of a set costs: k steps, plus one for the
 *  exchange that switches a commit in (both sets step once). */
double pfd_rate_exchange_ns(const pfd_rate *r);

/** CPU time, ns, that one wake-up of the loop costs the loop's thread:
 *  an absolute clock_nanosleep and the switch back (median of a few
 *  rounds of short sleeps; about 20 ms). On this project's test machine
 *  a wake-up costs 12-17 us, more than a hundred controller steps. */
double pfd_rate_measure_wakeup(void);

/** The loop's load, accumulated over its instances (pfd_load_add), as a
 *  fraction of one core. The loop wakes at every exchange instant;
 *  instances of the same rate share their wake-ups (pfd_loop.c keeps
 *  every schedule on the grid of its period), so a rate costs one
 *  wake-up per period however many instances run at it. */
typedef struct pfd_load {
    double wake_ns;   /**< one wake-up, pfd_rate_measure_wakeup() */
    double util;      /**< sum of fs x exchange cost, and of each distinct
                           rate x wake_ns */
    double cost_max;  /**< longest exchange, s */
    double fs_max;    /**< fastest exchange rate, Hz */
    unsigned n_periods;
    uint64_t periods[PFD_MAX_INSTANCES]; /**< the distinct periods, ns */
} pfd_load;

/** Start an empty load. */
void pfd_load_init(pfd_load *l, double wake_ns);

/** Add an instance exchanging at @p fs (at most PFD_MAX_INSTANCES). */
void pfd_load_add(pfd_load *l, double fs, const pfd_rate *r);

/** util + cost_max x fs_max: the share of one core the loop needs so that
 *  every exchange starts within its period. Over any interval of length
 *  L of at least the shortest period, the loop has at most L x util of
 *  work due, plus one exchange already under way (the loop never
 *  interrupts an exchange for another instance's): util + cost_max /
 *  T_min <= 1 is enough. Wake-up latency is not in it; the budget's
 *  headroom is for that (docs/pneufracd.md, "Loop budget"). */
double pfd_load_total(const pfd_load *l);

#endif
