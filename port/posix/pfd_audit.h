/* SPDX-License-Identifier: MIT */
/*
 * The audit trail: every write that changes how an instance behaves, with
 * who wrote it (address, role), the unit, the register, its old and new
 * value and the result; and every refused write, as a warning that is
 * rate-limited, since a client can provoke it at will. Writes of the
 * process inputs (e, sp, pv and their mirrors) and of tick are not logged:
 * a PLC writes them every cycle, and they change no setting.
 */
#ifndef PFD_AUDIT_H
#define PFD_AUDIT_H

#include "pfd_access.h"
#include "pfd_regmap.h"

/** Settings: one line per register of the live settings (mode,
 *  manual_out, failsafe_out, watchdog_ms, input_sel, param_lock) whose
 *  value differs between @p before and @p after. */
void pfd_audit_settings(const pfd_who *w, int unit, const pfd_hold *before,
                        const pfd_hold *after, const pfd_iparams *committed,
                        const char *result);

/** A commit: one line per staged parameter that differs between the
 *  running set @p old and the committed (or refused) @p new. */
void pfd_audit_params(const pfd_who *w, int unit, const pfd_iparams *old,
                      const pfd_iparams *new_set, const char *result);

/** A command (reset, clear statistics, discard). */
void pfd_audit_command(const pfd_who *w, int unit, unsigned command);

/** A refused write of [addr, addr+count): exception @p exc, because of
 *  @p reason. Rate-limited. */
void pfd_audit_refused(const pfd_who *w, int unit, unsigned addr, unsigned count,
                       int exc, const char *reason);

#endif
