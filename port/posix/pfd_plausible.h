/* SPDX-License-Identifier: MIT */
/*
 * Building a parameter set the daemon will run: the daemon's and the
 * library's checks (pfd_slot_build), then plausibility: the set's sampled
 * loop must be stable (pf_ctrl_spectral_radius), since an unstable one
 * drives the output without bound (k1 = k2 = 1e9 took Example 6 to
 * +-1.8e8). Used alike by commits, by the start-up and by --seal-config.
 */
#ifndef PFD_PLAUSIBLE_H
#define PFD_PLAUSIBLE_H

#include "pfd_instance.h"

/** pfd_fail.st of a set whose sampled loop is unstable. */
#define PFD_E_UNSTABLE (-101)

/** Build @p ip into @p s (pfd_slot_build) and check that its loop is
 *  stable, with @p scratch and @p work as scratch. An unstable set fails
 *  with why->st = PFD_E_UNSTABLE and why->param naming the parameter
 *  whose change from @p ref alone made it so (or, if no one change did,
 *  the one changed most, relatively; PF_P_COUNT if none changed).
 *  @return 0, or -1 with @p why set. */
int pfd_slot_prepare(pfd_slot *s, const pfd_iparams *ip, const pfd_iparams *ref,
                     pf_ctrl_design *scratch, pf_ctrl_check_work *work, pfd_fail *why);

/** The reference a set is judged against: @p committed if it has the
 *  same configuration (NULL: none), else the configuration's defaults. */
void pfd_plausible_ref(const pfd_iparams *ip, const pfd_iparams *committed,
                       pfd_iparams *ref);

#endif
