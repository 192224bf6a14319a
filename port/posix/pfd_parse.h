/* SPDX-License-Identifier: MIT */
/*
 * Text to values, for the command line and the config file alike: the
 * daemon's one number syntax, and lookup of a value by its name.
 */
#ifndef PFD_PARSE_H
#define PFD_PARSE_H

#include <stddef.h>

/** A decimal number: optional sign, digits, optional fraction and
 *  exponent, nothing else around it (no spaces, no hex, no inf or nan),
 *  and finite. @return 0, or -1 with @p out untouched. */
int pfd_parse_number(const char *text, double *out);

/** pfd_parse_number(), and an integer in [lo, hi]. @return 0 or -1. */
int pfd_parse_int(const char *text, long lo, long hi, long *out);

/** The value v in [0, n) whose name(v) is @p text, or -1. */
int pfd_parse_name(const char *text, const char *(*name)(int), int n);

/** The names of the values [0, n) for a message: "a, b or c". */
void pfd_parse_names(const char *(*name)(int), int n, char *buf, size_t len);

#endif
