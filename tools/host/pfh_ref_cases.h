/* SPDX-License-Identifier: MIT */
/**
 * @file pfh_ref_cases.h
 * @brief The cases of the exact reference table (tests/ref/
 *        paper_step_cases.json, written by make_reference.py): each case's
 *        configuration and parameters, read from the file so that the case
 *        set is defined once, in the script that computes the table.
 */
#ifndef PFH_REF_CASES_H
#define PFH_REF_CASES_H

#include "pneufrac/pf_params.h"

#define PFH_REF_MAX_CASES 16
#define PFH_REF_CASE_NAME_LEN 32
/** Largest case file accepted (the committed one is about 2.4 kB). */
#define PFH_REF_CASES_MAX_BYTES 65536

typedef struct pfh_ref_cases {
    int n;
    char name[PFH_REF_MAX_CASES][PFH_REF_CASE_NAME_LEN];
    pf_params p[PFH_REF_MAX_CASES]; /**< unused parameters are 0 */
} pfh_ref_cases;

/** Parse the case file's text: one JSON object whose members are
 *  "name": {"config": "p"|"dd"|"id"|"pid", "params": {"a": 1, ...}} with
 *  the paper's parameter names. Anything else (unknown names, duplicate
 *  cases, non-numbers, trailing text) is refused.
 *  @return 0 on success, non-zero on any error. */
int pfh_ref_cases_parse(const char *text, pfh_ref_cases *out);

/** Read and parse @p path. @return 0 on success, non-zero on any error. */
int pfh_ref_cases_load(const char *path, pfh_ref_cases *out);

/** @return the parameters of case @p name, or NULL if there is none. */
const pf_params *pfh_ref_cases_find(const pfh_ref_cases *c, const char *name);

#endif /* PFH_REF_CASES_H */
