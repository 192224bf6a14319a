/* SPDX-License-Identifier: MIT */
/*
 * The configuration a run starts from: the file of --config, accepted only
 * once every instance in it has been designed, or the default instances of
 * the command line; with --config-fallback-defaults, a file that fails is
 * left alone and the defaults run, read-only (docs/pneufracd.md). Also --seal-config and
 * --print-default-config, which check and write the same files.
 */
#ifndef PFD_START_H
#define PFD_START_H

#include <stddef.h>

#include "pfd_config.h"
#include "pfd_settings.h"

/** Exit status for bad arguments or a bad config file. */
#define PFD_EXIT_USAGE 2

/** Fill @p c for this run. With --config-fallback-defaults, a FILE that
 *  is missing, corrupt or cannot be designed gives the default instances
 *  instead, and is left as it is. @return 0, 1 for such a fallback (the
 *  run must not trust or rewrite FILE: see pfd_settings_fallback), or -1
 *  after a fatal message. */
int pfd_start_config(const pfd_run *run, pfd_config *c);

/** Why instance @p ci failed, "config FILE:LINE: [instance U]: why" (or
 *  "instance U: why" when @p path is NULL). */
void pfd_start_describe(char *buf, size_t n, const char *path,
                        const pfd_config_inst *ci, const pfd_fail *why);

/** --seal-config: accept a hand-edited file once it parses and designs.
 *  @return the exit status. */
int pfd_start_seal(const char *path);

/** --print-default-config. @return the exit status. */
int pfd_start_print_default(const pfd_run *run);

/** --init-config FILE: the config file of --print-default-config, into
 *  FILE unless it exists, once every instance designs. @return the exit
 *  status (0 also when FILE exists). */
int pfd_start_init(const pfd_run *run, const char *path);

#endif
