/* SPDX-License-Identifier: MIT */
/*
 * One client's staged parameter writes for one instance. A staged set is
 * the instance's committed set with this client's writes on top, so that
 * two clients staging at once never see, or commit, each other's partial
 * changes; and a client's commit applies exactly what it staged, on top of
 * whatever is committed by then (another client's commit in between is
 * kept, not reverted).
 */
#ifndef PFD_STAGE_H
#define PFD_STAGE_H

#include <stdint.h>

#include "pfd_regmap.h"

/** Writes of staged registers, by holding address. */
typedef struct pfd_stage {
    uint64_t mask[(PFD_HOLD_SIZE + 63) / 64]; /**< addresses written */
    double v[PFD_HOLD_SIZE];                  /**< their values */
} pfd_stage;

/** Record the staged-register writes of @p wl (the others are ignored). */
void pfd_stage_record(pfd_stage *st, const pfd_wlist *wl);

/** @p committed with the writes of @p st (NULL: none) and then the staged
 *  writes of @p wl (NULL: none) on top. */
void pfd_stage_compose(const pfd_stage *st, const pfd_wlist *wl,
                       const pfd_iparams *committed, pfd_iparams *out);

/** Whether @p st holds any write. */
int pfd_stage_any(const pfd_stage *st);

#endif
