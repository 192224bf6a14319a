/* SPDX-License-Identifier: MIT */
/*
 * The run-time choice of arithmetic (pf_runtime.h) and the Q15 edge rule
 * (pf_q15.h), against their headers:
 *  - pf_q15_quantize: round half up, saturation, NaN and bad full scales;
 *  - pf_runtime_* gives, sample for sample and bit for bit, what the typed
 *    runtimes give for the same design, with the documented conversions;
 *  - its signals: Q15 monitors scaled back, or physical values quantised;
 *  - its refusals: NULL, unknown arithmetic, Q15 full scales, buffers.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "pneufrac/pneufrac.h"

#define FS 2000.0
#define N 3000
#define DLEN 64

/* Q15 of full scale 1.0 for x/32768: the rounding cases by their x. */
static void test_quantize_rounds_half_up(void **state)
{
    static const struct {
        double x;
        int want;
    } cases[] = {
        {0.0, 0},           {0.25, 0},         {0.5, 1},
        {0.49999999999999994, 0},              {1.5, 2},
        {-0.25, 0},         {-0.5, 0},         {-0.75, -1},
        {-1.5, -1},         {-2.5, -2},        {100.7, 101},
        {-100.7, -101},     {32766.4, 32766},  {32766.5, 32767},
        {32767.0, 32767},   {32767.9, 32767},  {40000.0, 32767},
        {-32767.5, -32767}, {-32768.0, -32768}, {-32768.6, -32768},
        {-1e300, -32768},   {1e300, 32767},
    };
    size_t i;
    (void)state;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        int got = pf_q15_quantize(cases[i].x / 32768.0, 1.0);
        if (got != cases[i].want)
            print_error("x = %.17g: got %d, want %d\n", cases[i].x, got,
                        cases[i].want);
        assert_int_equal(got, cases[i].want);
    }
}

static void test_quantize_scales_and_edges(void **state)
{
    (void)state;
    /* v = full_scale / 2 is Q15 16384, whatever the full scale. */
    assert_int_equal(pf_q15_quantize(1.0, 2.0), 16384);
    assert_int_equal(pf_q15_quantize(-0.005, 0.01), -16384);
    assert_int_equal(pf_q15_quantize(1e9, 1e-9), INT16_MAX);
    assert_int_equal(pf_q15_quantize(NAN, 1.0), 0);
    assert_int_equal(pf_q15_quantize(INFINITY, 1.0), INT16_MAX);
    assert_int_equal(pf_q15_quantize(-INFINITY, 1.0), INT16_MIN);
    /* No full scale to divide by: 0, never a trap or a wrap. */
    assert_int_equal(pf_q15_quantize(1.0, 0.0), 0);
    assert_int_equal(pf_q15_quantize(1.0, -1.0), 0);
    assert_int_equal(pf_q15_quantize(1.0, NAN), 0);
    assert_int_equal(pf_q15_quantize(1.0, INFINITY), 0);
    /* Back: q * full_scale / 32768, and a round trip is exact. */
    assert_true(pf_q15_value(16384, 2.0) == 1.0);
    assert_true(pf_q15_value(INT16_MIN, 0.5) == -0.5);
    assert_int_equal(pf_q15_quantize(pf_q15_value(-12345, 0.3), 0.3), -12345);
}

static void test_arith_names(void **state)
{
    int a;
    (void)state;
    for (a = 0; a < PF_ARITH_COUNT; a++)
        assert_int_equal(pf_arith_lookup(pf_arith_name((pf_arith)a)), a);
    assert_string_equal(pf_arith_name(PF_ARITH_F64), "double");
    assert_string_equal(pf_arith_name(PF_ARITH_F32), "float");
    assert_string_equal(pf_arith_name(PF_ARITH_Q15), "q15");
    assert_string_equal(pf_arith_name(PF_ARITH_COUNT), "?");
    assert_int_equal(pf_arith_lookup("fixed"), PF_ARITH_COUNT);
    assert_int_equal(pf_arith_lookup(NULL), PF_ARITH_COUNT);
    assert_int_equal(pf_arith_sample_size(PF_ARITH_F64), sizeof(double));
    assert_int_equal(pf_arith_sample_size(PF_ARITH_F32), sizeof(float));
    assert_int_equal(pf_arith_sample_size(PF_ARITH_Q15), sizeof(int16_t));
    assert_int_equal(pf_arith_sample_size(PF_ARITH_COUNT), 0);
}

/* A varying input that crosses the Q15 range and its ties. */
static double input(long n)
{
    return 0.9 * sin(0.013 * (double)n) + 0.3 * ((n / 97) % 3 - 1);
}

typedef struct typed {
    pf_ctrl_f64 f64;
    pf_ctrl_coeffs_f32 cf;
    pf_ctrl_f32 f32;
    pf_ctrl_coeffs_q15 cq;
    pf_ctrl_q15 q15;
    double d64[DLEN];
    float d32[DLEN];
    int16_t dq[DLEN];
} typed;

static pf_ctrl_design design;
static pf_runtime rt;
static typed ty;

/* One sample of the typed runtime of @p arith, with the conversions the
 * header documents; for Q15, *x, *pb, *y receive its monitors scaled back
 * (double and float: the caller reads their sig after the step). */
static double step_typed(pf_arith arith, double e, double in_fs, double out_fs,
                         double *x, double *pb, double *y)
{
    int16_t q, xq, pbq, yq;
    switch (arith) {
    case PF_ARITH_F64:
        return pf_ctrl_step_f64(&ty.f64, e);
    case PF_ARITH_F32:
        return pf_ctrl_step_f32(&ty.f32, (float)e);
    default:
        q = pf_ctrl_step_q15(&ty.q15, pf_q15_quantize(e, in_fs));
        assert_int_equal(rt.out_q15, q);
        pf_ctrl_monitor_q15(&ty.q15, &xq, &pbq, &yq, NULL);
        *x = pf_q15_value(xq, in_fs);
        *pb = pf_q15_value(pbq, design.p.k1 * in_fs);
        *y = pf_q15_value(yq, in_fs);
        return (double)q * out_fs / 32768.0;
    }
}

static void reset_typed(pf_arith arith)
{
    if (arith == PF_ARITH_F64)
        pf_ctrl_reset_f64(&ty.f64);
    else if (arith == PF_ARITH_F32)
        pf_ctrl_reset_f32(&ty.f32);
    else
        pf_ctrl_reset_q15(&ty.q15);
}

/* The typed runtime of @p arith and the tagged one, fed the same input for
 * @p n samples: the outputs and the signals must agree exactly. */
static void compare_run(pf_arith arith, double in_fs, double out_fs, long n_end)
{
    pf_runtime_signals sig;
    long n;
    for (n = 0; n < n_end; n++) {
        double e = input(n), got = pf_runtime_step(&rt, e), x, pb, y;
        double want = step_typed(arith, e, in_fs, out_fs, &x, &pb, &y);
        if (arith == PF_ARITH_F64 || arith == PF_ARITH_F32) {
            /* the typed runtime's signals are read after its step */
            x = arith == PF_ARITH_F64 ? ty.f64.sig.x : ty.f32.sig.x;
            pb = arith == PF_ARITH_F64 ? ty.f64.sig.pb : ty.f32.sig.pb;
            y = arith == PF_ARITH_F64 ? ty.f64.sig.y : ty.f32.sig.y;
        }
        if (got != want)
            print_error("%s, sample %ld: got %.17g, want %.17g\n",
                        pf_arith_name(arith), n, got, want);
        assert_true(got == want);
        pf_runtime_signals_get(&rt, &sig);
        assert_true(sig.pc == got && sig.x == x && sig.pb == pb && sig.y == y);
        assert_int_equal(sig.pc_q15, pf_q15_quantize(got, out_fs));
        assert_int_equal(sig.x_q15, pf_q15_quantize(x, in_fs));
        assert_int_equal(sig.pb_q15, pf_q15_quantize(pb, design.p.k1 * in_fs));
        assert_int_equal(sig.y_q15, pf_q15_quantize(y, in_fs));
    }
}

static void compare(pf_arith arith, double in_fs, double out_fs)
{
    static double dbuf[DLEN];
    assert_int_equal(pf_runtime_init(&rt, &design, arith, in_fs, out_fs, dbuf,
                                     DLEN),
                     PF_OK);
    compare_run(arith, in_fs, out_fs, N);
    /* reset returns both to rest: the run repeats from its start */
    pf_runtime_reset(&rt);
    reset_typed(arith);
    compare_run(arith, in_fs, out_fs, 200);
}

static void setup_typed(pf_topology topo, const pf_effects *fx, double in_fs,
                        double out_fs)
{
    pf_params p;
    pf_design_opts o;
    pf_params_default(&p, topo);
    pf_design_opts_default(&o, FS);
    assert_int_equal(pf_ctrl_design_make(&design, &p, fx, &o), PF_OK);
    assert_int_equal(pf_ctrl_init_f64(&ty.f64, &design.rt, ty.d64, DLEN), PF_OK);
    pf_ctrl_coeffs_f32_make(&ty.cf, &design.rt);
    assert_int_equal(pf_ctrl_init_f32(&ty.f32, &ty.cf, ty.d32, DLEN), PF_OK);
    assert_int_equal(pf_ctrl_coeffs_q15_make(&ty.cq, &design, in_fs, out_fs), PF_OK);
    assert_int_equal(pf_ctrl_init_q15(&ty.q15, &ty.cq, ty.dq, DLEN), PF_OK);
}

static void test_matches_typed_runtimes(void **state)
{
    /* out_fs per configuration: roughly 1.5 x the peak for this input. */
    static const double out_fs[PF_TOPO_COUNT] = {0.03, 0.03, 16.0, 16.0};
    pf_effects fx;
    int c, a, kind;
    (void)state;
    memset(&fx, 0, sizeof fx);
    fx.sat_lo = -1.0;
    fx.sat_hi = 1.0;
    fx.lag = 0.002;
    fx.dead_time = 0.005;
    for (kind = PF_SAT_CLIP; kind <= PF_SAT_STOP; kind++) { /* both placements */
        fx.saturate = kind;
        for (c = 0; c < PF_TOPO_COUNT; c++)
            for (a = 0; a < PF_ARITH_COUNT; a++) {
                setup_typed((pf_topology)c, &fx, 1.25, out_fs[c]);
                compare((pf_arith)a, 1.25, out_fs[c]);
            }
    }
}

static void test_run_is_steps(void **state)
{
    static double e[N], pc[N];
    pf_runtime one;
    long n;
    (void)state;
    setup_typed(PF_TOPO_DD, NULL, 1.0, 0.01);
    for (n = 0; n < N; n++)
        e[n] = input(n);
    assert_int_equal(pf_runtime_init(&rt, &design, PF_ARITH_Q15, 1.0, 0.01, NULL, 0),
                     PF_OK);
    assert_int_equal(pf_runtime_init(&one, &design, PF_ARITH_Q15, 1.0, 0.01, NULL, 0),
                     PF_OK);
    pf_runtime_run(&rt, e, pc, 1000);
    pf_runtime_run(&rt, e + 1000, pc + 1000, N - 1000);
    for (n = 0; n < N; n++)
        assert_true(pc[n] == pf_runtime_step(&one, e[n]));
    /* in place, and reset returns to rest */
    pf_runtime_reset(&rt);
    pf_runtime_run(&rt, e, e, N);
    for (n = 0; n < N; n++)
        assert_true(e[n] == pc[n]);
}

static void test_refusals(void **state)
{
    static double dbuf[DLEN];
    pf_params p;
    pf_design_opts o;
    pf_effects fx;
    (void)state;
    pf_params_default(&p, PF_TOPO_DD);
    pf_design_opts_default(&o, FS);
    memset(&fx, 0, sizeof fx);
    fx.dead_time = 0.01; /* 20 samples */
    assert_int_equal(pf_ctrl_design_make(&design, &p, &fx, &o), PF_OK);
    assert_int_equal(pf_runtime_init(NULL, &design, PF_ARITH_F64, 1, 1, dbuf, DLEN),
                     PF_E_NULL);
    assert_int_equal(pf_runtime_init(&rt, NULL, PF_ARITH_F64, 1, 1, dbuf, DLEN),
                     PF_E_NULL);
    assert_int_equal(pf_runtime_init(&rt, &design, PF_ARITH_COUNT, 1, 1, dbuf, DLEN),
                     PF_E_UNSUPPORTED);
    assert_int_equal(pf_runtime_init(&rt, &design, PF_ARITH_F32, 1, 1, dbuf, 19),
                     PF_E_BUFFER);
    assert_int_equal(pf_runtime_init(&rt, &design, PF_ARITH_F64, 1, 1, NULL, 0),
                     PF_E_BUFFER);
    assert_int_equal(pf_runtime_init(&rt, &design, PF_ARITH_Q15, 0.0, 1, dbuf, DLEN),
                     PF_E_PARAM(PF_P_IN_FS));
    assert_int_equal(pf_runtime_init(&rt, &design, PF_ARITH_Q15, 1, NAN, dbuf, DLEN),
                     PF_E_PARAM(PF_P_OUT_FS));
    /* Double and float need no full scales: their Q15 views are then 0. */
    assert_int_equal(pf_runtime_init(&rt, &design, PF_ARITH_F32, 0, 0, dbuf, 20),
                     PF_OK);
    {
        pf_runtime_signals sig;
        long n;
        for (n = 0; n < 40; n++)
            (void)pf_runtime_step(&rt, 1.0);
        pf_runtime_signals_get(&rt, &sig);
        assert_true(sig.pc != 0.0);
        assert_int_equal(sig.pc_q15, 0);
        assert_int_equal(sig.x_q15, 0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_quantize_rounds_half_up),
        cmocka_unit_test(test_quantize_scales_and_edges),
        cmocka_unit_test(test_arith_names),
        cmocka_unit_test(test_matches_typed_runtimes),
        cmocka_unit_test(test_run_is_steps),
        cmocka_unit_test(test_refusals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
