/* SPDX-License-Identifier: MIT */
/*
 * Fractional operator gain * s^alpha: design formulas, frequency response in
 * the band, exact time responses of s^-a (t^a / Gamma(1+a)), and the three
 * runtimes against each other.
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

static pf_design_opts opts(double fs)
{
    pf_design_opts o;
    pf_design_opts_default(&o, fs);
    return o;
}

/* Round to nearest, ties toward zero: the documented split. */
static void test_split_rounding(void **state)
{
    static const double alpha[] = {0.3, 0.5, 0.6, 0.94, 1.0, 1.5, 1.7,
                                   -0.3, -0.5, -0.6, -0.94, -1.5, -1.9};
    static const int expect[] = {0, 0, 1, 1, 1, 1, 2, 0, 0, -1, -1, -1, -2};
    pf_design_opts o = opts(20000.0), r;
    size_t i;
    (void)state;
    assert_int_equal(pf_design_opts_resolve(&o, &r), PF_OK);
    for (i = 0; i < sizeof alpha / sizeof alpha[0]; i++) {
        double z[PF_MAX_SEC], p[PF_MAX_SEC], k;
        int m, nz, np;
        assert_int_equal(pf_fracop_zpk(alpha[i], &o, &m, &k, z, &nz, p, &np), PF_OK);
        assert_int_equal(m, expect[i]);
        /* an integer order has no approximant at all */
        assert_int_equal(np, fabs(alpha[i] - m) < 1e-12 ? 0 : 2 * r.order + 1);
    }
}

/* Oustaloup's closed form: interlaced zeros and poles, constant ratio
 * p_k/z_k = (wh/wb)^(f/(2N+1)), gain wh^f, all inside [wb, wh]. */
static void test_oustaloup_formula(void **state)
{
    pf_design_opts o = opts(20000.0);
    double z[PF_MAX_SEC], p[PF_MAX_SEC], k, f = 0.3;
    int m, nz, np, i;
    (void)state;
    o.wb = 0.01;
    o.wh = 1e4;
    o.order = 4;
    assert_int_equal(pf_fracop_zpk(f, &o, &m, &k, z, &nz, p, &np), PF_OK);
    assert_int_equal(np, 9);
    assert_true(fabs(k - pow(1e4, f)) < 1e-9 * k);
    for (i = 0; i < np; i++) {
        assert_true(fabs(p[i] / z[i] - pow(1e6, f / 9.0)) < 1e-12);
        assert_true(z[i] > o.wb && p[i] < o.wh);
        if (i > 0)
            assert_true(z[i] > p[i - 1]); /* interlaced */
    }
}

/* Discrete operator vs (j w)^alpha inside the band, away from the edges
 * and from Nyquist, both approximations. */
static void check_band(double alpha, pf_approx ap, double max_db, double max_deg)
{
    pf_design_opts o = opts(20000.0);
    pf_fracop_design op;
    double w, worst_db = 0, worst_deg = 0;
    o.approx = ap;
    assert_int_equal(pf_fracop_design_make(&op, alpha, 1.0, &o), PF_OK);
    for (w = 1.0; w < 1000.0; w *= 1.1) {
        double re, im;
        double complex h, ideal = cpow(I * w, alpha);
        pf_fracop_freqresp(&op, w, &re, &im);
        h = re + I * im;
        if (fabs(20 * log10(cabs(h) / cabs(ideal))) > worst_db)
            worst_db = fabs(20 * log10(cabs(h) / cabs(ideal)));
        if (fabs(carg(h / ideal)) * 180 / M_PI > worst_deg)
            worst_deg = fabs(carg(h / ideal)) * 180 / M_PI;
    }
    printf("alpha %+.2f %-9s in-band error %.3f dB, %.3f deg\n", alpha,
           ap == PF_APPROX_REFINED ? "refined" : "oustaloup", worst_db, worst_deg);
    assert_true(worst_db < max_db);
    assert_true(worst_deg < max_deg);
}

static void test_band_accuracy(void **state)
{
    static const double alphas[] = {0.5, -0.5, 0.8, -0.8, 0.94, -0.94, 1.3, -1.3};
    size_t i;
    (void)state;
    for (i = 0; i < sizeof alphas / sizeof alphas[0]; i++) {
        check_band(alphas[i], PF_APPROX_OUSTALOUP, 0.1, 0.6);
        check_band(alphas[i], PF_APPROX_REFINED, 0.1, 0.6);
    }
}

/* Step response of s^-a is t^a / Gamma(1+a): an exact check of the whole
 * chain (split, approximant, Tustin, parallel form, integer stage). */
static void test_time_response_exact(void **state)
{
    static const double alphas[] = {-0.3, -0.5, -0.8, -1.0, -1.5};
    double fs = 20000.0;
    size_t i;
    (void)state;
    for (i = 0; i < sizeof alphas / sizeof alphas[0]; i++) {
        pf_design_opts o = opts(fs);
        pf_fracop_design op;
        pf_fracop_f64 in;
        double a = -alphas[i], worst = 0, peak = pow(2.0, a) / tgamma(1.0 + a);
        long n;
        assert_int_equal(pf_fracop_design_make(&op, alphas[i], 1.0, &o), PF_OK);
        assert_int_equal(pf_fracop_init_f64(&in, &op), PF_OK);
        for (n = 0; n <= (long)(2.0 * fs); n++) {
            double t = n / fs, y = pf_fracop_step_f64(&in, 1.0);
            if (t >= 1e-3 && fabs(y - pow(t, a) / tgamma(1.0 + a)) > worst)
                worst = fabs(y - pow(t, a) / tgamma(1.0 + a));
        }
        /* Same metric as the controllers' accuracy figures: max error over
         * [1 ms, 2 s] relative to the peak of the response. */
        printf("s^%+.1f step vs t^%.1f/Gamma: max error %.3f %% of peak on [1 ms, 2 s]\n",
               alphas[i], a, 100.0 * worst / peak);
        assert_true(worst / peak < 5e-3);
    }
}

static void test_f32_matches_f64(void **state)
{
    pf_design_opts o = opts(20000.0);
    pf_fracop_design op;
    pf_fracop_coeffs_f32 cf;
    pf_fracop_f64 d;
    pf_fracop_f32 f;
    long n;
    double worst = 0;
    (void)state;
    assert_int_equal(pf_fracop_design_make(&op, -0.9, 2.0, &o), PF_OK);
    pf_fracop_coeffs_f32_make(&cf, &op);
    pf_fracop_init_f64(&d, &op);
    pf_fracop_init_f32(&f, &cf);
    for (n = 0; n < 40000; n++) {
        double u = (n / 4000) % 2 ? 1.0 : -0.5;
        double yd = pf_fracop_step_f64(&d, u);
        double yf = pf_fracop_step_f32(&f, (float)u);
        if (fabs(yd - yf) > worst)
            worst = fabs(yd - yf);
    }
    assert_true(worst < 1e-5 * 2.0 * 2.0); /* |y| stays below ~4 here */
}

/* Q15 operator vs the same design in double, in LSB of out_fs. */
static void test_q15_matches_f64(void **state)
{
    static const double alphas[] = {-0.5, -0.9, 0.5, 0.3};
    size_t i;
    (void)state;
    for (i = 0; i < sizeof alphas / sizeof alphas[0]; i++) {
        pf_design_opts o = opts(20000.0);
        pf_fracop_design op;
        pf_fracop_coeffs_q15 cq;
        pf_fracop_f64 d;
        pf_fracop_q15 q;
        double out_fs = alphas[i] < 0 ? 2.0 : 8.0, worst = 0;
        long n;
        assert_int_equal(pf_fracop_design_make(&op, alphas[i], 1.0, &o), PF_OK);
        assert_int_equal(pf_fracop_coeffs_q15_make(&cq, &op, 1.0, out_fs), PF_OK);
        pf_fracop_init_f64(&d, &op);
        pf_fracop_init_q15(&q, &cq);
        for (n = 0; n < 20000; n++) {
            int16_t u = (n / 2000) % 2 ? 16384 : -8192;
            double ref = pf_fracop_step_f64(&d, u / 32768.0) / out_fs * 32768.0;
            int16_t y = pf_fracop_step_q15(&q, u);
            if (ref > 32767 || ref < -32768)
                continue; /* saturated on purpose would not compare */
            if (fabs(y - ref) > worst)
                worst = fabs(y - ref);
        }
        printf("q15 s^%+.1f: max %.2f LSB vs double\n", alphas[i], worst);
        assert_true(worst <= 2.0);
    }
}

/*
 * The slowest Oustaloup pole of a default design sits within 1e-6 of z = 1.
 * A CMSIS-style Q15 coefficient (resolution 2^-15, or 2^-14 with postShift)
 * cannot hold it: it rounds onto z = 1, an integrator with unbounded DC
 * gain. The leak format holds lam = 1 - a itself with 15 significant bits.
 * The behavioural half: over 5 time constants of the slowest poles, the Q15
 * operator tracks the double design to within 2 LSB.
 */
static void test_q15_low_frequency_poles(void **state)
{
    pf_design_opts o = opts(20000.0);
    pf_fracop_design op;
    pf_fracop_coeffs_q15 cq;
    pf_fracop_f64 d;
    pf_fracop_q15 q;
    double a_min, lam_q, worst = 0;
    long n, N;
    int k;
    (void)state;
    o.t_slow = 0.1; /* wb = 0.1 rad/s keeps the run short */
    assert_int_equal(pf_fracop_design_make(&op, -0.5, 1.0, &o), PF_OK);
    a_min = 1.0 - op.lam[0];
    assert_true(op.lam[0] < 1e-5);
    /* CMSIS Q15: the pole rounds to exactly 1 (and so does Q14). */
    assert_true(round(a_min * 32768.0) / 32768.0 == 1.0);
    assert_true(round(a_min * 16384.0) / 16384.0 == 1.0);
    /* DC gain of the approximant is wb^-1/2 ~ 3.2: out_fs = 4 leaves the
     * half-scale step unsaturated. */
    assert_int_equal(pf_fracop_coeffs_q15_make(&cq, &op, 1.0, 4.0), PF_OK);
    /* The Q15 leak keeps a 15-bit mantissa however small it is: within
     * half a step, 2^-15 of itself. */
    for (k = 0; k < op.n_sec; k++) {
        lam_q = ldexp((double)cq.lam_m[k], -(int)cq.lam_sh[k]);
        assert_true(fabs(lam_q - op.lam[k]) <= ldexp(op.lam[k], -15));
    }
    pf_fracop_init_f64(&d, &op);
    pf_fracop_init_q15(&q, &cq);
    N = (long)(5.0 / (op.lam[0] * 0.5)); /* 5 time constants of the slowest pole */
    for (n = 0; n < N; n++) {
        int16_t u = n < N / 2 ? 16384 : 0;
        double ref = pf_fracop_step_f64(&d, u / 32768.0) / 4.0 * 32768.0;
        int16_t y = pf_fracop_step_q15(&q, u);
        if (fabs(y - ref) > worst)
            worst = fabs(y - ref);
    }
    printf("slowest pole 1-%.3g: q15 tracks double within %.2f LSB over %ld samples\n",
           op.lam[0], worst, N);
    assert_true(worst <= 2.0);
}

static void test_invalid(void **state)
{
    pf_design_opts o = opts(20000.0);
    pf_fracop_design op;
    (void)state;
    assert_int_equal(pf_fracop_design_make(&op, 0.0, 1.0, &o), PF_E_PARAM(PF_P_ALPHA));
    assert_int_equal(pf_fracop_design_make(&op, 2.0, 1.0, &o), PF_E_PARAM(PF_P_ALPHA));
    assert_int_equal(pf_fracop_design_make(&op, NAN, 1.0, &o), PF_E_PARAM(PF_P_ALPHA));
    assert_int_equal(pf_fracop_design_make(&op, 0.5, 0.0, &o), PF_E_PARAM(PF_P_GAIN));
    assert_int_equal(pf_fracop_design_make(&op, 0.5, INFINITY, &o), PF_E_PARAM(PF_P_GAIN));
    o.wb = 10.0;
    o.wh = 5.0;
    assert_int_equal(pf_fracop_design_make(&op, 0.5, 1.0, &o), PF_E_PARAM(PF_P_WB));
    o.wb = 1.0;
    o.wh = 1e6; /* above pi * fs */
    assert_int_equal(pf_fracop_design_make(&op, 0.5, 1.0, &o), PF_E_PARAM(PF_P_WH));
    o.wh = 1e3;
    o.order = PF_MAX_ORDER + 1;
    assert_int_equal(pf_fracop_design_make(&op, 0.5, 1.0, &o), PF_E_PARAM(PF_P_ORDER));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_split_rounding),
        cmocka_unit_test(test_oustaloup_formula),
        cmocka_unit_test(test_band_accuracy),
        cmocka_unit_test(test_time_response_exact),
        cmocka_unit_test(test_f32_matches_f64),
        cmocka_unit_test(test_q15_matches_f64),
        cmocka_unit_test(test_q15_low_frequency_poles),
        cmocka_unit_test(test_invalid),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
