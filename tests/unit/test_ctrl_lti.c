/* SPDX-License-Identifier: MIT */
/*
 * pf_ctrl_state_space (lib/src/pf_ctrl_lti.c): the state space, run as
 * x' = A x + B e, y = C x + D e, must give the runtime's own output, for
 * every configuration, with the lag and the held input or plain Tustin,
 * on an input that is not a step.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "pneufrac/pneufrac.h"

static double A[PF_CTRL_MAX_STATES * PF_CTRL_MAX_STATES];
static double B[PF_CTRL_MAX_STATES], C[PF_CTRL_MAX_STATES];
static double x[PF_CTRL_MAX_STATES], xn[PF_CTRL_MAX_STATES];

static double check(pf_topology cfg, double lag, pf_input_model in)
{
    static pf_ctrl_design d;
    static pf_ctrl_f64 r;
    pf_params p;
    pf_effects fx;
    pf_design_opts o;
    double D, worst = 0.0, peak = 0.0;
    int n, k, i, j;

    pf_params_default(&p, cfg);
    memset(&fx, 0, sizeof fx);
    fx.lag = lag;
    pf_design_opts_default(&o, 5000.0);
    o.input = in;
    assert_int_equal(pf_ctrl_design_make(&d, &p, &fx, &o), PF_OK);
    n = pf_ctrl_state_space(&d, 1, A, B, C, &D);
    assert_true(n > 0 && n <= PF_CTRL_MAX_STATES);
    assert_int_equal(pf_ctrl_init_f64(&r, &d.rt, NULL, 0), PF_OK);
    memset(x, 0, sizeof x);
    for (k = 0; k < 3000; k++) {
        double e = sin(0.013 * k) + (k % 400 < 200 ? 0.5 : -0.25), y = D * e;
        double want = pf_ctrl_step_f64(&r, e);
        for (i = 0; i < n; i++) {
            y += C[i] * x[i];
            xn[i] = B[i] * e;
            for (j = 0; j < n; j++)
                xn[i] += A[(size_t)i * (size_t)n + (size_t)j] * x[j];
        }
        memcpy(x, xn, sizeof(double) * (size_t)n);
        worst = fmax(worst, fabs(y - want));
        peak = fmax(peak, fabs(want));
    }
    return worst / peak;
}

static void state_space_runs_like_the_runtime(void **state)
{
    int cfg;
    (void)state;
    for (cfg = 0; cfg < PF_TOPO_COUNT; cfg++) {
        double a = check((pf_topology)cfg, 0.0, PF_INPUT_HOLD);
        double b = check((pf_topology)cfg, 0.002, PF_INPUT_LINEAR);
        printf("%-3s max |y - runtime| / peak: %.1e (held input), %.1e (lag, linear)\n",
               pf_topology_name((pf_topology)cfg), a, b);
        assert_true(a < 1e-12 && b < 1e-12);
    }
}

static void null_arguments(void **state)
{
    static pf_ctrl_design d;
    pf_params p;
    pf_design_opts o;
    (void)state;
    pf_params_default(&p, PF_TOPO_DD);
    pf_design_opts_default(&o, 1000.0);
    assert_int_equal(pf_ctrl_design_make(&d, &p, NULL, &o), PF_OK);
    assert_int_equal(pf_ctrl_state_space(NULL, 0, A, B, C, NULL), -1);
    assert_int_equal(pf_ctrl_state_space(&d, 0, NULL, B, C, NULL), -1);
    assert_true(pf_ctrl_state_space(&d, 0, A, NULL, NULL, NULL) > 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(state_space_runs_like_the_runtime),
        cmocka_unit_test(null_arguments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
