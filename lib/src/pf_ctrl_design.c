/* SPDX-License-Identifier: MIT */
/*
 * Controller design in double: validates everything, designs the four
 * operators and precomputes every constant of the per-sample loop solution
 * (see pf_controller.h for the block diagram).
 */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "pneufrac/pf_controller.h"
#include "pf_nozzle_shape.h"

/* Smallest accepted 1 + L0 (see derive_loop). */
#define PF_LOOP_MIN 1e-2
/* Longest dead time in samples (4 Mi samples: 210 s at 20 kHz). */
#define PF_DELAY_MAX 4194304.0

/* An operator of the model: its order and gain come from the parameters
 * named by order_id and gain_id, so a refusal names those, never the
 * internal "alpha" or "gain". */
static pf_status op_make(pf_fracop_design *op, double alpha, double gain,
                         const pf_design_opts *o, pf_param_id order_id,
                         pf_param_id gain_id)
{
    pf_status st = pf_fracop_design_make(op, alpha, gain, o);
    if (st == PF_E_PARAM(PF_P_ALPHA))
        return PF_E_PARAM(order_id);
    if (st == PF_E_PARAM(PF_P_GAIN))
        return PF_E_PARAM(gain_id);
    return st;
}

static pf_status design_ops(pf_ctrl_coeffs_f64 *c, const pf_params *p,
                            const pf_design_opts *o)
{
    pf_status st;
    int pid = p->topology == PF_TOPO_PID;
    double rcv = pid ? p->RCd : p->RC, rcw = pid ? p->RCi : p->RC;

    c->has_q = p->q > 0.0;
    c->has_v = p->topology == PF_TOPO_DD || pid;
    c->has_w = p->topology == PF_TOPO_ID || pid;
    /* Relay in integral form: w = (tau s)^-beta v (pf_controller.h). */
    st = op_make(&c->P, -p->beta, pow(p->tau, -p->beta), o, PF_P_BETA, PF_P_TAU);
    if (st == PF_OK && c->has_q)
        st = op_make(&c->Q, -p->q, p->A / p->ks, o, PF_P_Q, PF_P_KS);
    if (st == PF_OK && c->has_v)
        st = op_make(&c->V, -p->nu, 1.0 / rcv, o, PF_P_NU, pid ? PF_P_RCD : PF_P_RC);
    if (st == PF_OK && c->has_w)
        st = op_make(&c->W, -p->w, 1.0 / rcw, o, PF_P_W, pid ? PF_P_RCI : PF_P_RC);
    return st;
}

/* L0, the in-sample loop gain: x's own contribution to g(x) through the
 * nozzle, relay, feedback and restrictors within one sample. */
static double loop_gain(const pf_ctrl_coeffs_f64 *c)
{
    return c->cy * c->alpha_y * c->k2 * c->alpha_z * c->k1;
}

static pf_status derive_loop(pf_ctrl_coeffs_f64 *c, const pf_params *p)
{
    double DP = c->P.D, alpha_m, loop;
    c->ce = p->b / (p->a + p->b);
    c->cy = p->a / (p->a + p->b);
    c->k1 = p->k1;
    c->k2 = p->k2;
    c->kA = p->A / p->ks;
    c->k2_inv = 1.0 / p->k2;
    c->pmin = p->pmin;
    /* pmin w + pmax v = p_b with w = D_P v + S_P. */
    c->relay_den_inv = 1.0 / (p->pmax + p->pmin * DP);
    c->relay_d0 = 1.0 / p->pmax;
    c->relay_w = 1.0 - p->pmin / p->pmax;
    c->relay_sz = (p->pmax - p->pmin) * c->relay_den_inv;
    c->alpha_z = c->relay_d0 + c->relay_w * DP * c->relay_den_inv;
    /* r = D (p_c - r) + S  =>  r = D/(1+D) p_c + S/(1+D). */
    if (c->has_v) {
        c->v_den_inv = 1.0 / (1.0 + c->V.D);
        c->v_a = c->V.D * c->v_den_inv;
    }
    if (c->has_w) {
        c->w_den_inv = 1.0 / (1.0 + c->W.D);
        c->w_a = c->W.D * c->w_den_inv;
    }
    alpha_m = (c->has_v ? c->v_a : 1.0) - (c->has_w ? c->w_a : 0.0);
    c->alpha_y = (c->has_q ? c->Q.D : c->kA) * alpha_m;
    /* Within a sample the loop equation in x has slope 1 + L0 s, where L0
     * is the in-sample loop gain and s >= 0 the slope of the effects
     * (backlash, nozzle curve, saturation). It is uniquely solvable while
     * 1 + min(0, L0 s) > 0 for every s the effects take; the margin keeps
     * x from amplifying rounding by more than 1/PF_LOOP_MIN. Here s = 1,
     * the linear loop; derive_effects checks the nozzle's steeper curve.
     * L0 < 0 (net positive feedback within the sample) occurs only for
     * pid restrictors at extreme rates or bands. */
    loop = loop_gain(c);
    if (!isfinite(loop))
        return PF_E_PARAM(PF_P_K1);
    if (!(1.0 + loop >= PF_LOOP_MIN))
        return PF_E_PARAM(p->topology == PF_TOPO_PID ? PF_P_RCD : PF_P_RC);
    c->loop_inv = 1.0 / (1.0 + loop);
    c->slope_inv = 1.0 / (1.0 + fmin(0.0, loop));
    return PF_OK;
}

static pf_status derive_effects(pf_ctrl_coeffs_f64 *c, const pf_effects *fx,
                                double fs)
{
    double n, loop;
    c->play_r = 0.5 * fx->backlash;
    c->nozzle_xh = fx->nozzle_xh;
    c->nozzle_xh_inv = fx->nozzle_xh > 0.0 ? 1.0 / fx->nozzle_xh : 0.0;
    if (fx->nozzle_xh > 0.0) {
        pf_nozzle_shape nz;
        pf_nozzle_shape_make(&nz, fx->nozzle_xh, fx->nozzle_bias);
        c->nozzle_u0 = nz.u0;
        c->nozzle_f0 = nz.f0;
        c->nozzle_g = nz.g;
        /* A nozzle biased off its inflection is steeper than the linear
         * loop (s up to nz.steepest > 1): with L0 < 0 that part of the
         * curve would bend g back and the sample's x would not be unique
         * (several roots, the solve's pick among them arbitrary). Refused,
         * as the linear loop is, with the same margin. */
        loop = fmin(0.0, loop_gain(c)) * nz.steepest;
        if (!(1.0 + loop >= PF_LOOP_MIN))
            return PF_E_PARAM(PF_P_NOZZLE_BIAS);
        c->slope_inv = 1.0 / (1.0 + loop);
    }
    c->saturate = (uint8_t)fx->saturate; /* pf_sat_kind, validated */
    c->sat_lo = fx->saturate ? fx->sat_lo : 0.0;
    c->sat_hi = fx->saturate ? fx->sat_hi : 0.0;
    c->in_loop_fx = c->play_r > 0.0 || c->nozzle_xh > 0.0 || c->saturate;
    /* Exact discretisation of 1/(lag s + 1) for an input held over a sample. */
    c->lag_lam = fx->lag > 0.0 ? -expm1(-1.0 / (fs * fx->lag)) : 0.0;
    n = floor(fx->dead_time * fs + 0.5);
    if (n > PF_DELAY_MAX)
        return PF_E_PARAM(PF_P_DEAD_TIME);
    c->delay_len = (uint32_t)n;
    return PF_OK;
}

pf_status pf_ctrl_design_make(pf_ctrl_design *d, const pf_params *p,
                              const pf_effects *fx, const pf_design_opts *opt)
{
    pf_ctrl_design t;
    pf_effects none;
    pf_status st;
    if (d == NULL || p == NULL || opt == NULL)
        return PF_E_NULL;
    memset(&none, 0, sizeof none);
    if (fx == NULL)
        fx = &none;
    memset(&t, 0, sizeof t);
    st = pf_params_validate(p);
    if (st == PF_OK)
        st = pf_effects_validate(fx);
    if (st == PF_OK)
        st = pf_design_opts_resolve(opt, &t.opt);
    if (st == PF_OK)
        st = design_ops(&t.rt, p, &t.opt);
    if (st == PF_OK)
        st = derive_loop(&t.rt, p);
    if (st == PF_OK)
        st = derive_effects(&t.rt, fx, t.opt.fs);
    if (st != PF_OK)
        return st;
    t.rt.hold = t.opt.input == PF_INPUT_HOLD;
    t.p = *p;
    t.fx = *fx;
    *d = t;
    return PF_OK;
}

void pf_ctrl_coeffs_f32_make(pf_ctrl_coeffs_f32 *cf, const pf_ctrl_coeffs_f64 *c)
{
    if (cf == NULL || c == NULL)
        return;
    memset(cf, 0, sizeof *cf);
    cf->has_q = c->has_q;
    cf->has_v = c->has_v;
    cf->has_w = c->has_w;
    cf->in_loop_fx = c->in_loop_fx;
    cf->hold = c->hold;
    pf_fracop_coeffs_f32_make(&cf->P, &c->P);
    pf_fracop_coeffs_f32_make(&cf->Q, &c->Q);
    pf_fracop_coeffs_f32_make(&cf->V, &c->V);
    pf_fracop_coeffs_f32_make(&cf->W, &c->W);
    cf->ce = (float)c->ce;
    cf->cy = (float)c->cy;
    cf->k1 = (float)c->k1;
    cf->k2 = (float)c->k2;
    cf->kA = (float)c->kA;
    cf->k2_inv = (float)c->k2_inv;
    cf->pmin = (float)c->pmin;
    cf->relay_den_inv = (float)c->relay_den_inv;
    cf->relay_d0 = (float)c->relay_d0;
    cf->relay_w = (float)c->relay_w;
    cf->relay_sz = (float)c->relay_sz;
    cf->v_a = (float)c->v_a;
    cf->v_den_inv = (float)c->v_den_inv;
    cf->w_a = (float)c->w_a;
    cf->w_den_inv = (float)c->w_den_inv;
    cf->alpha_z = (float)c->alpha_z;
    cf->alpha_y = (float)c->alpha_y;
    cf->loop_inv = (float)c->loop_inv;
    cf->slope_inv = (float)c->slope_inv;
    cf->play_r = (float)c->play_r;
    cf->nozzle_xh = (float)c->nozzle_xh;
    cf->nozzle_xh_inv = (float)c->nozzle_xh_inv;
    cf->nozzle_u0 = (float)c->nozzle_u0;
    cf->nozzle_f0 = (float)c->nozzle_f0;
    cf->nozzle_g = (float)c->nozzle_g;
    cf->saturate = c->saturate;
    cf->sat_lo = (float)c->sat_lo;
    cf->sat_hi = (float)c->sat_hi;
    cf->lag_lam = (float)c->lag_lam;
    cf->delay_len = c->delay_len;
}
