/* SPDX-License-Identifier: MIT */
/*
 * Building a parameter set the daemon will run: the daemon's and the
 * library's checks (pfd_slot_build), then plausibility, because every
 * range check can pass while the set as a whole is absurd:
 *  - its sampled loop must be stable (pf_ctrl_spectral_radius), since an
 *    unstable one drives the output without bound (k1 = k2 = 1e9 took
 *    Example 6 at one step per exchange to +-1.8e8);
 *  - with substeps chosen by the rule (substeps = 0), the rule must reach
 *    its rate within the limits (pfd_rate_capped): a loop faster than
 *    200 kHz can resolve is not emulated, whatever its stability says
 *    (k1 = k2 = 1e9 is stable at the 200 kHz cap, and rings at +-1.7e11
 *    for a unit step). A client that gives substeps chooses the rate
 *    itself, and stability at that rate is what is checked.
 * Used alike by commits, by the start-up and by --seal-config;
 * docs/pneufracd.md, "Plausibility".
 */
#ifndef PFD_PLAUSIBLE_H
#define PFD_PLAUSIBLE_H

#include "pfd_instance.h"

/** pfd_fail.st of a set whose sampled loop is unstable. */
#define PFD_E_UNSTABLE (-101)
/** pfd_fail.st of a set for which the substep rule needs an internal rate
 *  beyond the limits (PFD_SUBSTEPS_MAX, PFD_INTERNAL_FS_MAX). */
#define PFD_E_RATE (-102)

/** Build @p ip into @p s (pfd_slot_build) and check that it is plausible,
 *  with @p scratch and @p work as scratch. A set that is not fails with
 *  why->st = PFD_E_UNSTABLE or PFD_E_RATE and why->param naming the
 *  parameter whose change from @p ref alone made it so (or, if no one
 *  change did, the one changed most, relatively; PF_P_COUNT if none
 *  changed). @return 0, or -1 with @p why set. */
int pfd_slot_prepare(pfd_slot *s, const pfd_iparams *ip, const pfd_iparams *ref,
                     pf_ctrl_design *scratch, pf_ctrl_check_work *work, pfd_fail *why);

/** The reference a set is judged against: @p committed if it has the
 *  same configuration (NULL: none), else the configuration's defaults. */
void pfd_plausible_ref(const pfd_iparams *ip, const pfd_iparams *committed,
                       pfd_iparams *ref);

#endif
