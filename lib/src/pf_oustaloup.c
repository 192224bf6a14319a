/* SPDX-License-Identifier: MIT */
/*
 * Design options and the continuous-time rational approximants of s^alpha.
 *
 * References (formulas only):
 *  - A. Oustaloup, F. Levron, B. Mathieu, F. Nanot, "Frequency-band complex
 *    noninteger differentiator: characterization and synthesis", IEEE TCAS-I
 *    47(1), 2000: zeros w'_k = wb (wh/wb)^((k+N+(1-r)/2)/(2N+1)), poles with
 *    (1+r)/2, gain wh^r, k = -N..N.
 *  - D. Xue, C. Zhao, Y.Q. Chen, "A modified approximation method of
 *    fractional order system", Proc. IEEE ICMA 2006: s^r ~ K
 *    (d s^2 + b wh s)/(d(1-r) s^2 + b wh s + d r) prod (s+w'_k)/(s+w_k), with
 *    the product spread over [d wb/b, b wh/d], b = 10, d = 9, 0 < r < 1.
 */
#include <math.h>
#include <stddef.h>

#include "pf_design_internal.h"

#define PF_PI 3.14159265358979323846
#define REF_B 10.0
#define PF_REFINED_MARGIN 1e-3
#define REF_D 9.0

void pf_design_opts_default(pf_design_opts *o, double fs)
{
    if (o == NULL)
        return;
    o->fs = fs;
    o->wb = 0.0;
    o->wh = 0.0;
    o->order = 0;
    o->approx = PF_APPROX_OUSTALOUP;
    o->prewarp = 0.0;
    o->t_slow = 0.0;
    o->input = PF_INPUT_HOLD;
}

pf_status pf_design_opts_resolve(const pf_design_opts *in, pf_design_opts *out)
{
    pf_design_opts o;
    double nyq;
    if (in == NULL || out == NULL)
        return PF_E_NULL;
    o = *in;
    PF_RETURN_IF_OUT(PF_P_FS, o.fs);
    nyq = PF_PI * o.fs;
    PF_RETURN_IF_OUT(PF_P_TSLOW, o.t_slow);
    if (o.t_slow == 0.0)
        o.t_slow = PF_DEFAULT_TSLOW;
    /* Default band: up to the Nyquist frequency (analog; Tustin compresses it to 0.64 of
     * Nyquist, so the approximant stays fractional across the usable band). */
    PF_RETURN_IF_OUT(PF_P_WB, o.wb);
    PF_RETURN_IF_OUT(PF_P_WH, o.wh);
    /* Two decades below 1/t_slow: the approximant's flattening at wb then
     * costs under 0.1 % at t = t_slow/5 even for |f| = 1/2 (measured in
     * docs/accuracy.md); kept above the lowest band the runtime resolves. */
    if (o.wb == 0.0)
        o.wb = fmax(0.01 / o.t_slow, 2.0 * PF_WB_MIN_PER_FS * o.fs);
    if (o.wh == 0.0)
        o.wh = nyq;
    if (o.wh > nyq * (1.0 + 1e-12))
        return PF_E_PARAM(PF_P_WH);
    if (o.wb / o.fs < PF_WB_MIN_PER_FS)
        return PF_E_PARAM(PF_P_WB);
    if (!(o.wb < o.wh))
        return PF_E_PARAM(PF_P_WB);
    PF_RETURN_IF_OUT(PF_P_INPUT, (double)o.input);
    PF_RETURN_IF_OUT(PF_P_APPROX, (double)o.approx);
    if (o.order == 0) {
        /* Two zero/pole pairs per decade keep Oustaloup's phase ripple
         * small; measured in docs/accuracy.md. */
        double dec = log10(o.wh / o.wb);
        int n = (int)ceil(dec);
        if (n < 1)
            n = 1;
        if (n > PF_MAX_ORDER)
            n = PF_MAX_ORDER;
        o.order = n;
    }
    PF_RETURN_IF_OUT(PF_P_ORDER, (double)o.order);
    PF_RETURN_IF_OUT(PF_P_PREWARP, o.prewarp);
    if (o.prewarp >= 0.99 * nyq)
        return PF_E_PARAM(PF_P_PREWARP);
    if (o.approx == PF_APPROX_REFINED) {
        /* The correction factor's poles must be real: (b wh/(d(1-r)))^2 >
         * 4 r/(1-r) for every r in [1/2, 1); wh >= 2 rad/s guarantees it. */
        if (o.wh < 2.0)
            return PF_E_PARAM(PF_P_WH);
    }
    *out = o;
    return PF_OK;
}

/* Round to nearest, ties toward zero: |f| <= 1/2 and the integer part is as
 * small as it can be (alpha = 0.5 needs no integrator at all). */
static int split_int(double alpha)
{
    return alpha > 0.0 ? (int)ceil(alpha - 0.5) : (int)floor(alpha + 0.5);
}

static void oustaloup_zp(double r, double wb, double wh, int N, double *z,
                         double *p)
{
    int k, i = 0;
    double span = wh / wb;
    for (k = -N; k <= N; k++, i++) {
        z[i] = wb * pow(span, (k + N + 0.5 * (1.0 - r)) / (2 * N + 1));
        p[i] = wb * pow(span, (k + N + 0.5 * (1.0 + r)) / (2 * N + 1));
    }
}

pf_status pf_fracop_zpk(double alpha, const pf_design_opts *opt, int *m,
                        double *k, double *zeros, int *nz, double *poles,
                        int *np)
{
    pf_design_opts o;
    pf_status st;
    int n;
    double f;
    if (opt == NULL || m == NULL || k == NULL || zeros == NULL || nz == NULL ||
        poles == NULL || np == NULL)
        return PF_E_NULL;
    PF_RETURN_IF_OUT(PF_P_ALPHA, alpha);
    st = pf_design_opts_resolve(opt, &o);
    if (st != PF_OK)
        return st;
    n = split_int(alpha);
    f = alpha - n;
    *m = n;
    *k = 1.0;
    *nz = 0;
    *np = 0;
    if (fabs(f) < 1e-12)
        return PF_OK;
    /* The refined correction factor degenerates as r -> 0 or r -> 1 (one
     * of its poles runs to 0 or to infinity, beyond any sample rate); so
     * close to an integer order the plain recursive distribution, which is
     * well conditioned there, is used instead. */
    if (o.approx == PF_APPROX_OUSTALOUP ||
        fabs(f) < PF_REFINED_MARGIN || fabs(f) > 1.0 - PF_REFINED_MARGIN) {
        oustaloup_zp(f, o.wb, o.wh, o.order, zeros, poles);
        *nz = *np = 2 * o.order + 1;
        *k = pow(o.wh, f);
    } else {
        /* The refined factor carries a zero at s = 0 that must cancel one
         * integer-part integrator exactly, not numerically: realise
         * s^alpha = s^(n+1) R(s) for f > 0 (r = f), or s^n R(s) for f < 0
         * (r = 1 + f, s^f = s^-1 s^r), with R free of the origin zero. */
        double r = f > 0.0 ? f : 1.0 + f;
        double wbp = REF_D * o.wb / REF_B, whp = REF_B * o.wh / REF_D;
        double B = REF_B * o.wh / (REF_D * (1.0 - r)), C = r / (1.0 - r);
        double disc = sqrt(B * B - 4.0 * C);
        int cnt = 2 * o.order + 1;
        oustaloup_zp(r, wbp, whp, o.order, zeros, poles);
        /* (d s + b wh) / (d(1-r) s^2 + b wh s + d r)
         *   = (s + b wh/d) / ((1-r)(s + p1)(s + p2)) */
        zeros[cnt] = REF_B * o.wh / REF_D;
        poles[cnt] = 0.5 * (B + disc);
        poles[cnt + 1] = 2.0 * C / (B + disc); /* small root, no cancellation */
        *nz = cnt + 1;
        *np = cnt + 2;
        /* With the product normalised to unit gain at s -> inf, as here,
         * the constant is (b wh/d)^r: the product then tends to
         * (w/(b wh/d))^r inside the band. The form (d wh/b)^r quoted with
         * the method belongs to a product normalised at s = 0 with
         * wb wh = 1; used here it would leave a (d/b)^(2r) gain error. */
        *k = pow(REF_B * o.wh / REF_D, r) / (1.0 - r);
        *m = f > 0.0 ? n + 1 : n;
    }
    return PF_OK;
}
