/* SPDX-License-Identifier: MIT */
/*
 * CMSIS-DSP export (pneufrac design --format cmsis-f32 / cmsis-q15), parsed
 * back by compiling the exported headers in, then run through tools/host/pfh_df1
 * (arm_biquad_cascade_df1_f32/_q15 semantics, written from CMSIS's
 * documentation) and compared with the design:
 *  - the conversion itself (pfh_sos in double) is the design's response;
 *  - the float arrays reproduce the operator's response and its step
 *    response (tight);
 *  - the q15 arrays are the documented quantisation of the same cascade,
 *    and a q15 run follows the same cascade computed in double with the
 *    quantised coefficients. How far that cascade is from the design is
 *    printed, not asserted: it is poor by construction (docs/benchmarks.md).
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <complex.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "pneufrac/pneufrac.h"
#include "pfh_sos.h"
#include "pfh_df1.h"
#include "pf_pid_cmsis_f32.h"
#include "pf_pid_cmsis_q15.h"

#define FS 20000.0
#define NOPS 4

typedef struct exported {
    const char *role;
    int n_f32, n_q15, post_shift;
    const float *f32;
    const int16_t *q15;
} exported;

static const exported ops[NOPS] = {
    {"relay", pid_relay_num_stages, pidq_relay_num_stages, pidq_relay_post_shift,
     pid_relay_coeffs, pidq_relay_coeffs},
    {"bellows", pid_bellows_num_stages, pidq_bellows_num_stages,
     pidq_bellows_post_shift, pid_bellows_coeffs, pidq_bellows_coeffs},
    {"restrictor_nu", pid_restrictor_nu_num_stages, pidq_restrictor_nu_num_stages,
     pidq_restrictor_nu_post_shift, pid_restrictor_nu_coeffs, pidq_restrictor_nu_coeffs},
    {"restrictor_w", pid_restrictor_w_num_stages, pidq_restrictor_w_num_stages,
     pidq_restrictor_w_post_shift, pid_restrictor_w_coeffs, pidq_restrictor_w_coeffs},
};

static pf_ctrl_design design;

static const pf_fracop_design *op_of(int i)
{
    const pf_fracop_design *o[NOPS] = {&design.rt.P, &design.rt.Q, &design.rt.V,
                                       &design.rt.W};
    return o[i];
}

static int setup(void **state)
{
    pf_params p;
    pf_design_opts o;
    (void)state;
    pf_params_default(&p, PF_TOPO_PID);
    p.q = 0.9; /* as exported (tests/CMakeLists.txt): all four operators */
    pf_design_opts_default(&o, FS);
    return pf_ctrl_design_make(&design, &p, NULL, &o) == PF_OK ? 0 : -1;
}

/* Worst relative response error over log-spaced omega in [w0, w1]. */
static double worst_rel(const pf_fracop_design *op, const pfh_sos *s,
                        double w0, double w1)
{
    double worst = 0.0;
    int i;
    for (i = 0; i <= 200; i++) {
        double w = w0 * pow(w1 / w0, i / 200.0);
        double complex want = pfh_sos_op_resp(op, w);
        double complex got = pfh_sos_resp(s, w);
        double e = cabs(got - want) / cabs(want);
        if (e > worst)
            worst = e;
    }
    return worst;
}

static void test_conversion_is_the_design(void **state)
{
    int i;
    (void)state;
    for (i = 0; i < NOPS; i++) {
        pfh_sos s;
        double e;
        assert_int_equal(pfh_sos_from_op(&s, op_of(i), &design.opt, 1.0), PF_OK);
        /* From the slowest pole to 0.9 x Nyquist, in double. */
        e = worst_rel(op_of(i), &s, 1e-4, 0.9 * M_PI * FS);
        printf("  %-14s double cascade vs design: %.2e\n", ops[i].role, e);
        assert_true(e < 1e-7);
    }
}

/* The float cascade computed in double: what the exported values stand
 * for, free of float's rounding of the signals. */
static double run_double(const pfh_sos *s, double st[][4], double v)
{
    int k;
    for (k = 0; k < s->n; k++) {
        double out = s->b[k][0] * v + s->b[k][1] * st[k][0] + s->b[k][2] * st[k][1] +
                     s->a[k][0] * st[k][2] + s->a[k][1] * st[k][3];
        st[k][1] = st[k][0];
        st[k][0] = v;
        st[k][3] = st[k][2];
        st[k][2] = out;
        v = out;
    }
    return v;
}

static void sos_of_f32(pfh_sos *s, const float *c, int n)
{
    int k;
    memset(s, 0, sizeof *s);
    s->n = n;
    s->fs = FS;
    for (k = 0; k < n; k++) {
        s->b[k][0] = c[5 * k];
        s->b[k][1] = c[5 * k + 1];
        s->b[k][2] = c[5 * k + 2];
        s->a[k][0] = c[5 * k + 3];
        s->a[k][1] = c[5 * k + 4];
    }
}

/* Float: the arrays are the design rounded to float. The rounding moves
 * the slow poles (a pole at 1 - lam with lam ~ 1e-7 .. 1e-4 is fixed by
 * 1 - a1 - a2 = lam1 lam2, below float's resolution), so the response is
 * checked where float can hold it: from 100 rad/s (0.5 %) and from
 * 1000 rad/s (1e-4) to half the Nyquist frequency; below, docs/benchmarks.md
 * shows the damage. The float run itself must follow the same cascade in
 * double over the first 50 ms of a step, up to float's rounding of the
 * signals, which the slow poles amplify (measured 1.6e-3 of the peak). */
static void test_f32_export(void **state)
{
    int i;
    (void)state;
    for (i = 0; i < NOPS; i++) {
        enum { LEN = 1000 };
        const pf_fracop_design *op = op_of(i);
        static float x[LEN], y[LEN];
        float st[4 * PFH_SOS_MAX];
        double ds[PFH_SOS_MAX][4], hi, mid, run = 0.0, peak = 0.0;
        pfh_df1_f32 f = {ops[i].n_f32, ops[i].f32, st};
        pfh_sos s;
        long n;

        sos_of_f32(&s, ops[i].f32, ops[i].n_f32);
        mid = worst_rel(op, &s, 100.0, 0.5 * M_PI * FS);
        hi = worst_rel(op, &s, 1000.0, 0.5 * M_PI * FS);
        memset(st, 0, sizeof st);
        memset(ds, 0, sizeof ds);
        for (n = 0; n < LEN; n++)
            x[n] = 1.0f;
        pfh_df1_run_f32(&f, x, y, LEN);
        for (n = 0; n < LEN; n++) {
            double r = run_double(&s, ds, 1.0);
            if (fabs(r) > peak)
                peak = fabs(r);
            if (fabs(y[n] - r) > run)
                run = fabs(y[n] - r);
        }
        printf("  %-14s f32: response %.2e from 100 rad/s, %.2e from 1000 rad/s; "
               "run vs double %.2e of peak\n", ops[i].role, mid, hi, run / peak);
        assert_true(mid < 5e-3);
        assert_true(hi < 1e-4);
        assert_true(run / peak < 5e-3);
    }
}

static void test_q15_layout(void **state)
{
    int i, k;
    (void)state;
    for (i = 0; i < NOPS; i++) {
        pfh_sos s;
        pfh_sos_q15 q;
        assert_int_equal(pfh_sos_from_op(&s, op_of(i), &design.opt, 1.0), PF_OK);
        assert_int_equal(pfh_sos_q15_make(&s, &q), PF_OK);
        assert_int_equal(q.n, ops[i].n_q15);
        assert_int_equal(q.post_shift, ops[i].post_shift);
        assert_true(q.post_shift >= 0 && q.post_shift <= 15);
        for (k = 0; k < q.n; k++) {
            const int16_t *c = ops[i].q15 + 6 * k;
            double v[5] = {s.b[k][0], s.b[k][1], s.b[k][2], s.a[k][0], s.a[k][1]};
            const int at[5] = {0, 2, 3, 4, 5};
            int j;
            assert_int_equal(c[1], 0); /* the documented padding */
            for (j = 0; j < 5; j++) /* rounding to nearest, one LSB apart */
                assert_true(fabs(pfh_sos_q15_value(&q, c[at[j]]) - v[j]) <=
                            0.5 * ldexp(1.0, q.post_shift - 15) + 1e-12);
        }
        assert_memory_equal(q.c, ops[i].q15, sizeof(int16_t) * 6 * (size_t)q.n);
    }
}

/* The q15 run is bit-exact with the documented arithmetic computed
 * independently in double (integer products and sums below 2^53 are exact
 * there): floor(acc / 2^(15 - postShift)), saturated to 16 bits. How far
 * that truncation takes it from the unrounded cascade is printed. */
static void test_q15_semantics(void **state)
{
    int i, k;
    (void)state;
    for (i = 0; i < NOPS; i++) {
        enum { LEN = 2000 };
        static int16_t x[LEN], y[LEN];
        int16_t st[4 * PFH_SOS_MAX];
        double ds[PFH_SOS_MAX][4], es[PFH_SOS_MAX][4], drift = 0.0;
        pfh_df1_q15 f = {ops[i].n_q15, ops[i].post_shift, ops[i].q15, st};
        pfh_sos exact;
        pfh_sos_q15 q;
        long n;

        q.post_shift = ops[i].post_shift;
        memset(&exact, 0, sizeof exact);
        exact.n = f.n;
        exact.fs = FS;
        for (k = 0; k < f.n; k++) {
            const int16_t *c = ops[i].q15 + 6 * k;
            exact.b[k][0] = pfh_sos_q15_value(&q, c[0]);
            exact.b[k][1] = pfh_sos_q15_value(&q, c[2]);
            exact.b[k][2] = pfh_sos_q15_value(&q, c[3]);
            exact.a[k][0] = pfh_sos_q15_value(&q, c[4]);
            exact.a[k][1] = pfh_sos_q15_value(&q, c[5]);
        }
        memset(st, 0, sizeof st);
        memset(ds, 0, sizeof ds);
        memset(es, 0, sizeof es);
        for (n = 0; n < LEN; n++)
            x[n] = (int16_t)lround(300.0 * sin(0.05 * n) + 200.0 * sin(0.9 * n));
        pfh_df1_run_q15(&f, x, y, LEN);
        for (n = 0; n < LEN; n++) {
            double v = x[n], d = run_double(&exact, es, x[n]);
            for (k = 0; k < f.n; k++) {
                const int16_t *c = ops[i].q15 + 6 * k;
                double acc = c[0] * v + c[2] * ds[k][0] + c[3] * ds[k][1] +
                             c[4] * ds[k][2] + c[5] * ds[k][3];
                double out = floor(acc / ldexp(1.0, 15 - f.post_shift));
                out = out > 32767.0 ? 32767.0 : (out < -32768.0 ? -32768.0 : out);
                ds[k][1] = ds[k][0];
                ds[k][0] = v;
                ds[k][3] = ds[k][2];
                ds[k][2] = out;
                v = out;
            }
            assert_true(y[n] == v);
            if (fabs(y[n] - d) > drift)
                drift = fabs(y[n] - d);
        }
        printf("  %-14s q15 run bit-exact with CMSIS arithmetic; %.0f LSB from the "
               "unrounded cascade after %d samples\n", ops[i].role, drift, LEN);
    }
}

static void test_q15_against_design(void **state)
{
    int i;
    (void)state;
    for (i = 0; i < NOPS; i++) {
        pfh_sos s;
        int k, j;
        double e_lo, e_mid;
        s.n = ops[i].n_q15;
        s.fs = FS;
        for (k = 0; k < s.n; k++) {
            pfh_sos_q15 q;
            const int16_t *c = ops[i].q15 + 6 * k;
            q.post_shift = ops[i].post_shift;
            for (j = 0; j < 3; j++)
                s.b[k][j] = pfh_sos_q15_value(&q, c[j == 0 ? 0 : j + 1]);
            s.a[k][0] = pfh_sos_q15_value(&q, c[4]);
            s.a[k][1] = pfh_sos_q15_value(&q, c[5]);
        }
        e_lo = worst_rel(op_of(i), &s, 10 * design.opt.wb, 10.0);
        e_mid = worst_rel(op_of(i), &s, 100.0, 0.5 * M_PI * FS);
        printf("  %-14s q15 coefficients vs design: %.3g below 10 rad/s, %.3g above 100 rad/s\n",
               ops[i].role, e_lo, e_mid);
        assert_true(isfinite(e_mid));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_conversion_is_the_design),
        cmocka_unit_test(test_f32_export),
        cmocka_unit_test(test_q15_layout),
        cmocka_unit_test(test_q15_semantics),
        cmocka_unit_test(test_q15_against_design),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
