/* SPDX-License-Identifier: MIT */
/* Reader of the input sequence e(t) for "pneufrac simulate --input". */
#ifndef PNEUFRAC_CLI_CSV_H
#define PNEUFRAC_CLI_CSV_H

#include <stddef.h>
#include <stdio.h>

/** Most data rows an input file may hold; beyond it the file is refused,
 *  so that a wrong file cannot exhaust memory. */
#define CLI_CSV_MAX_ROWS 50000000UL

/** Longest line accepted, bytes (without the newline). */
#define CLI_CSV_MAX_LINE 65536

/**
 * Read the columns t and e of a CSV file ("-" is standard input).
 *
 * The first line that is neither blank nor a '#' comment is the header; it
 * must name columns "t" and "e" once each (other columns are ignored but
 * every row must have as many fields as the header). t must rise by 1/fs
 * from row to row, within 1e-6 of a step (plus the rounding of t itself).
 * Every row is checked, but only the first @p keep values of e are stored.
 *
 * @param path  file name, used in messages as "path:line"
 * @param fs    sample rate of the run, Hz
 * @param keep  number of samples the run needs (>= 1)
 * @param e     out: malloc'd array of min(rows, keep) values; caller frees
 * @param n     out: its length (>= 1 on success)
 * @return 0, or -1 after printing one error line.
 */
int cli_csv_read_input(const char *path, double fs, size_t keep, double **e,
                       size_t *n);

/**
 * Write the head of a CSV file the tools produce: the header line
 * @p columns, then "# units: " @p units, one unit per column in the same
 * order, as a comment that pandas (comment='#'), numpy and the tools' own
 * readers skip. @return 0, or -1 on a write error.
 */
int cli_csv_head(FILE *f, const char *columns, const char *units);

#endif /* PNEUFRAC_CLI_CSV_H */
