/* SPDX-License-Identifier: MIT */
#include "pfd_instance.h"

#include <math.h>
#include <string.h>

#include "pfd_rate.h"

void pfd_iparams_default(pfd_iparams *ip)
{
    memset(ip, 0, sizeof *ip);
    pf_params_default(&ip->p, PF_TOPO_DD);
    ip->arith = PFD_ARITH_FLOAT;
    ip->fs = 1000.0;
    ip->substeps = 0;
    ip->in_fs = 1.0;
    /* Example 6's unit-step response peaks near 0.009. */
    ip->out_fs = 0.01;
    ip->bump_tau = 1.0;
}

static int fail(pfd_fail *why, pf_status st, int id)
{
    why->st = st;
    why->param = id;
    return -1;
}

int pfd_slot_build(pfd_slot *s, const pfd_iparams *ip, pf_ctrl_design *scratch,
                   pfd_fail *why)
{
    pf_design_opts o;
    pf_status st;
    unsigned k;

    /* The daemon's own limits, before the library's. */
    if (!(ip->fs >= PFD_FS_MIN && ip->fs <= PFD_FS_MAX))
        return fail(why, PF_E_PARAM(PF_P_FS), PF_P_FS);
    /* The full scales matter in float too (the int16 mirrors). */
    if (pf_param_check(PF_P_IN_FS, ip->in_fs) != PF_OK)
        return fail(why, PF_E_PARAM(PF_P_IN_FS), PF_P_IN_FS);
    if (pf_param_check(PF_P_OUT_FS, ip->out_fs) != PF_OK)
        return fail(why, PF_E_PARAM(PF_P_OUT_FS), PF_P_OUT_FS);
    if (!(ip->bump_tau >= 0.0 && ip->bump_tau <= PFD_BUMP_TAU_MAX))
        return fail(why, PFD_E_DAEMON, PFD_P_BUMP_TAU);
    if (ip->arith != PFD_ARITH_FLOAT && ip->arith != PFD_ARITH_Q15)
        return fail(why, PFD_E_DAEMON, PFD_P_ARITH);
    if (pf_param_check(PF_P_CONFIG, (double)ip->p.topology) != PF_OK)
        return fail(why, PF_E_PARAM(PF_P_CONFIG), PF_P_CONFIG);
    /* The rule reads the parameters: only valid ones. */
    st = pf_params_validate(&ip->p);
    if (st != PF_OK)
        return fail(why, st, pf_status_param(st));
    k = ip->substeps != 0 ? ip->substeps : pfd_rate_substeps(&ip->p, ip->fs);
    if (k > PFD_SUBSTEPS_MAX || (double)k * ip->fs > PFD_INTERNAL_FS_MAX * (1.0 + 1e-12))
        return fail(why, PFD_E_DAEMON, PFD_P_SUBSTEPS);

    /* Zero fields ask the library for the same defaults as
     * `pneufrac simulate --fs <internal rate>`, so both run the identical
     * design. */
    memset(&o, 0, sizeof o);
    o.fs = ip->fs * (double)k;
    st = pf_ctrl_design_make(scratch, &ip->p, NULL, &o);
    if (st != PF_OK)
        return fail(why, st, pf_status_param(st));

    /* The float runtime copies its coefficients into the slot, so the
     * scratch design may be reused once this returns. */
    memset(s, 0, sizeof *s);
    s->ip = *ip;
    s->rate.k = k;
    s->rate.internal_fs = o.fs;
    s->rate.wanted_fs = ip->substeps != 0 ? 0.0 : pfd_rate_wanted_fs(&ip->p);
    st = pf_runtime_init(&s->rt, scratch, pfd_arith_lib(ip->arith), ip->in_fs,
                         ip->out_fs, NULL, 0);
    if (st != PF_OK)
        return fail(why, st, pf_status_param(st));

    s->period_ns = pfd_period_ns(ip->fs);
    s->decay = ip->bump_tau > 0.0 ? exp(-1.0 / (ip->fs * ip->bump_tau)) : 0.0;
    return 0;
}

uint64_t pfd_period_ns(double fs)
{
    return (uint64_t)llround(1e9 / fs);
}

void pfd_slot_reset(pfd_slot *s)
{
    pf_runtime_reset(&s->rt);
}

pf_arith pfd_arith_lib(int arith)
{
    return arith == PFD_ARITH_Q15 ? PF_ARITH_Q15 : PF_ARITH_F32;
}

void pfd_slot_step(pfd_slot *s, float e, pfd_sig *out)
{
    pf_runtime_signals sig;

    out->e = e;
    out->pc = (float)pf_runtime_step(&s->rt, (double)e);
    pf_runtime_signals_get(&s->rt, &sig);
    out->x = (float)sig.x;
    out->pb = (float)sig.pb;
    out->y = (float)sig.y;
    out->pc_q15 = sig.pc_q15;
    out->x_q15 = sig.x_q15;
    out->pb_q15 = sig.pb_q15;
    out->y_q15 = sig.y_q15;
}

void pfd_slot_hold(pfd_slot *s, float e, uint32_t n)
{
    uint32_t i;

    /* The step of pfd_slot_step() and of `pneufrac simulate`, without the
     * signals nobody reads. */
    for (i = 0; i < n; i++)
        (void)pf_runtime_step(&s->rt, (double)e);
}

const char *pfd_param_name(int id)
{
    if (id == PFD_P_BUMP_TAU)
        return "bump_tau";
    if (id == PFD_P_ARITH)
        return "arith";
    if (id == PFD_P_SUBSTEPS)
        return "substeps";
    return pf_param_name((pf_param_id)id);
}

const char *pfd_arith_name(int arith)
{
    if (arith != PFD_ARITH_FLOAT && arith != PFD_ARITH_Q15)
        return "?";
    return pf_arith_name(pfd_arith_lib(arith));
}

const char *pfd_topology_name(int config)
{
    return pf_topology_name((pf_topology)config);
}
