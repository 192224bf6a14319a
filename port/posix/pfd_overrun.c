/* SPDX-License-Identifier: MIT */
#include "pfd_overrun.h"

#include <stdio.h>
#include <string.h>

#include "pfd_log.h"

void pfd_overrun_init(pfd_overrun_report *r, int interval_s, int64_t now_ns)
{
    memset(r, 0, sizeof *r);
    r->interval_ns = (int64_t)interval_s * 1000000000;
    r->last_line_ns = now_ns;
}

void pfd_overrun_look(pfd_overrun_report *r, int i, int unit, uint32_t overruns,
                      int64_t late_ns)
{
    /* A counter that went down was cleared; u32 wrap-around after 2^32
     * overruns would look the same and cost a count, once. */
    uint32_t fresh = overruns >= r->seen[i] ? overruns - r->seen[i] : overruns;
    r->seen[i] = overruns;
    r->pending[i] += fresh;
    r->unit[i] = unit;
    if (late_ns > r->late_ns) {
        r->late_ns = late_ns;
        r->late_unit = unit;
    }
}

void pfd_overrun_emit(pfd_overrun_report *r, int n, int64_t now_ns, int final)
{
    /* 64 instances of "247:4294967295," fit, with the line's head. */
    char units[64 * 16 + 1];
    size_t k = 0;
    uint64_t total = 0;
    int i, with = 0;

    for (i = 0; i < n; i++)
        total += r->pending[i];
    if (total == 0)
        return;
    if (!final && r->lines > 0 && now_ns - r->last_line_ns < r->interval_ns)
        return;
    units[0] = '\0';
    for (i = 0; i < n; i++) {
        int w;
        if (r->pending[i] == 0)
            continue;
        w = snprintf(units + k, sizeof units - k, "%s%d:%llu", with ? "," : "", r->unit[i],
                     (unsigned long long)r->pending[i]);
        if (w > 0 && (size_t)w < sizeof units - k)
            k += (size_t)w;
        with++;
        r->pending[i] = 0;
    }
    pfd_log(PFD_LOG_WARN, "overruns",
            "since_s=%.1f overruns=%llu instances=%d worst_late_us=%.0f worst_unit=%d units=%s",
            (double)(now_ns - r->last_line_ns) / 1e9, (unsigned long long)total, with,
            (double)r->late_ns / 1000.0, r->late_unit, units);
    r->last_line_ns = now_ns;
    r->late_ns = 0;
    r->late_unit = 0;
    r->lines++;
}
