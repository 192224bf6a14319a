/* SPDX-License-Identifier: MIT */
/*
 * The Modbus side of the instances: creating them, handing live inputs to
 * the loop, committing a staged parameter set (designed into a free slot
 * outside every lock the loop or the readers need, then handed over), and
 * persisting the committed state.
 */
#ifndef PFD_COMMIT_H
#define PFD_COMMIT_H

#include <stddef.h>

#include "pfd_access.h"
#include "pfd_config.h"
#include "pfd_rate.h"
#include "pfd_regmap.h"
#include "pfd_stage.h"
#include "pfd_state.h"

/** Initialise locks and the design scratch. @return 0 or -1. */
int pfd_daemon_init(pfd_daemon *d, const pfd_settings *set);

/** Add an instance (allocates its slots, builds the first at rest).
 *  @return 0, or -1 with @p why set (-1 with why->st == PF_E_NULL: out of
 *  memory). */
int pfd_inst_add(pfd_daemon *d, const pfd_config_inst *ci, pfd_fail *why);

void pfd_daemon_free(pfd_daemon *d);

/** Under regs_mx: give the loop the current live registers. */
void pfd_publish_live(pfd_inst *in);

/** Under regs_mx: the live settings and the lock that @p wl writes (not
 *  its staged parameters, not its actions), logged for the audit, and
 *  handed to the loop. Writing param_lock 1 makes @p w its holder. */
void pfd_apply_settings(pfd_inst *in, const pfd_who *w, const pfd_wlist *wl);

/** Under regs_mx: release the lock @p w holds, logged with @p why. */
void pfd_release_lock(pfd_inst *in, const pfd_who *w, const char *why);

/** Under regs_mx: status bits for the status register, as a client
 *  whose staged set is @p staged sees them. */
uint16_t pfd_status_bits(const pfd_daemon *d, const pfd_inst *in,
                         const pfd_snap *s, const pfd_iparams *staged);

/** Client @p w's commit: the committed set with its staged writes @p st
 *  (NULL: none) and the staged writes of @p wl on top, switched in at the
 *  next sample, with the live writes of @p wl; persisted if a config file
 *  is in use. Takes the locks it needs. @return 0 or a MODBUS_EXCEPTION_*
 *  code: ILLEGAL_FUNCTION another client took param_lock meanwhile;
 *  ILLEGAL_DATA_VALUE refused (commit_result and err_* say why: an invalid
 *  parameter, an unstable loop, or a set the loop could not sustain within
 *  loop_budget); SLAVE_OR_SERVER_BUSY no free slot;
 *  SLAVE_OR_SERVER_FAILURE another library error. Nothing changes on any
 *  of these, and a set already pending stays pending. Except
 *  SLAVE_OR_SERVER_FAILURE with commit_result PFD_COMMIT_UNSAVED: the set
 *  was applied and runs, but the config file could not be written. */
int pfd_commit(pfd_daemon *d, pfd_inst *in, const pfd_who *w, const pfd_stage *st,
               const pfd_wlist *wl);

/** Write the config file (if any) from the committed and live state.
 *  Takes commit_mx. @return 0, or -1 after logging. */
int pfd_persist(pfd_daemon *d);

/** Steps a new parameter set is pre-run with the held input before the
 *  switch, at its internal rate (docs/pneufracd.md, "Bumpless commit"). */
unsigned pfd_settle_samples(double internal_fs);

/** The loop's load (pfd_load_total() of @p out is a fraction of one
 *  core) with every instance's committed set, except that @p in (if not
 *  NULL) runs at @p fs with @p r. Under commit_mx, or before the threads
 *  start. */
void pfd_loop_load(const pfd_daemon *d, const pfd_inst *in, double fs, const pfd_rate *r,
                   pfd_load *out);

#endif
