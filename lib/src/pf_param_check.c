/* SPDX-License-Identifier: MIT */
/* A value against its parameter's row of the table (pf_param_info.h). */
#include "pneufrac/pf_param_info.h"

#include <math.h>
#include <stddef.h>

pf_status pf_param_check(pf_param_id id, double v)
{
    const pf_param_spec *s = pf_param_info(id);
    int ok;
    if (s == NULL || !isfinite(v))
        return PF_E_PARAM(id);
    ok = (s->flags & PF_PARAM_LO_OPEN) ? v > s->lo : v >= s->lo;
    ok = ok && ((s->flags & PF_PARAM_HI_OPEN) ? v < s->hi : v <= s->hi);
    ok = ok && (!(s->flags & PF_PARAM_INTEGER) || v == floor(v));
    ok = ok && (!(s->flags & PF_PARAM_NONZERO) || v != 0.0);
    return ok ? PF_OK : PF_E_PARAM(id);
}
