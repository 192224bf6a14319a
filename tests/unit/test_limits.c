/* SPDX-License-Identifier: MIT */
/*
 * At high loop gain the full models approach the paper's limits:
 *   dd  (eq. 19):  M (RC s^(q+nu) + s^q)
 *   id  (eq. 21):  M s^q (1 + 1/(RC s^w))
 *   pid (docs/pid.md): M s^q (RCd s^nu + 1)(RCi s^w + 1)/(RCi s^w - RCd s^nu)
 * with M = b ks/(a A). The loop gain is raised through the nozzle gain k1;
 * the error against the limit must shrink as it grows and end below 1 %.
 * The comparison runs on the discrete design's frequency response, well
 * inside the Oustaloup band and far below Nyquist.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <complex.h>
#include <math.h>
#include <stdio.h>

#include "pneufrac/pneufrac.h"

static double complex limit_tf(const pf_params *p, double w)
{
    double complex s = I * w, sq = p->q > 0 ? cpow(s, p->q) : 1.0;
    double M = p->b * p->ks / (p->a * p->A);
    switch (p->topology) {
    case PF_TOPO_DD:
        return M * (p->RC * cpow(s, p->q + p->nu) + sq);
    case PF_TOPO_ID:
        return M * sq * (1.0 + 1.0 / (p->RC * cpow(s, p->w)));
    default: {
        double complex d = p->RCd * cpow(s, p->nu), i = p->RCi * cpow(s, p->w);
        return M * sq * (d + 1.0) * (i + 1.0) / (i - d);
    }
    }
}

/* Worst relative error |H - H_lim|/|H_lim| over w in [0.5, 20] rad/s. */
static double limit_error(pf_topology cfg, double k1)
{
    static pf_ctrl_design d;
    pf_params p;
    pf_design_opts o;
    double w, worst = 0;
    pf_params_default(&p, cfg);
    p.k1 = k1;
    pf_design_opts_default(&o, 20000.0);
    assert_int_equal(pf_ctrl_design_make(&d, &p, NULL, &o), PF_OK);
    for (w = 0.5; w <= 20.0; w *= 1.2) {
        double re, im;
        double complex lim = limit_tf(&p, w);
        pf_ctrl_freqresp(&d, w, &re, &im);
        worst = fmax(worst, cabs(re + I * im - lim) / cabs(lim));
    }
    return worst;
}

/* Between the paper's gain and the high-gain regime the distance is not
 * monotone (where |L| ~ 1 the loop resonates), so the check compares the
 * paper's gain with two high gains: far closer, and below 1 %; from 1e6 on
 * only the Oustaloup approximation's own error remains. */
static void check_limit(pf_topology cfg)
{
    pf_params p;
    double e0, e6, e8;
    pf_params_default(&p, cfg);
    e0 = limit_error(cfg, p.k1);
    e6 = limit_error(cfg, 1e6);
    e8 = limit_error(cfg, 1e8);
    printf("%-3s distance to the limit: k1 = %g (paper) %.2e, k1 = 1e6 %.2e, "
           "k1 = 1e8 %.2e\n", pf_topology_name(cfg), p.k1, e0, e6, e8);
    assert_true(e6 < e0 / 10.0);
    assert_true(e8 <= e6 * 1.05);
    assert_true(e8 < 1e-2);
}

static void test_dd_limit_eq19(void **state) { (void)state; check_limit(PF_TOPO_DD); }
static void test_id_limit_eq21(void **state) { (void)state; check_limit(PF_TOPO_ID); }
static void test_pid_limit(void **state) { (void)state; check_limit(PF_TOPO_PID); }

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_dd_limit_eq19),
        cmocka_unit_test(test_id_limit_eq21),
        cmocka_unit_test(test_pid_limit),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
