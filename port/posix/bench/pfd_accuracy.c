/* SPDX-License-Identifier: MIT */
#include "pfd_accuracy.h"

#include <math.h>
#include <stdlib.h>

#include "pfd_commit.h"
#include "pfd_sample.h"

int pfd_acc_error(const pfh_acc_ref *r, int arith, unsigned substeps, pfd_acc_result *out)
{
    pfd_daemon *d = malloc(sizeof *d);
    pfd_settings set;
    pfd_config_inst ci;
    pfd_fail why;
    pfd_inst *in;
    long n;

    pfd_settings_default(&set);
    if (d == NULL || pfd_daemon_init(d, &set) != 0) {
        free(d);
        return -1;
    }
    pfd_config_inst_default(&ci, 1);
    ci.ip.p = r->p;
    ci.ip.fs = r->fs;
    ci.ip.substeps = substeps;
    ci.ip.arith = arith;
    if (arith == PFD_ARITH_Q15) {
        ci.ip.in_fs = 2.0;
        ci.ip.out_fs = 1.25 * r->peak;
    }
    ci.live.e = 1.0f;
    if (pfd_inst_add(d, &ci, &why) != 0) {
        pfd_daemon_free(d);
        free(d);
        return -1;
    }
    in = d->inst[0];
    out->err = 0.0;
    out->t_worst = 0.0;
    out->k = in->rate.k;
    for (n = 0; n <= r->n1; n++) {
        const pfd_snap *s;
        double err;
        pfd_sample_run(in, &d->loop.jitter, 0, -1);
        s = (const pfd_snap *)pfd_tbuf_latest(&in->out_tb);
        if (n < r->n0)
            continue;
        err = fabs((double)s->sig.pc - r->y[n - r->n0]);
        if (err > out->err) {
            out->err = err;
            out->t_worst = (double)n / r->fs;
        }
    }
    out->err /= r->peak;
    pfd_daemon_free(d);
    free(d);
    return 0;
}
