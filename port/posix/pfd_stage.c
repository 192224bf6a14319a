/* SPDX-License-Identifier: MIT */
#include "pfd_stage.h"

#include <string.h>

static int is_staged(const pfd_reg *r)
{
    return (r->flags & PFD_F_STAGED) && !(r->flags & PFD_F_ACTION);
}

void pfd_stage_record(pfd_stage *st, const pfd_wlist *wl)
{
    unsigned i;
    for (i = 0; i < wl->n; i++) {
        const pfd_reg *r = wl->w[i].r;
        if (!is_staged(r))
            continue;
        st->mask[r->addr / 64] |= (uint64_t)1 << (r->addr % 64);
        st->v[r->addr] = wl->w[i].v;
    }
}

void pfd_stage_compose(const pfd_stage *st, const pfd_wlist *wl,
                       const pfd_iparams *committed, pfd_iparams *out)
{
    /* Replayed as the register writes they were, through the one apply. */
    pfd_hold h;
    pfd_wlist tmp;
    unsigned a;

    memset(&h, 0, sizeof h);
    h.staged = *committed;
    if (st != NULL) {
        memset(&tmp, 0, sizeof tmp);
        for (a = 0; a < PFD_HOLD_SIZE; a++)
            if (st->mask[a / 64] & ((uint64_t)1 << (a % 64))) {
                tmp.w[tmp.n].r = pfd_reg_at(PFD_HOLD, a);
                tmp.w[tmp.n].v = st->v[a];
                tmp.n++;
            }
        pfd_regmap_apply(&h, committed, &tmp);
    }
    if (wl != NULL) {
        unsigned i;
        memset(&tmp, 0, sizeof tmp);
        for (i = 0; i < wl->n; i++)
            if (is_staged(wl->w[i].r))
                tmp.w[tmp.n++] = wl->w[i];
        pfd_regmap_apply(&h, committed, &tmp);
    }
    *out = h.staged;
}

int pfd_stage_any(const pfd_stage *st)
{
    unsigned k;
    if (st == NULL)
        return 0;
    for (k = 0; k < sizeof st->mask / sizeof st->mask[0]; k++)
        if (st->mask[k] != 0)
            return 1;
    return 0;
}
