/* SPDX-License-Identifier: MIT */
/* Status and parameter names. Constant tables only: no mutable static data. */
#include "pneufrac/pf_status.h"

#include <string.h>

static const char *const param_names[PF_P_COUNT] = {
    "a", "b", "k1", "k2", "A", "ks", "tau", "pmin", "pmax", "beta", "q", "nu",
    "w", "RC", "RCd", "RCi",
    "config", "fs", "wb", "wh", "order", "approx", "prewarp", "t_slow", "input",
    "alpha", "gain",
    "in_fs", "out_fs",
    "backlash", "nozzle_xh", "sat_lo", "sat_hi", "dead_time", "lag",
};

pf_param_id pf_status_param(pf_status st)
{
    if (st >= PF_E_PARAM_BASE && st < PF_E_PARAM_BASE + (int)PF_P_COUNT)
        return (pf_param_id)(st - PF_E_PARAM_BASE);
    return PF_P_COUNT;
}

const char *pf_param_name(pf_param_id id)
{
    if ((unsigned)id >= (unsigned)PF_P_COUNT)
        return "?";
    return param_names[id];
}

pf_param_id pf_param_lookup(const char *name)
{
    int i;
    if (name == NULL)
        return PF_P_COUNT;
    for (i = 0; i < (int)PF_P_COUNT; i++)
        if (strcmp(name, param_names[i]) == 0)
            return (pf_param_id)i;
    return PF_P_COUNT;
}

const char *pf_status_str(pf_status st)
{
    switch (st) {
    case PF_OK: return "ok";
    case PF_E_NULL: return "null pointer";
    case PF_E_UNSUPPORTED: return "not supported in this arithmetic";
    case PF_E_BUFFER: return "buffer too small";
    case PF_E_SCALE: return "a fixed-point coefficient does not fit its format";
    default: break;
    }
    if (pf_status_param(st) != PF_P_COUNT)
        return "invalid parameter";
    return "unknown status";
}
