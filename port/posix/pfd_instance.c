/* SPDX-License-Identifier: MIT */
#include "pfd_instance.h"

#include <math.h>
#include <string.h>

#include "pfd_rate.h"

void pfd_iparams_default(pfd_iparams *ip)
{
    memset(ip, 0, sizeof *ip);
    pf_params_default(&ip->p, PF_CFG_DD);
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
    if (!(ip->in_fs >= PFD_FULLSCALE_MIN && ip->in_fs <= PFD_FULLSCALE_MAX))
        return fail(why, PF_E_PARAM(PF_P_IN_FS), PF_P_IN_FS);
    if (!(ip->out_fs >= PFD_FULLSCALE_MIN && ip->out_fs <= PFD_FULLSCALE_MAX))
        return fail(why, PF_E_PARAM(PF_P_OUT_FS), PF_P_OUT_FS);
    if (!(ip->bump_tau >= 0.0 && ip->bump_tau <= PFD_BUMP_TAU_MAX))
        return fail(why, PFD_E_DAEMON, PFD_P_BUMP_TAU);
    if (ip->arith != PFD_ARITH_FLOAT && ip->arith != PFD_ARITH_Q15)
        return fail(why, PFD_E_DAEMON, PFD_P_ARITH);
    if ((unsigned)ip->p.config >= (unsigned)PF_CFG_COUNT)
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

    memset(s, 0, sizeof *s);
    s->ip = *ip;
    s->rate.k = k;
    s->rate.internal_fs = o.fs;
    s->rate.wanted_fs = ip->substeps != 0 ? 0.0 : pfd_rate_wanted_fs(&ip->p);
    if (ip->arith == PFD_ARITH_Q15) {
        st = pf_ctrl_coeffs_q15_make(&s->cq, scratch, ip->in_fs, ip->out_fs);
        if (st == PF_OK)
            st = pf_ctrl_init_q15(&s->q, &s->cq, NULL, 0);
    } else {
        pf_ctrl_coeffs_f32_make(&s->cf, &scratch->rt);
        st = pf_ctrl_init_f32(&s->f, &s->cf, NULL, 0);
    }
    if (st != PF_OK)
        return fail(why, st, pf_status_param(st));

    s->period_ns = pfd_period_ns(ip->fs);
    s->decay = ip->bump_tau > 0.0 ? exp(-1.0 / (ip->fs * ip->bump_tau)) : 0.0;
    s->inv_in_fs = 1.0 / ip->in_fs;
    s->inv_out_fs = 1.0 / ip->out_fs;
    s->inv_pb_fs = s->inv_in_fs / ip->p.k1;
    return 0;
}

uint64_t pfd_period_ns(double fs)
{
    return (uint64_t)llround(1e9 / fs);
}

void pfd_slot_reset(pfd_slot *s)
{
    if (s->ip.arith == PFD_ARITH_Q15)
        pf_ctrl_reset_q15(&s->q);
    else
        pf_ctrl_reset_f32(&s->f);
}

int16_t pfd_to_q15(double v, double inv_fullscale)
{
    double x = v * inv_fullscale * 32768.0;
    double r;

    if (!(x < 32767.0))
        return x != x ? 0 : INT16_MAX;
    if (!(x > -32768.0))
        return INT16_MIN;
    /* Round half up without floor(): the cast truncates toward zero, so
     * step back one for negative non-integers. */
    r = (double)(long)x;
    if (r > x)
        r -= 1.0;
    if (x - r >= 0.5)
        r += 1.0;
    return (int16_t)r;
}

void pfd_slot_step(pfd_slot *s, float e, pfd_sig *out)
{
    if (s->ip.arith == PFD_ARITH_Q15) {
        const double sc_in = s->ip.in_fs / 32768.0;
        int16_t eq = pfd_to_q15((double)e, s->inv_in_fs);
        int16_t pq = pf_ctrl_step_q15(&s->q, eq);
        int16_t xq, pbq, yq, pcq;

        pf_ctrl_monitor_q15(&s->q, &xq, &pbq, &yq, &pcq);
        out->e = e;
        out->pc_q15 = pq;
        out->x_q15 = xq;
        out->pb_q15 = pbq;
        out->y_q15 = yq;
        out->pc = (float)((double)pq * s->ip.out_fs / 32768.0);
        out->x = (float)((double)xq * sc_in);
        out->pb = (float)((double)pbq * sc_in * s->ip.p.k1);
        out->y = (float)((double)yq * sc_in);
    } else {
        float pc = pf_ctrl_step_f32(&s->f, e);
        out->e = e;
        out->pc = pc;
        out->x = s->f.sig.x;
        out->pb = s->f.sig.pb;
        out->y = s->f.sig.y;
        out->pc_q15 = pfd_to_q15((double)pc, s->inv_out_fs);
        out->x_q15 = pfd_to_q15((double)out->x, s->inv_in_fs);
        out->pb_q15 = pfd_to_q15((double)out->pb, s->inv_pb_fs);
        out->y_q15 = pfd_to_q15((double)out->y, s->inv_in_fs);
    }
}

void pfd_slot_hold(pfd_slot *s, float e, uint32_t n)
{
    uint32_t i;

    if (s->ip.arith == PFD_ARITH_Q15) {
        /* Quantised once, as pfd_slot_step() would each time. */
        const int16_t eq = pfd_to_q15((double)e, s->inv_in_fs);
        for (i = 0; i < n; i++)
            (void)pf_ctrl_step_q15(&s->q, eq);
    } else {
        for (i = 0; i < n; i++)
            (void)pf_ctrl_step_f32(&s->f, e);
    }
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
    return arith == PFD_ARITH_Q15 ? "q15" : arith == PFD_ARITH_FLOAT ? "float" : "?";
}

const char *pfd_topology_name(int config)
{
    return pf_config_name((pf_config)config);
}
