/* SPDX-License-Identifier: MIT */
/**
 * @file pf_ref_csv.h
 * @brief Loader for the exact reference table (tests/ref/
 *        paper_step_exact.csv), for the test suite. No malloc: the caller
 *        provides the table.
 */
#ifndef PF_REF_CSV_H
#define PF_REF_CSV_H

#define PF_REF_CSV_MAX_ROWS 200
#define PF_REF_CSV_MAX_COLS 16
#define PF_REF_CSV_NAME_LEN 32

/** A numeric CSV with one header line; col[j][i] is row i of column j. */
typedef struct pf_ref_csv {
    int ncols, nrows;
    char name[PF_REF_CSV_MAX_COLS][PF_REF_CSV_NAME_LEN];
    double col[PF_REF_CSV_MAX_COLS][PF_REF_CSV_MAX_ROWS];
} pf_ref_csv;

/** Load @p path into @p out. Every data line must have exactly as many
 *  fields as the header, all numbers.
 *  @return 0 on success, non-zero if the file cannot be opened or read, is
 *          malformed, or exceeds the fixed limits. */
int pf_ref_csv_load(const char *path, pf_ref_csv *out);

#endif /* PF_REF_CSV_H */
