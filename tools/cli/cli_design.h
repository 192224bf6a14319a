/* SPDX-License-Identifier: MIT */
/* "pneufrac design": design a controller and export its coefficients. */
#ifndef PNEUFRAC_CLI_DESIGN_H
#define PNEUFRAC_CLI_DESIGN_H

#include <stdio.h>

/** Entry point; argv[0] is "design". @return the exit status. */
int cli_design_main(int argc, char **argv);

/** Print the usage of the design command. */
void cli_design_usage(FILE *f);

#endif
