/* SPDX-License-Identifier: MIT */
/*
 * Closed-loop discrete frequency responses of a controller design: the same
 * block algebra as the runtime (pf_ctrl_float.inc), in complex double. Used
 * for the Q15 node scaling and for Bode plots.
 */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "pf_ctrl_internal.h"

/* Node responses per unit e at one frequency. */
void pf_ctrl_node_resp(const pf_ctrl_coeffs_f64 *c, double omega,
                      double complex g[PF_N_COUNT])
{
    double complex fP, fQ = 0, fV = 0, fW = 0, zi = cexp(-I * omega / c->P.fs);
    double complex OP = pf_op_resp(&c->P, omega, &fP);
    double complex OQ = c->has_q ? pf_op_resp(&c->Q, omega, &fQ) : c->kA;
    double complex OV = c->has_v ? pf_op_resp(&c->V, omega, &fV) : 0;
    double complex OW = c->has_w ? pf_op_resp(&c->W, omega, &fW) : 0;
    double complex rv = OV / (1.0 + OV), rw = OW / (1.0 + OW);
    double complex mm = (c->has_v ? rv : 1.0) - (c->has_w ? rw : 0.0);
    double complex yy = OQ * mm;
    double complex v_pb = 1.0 / (1.0 / c->relay_d0 + c->pmin * OP);
    double complex z_pb = c->relay_d0 + c->relay_w * OP * v_pb;
    double complex G = c->k2 * z_pb * c->k1;
    double complex e = c->hold ? 0.5 * (1.0 + zi) : 1.0;
    double complex x = c->ce * e / (1.0 + c->cy * yy * G), pc = G * x;
    memset(g, 0, sizeof(double complex) * PF_N_COUNT);
    g[PF_N_E] = e;
    g[PF_N_X] = x;
    g[PF_N_PB] = c->k1 * x;
    g[PF_N_V] = v_pb * g[PF_N_PB];
    g[PF_N_W] = OP * g[PF_N_V];
    g[PF_N_PC] = pc;
    g[PF_N_DV] = pc / (1.0 + OV);
    g[PF_N_RV] = rv * pc;
    g[PF_N_DW] = pc / (1.0 + OW);
    g[PF_N_RW] = rw * pc;
    g[PF_N_M] = mm * pc;
    g[PF_N_Y] = yy * pc;
    g[PF_N_FP] = fP * g[PF_N_V];
    g[PF_N_FQ] = fQ * g[PF_N_M];
    g[PF_N_FV] = fV * g[PF_N_DV];
    g[PF_N_FW] = fW * g[PF_N_DW];
}

void pf_ctrl_freqresp(const pf_ctrl_design *d, double omega, double *re,
                      double *im)
{
    const pf_ctrl_coeffs_f64 *c;
    double complex g[PF_N_COUNT], h;
    if (d == NULL || re == NULL || im == NULL)
        return;
    c = &d->rt;
    pf_ctrl_node_resp(c, omega, g);
    h = g[PF_N_PC];
    /* The output line after p_c, as pf_ctrl_float.inc runs it: the lag
     * lag += lam (p_c - lag) is lam/(1 - (1 - lam) z^-1); the dead time
     * z^-delay_len. */
    if (c->lag_lam > 0)
        h *= c->lag_lam / (1.0 - (1.0 - c->lag_lam) * cexp(-I * omega / c->P.fs));
    if (c->delay_len > 0)
        h *= cexp(-I * omega * (double)c->delay_len / c->P.fs);
    *re = creal(h);
    *im = cimag(h);
}
