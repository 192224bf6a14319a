/* SPDX-License-Identifier: MIT */
/* "pneufrac step": the unit-step response of the realised controller and
 * of the exact one, as CSV (and a plot). */
#ifndef PNEUFRAC_CLI_STEP_H
#define PNEUFRAC_CLI_STEP_H

#include <stdio.h>

/** Entry point; argv[0] is "step". @return the exit status. */
int cli_step_main(int argc, char **argv);

/** Print the usage of the step command. */
void cli_step_usage(FILE *f);

#endif
