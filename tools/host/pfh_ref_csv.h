/* SPDX-License-Identifier: MIT */
/**
 * @file pfh_ref_csv.h
 * @brief Loader for the exact reference table (tests/ref/
 *        paper_step_exact.csv), for the test suite. No malloc: the caller
 *        provides the table.
 */
#ifndef PFH_REF_CSV_H
#define PFH_REF_CSV_H

#define PFH_REF_CSV_MAX_ROWS 200
#define PFH_REF_CSV_MAX_COLS 16
#define PFH_REF_CSV_NAME_LEN 32

/** A numeric CSV with one header line; col[j][i] is row i of column j. */
typedef struct pfh_ref_csv {
    int ncols, nrows;
    char name[PFH_REF_CSV_MAX_COLS][PFH_REF_CSV_NAME_LEN];
    double col[PFH_REF_CSV_MAX_COLS][PFH_REF_CSV_MAX_ROWS];
} pfh_ref_csv;

/** Load @p path into @p out. Every data line must have exactly as many
 *  fields as the header, all numbers.
 *  @return 0 on success, non-zero if the file cannot be opened or read, is
 *          malformed, or exceeds the fixed limits. */
int pfh_ref_csv_load(const char *path, pfh_ref_csv *out);

#endif /* PFH_REF_CSV_H */
