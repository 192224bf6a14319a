/* SPDX-License-Identifier: MIT */
/* Options shared by the commands that design a controller. */
#ifndef PNEUFRAC_CLI_OPTIONS_H
#define PNEUFRAC_CLI_OPTIONS_H

#include <stdio.h>

#include "cli_args.h"
#include "cli_simulate.h"

/* Options (bits of cli_command.allowed and of cli_opts.seen). */
enum {
    CLI_OPT_CONFIG = 1u << 0,
    CLI_OPT_FS = 1u << 1,
    CLI_OPT_DURATION = 1u << 2,
    CLI_OPT_ARITH = 1u << 3,
    CLI_OPT_IN_FS = 1u << 4,
    CLI_OPT_OUT_FS = 1u << 5,
    CLI_OPT_BAND = 1u << 6,
    CLI_OPT_ORDER = 1u << 7,
    CLI_OPT_APPROX = 1u << 8,
    CLI_OPT_INPUT_MODEL = 1u << 9,
    CLI_OPT_TSLOW = 1u << 10,
    CLI_OPT_INPUT = 1u << 11,
    CLI_OPT_FORMAT = 1u << 12,
    CLI_OPT_NAME = 1u << 13,
    CLI_OPT_SET = 1u << 14,    /* repeatable */
    CLI_OPT_EFFECT = 1u << 15, /* repeatable */
    CLI_OPT_OMEGA = 1u << 16,
    CLI_OPT_POINTS = 1u << 17,
    CLI_OPT_PLOT = 1u << 18
};

/** Most frequencies --points may ask for. */
#define CLI_MAX_POINTS 100000

/* What every designing command takes: the model and its discretisation. */
#define CLI_OPTS_DESIGN                                                        \
    (CLI_OPT_CONFIG | CLI_OPT_FS | CLI_OPT_BAND | CLI_OPT_ORDER |              \
     CLI_OPT_APPROX | CLI_OPT_INPUT_MODEL | CLI_OPT_TSLOW | CLI_OPT_SET |      \
     CLI_OPT_EFFECT)
/* The arithmetic and its Q15 full scales. */
#define CLI_OPTS_ARITH (CLI_OPT_ARITH | CLI_OPT_IN_FS | CLI_OPT_OUT_FS)

/** A command: its name for messages, its usage, the options it takes. */
typedef struct cli_command {
    const char *name;
    void (*usage)(FILE *f);
    unsigned allowed;
} cli_command;

/** Parsed command line, before the defaults of the configuration apply. */
typedef struct cli_opts {
    unsigned seen;
    pf_topology topology;
    double fs, duration, in_fs, out_fs, wb, wh, t_slow;
    int order;
    pf_approx approx;
    pf_input_model input_model;
    pf_arith arith;
    const char *input, *format, *name, *plot;
    double w_lo, w_hi;   /* --omega; 0: the command's default */
    int points;          /* --points; 0: the command's default */
    unsigned set_mask;
    double set_val[PF_P_CONFIG];
    cli_effects fx;
} cli_opts;

/** Parse argv[1..] (argv[0] is the command) into @p a, check the options
 *  against each other, and describe the run in @p run (duration is
 *  required only if the command takes it). Prints every error.
 *  @return 1 if help was printed, 0 if @p run is ready, -1 after an error. */
int cli_opts_read(int argc, char **argv, const cli_command *cmd, cli_opts *a,
                  cli_run *run);

#endif
