/* SPDX-License-Identifier: MIT */
/**
 * @file pf_status.h
 * @brief Status codes. A rejected parameter is named by its status code.
 *
 * Checks of untrusted input return a status; they never assert. Step
 * functions return nothing: they are total and saturate.
 */
#ifndef PNEUFRAC_PF_STATUS_H
#define PNEUFRAC_PF_STATUS_H

/** Parameters, named as in the paper, plus the design options. */
typedef enum pf_param_id {
    PF_P_A = 0, PF_P_B, PF_P_K1, PF_P_K2, PF_P_AREA, PF_P_KS, PF_P_TAU,
    PF_P_PMIN, PF_P_PMAX, PF_P_BETA, PF_P_Q, PF_P_NU, PF_P_W, PF_P_RC,
    PF_P_RCD, PF_P_RCI,
    /* design options */
    PF_P_CONFIG, PF_P_FS, PF_P_WB, PF_P_WH, PF_P_ORDER, PF_P_APPROX,
    PF_P_PREWARP, PF_P_TSLOW, PF_P_INPUT, PF_P_ALPHA, PF_P_GAIN,
    /* fixed-point full scales */
    PF_P_IN_FS, PF_P_OUT_FS,
    /* effects */
    PF_P_BACKLASH, PF_P_NOZZLE_XH, PF_P_SAT_LO, PF_P_SAT_HI, PF_P_DEAD_TIME,
    PF_P_LAG, PF_P_NOZZLE_BIAS, PF_P_SATURATE,
    PF_P_COUNT
} pf_param_id;

/** 0 is success; negative values are general errors; PF_E_PARAM_BASE + id
 *  means "parameter id is invalid" (NaN, out of range, inconsistent). */
typedef int pf_status;

#define PF_OK 0
#define PF_E_NULL (-1)        /**< a required pointer was NULL */
#define PF_E_UNSUPPORTED (-2) /**< feature not available for this arithmetic */
#define PF_E_BUFFER (-3)      /**< caller-supplied buffer too small */
#define PF_E_SCALE (-4)       /**< a fixed-point coefficient does not fit */
#define PF_E_PARAM_BASE 100
#define PF_E_PARAM(id) (PF_E_PARAM_BASE + (int)(id))

#ifdef __cplusplus
extern "C" {
#endif

/** @return the parameter a status names, or PF_P_COUNT if it names none. */
pf_param_id pf_status_param(pf_status st);

/** @return the parameter's name as used in the paper and the CLI ("beta"),
 *          or "?" for an unknown id. */
const char *pf_param_name(pf_param_id id);

/** @return the id for a parameter name, or PF_P_COUNT if unknown. */
pf_param_id pf_param_lookup(const char *name);

/** @return a constant, human-readable description of a status. */
const char *pf_status_str(pf_status st);

#ifdef __cplusplus
}
#endif
#endif /* PNEUFRAC_PF_STATUS_H */
