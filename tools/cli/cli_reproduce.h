/* SPDX-License-Identifier: MIT */
/* "pneufrac reproduce": the data behind the paper's figures, as CSV. */
#ifndef PNEUFRAC_CLI_REPRODUCE_H
#define PNEUFRAC_CLI_REPRODUCE_H

#include <stdio.h>

/** Entry point; argv[0] is "reproduce". @return the exit status. */
int cli_reproduce_main(int argc, char **argv);

/** Print the usage of the reproduce command. */
void cli_reproduce_usage(FILE *f);

#endif
