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

#include "pfd_instance.h"

/** Internal rate the rule asks for, as a multiple of 1/tau_fast: the
 *  error over t >= tau_fast is about c/(f tau_fast) % of the peak with c
 *  at most 6.7 over the relays measured (bench/bench_rate), so 20 leaves
 *  a factor 3 below 0.1 %. */
#define PFD_RATE_STEPS_PER_TAU 20.0

/** The design's fastest time constant, s: the smallest of the relay's tau,
 *  each restrictor's RC^(1/order), and 1/w_c where w_c is the highest
 *  frequency at which the flapper-bellows loop gain falls through 1.
 *  @p p must be valid (pf_params_validate). */
double pfd_rate_fastest(const pf_params *p);

/** The rule: the fewest substeps k >= 1 with fs x k >= 20 / tau_fast,
 *  within k <= PFD_SUBSTEPS_MAX and fs x k <= max(fs, PFD_INTERNAL_FS_MAX). */
unsigned pfd_rate_substeps(const pf_params *p, double fs);

/** Measure @p s's CPU time per controller step (this thread's CPU clock,
 *  the median of a few rounds with a mid-scale input) into
 *  s->rate.step_ns, and leave @p s at rest. About a millisecond of work;
 *  not for the real-time thread. */
void pfd_rate_measure(pfd_slot *s);

/** CPU ns the worst exchange of a set costs: k steps, plus one for the
 *  exchange that switches a commit in (both sets step once). */
double pfd_rate_exchange_ns(const pfd_rate *r);

/** The loop's load, accumulated over its instances (pfd_load_add), as a
 *  fraction of one core: utilisation, sum of fs x exchange cost, plus the
 *  blocking term, the longest exchange over the shortest period (an
 *  exchange is never preempted by another instance's). */
typedef struct pfd_load {
    double util;      /**< sum of fs x exchange cost */
    double cost_max;  /**< longest exchange, s */
    double fs_max;    /**< fastest exchange rate, Hz */
} pfd_load;

void pfd_load_add(pfd_load *l, double fs, const pfd_rate *r);

/** util + cost_max x fs_max: the fraction of one core the loop needs for
 *  every sample to meet its deadline (a sufficient condition for the
 *  earliest-deadline-first loop without preemption). */
double pfd_load_total(const pfd_load *l);

#endif
