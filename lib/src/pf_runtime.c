/* SPDX-License-Identifier: MIT */
/* A runtime of any arithmetic behind one interface (pf_runtime.h): the one
 * f64/f32/q15 dispatch of the CLI, the daemon and the accuracy runner. */
#include "pneufrac/pf_runtime.h"

#include <string.h>

#include "pneufrac/pf_q15.h"
#include "pf_names.h"

static const char *const arith_names[PF_ARITH_COUNT] = {"double", "float",
                                                         "q15"};

const char *pf_arith_name(pf_arith arith)
{
    return pf_name_of(arith_names, PF_ARITH_COUNT, (int)arith);
}

pf_arith pf_arith_lookup(const char *name)
{
    return (pf_arith)pf_name_find(arith_names, PF_ARITH_COUNT, name);
}

size_t pf_arith_sample_size(pf_arith arith)
{
    switch (arith) {
    case PF_ARITH_F64: return sizeof(double);
    case PF_ARITH_F32: return sizeof(float);
    case PF_ARITH_Q15: return sizeof(int16_t);
    default: return 0;
    }
}

pf_status pf_runtime_init(pf_runtime *S, const pf_ctrl_design *d,
                          pf_arith arith, double in_fs, double out_fs,
                          void *dbuf, size_t dlen)
{
    pf_status st;
    if (S == NULL || d == NULL)
        return PF_E_NULL;
    memset(S, 0, sizeof *S);
    S->arith = arith;
    S->in_fs = in_fs;
    S->out_fs = out_fs;
    S->pb_fs = d->p.k1 * in_fs;
    switch (arith) {
    case PF_ARITH_F64:
        return pf_ctrl_init_f64(&S->u.f64, &d->rt, dbuf, dlen);
    case PF_ARITH_F32:
        pf_ctrl_coeffs_f32_make(&S->u.f32.c, &d->rt);
        return pf_ctrl_init_f32(&S->u.f32.S, &S->u.f32.c, dbuf, dlen);
    case PF_ARITH_Q15:
        st = pf_ctrl_coeffs_q15_make_nz(&S->u.q15.c, &S->u.q15.nz, d, in_fs, out_fs);
        if (st != PF_OK)
            return st;
        return pf_ctrl_init_q15(&S->u.q15.S, &S->u.q15.c, dbuf, dlen);
    default:
        return PF_E_UNSUPPORTED;
    }
}

void pf_runtime_reset(pf_runtime *S)
{
    if (S == NULL)
        return;
    S->out_q15 = 0;
    switch (S->arith) {
    case PF_ARITH_F64: pf_ctrl_reset_f64(&S->u.f64); break;
    case PF_ARITH_F32: pf_ctrl_reset_f32(&S->u.f32.S); break;
    case PF_ARITH_Q15: pf_ctrl_reset_q15(&S->u.q15.S); break;
    default: break;
    }
}

double pf_runtime_step(pf_runtime *S, double e)
{
    switch (S->arith) {
    case PF_ARITH_F64:
        return pf_ctrl_step_f64(&S->u.f64, e);
    case PF_ARITH_F32:
        return (double)pf_ctrl_step_f32(&S->u.f32.S, (float)e);
    case PF_ARITH_Q15:
        S->out_q15 = pf_ctrl_step_q15(&S->u.q15.S, pf_q15_quantize(e, S->in_fs));
        return pf_q15_value(S->out_q15, S->out_fs);
    default:
        return 0.0;
    }
}

void pf_runtime_run(pf_runtime *S, const double *e, double *pc, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++)
        pc[i] = pf_runtime_step(S, e[i]);
}

/* Double and float: the physical signals, quantised for the Q15 views. */
static void float_signals(pf_runtime_signals *sig, const pf_runtime *S,
                          double x, double pb, double y, double pc)
{
    sig->x = x;
    sig->pb = pb;
    sig->y = y;
    sig->pc = pc;
    sig->x_q15 = pf_q15_quantize(x, S->in_fs);
    sig->pb_q15 = pf_q15_quantize(pb, S->pb_fs);
    sig->y_q15 = pf_q15_quantize(y, S->in_fs);
    sig->pc_q15 = pf_q15_quantize(pc, S->out_fs);
}

void pf_runtime_signals_get(const pf_runtime *S, pf_runtime_signals *sig)
{
    const pf_ctrl_signals_f64 *s64;
    const pf_ctrl_signals_f32 *s32;
    memset(sig, 0, sizeof *sig);
    switch (S->arith) {
    case PF_ARITH_F64:
        s64 = &S->u.f64.sig;
        float_signals(sig, S, s64->x, s64->pb, s64->y, s64->out);
        break;
    case PF_ARITH_F32:
        s32 = &S->u.f32.S.sig;
        float_signals(sig, S, s32->x, s32->pb, s32->y, s32->out);
        break;
    case PF_ARITH_Q15:
        /* The output is the line's end (after lag and dead time), as in
         * double and float, not p_c's monitor (before the line). */
        pf_ctrl_monitor_q15(&S->u.q15.S, &sig->x_q15, &sig->pb_q15,
                            &sig->y_q15, NULL);
        sig->pc_q15 = S->out_q15;
        sig->x = pf_q15_value(sig->x_q15, S->in_fs);
        sig->pb = pf_q15_value(sig->pb_q15, S->pb_fs);
        sig->y = pf_q15_value(sig->y_q15, S->in_fs);
        sig->pc = pf_q15_value(sig->pc_q15, S->out_fs);
        break;
    default:
        break;
    }
}
