/* SPDX-License-Identifier: MIT */
/*
 * Every case of the shared reference (the paper's Examples 4, 6, 7) at
 * fs = 20 kHz with the default band and order, against the exact response
 * computed here by numerical inverse Laplace (pf_ref.c, itself validated
 * against ../shared/reference to 1.5e-10): max error over t in [1 ms, 2 s]
 * relative to the peak |response|, in double and float. The requirement is
 * 0.5 %; the test holds the design to its aim, 0.1 %.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>

#include "pf_accuracy.h"
#include "pf_ref_csv.h"

#define FS 20000.0
#define AIM 1e-3

static void test_reference_cases_20khz(void **state)
{
    int i, n = pf_ref_case_count();
    (void)state;
    assert_int_equal(n, 10);
    printf("case          double    float   (max |error|/peak, t in [1 ms, 2 s], 20 kHz)\n");
    for (i = 0; i < n; i++) {
        pf_params p;
        pf_design_opts o;
        pf_acc_ref r;
        double e64, e32;
        assert_int_equal(pf_ref_case(pf_ref_case_name(i), &p), 0);
        assert_int_equal(pf_acc_ref_make(&r, &p, FS, 1e-3, 2.0), 0);
        pf_design_opts_default(&o, FS);
        e64 = pf_acc_error(&r, &o, PF_ACC_F64, NULL);
        e32 = pf_acc_error(&r, &o, PF_ACC_F32, NULL);
        printf("%-12s  %.4f %%  %.4f %%\n", pf_ref_case_name(i), 100 * e64, 100 * e32);
        assert_true(e64 >= 0 && e64 <= AIM);
        assert_true(e32 >= 0 && e32 <= AIM);
        pf_acc_ref_free(&r);
    }
}

/* The check can fail: the toolbox-default band [1e-3, 1e3] rad/s with
 * N = 5 misses the relay's dynamics (50 .. 20000 rad/s) and breaks the
 * 0.5 % requirement (measured: 1.2 % of peak; 6.2 % of the local value at
 * t = 1 ms, in line with the reference README's warning). */
static void test_toolbox_band_is_off(void **state)
{
    pf_params p;
    pf_design_opts o;
    pf_acc_ref r;
    double e;
    (void)state;
    assert_int_equal(pf_ref_case("ex4_q0.9", &p), 0);
    assert_int_equal(pf_acc_ref_make(&r, &p, 10000.0, 1e-3, 2.0), 0);
    pf_design_opts_default(&o, 10000.0);
    o.wb = 1e-3;
    o.wh = 1e3;
    o.order = 5;
    e = pf_acc_error(&r, &o, PF_ACC_F64, NULL);
    printf("toolbox band [1e-3, 1e3], N = 5, 10 kHz: %.2f %%\n", 100 * e);
    assert_true(e > 5e-3);
    pf_acc_ref_free(&r);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_reference_cases_20khz),
        cmocka_unit_test(test_toolbox_band_is_off),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
