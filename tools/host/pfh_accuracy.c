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

int pfh_acc_run(const pf_params *p, const pf_design_opts *o, pf_arith arith,
               double out_fs, long n_last, pfh_acc_sink fn, void *ctx)
{
    /* static: a design is a few KB; the accuracy tools are single-threaded */
    static pf_ctrl_design d;
    static pf_runtime rt;
    long n;

    if (pf_ctrl_design_make(&d, p, NULL, o) != PF_OK)
        return -1;
    /* Q15: a unit step is half of in_fs = 2, Q15 16384 exactly. */
    if (pf_runtime_init(&rt, &d, arith, 2.0, out_fs, NULL, 0) != PF_OK)
        return -1;
    for (n = 0; n <= n_last; n++)
        fn(ctx, n, pf_runtime_step(&rt, 1.0));
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
                    pf_arith arith, double *t_worst)
{
    err_ctx e = {NULL, 0.0, 0.0};
    e.r = r;
    if (pfh_acc_run(&r->p, o, arith, 1.25 * r->peak, r->n1, track_error, &e) != 0)
        return -1.0;
    if (t_worst != NULL)
        *t_worst = e.t_worst;
    return e.worst / r->peak;
}
