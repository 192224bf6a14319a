/* SPDX-License-Identifier: MIT */
/* Argument helpers of the pneufrac CLI: one-line errors, strict numbers,
 * and the structured option values (--set, --effect, --band). */
#ifndef PNEUFRAC_CLI_ARGS_H
#define PNEUFRAC_CLI_ARGS_H

#include <stddef.h>
#include <stdio.h>

#include "pneufrac/pneufrac.h"

/** Exit statuses of the tool (cli_exit_status_help prints them). */
#define CLI_EXIT_OK 0
#define CLI_EXIT_IO 1    /**< output could not be written; out of memory */
#define CLI_EXIT_USAGE 2 /**< bad arguments, bad input, invalid design */
#define CLI_EXIT_PLOT 3  /**< --plot: no plot (the CSV was written) */

/** The exit statuses, for the end of every --help; @p with_plot: the
 *  command has --plot, so status 3 can happen. */
void cli_exit_status_help(FILE *f, int with_plot);

#if defined(__GNUC__)
#define CLI_PRINTF(f, a) __attribute__((format(printf, f, a)))
#else
#define CLI_PRINTF(f, a)
#endif

/** Print "pneufrac: <message>" as exactly one line on stderr; control
 *  characters from user text are replaced so the line cannot break. */
void cli_error(const char *fmt, ...) CLI_PRINTF(1, 2);

/** Copy @p s into @p buf (size @p n), shortened with "..." if needed, for
 *  quoting user text in messages. @return buf. */
const char *cli_quote(char *buf, size_t n, const char *s);

/** The same for the first @p len bytes of @p s (an option name cut at '='). */
const char *cli_quote_n(char *buf, size_t n, const char *s, size_t len);

/** Strict conversion of a whole string to a finite double.
 *  @return 0 on success, -1 (no message) otherwise. */
int cli_parse_double(const char *s, double *out);

/** Strict conversion of a whole string to a decimal int.
 *  @return 0 on success, -1 (no message) otherwise. */
int cli_parse_int(const char *s, int *out);

/** Write parameter @p id's range from the library's table, with its unit,
 *  as "(0, 1e+07] Hz" into @p buf (size @p n). */
void cli_param_range(pf_param_id id, char *buf, size_t n);

/** Parse the value of option @p opt as a finite double > 0; prints the
 *  error. @return 0 or -1. */
int cli_parse_positive(const char *opt, const char *s, double *out);

/** One --set NAME=VALUE, parsed but not yet applied (the configuration may
 *  come later on the command line). */
typedef struct cli_set {
    pf_param_id id;
    double value;
} cli_set;

/** Parse "NAME=VALUE" into @p out; prints the error. @return 0 or -1. */
int cli_parse_set(const char *arg, cli_set *out);

/** Which effects a command line has set, to refuse repeats. */
typedef struct cli_effects {
    pf_effects fx;
    unsigned seen; /**< bit per effect name */
} cli_effects;

/** Parse one --effect NAME:K=V[,K=V] into @p acc; prints the error.
 *  @return 0 or -1. */
int cli_parse_effect(const char *arg, cli_effects *acc);

/** Parse the value of option @p opt, LO:HI in rad/s with 0 < LO < HI
 *  (named @p lo_name and @p hi_name in messages, e.g. "WB", "WH"); prints
 *  the error. @return 0 or -1. */
int cli_parse_range(const char *opt, const char *lo_name, const char *hi_name,
                    const char *arg, double *lo, double *hi);

#endif /* PNEUFRAC_CLI_ARGS_H */
