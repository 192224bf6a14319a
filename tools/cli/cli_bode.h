/* SPDX-License-Identifier: MIT */
/* "pneufrac bode": frequency response of the ideal and the realised
 * controller, as CSV (and a plot). */
#ifndef PNEUFRAC_CLI_BODE_H
#define PNEUFRAC_CLI_BODE_H

#include <stdio.h>

/** Entry point; argv[0] is "bode". @return the exit status. */
int cli_bode_main(int argc, char **argv);

/** Print the usage of the bode command. */
void cli_bode_usage(FILE *f);

#endif
