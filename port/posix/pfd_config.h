/* SPDX-License-Identifier: MIT */
/*
 * What the config file means: a `[daemon]` section of settings (the keys
 * of the settings table) and one `[instance UNIT]` section per instance
 * (the names of its holding registers). The text format, checksum
 * included, is pfd_ini.h's; the atomic, durable rewrite is pfd_file.h's.
 * The daemon rewrites the file on every commit. Format: docs/pneufracd.md.
 */
#ifndef PFD_CONFIG_H
#define PFD_CONFIG_H

#include <stddef.h>
#include <stdio.h>

#include "pfd_state.h"

/** Modbus unit ids an instance may have. */
#define PFD_UNIT_MIN 1
#define PFD_UNIT_MAX 247

typedef struct pfd_config_inst {
    int unit;
    int line;          /* of the [instance] header, for messages */
    pfd_iparams ip;
    pfd_live live;     /* sp, input_sel, mode, manual_out, failsafe_out, watchdog_ms */
} pfd_config_inst;

typedef struct pfd_config {
    pfd_settings set;
    pfd_mask set_mask; /**< pfd_setting_bit() of every [daemon] key given */
    int n;
    pfd_config_inst inst[PFD_MAX_INSTANCES];
} pfd_config;

/** Defaults for one instance: Example 6 (pfd_iparams_default), at rest. */
void pfd_config_inst_default(pfd_config_inst *ci, int unit);

/** Read and check @p path. With @p need_checksum 0 the checksum line may
 *  be missing or stale (--seal-config). @return 0, or -1 with a one-line
 *  message "config FILE:LINE: ..." in @p err. */
int pfd_config_load(const char *path, pfd_config *c, int need_checksum,
                    char *err, size_t errlen);

/** The file's text, checksum line included, into @p f. */
int pfd_config_print(const pfd_config *c, FILE *f);

/** Replace @p path atomically and durably. @return 0, or -1 with @p err. */
int pfd_config_write(const char *path, const pfd_config *c, char *err,
                     size_t errlen);

/** Create @p path unless it exists (pfd_file_create). @return 0 created,
 *  1 it exists (untouched), or -1 with @p err. */
int pfd_config_create(const char *path, const pfd_config *c, char *err,
                      size_t errlen);

#endif
