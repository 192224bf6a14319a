/* SPDX-License-Identifier: MIT */
/*
 * Operator design: Tustin discretisation of the rational approximant and
 * its parallel (partial-fraction) realisation, in double.
 *
 * With real, distinct poles the approximant splits into
 *     H(s) = H(inf) + sum_k r_k/(s + p_k),
 *     r_k  = K prod_i (z_i - p_k) / prod_{l != k} (p_l - p_k).
 * Oustaloup's zeros and poles interlace, so H is an RC driving-point-like
 * function whose residues share one sign: the parallel sum has no
 * cancellation, unlike the expanded polynomial (whose coefficients span
 * tens of decades). Tustin maps each r/(s+p), with s = c (z-1)/(z+1), to a
 * feedthrough r/(c+p) plus a one-pole branch with pole a = (c-p)/(c+p),
 * leak lam = 1 - a = 2p/(c+p) and DC gain G = r/p - r/(c+p).
 */
#include <complex.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "pf_design_internal.h"

pf_status pf_fracop_design_make(pf_fracop_design *op, double alpha, double gain,
                                const pf_design_opts *opt)
{
    double z[PF_MAX_SEC], p[PF_MAX_SEC], K, c;
    int m, nz, np, i, j;
    pf_design_opts o;
    pf_status st;

    if (op == NULL || opt == NULL)
        return PF_E_NULL;
    PF_RETURN_IF_OUT(PF_P_GAIN, gain);
    st = pf_design_opts_resolve(opt, &o);
    if (st == PF_OK)
        st = pf_fracop_zpk(alpha, &o, &m, &K, z, &nz, p, &np);
    if (st != PF_OK)
        return st;

    memset(op, 0, sizeof *op);
    op->alpha = alpha;
    op->gain = gain;
    op->fs = o.fs;
    op->hold = o.input == PF_INPUT_HOLD;
    /* Prewarping at w0 maps w0 exactly; the default (none) maps DC exactly
     * and keeps every operator of a controller on one frequency map. */
    c = o.prewarp > 0.0 ? o.prewarp / tan(o.prewarp / (2.0 * o.fs)) : 2.0 * o.fs;
    op->c = c;

    /* Feedthrough: H at s = c, i.e. z = infinity. */
    op->d = gain * K;
    for (i = 0; i < nz; i++)
        op->d *= c + z[i];
    for (j = 0; j < np; j++)
        op->d /= c + p[j];

    op->n_sec = np;
    for (j = 0; j < np; j++) {
        double r = K;
        for (i = 0; i < nz; i++)
            r *= z[i] - p[j];
        for (i = 0; i < np; i++)
            if (i != j)
                r /= p[i] - p[j];
        op->lam[j] = 2.0 * p[j] / (c + p[j]);
        op->G[j] = gain * (r / p[j] - r / (c + p[j]));
    }

    op->n_int = m;
    if (m < 0) {        /* Tustin integrator 1/s */
        op->int_d = 1.0 / c;
        op->int_k = 2.0 / c;
        op->int_rho = 1;
    } else if (m > 0) { /* Tustin differentiator s */
        op->int_d = c;
        op->int_k = -2.0 * c;
        op->int_rho = -1;
    }
    op->D = op->d;
    for (i = 0; i < abs(m); i++)
        op->D *= op->int_d;
    /* Last line of defence: an approximant whose poles left the range a
     * sample rate can hold would run unstable or produce NaN. */
    if (!isfinite(op->d) || !isfinite(op->D))
        return PF_E_PARAM(PF_P_ALPHA);
    for (j = 0; j < np; j++)
        if (!(op->lam[j] > 0.0 && op->lam[j] < 2.0 - 1e-9) || !isfinite(op->G[j]))
            return PF_E_PARAM(PF_P_ALPHA);
    return PF_OK;
}

double complex pf_op_resp(const pf_fracop_design *op, double omega,
                          double complex *frac)
{
    double complex zi = cexp(-I * omega / op->fs), h = op->d, stage = 1.0;
    int k;
    for (k = 0; k < op->n_sec; k++) {
        double lam = op->lam[k];
        h += op->G[k] * lam * zi / (1.0 - (1.0 - lam) * zi);
    }
    if (frac != NULL)
        *frac = h;
    if (op->n_int < 0)
        stage = (1.0 + zi) / (op->c * (1.0 - zi));
    else if (op->n_int > 0)
        stage = op->c * (1.0 - zi) / (1.0 + zi);
    for (k = 0; k < abs(op->n_int); k++)
        h *= stage;
    return h;
}

void pf_fracop_freqresp(const pf_fracop_design *op, double omega, double *re,
                        double *im)
{
    double complex h;
    if (op == NULL || re == NULL || im == NULL)
        return;
    h = pf_op_resp(op, omega, NULL);
    *re = creal(h);
    *im = cimag(h);
}
