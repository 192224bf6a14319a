/* SPDX-License-Identifier: MIT */
/*
 * The typed runtimes a firmware links (pf_ctrl_run_f32, pf_ctrl_run_q15),
 * on a record, for test_api_simulate.py to hold the Python API to them
 * sample for sample. Not pf_runtime: the Python API goes through that one.
 *
 *   typed_runtime MODE CONFIG FS IN_FS OUT_FS [NAME=VALUE ...] <in >out
 *
 * MODE f32: doubles in, each rounded to float, floats out; q15: int16 in
 * and out (raw counts). NAME is a model parameter of the paper or an
 * effect (backlash, nozzle_xh, sat_lo, sat_hi, dead_time, lag). Exit 2
 * when the library refuses the design.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pneufrac/pneufrac.h"

#define MAX_N 1000000

static int set_effect(pf_effects *fx, const char *name, double v)
{
    if (strcmp(name, "backlash") == 0)
        fx->backlash = v;
    else if (strcmp(name, "nozzle_xh") == 0)
        fx->nozzle_xh = v;
    else if (strcmp(name, "sat_lo") == 0)
        fx->saturate = 1, fx->sat_lo = v;
    else if (strcmp(name, "sat_hi") == 0)
        fx->saturate = 1, fx->sat_hi = v;
    else if (strcmp(name, "dead_time") == 0)
        fx->dead_time = v;
    else if (strcmp(name, "lag") == 0)
        fx->lag = v;
    else
        return -1;
    return 0;
}

int main(int argc, char **argv)
{
    static pf_ctrl_design d;
    static double e64[MAX_N];
    static float e32[MAX_N], o32[MAX_N], d32[MAX_N];
    static int16_t eq[MAX_N], oq[MAX_N], dq[MAX_N];
    static pf_ctrl_coeffs_f32 cf;
    static pf_ctrl_coeffs_q15 cq;
    static pf_nozzle_q15 nz;     /* the nozzle curve's table, when there is one */
    pf_params p;
    pf_effects fx;
    pf_design_opts o;
    size_t n, i;
    int a;

    if (argc < 6)
        return 2;
    memset(&fx, 0, sizeof fx);
    pf_params_default(&p, pf_topology_lookup(argv[2]));
    pf_design_opts_default(&o, strtod(argv[3], NULL));
    for (a = 6; a < argc; a++) {
        char *eq_sign = strchr(argv[a], '=');
        double v;
        if (eq_sign == NULL)
            return 2;
        *eq_sign = '\0';
        v = strtod(eq_sign + 1, NULL);
        if (set_effect(&fx, argv[a], v) != 0 &&
            pf_params_set(&p, pf_param_lookup(argv[a]), v) != PF_OK)
            return 2;
    }
    if (pf_ctrl_design_make(&d, &p, &fx, &o) != PF_OK || d.rt.delay_len > MAX_N)
        return 2;
    if (strcmp(argv[1], "f32") == 0) {
        pf_ctrl_f32 S;
        n = fread(e64, sizeof e64[0], MAX_N, stdin);
        for (i = 0; i < n; i++)
            e32[i] = (float)e64[i];
        pf_ctrl_coeffs_f32_make(&cf, &d.rt);
        if (pf_ctrl_init_f32(&S, &cf, d32, d.rt.delay_len) != PF_OK)
            return 2;
        pf_ctrl_run_f32(&S, e32, o32, n);
        return fwrite(o32, sizeof o32[0], n, stdout) == n ? 0 : 1;
    }
    if (strcmp(argv[1], "q15") == 0) {
        pf_ctrl_q15 S;
        n = fread(eq, sizeof eq[0], MAX_N, stdin);
        if (pf_ctrl_coeffs_q15_make_nz(&cq, &nz, &d, strtod(argv[4], NULL),
                                       strtod(argv[5], NULL)) != PF_OK ||
            pf_ctrl_init_q15(&S, &cq, dq, d.rt.delay_len) != PF_OK)
            return 2;
        pf_ctrl_run_q15(&S, eq, oq, n);
        return fwrite(oq, sizeof oq[0], n, stdout) == n ? 0 : 1;
    }
    return 2;
}
