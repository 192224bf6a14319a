/* SPDX-License-Identifier: MIT */
#include "pfd_audit.h"

#include <string.h>

#include "pfd_log.h"

static void line(const pfd_who *w, int unit, const char *reg, double old_v,
                 double new_v, const char *result)
{
    pfd_log(PFD_LOG_INFO, "write", "peer=%s role=%s unit=%d reg=%s old=%.9g new=%.9g result=%s",
            w->peer, w->role, unit, reg, old_v, new_v, result);
}

void pfd_audit_settings(const pfd_who *w, int unit, const pfd_hold *before,
                        const pfd_hold *after, const pfd_iparams *committed,
                        const char *result)
{
    unsigned i;
    for (i = 0; i < pfd_nregs; i++) {
        const pfd_reg *r = &pfd_regs[i];
        double a, b;
        if (r->space != PFD_HOLD || r->access == PFD_R ||
            (r->flags & (PFD_F_OPEN | PFD_F_STAGED | PFD_F_ACTION)))
            continue;
        a = pfd_regmap_hold_value(r, before, committed);
        b = pfd_regmap_hold_value(r, after, committed);
        if (a != b)
            line(w, unit, r->name, a, b, result);
    }
}

void pfd_audit_params(const pfd_who *w, int unit, const pfd_iparams *old,
                      const pfd_iparams *new_set, const char *result)
{
    pfd_hold a, b;
    unsigned i;

    memset(&a, 0, sizeof a);
    memset(&b, 0, sizeof b);
    a.staged = *old;
    b.staged = *new_set;
    for (i = 0; i < pfd_nregs; i++) {
        const pfd_reg *r = &pfd_regs[i];
        double x, y;
        if (r->space != PFD_HOLD || !(r->flags & PFD_F_STAGED) || (r->flags & PFD_F_ACTION))
            continue;
        x = pfd_regmap_hold_value(r, &a, old);
        y = pfd_regmap_hold_value(r, &b, old);
        if (x != y)
            line(w, unit, r->name, x, y, result);
    }
}

void pfd_audit_command(const pfd_who *w, int unit, unsigned command)
{
    static const char *const names[] = {"?", "discard-staged", "reset", "clear-statistics"};
    pfd_log(PFD_LOG_INFO, "command", "peer=%s role=%s unit=%d command=%s result=ok", w->peer,
            w->role, unit, names[command < 4 ? command : 0]);
}

void pfd_audit_refused(const pfd_who *w, int unit, unsigned addr, unsigned count,
                       int exc, const char *reason)
{
    static pfd_ratelimit rl = PFD_RATELIMIT("write-refused");
    const pfd_reg *r = pfd_reg_at(PFD_HOLD, addr);
    if (pfd_log_ratelimit(&rl))
        pfd_log(PFD_LOG_WARN, "write-refused",
                "peer=%s role=%s unit=%d addr=%u count=%u reg=%s exception=%d reason=%s",
                w->peer, w->role, unit, addr, count, r != NULL ? r->name : "?", exc, reason);
}
