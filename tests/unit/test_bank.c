/* SPDX-License-Identifier: MIT */
/*
 * The bank runtimes (lib/src/pf_bank_q15.c, pf_bank_f32.c) on small sets
 * written by hand, so that the expected outputs are known exactly:
 *  - one Q15 section with lam = 1/2 and beta = 1/2 is exact arithmetic:
 *    its output is the recursion's, rounded half up, sample for sample;
 *  - a section at the edge of the normalisation (beta l1 = 0.98, lam
 *    = 1.99, a pole near z = -1) under its worst input stays in range
 *    (UBSan would see an overflow) and follows double within 1 LSB;
 *  - run() equals step() over any split, reset() returns to rest, the dead
 *    time delays by exactly its samples;
 *  - float: NaN input counts as 0, infinities saturate, the output stays
 *    finite;
 *  - init refuses NULL, a short buffer and shifts out of range.
 * The reduced designs themselves (pneufrac-reduce) are tested in
 * tests/python/test_reduce.py and on the emulated cores in tests/target.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "pneufrac/pneufrac.h"

/* One section: lam = m 2^(v - 46), beta, output shift 0 and out_q 13, so
 * that the output is the state in Q15 units. */
static pf_bank_coeffs_q15 one_q15(double lam, double beta, uint32_t delay)
{
    pf_bank_coeffs_q15 c;
    int e;
    double f = frexp(lam, &e);
    memset(&c, 0, sizeof c);
    c.n_sec = 1;
    c.out_q = 13;
    c.delay_len = delay;
    c.sec[0].beta = (int32_t)lround(beta * 536870912.0);
    c.sec[0].lam_m = (uint16_t)lround(f * 65536.0);
    c.sec[0].lam_v = (uint8_t)(46 - (16 - e));
    return c;
}

static int16_t round_q15(double v)
{
    double r = floor(v + 0.5);
    return (int16_t)(r > 32767 ? 32767 : (r < -32768 ? -32768 : r));
}

static void exact_section(void **state)
{
    pf_bank_coeffs_q15 c = one_q15(0.5, 0.5, 0);
    pf_bank_q15 S;
    double hi = 0.0; /* the state in units of 2^-28 of full scale: halves only */
    int n;
    (void)state;
    assert_int_equal(c.sec[0].lam_m, 32768);
    assert_int_equal(pf_bank_init_q15(&S, &c, NULL, 0), PF_OK);
    for (n = 0; n < 200; n++) {
        int16_t u = (int16_t)(n < 100 ? 32767 : -32768 + n);
        /* y = round(hi / 2^13); hi <- hi + (u 2^12 - floor(hi)) / 2: the
         * kernel's arithmetic, exact in double */
        assert_int_equal(pf_bank_step_q15(&S, u), round_q15(floor(hi) / 8192.0));
        hi += 0.5 * (4096.0 * u - floor(hi));
    }
}

static void edge_of_the_bound(void **state)
{
    /* lam = 1.99: l1 = lam/(2 - lam) = 199, beta = 0.98/199; the worst
     * input alternates with the impulse response's sign, (-0.99)^n. */
    const double lam = 1.99, beta = 0.98 / 199.0;
    pf_bank_coeffs_q15 c = one_q15(lam, beta, 0);
    pf_bank_q15 S;
    double s = 0.0, lq;
    int n;
    (void)state;
    lq = ldexp((double)c.sec[0].lam_m, c.sec[0].lam_v - 46);
    assert_int_equal(pf_bank_init_q15(&S, &c, NULL, 0), PF_OK);
    for (n = 0; n < 5000; n++) {
        int16_t u = (int16_t)(n % 2 ? -32768 : 32767);
        int16_t got = pf_bank_step_q15(&S, u);
        if (fabs(got - s) > 1.0)
            fail_msg("sample %d: %d, double %.3f", n, got, s);
        s += lq * (c.sec[0].beta / 536870912.0 * u - s);
        assert_true(fabs(s) < 0.99 * 32768.0);
    }
    /* it did get near the bound */
    assert_true(fabs(s) > 0.9 * 32768.0 * 0.98);
}

static void run_reset_and_delay(void **state)
{
    pf_bank_coeffs_q15 c = one_q15(1e-3, 0.9, 0), cd = one_q15(1e-3, 0.9, 7);
    pf_bank_q15 A, B, D;
    int16_t u[300], y[300], yd[300], one[300], dbuf[7];
    int n;
    (void)state;
    for (n = 0; n < 300; n++)
        u[n] = (int16_t)((n * 7919) % 65536 - 32768);
    assert_int_equal(pf_bank_init_q15(&A, &c, NULL, 0), PF_OK);
    assert_int_equal(pf_bank_init_q15(&B, &c, NULL, 0), PF_OK);
    pf_bank_run_q15(&A, u, y, 120);
    pf_bank_run_q15(&A, u + 120, y + 120, 180);
    for (n = 0; n < 300; n++)
        one[n] = pf_bank_step_q15(&B, u[n]);
    assert_memory_equal(y, one, sizeof y);
    pf_bank_reset_q15(&A);
    pf_bank_run_q15(&A, u, y, 300);
    assert_memory_equal(y, one, sizeof y);
    assert_int_equal(pf_bank_init_q15(&D, &cd, dbuf, 7), PF_OK);
    pf_bank_run_q15(&D, u, yd, 300);
    for (n = 0; n < 300; n++)
        assert_int_equal(yd[n], n < 7 ? 0 : one[n - 7]);
}

static void init_refuses(void **state)
{
    pf_bank_coeffs_q15 c = one_q15(0.5, 0.5, 0);
    pf_bank_coeffs_f32 cf;
    pf_bank_q15 S;
    pf_bank_f32 F;
    int16_t b[2];
    (void)state;
    assert_int_equal(pf_bank_init_q15(NULL, &c, NULL, 0), PF_E_NULL);
    assert_int_equal(pf_bank_init_q15(&S, NULL, NULL, 0), PF_E_NULL);
    c.sec[0].lam_v = 0;
    assert_int_equal(pf_bank_init_q15(&S, &c, NULL, 0), PF_E_SCALE);
    c.sec[0].lam_v = 32;
    assert_int_equal(pf_bank_init_q15(&S, &c, NULL, 0), PF_E_SCALE);
    c = one_q15(0.5, 0.5, 0);
    c.sec[0].out_sh = 32;
    assert_int_equal(pf_bank_init_q15(&S, &c, NULL, 0), PF_E_SCALE);
    c = one_q15(0.5, 0.5, 0);
    c.out_q = 0;
    assert_int_equal(pf_bank_init_q15(&S, &c, NULL, 0), PF_E_SCALE);
    c.out_q = 14;
    assert_int_equal(pf_bank_init_q15(&S, &c, NULL, 0), PF_E_SCALE);
    c = one_q15(0.5, 0.5, 0);
    c.n_pair = PF_BANK_MAX_ORDER / 2;
    assert_int_equal(pf_bank_init_q15(&S, &c, NULL, 0), PF_E_SCALE);
    c = one_q15(0.5, 0.5, 3);
    assert_int_equal(pf_bank_init_q15(&S, &c, NULL, 0), PF_E_BUFFER);
    assert_int_equal(pf_bank_init_q15(&S, &c, b, 2), PF_E_BUFFER);
    memset(&cf, 0, sizeof cf);
    assert_int_equal(pf_bank_init_f32(&F, NULL, NULL, 0), PF_E_NULL);
    cf.n_sec = PF_BANK_MAX_ORDER + 1;
    assert_int_equal(pf_bank_init_f32(&F, &cf, NULL, 0), PF_E_SCALE);
    cf.n_sec = 0;
    cf.delay_len = 1;
    assert_int_equal(pf_bank_init_f32(&F, &cf, NULL, 0), PF_E_BUFFER);
}

static void float_is_total(void **state)
{
    pf_bank_coeffs_f32 c;
    pf_bank_f32 S;
    const float inputs[] = {NAN, INFINITY, -INFINITY, 3e38f, -3e38f, 1e-40f, 0.5f};
    float y, want = 0.0f;
    int n;
    (void)state;
    memset(&c, 0, sizeof c);
    c.n_sec = 1;
    c.d = 2.0f;
    c.sec[0].lam = 1.5f; /* a pole at z = -0.5 */
    c.sec[0].beta = 0.3f;
    c.sec[0].c = 4.0f;
    assert_int_equal(pf_bank_init_f32(&S, &c, NULL, 0), PF_OK);
    y = pf_bank_step_f32(&S, NAN);
    assert_true(y == 0.0f);
    for (n = 0; n < 7; n++) {
        y = pf_bank_step_f32(&S, inputs[n]);
        assert_true(isfinite(y) && fabsf(y) <= 1e30f);
    }
    /* and it settles back: the states follow the input again */
    for (n = 0; n < 200; n++)
        y = pf_bank_step_f32(&S, 1.0f);
    want = 2.0f + 4.0f * 0.3f;
    assert_true(fabsf(y - want) < 1e-6f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(exact_section),
        cmocka_unit_test(edge_of_the_bound),
        cmocka_unit_test(run_reset_and_delay),
        cmocka_unit_test(init_refuses),
        cmocka_unit_test(float_is_total),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
