/* SPDX-License-Identifier: MIT */
/**
 * @file pf_param_info.h
 * @brief The parameter table: for every parameter (the paper's model
 *        parameters, the design options, the Q15 full scales and the
 *        effects) its name, range, unit and a one-line description.
 *
 * This table is the one place a parameter's range is written. The
 * library's validation (pf_params_validate, pf_design_opts_resolve,
 * pf_effects_validate, the operator and Q15 designs) checks each value
 * against it with pf_param_check(), and the tools (CLI messages, the
 * daemon's register map, the Python binding) read it from here. Rules
 * that tie two values together (pmin <= pmax, wb < wh <= pi*fs, sat_lo <
 * sat_hi, ...) are not ranges: the validating function states and checks
 * them.
 */
#ifndef PNEUFRAC_PF_PARAM_INFO_H
#define PNEUFRAC_PF_PARAM_INFO_H

#include "pf_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Bits of pf_param_spec.flags. */
#define PF_PARAM_LO_OPEN 0x1u /**< lo itself is out of range: (lo, ... */
#define PF_PARAM_HI_OPEN 0x2u /**< hi itself is out of range: ..., hi) */
#define PF_PARAM_INTEGER 0x4u /**< whole numbers only (an int or enum field) */
#define PF_PARAM_NONZERO 0x8u /**< 0 is out of range, though it lies within */

/** One row of the parameter table. */
typedef struct pf_param_spec {
    const char *name; /**< as in the paper and the CLI: "beta" */
    const char *unit; /**< "s", "Hz", "rad/s", or "" (the paper's
                           consistent units, or dimensionless) */
    const char *desc; /**< one line: what it is, what 0 means if special */
    double lo, hi;    /**< bounds; every value must also be finite
                           (hi = HUGE_VAL: no bound of its own) */
    unsigned flags;   /**< PF_PARAM_* */
    unsigned topologies; /**< model parameters: bit (1 << t) is set when
                              topology t (pf_topology) uses it; 0 otherwise */
} pf_param_spec;

/** @return the row of parameter @p id, or NULL for an unknown id. */
const pf_param_spec *pf_param_info(pf_param_id id);

/** @return the number of parameters, PF_P_COUNT (for bindings). */
int pf_param_count(void);

/** Check @p v against the range of parameter @p id: finite, within
 *  [lo, hi] (open ends as flagged), whole if PF_PARAM_INTEGER, not 0 if
 *  PF_PARAM_NONZERO. @return PF_OK or PF_E_PARAM(id); PF_E_PARAM(id) also
 *  for an unknown id. */
pf_status pf_param_check(pf_param_id id, double v);

#ifdef __cplusplus
}
#endif
#endif /* PNEUFRAC_PF_PARAM_INFO_H */
