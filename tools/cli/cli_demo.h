/* SPDX-License-Identifier: MIT */
/* "pneufrac demo": the paper's Example 6, with a printed summary. */
#ifndef PNEUFRAC_CLI_DEMO_H
#define PNEUFRAC_CLI_DEMO_H

#include <stdio.h>

/** Entry point; argv[0] is "demo". @return the exit status. */
int cli_demo_main(int argc, char **argv);

/** Print the usage of the demo command. */
void cli_demo_usage(FILE *f);

#endif /* PNEUFRAC_CLI_DEMO_H */
