/* SPDX-License-Identifier: MIT */
#include "pfd_plausible.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int stable(const pf_ctrl_design *d, pf_ctrl_check_work *work)
{
    double rho;
    return pf_ctrl_spectral_radius(d, work, &rho) == PF_OK && rho <= 1.0 + PF_CTRL_RHO_TOL;
}

/* Parameter k of a set: the paper's (pf_param_id), or fs as PF_P_FS. */
static double get(const pfd_iparams *ip, int k)
{
    return k == PF_P_FS ? ip->fs : pf_params_get(&ip->p, (pf_param_id)k);
}

static void set(pfd_iparams *ip, int k, double v)
{
    if (k == PF_P_FS)
        ip->fs = v;
    else
        (void)pf_params_set(&ip->p, (pf_param_id)k, v);
}

/* Whether @p ip designs, at its rate, into a stable loop. */
static int designs_stable(const pfd_iparams *ip, pf_ctrl_design *d, pf_ctrl_check_work *work)
{
    pf_design_opts o;
    memset(&o, 0, sizeof o);
    o.fs = ip->fs; /* the other options at the library's defaults, as pfd_slot_build */
    return pf_ctrl_design_make(d, &ip->p, NULL, &o) == PF_OK && stable(d, work);
}

/* The parameter to blame for @p ip's instability, against @p ref. */
static int culprit(const pfd_iparams *ip, const pfd_iparams *ref, pf_ctrl_check_work *work)
{
    pf_ctrl_design *d = malloc(sizeof *d);
    int k, worst = PF_P_COUNT;
    double worst_ratio = 0.0;

    for (k = PF_P_A; k <= PF_P_FS; k++) {
        double a, b, ratio;
        pfd_iparams alt;
        if (k > PF_P_RCI && k != PF_P_FS)
            continue;
        if (k < PF_P_CONFIG && !pf_param_used(ip->p.topology, (pf_param_id)k))
            continue;
        a = get(ip, k);
        b = get(ref, k);
        if (a == b)
            continue;
        alt = *ip;
        set(&alt, k, b);
        if (d != NULL && designs_stable(&alt, d, work)) {
            worst = k;
            break;
        }
        ratio = a > 0.0 && b > 0.0 ? fabs(log(a / b)) : fabs(a - b);
        if (ratio > worst_ratio) {
            worst_ratio = ratio;
            worst = k;
        }
    }
    free(d);
    return worst;
}

int pfd_slot_prepare(pfd_slot *s, const pfd_iparams *ip, const pfd_iparams *ref,
                     pf_ctrl_design *scratch, pf_ctrl_check_work *work, pfd_fail *why)
{
    if (pfd_slot_build(s, ip, scratch, why) != 0)
        return -1;
    /* pfd_slot_build left the design in scratch. */
    if (stable(scratch, work))
        return 0;
    why->st = PFD_E_UNSTABLE;
    why->param = culprit(ip, ref, work);
    return -1;
}

void pfd_plausible_ref(const pfd_iparams *ip, const pfd_iparams *committed,
                       pfd_iparams *ref)
{
    if (committed != NULL && committed->p.topology == ip->p.topology) {
        *ref = *committed;
        return;
    }
    *ref = *ip;
    pf_params_default(&ref->p, ip->p.topology);
}
