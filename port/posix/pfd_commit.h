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

#include "pfd_config.h"
#include "pfd_regmap.h"
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

/** Under regs_mx: status bits for the status register. */
uint16_t pfd_status_bits(const pfd_daemon *d, const pfd_inst *in,
                         const pfd_snap *s);

/** Commit: the data writes of @p wl, then the staged set that results,
 *  switched in at the next sample; persisted if a config file is in use.
 *  Takes the locks it needs. @return 0 or a MODBUS_EXCEPTION_* code:
 *  ILLEGAL_FUNCTION param_lock set meanwhile; ILLEGAL_DATA_VALUE refused
 *  (commit_result and err_* say why); SLAVE_OR_SERVER_BUSY no free slot;
 *  SLAVE_OR_SERVER_FAILURE another library error. Nothing changes on any
 *  of these, and a set already pending stays pending. Except
 *  SLAVE_OR_SERVER_FAILURE with commit_result PFD_COMMIT_UNSAVED: the set
 *  was applied and runs, but the config file could not be written. */
int pfd_commit(pfd_daemon *d, pfd_inst *in, const pfd_wlist *wl);

/** Write the config file (if any) from the committed and live state.
 *  Takes commit_mx. @return 0, or -1 after logging. */
int pfd_persist(pfd_daemon *d);

/** Samples a new parameter set is pre-run with the held input before the
 *  switch (docs/pneufracd.md, "Bumpless commit"). */
unsigned pfd_settle_samples(double fs);

#endif
