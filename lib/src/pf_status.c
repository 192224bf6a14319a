/* SPDX-License-Identifier: MIT */
/* Status codes: which parameter a status names, and a text for each.
 * Parameter names are in the table (pf_param_table.c). */
#include "pneufrac/pf_status.h"

pf_param_id pf_status_param(pf_status st)
{
    if (st >= PF_E_PARAM_BASE && st < PF_E_PARAM_BASE + (int)PF_P_COUNT)
        return (pf_param_id)(st - PF_E_PARAM_BASE);
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
