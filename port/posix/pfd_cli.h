/* SPDX-License-Identifier: MIT */
/* The command line, read through the settings table (pfd_settings.h). */
#ifndef PFD_CLI_H
#define PFD_CLI_H

#include <stddef.h>
#include <stdio.h>

#include "pfd_settings.h"

typedef struct pfd_cli {
    pfd_settings set; /**< defaults, then what the command line gives */
    pfd_mask given;   /**< pfd_setting_bit() of every row given */
    pfd_run run;
} pfd_cli;

/** Parse argv into @p a. Stops early at --help or --version (run.help,
 *  run.version). @return 0, or -1 with a one-line message in @p err. */
int pfd_cli_parse(int argc, char *const *argv, pfd_cli *a, char *err, size_t errlen);

/** `pneufracd --help`, from the table. */
void pfd_cli_help(FILE *f);

#endif
