/* SPDX-License-Identifier: MIT */
/* "pneufrac simulate": run a controller over an input sequence, write CSV. */
#ifndef PNEUFRAC_CLI_SIMULATE_H
#define PNEUFRAC_CLI_SIMULATE_H

#include <stddef.h>
#include <stdio.h>

#include "pneufrac/pneufrac.h"

/** Longest run accepted, in samples (duration * fs). */
#define CLI_MAX_SAMPLES 1e9

/** Everything one run needs, already checked for syntax. */
typedef struct cli_run {
    pf_params p;
    pf_effects fx;
    pf_design_opts opt;  /**< opt.fs is the run's sample rate */
    pf_arith arith;
    double in_fs, out_fs; /**< Q15 full scales (q15 only) */
    double duration;      /**< s; the run has round(duration*fs)+1 samples */
    const double *input;  /**< NULL: unit step at n = 0 */
    size_t n_input;       /**< >= 1 when input is set; last value is held */
    int exact;            /**< add the column pc_exact: the exact unit-step
                               response (input NULL, linear effects only) */
} cli_run;

/** Observer of every output sample, physical units. */
typedef void (*cli_sample_fn)(void *ctx, size_t n, double pc);

/** Number of samples of a run (round(duration*fs) + 1). */
size_t cli_run_samples(const cli_run *run);

/** Design the run's controller; prints the error.
 *  @return CLI_EXIT_OK or CLI_EXIT_USAGE. */
int cli_run_design(const cli_run *run, pf_ctrl_design *d);

/** Run the designed controller and write the CSV to @p out (named
 *  @p out_name in messages); @p fn, if not NULL, sees every sample.
 *  @return CLI_EXIT_OK, CLI_EXIT_USAGE (q15 coefficients) or CLI_EXIT_IO. */
int cli_run_write(const cli_run *run, const pf_ctrl_design *d, FILE *out,
                  const char *out_name, cli_sample_fn fn, void *ctx);

/** Entry point; argv[0] is "simulate". @return the exit status. */
int cli_simulate_main(int argc, char **argv);

/** Print the usage of the simulate command. */
void cli_simulate_usage(FILE *f);

#endif /* PNEUFRAC_CLI_SIMULATE_H */
