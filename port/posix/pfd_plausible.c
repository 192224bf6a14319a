/* SPDX-License-Identifier: MIT */
#include "pfd_plausible.h"

#include <math.h>
#include <stdlib.h>

#include "pfd_rate.h"

static int stable(const pf_ctrl_design *d, pf_ctrl_check_work *work)
{
    double rho;
    return pf_ctrl_spectral_radius(d, work, &rho) == PF_OK && rho <= 1.0 + PF_CTRL_RHO_TOL;
}

/* Parameter k of a set: the paper's (pf_param_id), fs as PF_P_FS, or
 * substeps as PFD_P_SUBSTEPS. */
static double get(const pfd_iparams *ip, int k)
{
    if (k == PF_P_FS)
        return ip->fs;
    if (k == PFD_P_SUBSTEPS)
        return (double)ip->substeps;
    return pf_params_get(&ip->p, (pf_param_id)k);
}

static void set(pfd_iparams *ip, int k, double v)
{
    if (k == PF_P_FS)
        ip->fs = v;
    else if (k == PFD_P_SUBSTEPS)
        ip->substeps = (unsigned)v;
    else
        (void)pf_params_set(&ip->p, (pf_param_id)k, v);
}

/* Why a built set (@p s, designed in @p d) is not plausible: 0 if it is,
 * else PFD_E_UNSTABLE or PFD_E_RATE. */
static pf_status implausible(const pfd_slot *s, const pf_ctrl_design *d,
                             pf_ctrl_check_work *work)
{
    if (!stable(d, work))
        return PFD_E_UNSTABLE;
    return pfd_rate_capped(&s->rate) ? PFD_E_RATE : 0;
}

/* Whether @p ip builds as a commit would build it (the same limits, the
 * same substeps, designed at the same internal rate fs x substeps) into a
 * plausible set. */
static int builds_plausible(const pfd_iparams *ip, pfd_slot *s, pf_ctrl_design *d,
                            pf_ctrl_check_work *work)
{
    pfd_fail why;
    return pfd_slot_build(s, ip, d, &why) == 0 && implausible(s, d, work) == 0;
}

/* The parameter to blame for @p ip's implausibility, against @p ref: the
 * paper's parameters the configuration uses, then fs and substeps, which
 * together set the rate the loop is sampled at. */
static int culprit(const pfd_iparams *ip, const pfd_iparams *ref, pf_ctrl_check_work *work)
{
    pf_ctrl_design *d = malloc(sizeof *d);
    pfd_slot *s = malloc(sizeof *s);
    int k, worst = PF_P_COUNT;
    double worst_ratio = 0.0;

    for (k = PF_P_A; k <= PFD_P_SUBSTEPS; k++) {
        double a, b, ratio;
        pfd_iparams alt;
        if (k > PF_P_RCI && k != PF_P_FS && k != PFD_P_SUBSTEPS)
            continue;
        if (k < PF_P_CONFIG && !pf_param_used(ip->p.topology, (pf_param_id)k))
            continue;
        a = get(ip, k);
        b = get(ref, k);
        if (a == b)
            continue;
        alt = *ip;
        set(&alt, k, b);
        if (d != NULL && s != NULL && builds_plausible(&alt, s, d, work)) {
            worst = k;
            break;
        }
        ratio = a > 0.0 && b > 0.0 ? fabs(log(a / b)) : fabs(a - b);
        if (ratio > worst_ratio) {
            worst_ratio = ratio;
            worst = k;
        }
    }
    free(s);
    free(d);
    return worst;
}

int pfd_slot_prepare(pfd_slot *s, const pfd_iparams *ip, const pfd_iparams *ref,
                     pf_ctrl_design *scratch, pf_ctrl_check_work *work, pfd_fail *why)
{
    pf_status st;

    if (pfd_slot_build(s, ip, scratch, why) != 0)
        return -1;
    /* pfd_slot_build left the design in scratch. */
    st = implausible(s, scratch, work);
    if (st == 0)
        return 0;
    why->st = st;
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
