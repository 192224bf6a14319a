/* SPDX-License-Identifier: MIT */
#include "pfh_accuracy.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pfh_ref.h"

int pfh_acc_ref_make(pfh_acc_ref *r, const pf_params *p, double fs, double t0,
                    double t1)
{
    long n;
    memset(r, 0, sizeof *r);
    r->p = *p;
    r->fs = fs;
    r->n0 = (long)ceil(t0 * fs - 1e-9);
    r->n1 = (long)floor(t1 * fs + 1e-9);
    r->y = malloc(sizeof(double) * (size_t)(r->n1 - r->n0 + 1));
    if (r->y == NULL)
        return -1;
    for (n = r->n0; n <= r->n1; n++) {
        r->y[n - r->n0] = pfh_ref_step(p, n / fs);
        if (fabs(r->y[n - r->n0]) > r->peak)
            r->peak = fabs(r->y[n - r->n0]);
    }
    return 0;
}

void pfh_acc_ref_free(pfh_acc_ref *r)
{
    free(r->y);
    r->y = NULL;
}

int pfh_acc_run(const pf_params *p, const pf_design_opts *o, pfh_acc_arith arith,
               double out_fs, long n_last, pfh_acc_sink fn, void *ctx)
{
    /* static: a design is a few KB; the accuracy tools are single-threaded */
    static pf_ctrl_design d;
    static pf_ctrl_f64 c64;
    static pf_ctrl_coeffs_f32 cf;
    static pf_ctrl_f32 c32;
    static pf_ctrl_coeffs_q15 cq;
    static pf_ctrl_q15 cq15;
    long n;

    if (pf_ctrl_design_make(&d, p, NULL, o) != PF_OK)
        return -1;
    pf_ctrl_init_f64(&c64, &d.rt, NULL, 0);
    pf_ctrl_coeffs_f32_make(&cf, &d.rt);
    pf_ctrl_init_f32(&c32, &cf, NULL, 0);
    if (arith == PFH_ACC_Q15) {
        if (pf_ctrl_coeffs_q15_make(&cq, &d, 2.0, out_fs) != PF_OK)
            return -1;
        pf_ctrl_init_q15(&cq15, &cq, NULL, 0);
    }
    for (n = 0; n <= n_last; n++) {
        double y;
        if (arith == PFH_ACC_F64)
            y = pf_ctrl_step_f64(&c64, 1.0);
        else if (arith == PFH_ACC_F32)
            y = pf_ctrl_step_f32(&c32, 1.0f);
        else /* a unit step is half of in_fs = 2: Q15 16384 exactly */
            y = pf_ctrl_step_q15(&cq15, 16384) * out_fs / 32768.0;
        fn(ctx, n, y);
    }
    return 0;
}

typedef struct err_ctx {
    const pfh_acc_ref *r;
    double worst, t_worst;
} err_ctx;

static void track_error(void *ctx, long n, double y)
{
    err_ctx *e = ctx;
    if (n >= e->r->n0 && fabs(y - e->r->y[n - e->r->n0]) > e->worst) {
        e->worst = fabs(y - e->r->y[n - e->r->n0]);
        e->t_worst = n / e->r->fs;
    }
}

double pfh_acc_error(const pfh_acc_ref *r, const pf_design_opts *o,
                    pfh_acc_arith arith, double *t_worst)
{
    err_ctx e = {NULL, 0.0, 0.0};
    e.r = r;
    if (pfh_acc_run(&r->p, o, arith, 1.25 * r->peak, r->n1, track_error, &e) != 0)
        return -1.0;
    if (t_worst != NULL)
        *t_worst = e.t_worst;
    return e.worst / r->peak;
}
