/* SPDX-License-Identifier: MIT */
/* Quantisation of designs into Q15 coefficient sets (design side, double). */
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "pf_design_internal.h"

#define PF_PI 3.14159265358979323846

/* v = m 2^-sh with |m| in [2^(bits-1), 2^bits): as many significant bits
 * as the mantissa holds, whatever the magnitude of v. */
static pf_status qc_norm(int32_t *m, uint8_t *sh, double v, int bits)
{
    int e, s;
    double r;
    if (!isfinite(v))
        return PF_E_SCALE;
    if (v == 0.0) {
        *m = 0;
        *sh = 0;
        return PF_OK;
    }
    (void)frexp(v, &e);        /* v = f 2^e, 0.5 <= |f| < 1 */
    s = bits - e;
    if (s < 0)
        return PF_E_SCALE;
    if (s > 62) {              /* a value this small keeps fewer bits */
        *m = (int32_t)llround(ldexp(v, 62));
        *sh = 62;
        return PF_OK;
    }
    r = (double)llround(ldexp(v, s));
    if (fabs(r) >= ldexp(1.0, bits)) { /* rounding carried into a new bit */
        if (s == 0)
            return PF_E_SCALE;
        s--;
        r = (double)llround(ldexp(v, s));
    }
    *m = (int32_t)r;
    *sh = (uint8_t)s;
    return PF_OK;
}

/* Below 2^28, so that a term c x (|x| < 2^31) stays below 2^59 and a node's
 * sum of up to eight terms cannot wrap (pf_mulw). */
pf_status pf_qc_make(pf_qc *q, double v)
{
    if (fabs(v) >= 268435456.0)
        return PF_E_SCALE;
    return qc_norm(&q->m, &q->sh, v, 31);
}

/* The state-gain format of pf_q_advance: |v| < 2 with shift >= 30, so the
 * increment is one arithmetic right shift. Below 1 the mantissa keeps 30
 * significant bits however small v is; in [1, 2) it takes 31 bits at
 * shift 30. */
static pf_status qc_gain(int32_t *m, uint8_t *sh, double v)
{
    pf_status st = qc_norm(m, sh, v, 30);
    if (st == PF_OK && *sh < 30) {
        double r = llround(ldexp(v, 30));
        if (!(fabs(r) < 2147483648.0))
            return PF_E_SCALE;
        *m = (int32_t)r;
        *sh = 30;
    }
    return st;
}

pf_status pf_qc_leak(int32_t *m, uint8_t *sh, double lam)
{
    pf_status st = qc_gain(m, sh, lam);
    /* A leak must stay a leak: a rounded-away pole would be an integrator. */
    if (st == PF_OK && *m <= 0)
        return PF_E_SCALE;
    return st;
}

pf_status pf_qc_leak_signed(pf_qc *q, double v)
{
    return qc_gain(&q->m, &q->sh, v);
}

double pf_grid_omega(const pf_fracop_design *op, double wb, int i)
{
    double lo = wb / 100.0, hi = 0.999 * PF_PI * op->fs;
    return lo * pow(hi / lo, (double)i / (PF_GRID - 1));
}

/* A section's leak in the kernel's format (pf_q15_ops.h): lam = m 2^-sh
 * with a 15-bit mantissa m in [2^14, 2^15) and sh in [14, 44], which
 * holds every leak the design allows (lam >= 1e-9). */
static pf_status q15_leak(int16_t *m, uint8_t *sh, double lam)
{
    int e, s;
    double r;
    if (!(lam > 0.0 && lam < 2.0))
        return PF_E_SCALE;
    (void)frexp(lam, &e); /* lam in [2^(e-1), 2^e) */
    s = 15 - e;
    r = round(ldexp(lam, s));
    if (r >= 32768.0) {   /* rounding carried into bit 15 */
        s--;
        r = round(ldexp(lam, s));
    }
    if (s < 14 || s > 44)
        return PF_E_SCALE;
    *m = (int16_t)r;
    *sh = (uint8_t)s;
    return PF_OK;
}

pf_status pf_q15_op_make(pf_fracop_coeffs_q15 *cq, const pf_fracop_design *op,
                         double s_in, double s_frac, double s_out)
{
    pf_status st;
    int k, j, n = abs(op->n_int), order[PF_MAX_SEC];
    double prev = s_frac;
    memset(cq, 0, sizeof *cq);
    if (op->n_sec > PF_Q15_MAX_SEC)
        return PF_E_UNSUPPORTED; /* the refined approximant's extra sections */
    cq->n_int = (int8_t)op->n_int;
    cq->int_rho = (int8_t)op->int_rho;
    cq->n_sec = (uint8_t)op->n_sec;
    cq->hold = (uint8_t)op->hold;
    if (n == 0)
        s_frac = s_out;
    st = pf_qc_make(&cq->d, op->d * s_frac / s_in);
    /* Slowest first (insertion sort: at most PF_MAX_SEC), so that the
     * kernel runs the sections with a fraction word in one loop. */
    for (k = 0; k < op->n_sec; k++) {
        for (j = k; j > 0 && op->lam[order[j - 1]] > op->lam[k]; j--)
            order[j] = order[j - 1];
        order[j] = k;
    }
    for (k = 0; st == PF_OK && k < op->n_sec; k++) {
        st = q15_leak(&cq->lam_m[k], &cq->lam_sh[k], op->lam[order[k]]);
        if (st == PF_OK && cq->lam_sh[k] >= 18)
            cq->n_slow = (uint8_t)(k + 1);
    }
    if (st == PF_OK && op->n_sec > 0) {
        /* One shift for all branches, the largest |G_m| in [2^25, 2^26):
         * 19 products of 2^57 sum below 2^62. */
        double gmax = 0.0;
        int e, sh;
        for (k = 0; k < op->n_sec; k++)
            gmax = fmax(gmax, fabs(op->G[k]));
        (void)frexp(gmax * s_frac / s_in, &e);
        sh = 26 - e;
        if (sh < 0 || sh > 62)
            return PF_E_SCALE;
        cq->G_sh = (uint8_t)sh;
        for (k = 0; k < op->n_sec; k++)
            cq->G_m[k] = (int32_t)llround(ldexp(op->G[order[k]] * s_frac / s_in, sh));
    }
    for (k = 0; st == PF_OK && k < n; k++) {
        /* Integer stages: the last ends in s_out; an intermediate one
         * (|n| = 2) sits at the geometric mean of its neighbours. */
        double s_k = k == n - 1 ? s_out : sqrt(prev * s_out);
        st = pf_qc_make(&cq->int_d[k], op->int_d * s_k / prev);
        /* the state gain uses the leak format: |k| < 2 (pf_q_advance) */
        if (st == PF_OK)
            st = pf_qc_leak_signed(&cq->int_k[k], op->int_k * s_k / prev);
        prev = s_k;
    }
    return st;
}

pf_status pf_fracop_coeffs_q15_make(pf_fracop_coeffs_q15 *cq,
                                    const pf_fracop_design *op, double in_fs,
                                    double out_fs)
{
    double s_in, s_frac, s_out, peak, lam = 1.0;
    pf_status st;
    int i;
    if (cq == NULL || op == NULL)
        return PF_E_NULL;
    st = pf_q15_scales_check(in_fs, out_fs);
    if (st != PF_OK)
        return st;
    /* The fractional part's peak gain: at DC (|d + sum G|) for an integrating
     * s^f, near Nyquist for a differentiating one, in between for neither;
     * the grid starts below the slowest pole, p = c lam/(2 - lam). */
    peak = fabs(op->d);
    for (i = 0; i < op->n_sec; i++)
        peak += op->G[i];
    peak = fabs(peak);
    for (i = 0; i < op->n_sec; i++)
        lam = fmin(lam, op->lam[i]);
    for (i = 0; i < PF_GRID; i++) {
        double complex f;
        (void)pf_op_resp(op, pf_grid_omega(op, op->c * lam / (2.0 - lam), i), &f);
        if (cabs(f) > peak)
            peak = cabs(f);
    }
    s_in = PF_Q_TARGET / in_fs;
    s_frac = PF_Q_TARGET / (peak * in_fs);
    s_out = PF_Q_TARGET / out_fs;
    st = pf_q15_op_make(cq, op, s_in, s_frac, s_out);
    if (st == PF_OK)
        st = pf_qc_make(&cq->in_q, s_in * in_fs / 32768.0 * (op->hold ? 0.5 : 1.0));
    if (st == PF_OK)
        st = pf_qc_make(&cq->out_q, 32768.0 / (out_fs * s_out));
    return st;
}
