/* SPDX-License-Identifier: MIT */
/*
 * Float runtime of a reduced-order bank (pf_bank.h): no libm, no division.
 * Each state update is compensated (Kahan): the increment lam (beta u - s)
 * of a slow section is often below half an ulp of s, and would otherwise
 * be lost every sample (a section with lam = 2.5e-9 would never move).
 */
#include <stddef.h>
#include <string.h>

#include "pneufrac/pf_bank.h"

#define PF_BANK_BIG 1e30f

static float clamp(float v)
{
    if (!(v < PF_BANK_BIG))
        return PF_BANK_BIG;
    if (!(v > -PF_BANK_BIG))
        return -PF_BANK_BIG;
    return v;
}

/* s <- s + inc, with the rounding error of the last sum carried over */
static inline void add(pf_bank_state_f32 *st, float inc)
{
    float s = st->s, i = inc - st->comp, t = s + i;
    st->comp = (t - s) - i;
    st->s = t;
}

static float output(pf_bank_f32 *S, float y)
{
    const pf_bank_coeffs_f32 *c = S->c;
    if (c->delay_len > 0) {
        float d = S->dbuf[S->didx];
        S->dbuf[S->didx] = y;
        if (++S->didx >= c->delay_len)
            S->didx = 0;
        y = d;
    }
    return y;
}

float pf_bank_step_f32(pf_bank_f32 *S, float u)
{
    const pf_bank_coeffs_f32 *c = S->c;
    const pf_bank_sec_f32 *k = c->sec, *end = k + c->n_sec;
    const pf_bank_pair_f32 *pr = c->pair, *pend = pr + c->n_pair;
    pf_bank_state_f32 *s = S->s;
    float y;

    /* A NaN input (a failed sensor) counts as zero error. With |u| <=
     * 1e30 every state stays within 1e30 (pf_bank.h). */
    u = u == u ? clamp(u) : 0.0f;
    y = c->d * u;
    for (; k < end; k++, s++) {
        float sk = s->s;
        y += k->c * sk;
        add(s, k->lam * (k->beta * u - sk));
    }
    for (; pr < pend; pr++, s += 2) {
        float s1 = s[0].s, s2 = s[1].s;
        float d1 = pr->beta1 * u - s1, d2 = pr->beta2 * u - s2;
        y += pr->c * s1;
        add(&s[0], pr->alpha * d1 + pr->omega * d2);
        add(&s[1], pr->alpha * d2 - pr->omega * d1);
    }
    return output(S, clamp(y));
}

void pf_bank_run_f32(pf_bank_f32 *S, const float *u, float *y, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++)
        y[i] = pf_bank_step_f32(S, u[i]);
}

void pf_bank_reset_f32(pf_bank_f32 *S)
{
    if (S == NULL || S->c == NULL)
        return;
    memset(S->s, 0, sizeof S->s);
    S->didx = 0;
    if (S->dbuf != NULL)
        memset(S->dbuf, 0, sizeof(float) * S->c->delay_len);
}

pf_status pf_bank_init_f32(pf_bank_f32 *S, const pf_bank_coeffs_f32 *c, float *dbuf,
                           size_t dlen)
{
    if (S == NULL || c == NULL)
        return PF_E_NULL;
    if (c->n_sec + 2 * c->n_pair > PF_BANK_MAX_ORDER)
        return PF_E_SCALE;
    if (c->delay_len > 0 && (dbuf == NULL || dlen < c->delay_len))
        return PF_E_BUFFER;
    S->c = c;
    S->dbuf = c->delay_len > 0 ? dbuf : NULL;
    pf_bank_reset_f32(S);
    return PF_OK;
}
