/* SPDX-License-Identifier: MIT */
/*
 * pf_ctrl_spectral_radius (lib/src/pf_ctrl_check.c): the largest |z| of a
 * design's discrete closed-loop poles.
 *  - The paper's four configurations, at 100 Hz to 50 kHz, are stable.
 *  - An integrating set (FrID with a pure integrator in the bellows,
 *    q = 1) has its pole on the unit circle, within the tolerance, so it
 *    is not called unstable.
 *  - Extreme gains (k1 = k2 = 1e3 or 1e5 in Example 6) make the loop
 *    unstable, and the radius equals the growth rate of the runtime's own
 *    output, measured by stepping it: two independent routes agree.
 *  - The effects are left out: saturation does not change the radius.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pneufrac/pneufrac.h"

static pf_ctrl_check_work work;

static double radius(pf_topology cfg, double fs, const char *name, double v,
                     const char *name2, double v2, const pf_effects *fx)
{
    static pf_ctrl_design d;
    pf_design_opts o;
    pf_params p;
    double rho = -1.0;

    pf_params_default(&p, cfg);
    if (name != NULL)
        assert_int_equal(pf_params_set(&p, pf_param_lookup(name), v), PF_OK);
    if (name2 != NULL)
        assert_int_equal(pf_params_set(&p, pf_param_lookup(name2), v2), PF_OK);
    memset(&o, 0, sizeof o);
    o.fs = fs;
    assert_int_equal(pf_ctrl_design_make(&d, &p, fx, &o), PF_OK);
    assert_int_equal(pf_ctrl_spectral_radius(&d, &work, &rho), PF_OK);
    return rho;
}

static void paper_examples_are_stable(void **state)
{
    static const double rates[] = {100.0, 1000.0, 10000.0, 50000.0};
    int c, k;
    (void)state;
    for (c = 0; c < PF_TOPO_COUNT; c++)
        for (k = 0; k < 4; k++) {
            double rho = radius((pf_topology)c, rates[k], NULL, 0, NULL, 0, NULL);
            if (!(rho <= 1.0 + PF_CTRL_RHO_TOL && rho > 0.5))
                fail_msg("%s at %g Hz: rho = %.17g", pf_topology_name((pf_topology)c), rates[k],
                         rho);
        }
}

static void integrator_is_on_the_circle(void **state)
{
    double rho = radius(PF_TOPO_ID, 1000.0, "q", 1.0, NULL, 0, NULL);
    (void)state;
    assert_true(fabs(rho - 1.0) <= PF_CTRL_RHO_TOL);
}

/* The growth per sample of the runtime's output under a unit step,
 * between samples n1 and n2 (envelopes over 64 samples). */
static double measured_growth(pf_topology cfg, double k, uint32_t n1, uint32_t n2)
{
    static pf_ctrl_design d;
    pf_design_opts o;
    pf_params p;
    pf_ctrl_f64 r;
    double m1 = 0.0, m2 = 0.0;
    uint32_t n;

    pf_params_default(&p, cfg);
    pf_params_set(&p, PF_P_K1, k);
    pf_params_set(&p, PF_P_K2, k);
    memset(&o, 0, sizeof o);
    o.fs = 1000.0;
    assert_int_equal(pf_ctrl_design_make(&d, &p, NULL, &o), PF_OK);
    assert_int_equal(pf_ctrl_init_f64(&r, &d.rt, NULL, 0), PF_OK);
    for (n = 0; n < n2 + 64; n++) {
        double y = fabs(pf_ctrl_step_f64(&r, 1.0));
        if (n >= n1 && n < n1 + 64 && y > m1)
            m1 = y;
        if (n >= n2 && y > m2)
            m2 = y;
    }
    return pow(m2 / m1, 1.0 / (double)(n2 - n1));
}

static void extreme_gains_are_unstable(void **state)
{
    static const double gains[] = {1e3, 1e5};
    int i;
    (void)state;
    for (i = 0; i < 2; i++) {
        double rho = radius(PF_TOPO_DD, 1000.0, "k1", gains[i], "k2", gains[i], NULL);
        double grow = measured_growth(PF_TOPO_DD, gains[i], 1000, 3000);
        if (!(rho > 1.001 && fabs(rho - grow) < 1e-4))
            fail_msg("k1 = k2 = %g: rho %.9g, measured growth %.9g", gains[i], rho, grow);
    }
    /* The issue's own case: Example 6 with k1 = k2 = 1e9 at 1 kHz. */
    assert_true(radius(PF_TOPO_DD, 1000.0, "k1", 1e9, "k2", 1e9, NULL) > 1.0 + PF_CTRL_RHO_TOL);
}

static void effects_are_left_out(void **state)
{
    pf_effects fx;
    (void)state;
    memset(&fx, 0, sizeof fx);
    fx.saturate = 1;
    fx.sat_lo = -0.001;
    fx.sat_hi = 0.001;
    fx.lag = 0.01;
    assert_true(radius(PF_TOPO_DD, 1000.0, "k1", 1e5, "k2", 1e5, &fx) ==
                radius(PF_TOPO_DD, 1000.0, "k1", 1e5, "k2", 1e5, NULL));
}

static void null_arguments(void **state)
{
    static pf_ctrl_design d;
    double rho;
    (void)state;
    assert_int_equal(pf_ctrl_spectral_radius(NULL, &work, &rho), PF_E_NULL);
    assert_int_equal(pf_ctrl_spectral_radius(&d, NULL, &rho), PF_E_NULL);
    assert_int_equal(pf_ctrl_spectral_radius(&d, &work, NULL), PF_E_NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(paper_examples_are_stable),
        cmocka_unit_test(integrator_is_on_the_circle),
        cmocka_unit_test(extreme_gains_are_unstable),
        cmocka_unit_test(effects_are_left_out),
        cmocka_unit_test(null_arguments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
