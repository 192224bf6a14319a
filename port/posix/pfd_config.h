/* SPDX-License-Identifier: MIT */
/*
 * The configuration file: INI-like text, `[daemon]` and `[instance UNIT]`
 * sections of `key = value` lines, '#' comments, and a last line
 * `checksum = <crc32 hex>` over every byte before it. The daemon rewrites
 * the file on every commit (temp file, fsync, rename, fsync of the
 * directory), so a crash leaves the old or the new file, never a mix; the
 * checksum catches anything else (a truncated copy, a bad disk, an edit
 * that was not re-sealed). Format: docs/pneufracd.md.
 */
#ifndef PFD_CONFIG_H
#define PFD_CONFIG_H

#include <stddef.h>
#include <stdio.h>

#include "pfd_state.h"

/* Bits of pfd_config.set_mask: [daemon] keys the file sets. */
enum {
    PFD_K_LISTEN = 1 << 0, PFD_K_CLOCK = 1 << 1, PFD_K_MAX_CLIENTS = 1 << 2,
    PFD_K_ALLOW = 1 << 3, PFD_K_READ_ONLY = 1 << 4, PFD_K_PARAM_LOCK = 1 << 5,
    PFD_K_RT_PRIORITY = 1 << 6, PFD_K_MLOCK = 1 << 7,
    PFD_K_BYTE_TIMEOUT = 1 << 8, PFD_K_IDLE_TIMEOUT = 1 << 9
};

typedef struct pfd_config_inst {
    int unit;
    int line;          /* of the [instance] header, for messages */
    pfd_iparams ip;
    pfd_live live;     /* sp, input_sel, mode, manual_out, failsafe_out, watchdog_ms */
} pfd_config_inst;

typedef struct pfd_config {
    pfd_settings set;
    unsigned set_mask;
    int n;
    pfd_config_inst inst[PFD_MAX_INSTANCES];
} pfd_config;

/** Built-in defaults: 127.0.0.1:1502, internal clock, 16 clients. */
void pfd_settings_default(pfd_settings *s);

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

/** "ADDR:PORT" (IPv4 dotted quad, port 0..65535) into @p s.
 *  @return 0 or -1. */
int pfd_parse_listen(const char *v, pfd_settings *s);

/** IEEE 802.3 CRC-32 (as zlib's crc32). */
unsigned long pfd_crc32(const unsigned char *p, size_t n);

#endif
