/* SPDX-License-Identifier: MIT */
/*
 * Every case of the exact reference (tests/ref/paper_step_cases.json: the
 * paper's Examples 4, 6, 7 and a pid) at fs = 20 kHz with the default band
 * and order, against the exact response computed here by numerical inverse
 * Laplace (pfh_ref.c, itself validated by test_reference against the
 * committed mpmath table): max error over t in [1 ms, 2 s]
 * relative to the peak |response|, in double and float. The requirement is
 * 0.5 %; the test holds the design to its aim, 0.1 %.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>

#include "pfh_accuracy.h"
#include "pfh_ref_cases.h"

#define FS 20000.0
#define AIM 1e-3

static pfh_ref_cases cases;

static int setup_cases(void **state)
{
    (void)state;
    return pfh_ref_cases_load(REF_DATA_DIR "/paper_step_cases.json", &cases);
}

static void test_reference_cases_20khz(void **state)
{
    int i;
    (void)state;
    assert_int_equal(cases.n, 11);
    printf("case          double    float   (max |error|/peak, t in [1 ms, 2 s], 20 kHz)\n");
    for (i = 0; i < cases.n; i++) {
        pf_design_opts o;
        pfh_acc_ref r;
        double e64, e32;
        assert_int_equal(pfh_acc_ref_make(&r, &cases.p[i], FS, 1e-3, 2.0), 0);
        pf_design_opts_default(&o, FS);
        e64 = pfh_acc_error(&r, &o, PF_ARITH_F64, NULL);
        e32 = pfh_acc_error(&r, &o, PF_ARITH_F32, NULL);
        printf("%-12s  %.4f %%  %.4f %%\n", cases.name[i], 100 * e64, 100 * e32);
        assert_true(e64 >= 0 && e64 <= AIM);
        assert_true(e32 >= 0 && e32 <= AIM);
        pfh_acc_ref_free(&r);
    }
}

/* The check can fail: the toolbox-default band [1e-3, 1e3] rad/s with
 * N = 5 misses the relay's dynamics (50 .. 20000 rad/s) and breaks the
 * 0.5 % requirement (measured: 1.2 % of peak; 6.2 % of the local value at
 * t = 1 ms, in line with the reference README's warning). */
static void test_toolbox_band_is_off(void **state)
{
    const pf_params *p = pfh_ref_cases_find(&cases, "ex4_q0.9");
    pf_design_opts o;
    pfh_acc_ref r;
    double e;
    (void)state;
    assert_non_null(p);
    assert_int_equal(pfh_acc_ref_make(&r, p, 10000.0, 1e-3, 2.0), 0);
    pf_design_opts_default(&o, 10000.0);
    o.wb = 1e-3;
    o.wh = 1e3;
    o.order = 5;
    e = pfh_acc_error(&r, &o, PF_ARITH_F64, NULL);
    printf("toolbox band [1e-3, 1e3], N = 5, 10 kHz: %.2f %%\n", 100 * e);
    assert_true(e > 5e-3);
    pfh_acc_ref_free(&r);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_reference_cases_20khz),
        cmocka_unit_test(test_toolbox_band_is_off),
    };
    return cmocka_run_group_tests(tests, setup_cases, NULL);
}
