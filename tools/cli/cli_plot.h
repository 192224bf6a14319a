/* SPDX-License-Identifier: MIT */
/* --plot FILE.png: the CSV a command writes goes to standard output as
 * always, and through a temporary file to the plotting program of the
 * Python tools (pneufrac-plot, tools/python/pneufrac_plot): no image code
 * in C. */
#ifndef PNEUFRAC_CLI_PLOT_H
#define PNEUFRAC_CLI_PLOT_H

#include <stddef.h>
#include <stdio.h>

/** Where a command writes its CSV: standard output, or with a plot asked
 *  for, a temporary file that cli_plot_finish copies to standard output. */
typedef struct cli_plot {
    const char *png;   /**< NULL: no plot */
    FILE *csv;         /**< write the CSV here */
    char path[64];     /**< the temporary file */
} cli_plot;

/** Start: @p png NULL writes straight to stdout. Prints the error.
 *  @return 0 or -1 (CLI_EXIT_IO). */
int cli_plot_begin(cli_plot *p, const char *png);

/** The CSV is complete (@p rc is the command's status so far): copy it
 *  to stdout, run `pneufrac-plot KIND CSV PNG` (or the program named by
 *  $PNEUFRAC_PLOT), remove the file. Prints one line on failure.
 *  @return rc if it is not CLI_EXIT_OK; else CLI_EXIT_OK, CLI_EXIT_IO or
 *  CLI_EXIT_PLOT. */
int cli_plot_finish(cli_plot *p, const char *kind, int rc);

#endif
