/* SPDX-License-Identifier: MIT */
/**
 * @file pfh_fmt.h
 * @brief Shortest round-trip decimal text of a double or a float: the
 *        number format of every file the tools and the daemon write (CSV
 *        of `pneufrac simulate`, `bode`, `step`; pneufracd's config files),
 *        so that 0.1 is written "0.1", not "0.10000000000000001", and
 *        reading the text back gives the same bits.
 *
 * Layout, as Python's repr: positional for decimal exponents -4..15
 * ("0.0001", "123.5", "1000"), otherwise "1.5e+16", "1e-05"; "nan", "inf",
 * "-inf" for the non-finite. Integral values have no ".0".
 */
#ifndef PFH_FMT_H
#define PFH_FMT_H

#include <stdio.h>

/** Room for any text pfh_fmt_* writes, with the terminating NUL. */
#define PFH_FMT_LEN 32

/** Write into @p buf the shortest decimal that strtod() reads back as
 *  exactly @p v (of the shortest ones, the nearest to v).
 *  @return the length of the text. */
int pfh_fmt_double(char buf[PFH_FMT_LEN], double v);

/** The same for a float: the shortest decimal that strtof() reads back as
 *  exactly @p v ("0.1" for 0.1f, where %.9g writes "0.100000001"). */
int pfh_fmt_float(char buf[PFH_FMT_LEN], float v);

/** fputs(pfh_fmt_double(v)) to @p f. @return as fputs. */
int pfh_fput_double(FILE *f, double v);

#endif /* PFH_FMT_H */
