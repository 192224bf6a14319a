/* SPDX-License-Identifier: MIT */
/*
 * THE settings table: every option of pneufracd, one row each, with its
 * command-line flag, its config-file key (for the daemon-wide settings),
 * its type and range, the field it sets, and a line of help. Argument
 * parsing (pfd_cli.c), the config file's [daemon] section (pfd_config.c)
 * and `pneufracd --help` all read it; docs/pneufracd.md shows `--help`.
 */
#ifndef PFD_SETTINGS_H
#define PFD_SETTINGS_H

#include <stddef.h>
#include <stdint.h>

#include "pfd_addr.h"

/** Bits of settings-table rows, one per row (pfd_setting_bit). */
typedef uint64_t pfd_mask;

/** Room for a file name or a list in a setting (PFD_ST_FILE, PFD_ST_ROLES). */
#define PFD_SETTING_TEXT 256

/** Daemon-wide settings: the rows with a config key (the [daemon]
 *  section), overridden by the same flags on the command line. */
typedef struct pfd_settings {
    pfd_endpoint listen;
    int external_clock;
    int word_order;      /**< enum pfd_word_order of every 32-bit register */
    int max_clients;
    char allow[512];     /**< comma-separated CIDR list (pfd_allow_parse) */
    int read_only;
    int param_lock;      /**< locked at start, and the lock register is fixed */
    int rt_priority;     /**< SCHED_FIFO priority; 0 = do not try */
    int loop_budget;     /**< % of one core the loop's measured load may reach */
    int mlock;
    int overrun_report_s; /**< at most one msg=overruns line this often */
    int byte_timeout_ms;
    int idle_timeout_s;
    int max_per_addr;    /**< clients from one IPv4 address */
    int first_request_ms; /**< a connection must complete a request (and its
                               TLS handshake) this soon after it is accepted */
    int plain_access;    /**< enum pfd_access_level of plain TCP clients; NONE: no
                              plain listener */
    pfd_endpoint tls_listen; /**< Modbus/TCP Security listener; addr "" = off */
    char tls_cert[PFD_SETTING_TEXT], tls_key[PFD_SETTING_TEXT],
        tls_ca[PFD_SETTING_TEXT];
    char tls_roles[PFD_SETTING_TEXT]; /**< NAME:ACCESS list (pfd_access.h) */
} pfd_settings;

/** What only the command line gives: the rows without a config key. */
typedef struct pfd_run {
    const char *config;  /**< --config FILE, or NULL */
    int fallback;        /**< --config-fallback-defaults */
    /* the default instances, without --config */
    int instances;
    int controller;      /**< pf_topology */
    double fs;
    int substeps;        /**< 0 = the rule's (pfd_rate_substeps) */
    int arith;           /**< enum pfd_arith */
    double run_for;      /**< s; 0 = until a signal */
    int verbose;
    /* print something and exit */
    int print_map, print_config;
    const char *seal, *init;
    int version, help;
} pfd_run;

enum pfd_setting_type {
    PFD_ST_BOOL,     /**< int 0/1; the bare flag sets flag_value */
    PFD_ST_INT,      /**< int in [lo, hi] */
    PFD_ST_REAL,     /**< double in [lo, hi] */
    PFD_ST_CHOICE,   /**< int in [0, hi], written as name(value) */
    PFD_ST_ENDPOINT, /**< pfd_endpoint, ADDR:PORT */
    PFD_ST_NETS,     /**< char[], a CIDR list */
    PFD_ST_FILE,     /**< char[PFD_SETTING_TEXT], a file name; "" = none */
    PFD_ST_ROLES,    /**< char[PFD_SETTING_TEXT], certificate roles (pfd_access.h) */
    PFD_ST_PATH      /**< const char *, a file name (command line only) */
};

/** Groups, in the order --help lists them. */
enum pfd_setting_group {
    PFD_SG_DAEMON,    /**< has a config key; field in pfd_settings */
    PFD_SG_INSTANCES, /**< the default instances; field in pfd_run */
    PFD_SG_RUN,       /**< field in pfd_run */
    PFD_SG_EXIT,      /**< print something and exit; field in pfd_run */
    PFD_SG_COUNT
};

/* pfd_setting.flags */
#define PFD_SF_STOP 0x1u   /**< parsing stops at this flag (--help, --version) */
#define PFD_SF_NODEF 0x2u  /**< --help shows no default (it means "off") */
#define PFD_SF_SECURE 0x4u /**< a security setting: a fallback run never takes
                                it from the file, only from the command line
                                or its `fallback` value (pfd_settings_fallback) */
#define PFD_SF_OFF 0x8u    /**< PFD_ST_ENDPOINT: "none" turns it off */

typedef struct pfd_setting {
    const char *flag;     /**< "--max-clients" */
    const char *alias;    /**< another spelling of the flag, or NULL */
    const char *key;      /**< config key (PFD_SG_DAEMON only), or NULL */
    unsigned char type, group, flags;
    int flag_value;       /**< PFD_ST_BOOL: what the bare flag sets */
    double lo, hi;        /**< INT, REAL: the closed range; CHOICE: 0, count-1;
                               ENDPOINT: lo > 0 is the port when none is given */
    const char *(*choice)(int); /**< PFD_ST_CHOICE: the name of a value */
    size_t off, size;     /**< the field in pfd_settings or pfd_run */
    const char *metavar;  /**< what the value looks like in --help */
    const char *help;     /**< one line */
    const char *fallback; /**< PFD_SF_SECURE: the value a fallback run forces
                               unless the command line gives one; NULL: the
                               default */
} pfd_setting;

extern const pfd_setting pfd_settings_table[];
extern const unsigned pfd_settings_count;

/** The row with this flag (or alias), or NULL. */
const pfd_setting *pfd_setting_by_flag(const char *flag);

/** The row with this config key, or NULL. */
const pfd_setting *pfd_setting_by_key(const char *key);

/** The row's bit in a mask of given settings (pfd_cli.given,
 *  pfd_config.set_mask). */
pfd_mask pfd_setting_bit(const pfd_setting *r);

/** Whether the row takes a value on the command line (BOOL rows do not). */
int pfd_setting_takes_value(const pfd_setting *r);

/** Parse @p text into the row's field, in @p s (PFD_SG_DAEMON) or @p run
 *  (the others). @p text NULL, for a PFD_ST_BOOL row: the bare flag, which
 *  sets flag_value. @return 0, or -1 with a message "'TEXT' is not ..." in
 *  @p msg (the caller names the flag or key), the field untouched. */
int pfd_setting_parse(const pfd_setting *r, const char *text, pfd_settings *s,
                      pfd_run *run, char *msg, size_t n);

/** The field as text that pfd_setting_parse() reads back ("" for a NULL
 *  path). */
void pfd_setting_format(const pfd_setting *r, const pfd_settings *s,
                        const pfd_run *run, char *buf, size_t n);

/** Copy the fields of the rows whose bits are in @p mask from @p src. */
void pfd_settings_copy(pfd_settings *dst, const pfd_settings *src, pfd_mask mask);

/** "internal" or "external" (pfd_settings.external_clock 0 or 1). */
const char *pfd_clock_name(int external);

/** Built-in defaults: 127.0.0.1:1502, internal clock, 16 clients, ... */
void pfd_settings_default(pfd_settings *s);

/** What a run that falls back to the defaults uses (--config-fallback-
 *  defaults): the defaults, with every PFD_SF_SECURE row that has a
 *  `fallback` value set to it (read-only, parameters locked). The file
 *  that could not be used gives nothing. */
void pfd_settings_fallback(pfd_settings *s);

/** The rules that tie settings together, checked on the merged settings
 *  (file, then command line) before anything starts, so that a bad
 *  combination is refused as bad arguments (exit 2), not found by the
 *  server after the loop has started: --tls-listen needs its three files,
 *  each readable; --plain-access none needs --tls-listen. @return 0, or
 *  -1 with one line in @p err naming the options and their config keys. */
int pfd_settings_check(const pfd_settings *s, char *err, size_t n);

/** One default instance (pfd_iparams_default), nothing else set. */
void pfd_run_default(pfd_run *run);

#endif
