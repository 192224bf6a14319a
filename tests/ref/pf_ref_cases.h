/* SPDX-License-Identifier: MIT */
/**
 * @file pf_ref_cases.h
 * @brief The cases of the exact reference table (tests/ref/
 *        paper_step_cases.json, written by make_reference.py): each case's
 *        configuration and parameters, read from the file so that the case
 *        set is defined once, in the script that computes the table.
 */
#ifndef PF_REF_CASES_H
#define PF_REF_CASES_H

#include "pneufrac/pf_params.h"

#define PF_REF_MAX_CASES 16
#define PF_REF_CASE_NAME_LEN 32
/** Largest case file accepted (the committed one is about 2.4 kB). */
#define PF_REF_CASES_MAX_BYTES 65536

typedef struct pf_ref_cases {
    int n;
    char name[PF_REF_MAX_CASES][PF_REF_CASE_NAME_LEN];
    pf_params p[PF_REF_MAX_CASES]; /**< unused parameters are 0 */
} pf_ref_cases;

/** Parse the case file's text: one JSON object whose members are
 *  "name": {"config": "p"|"dd"|"id"|"pid", "params": {"a": 1, ...}} with
 *  the paper's parameter names. Anything else (unknown names, duplicate
 *  cases, non-numbers, trailing text) is refused.
 *  @return 0 on success, non-zero on any error. */
int pf_ref_cases_parse(const char *text, pf_ref_cases *out);

/** Read and parse @p path. @return 0 on success, non-zero on any error. */
int pf_ref_cases_load(const char *path, pf_ref_cases *out);

/** @return the parameters of case @p name, or NULL if there is none. */
const pf_params *pf_ref_cases_find(const pf_ref_cases *c, const char *name);

#endif /* PF_REF_CASES_H */
