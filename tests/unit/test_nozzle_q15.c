/* SPDX-License-Identifier: MIT */
/*
 * The nozzle curve in Q15 against double (bound: docs/architecture.md,
 * "Effects in Q15").
 *  - The table (pf_nozzle_q15.h) against pf_nozzle(): the curve, and the
 *    in-sample loop's solution, for x_1/2 from 2^-24 to 2^6 of x's range
 *    and loop gains L0 from 0 to 1e4 and down to -0.9, over the whole
 *    range of x (both flat ends of the curve included).
 *  - The controller in Q15 against the double runtime, in LSB of out_fs:
 *    every configuration, x_1/2 over four decades, inputs from small
 *    signals to full scale (x far out on both flat ends), with a higher
 *    loop gain, with backlash and supply limits.
 *  - Zero in, zero out; block splitting; refusals.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pf_ctrl_internal.h"
#include "pf_nozzle_q15.h"
#include "pneufrac/pneufrac.h"

#define FS 20000.0
#define XMAX 1073741824.0 /* x's internal range, 2^30 */
#define NRUN 8000          /* samples per controller run */

/* ---- the table ---------------------------------------------------- */

/* The exact loop map W(x) = (x + L0 h(x))/max(1, 1 + L0), unit scale. */
static double exact_map(double x, double xh, double L0)
{
    return (x + L0 * pf_nozzle(x, xh)) / fmax(1.0, 1.0 + L0);
}

/* The x where the exact W(x) = w (bisection; W increases), within
 * [lo, hi]. */
static double exact_inverse(double w, double xh, double L0, double lo, double hi)
{
    int i;
    for (i = 0; i < 60; i++) {
        double mid = 0.5 * (lo + hi);
        if (exact_map(mid, xh, L0) < w)
            lo = mid;
        else
            hi = mid;
    }
    return 0.5 * (lo + hi);
}

/* Largest |table - exact| over x (curve) and over W (solution), in units
 * of the curve's span g = x_1/2/|F'(u0)|, beyond a slack for rounding to
 * integers: 2 units of x for the curve; for the solution 2 more, plus the
 * knots' W rounded by half a unit, which a loop gain L0 < 0 amplifies by
 * up to 1/(1 + L0) on x (pf_controller.h). One unit is x's internal unit
 * (the coefficient set's x scale is 1 here). */
static void table_errors(double xh, double L0, double *curve, double *solve)
{
    static pf_ctrl_coeffs_f64 c;
    static pf_nozzle_q15 nz;
    const double g = xh * 1.5396007178390020;
    /* W's slope is at least min(1 + L0, 1)/max(1 + L0, 1): W rounded to
     * an integer moves the solution by at most half its inverse */
    const double reach = 1.0 + 0.5 * fmax(1.0 + L0, 1.0 / (1.0 + L0));
    double hs;
    long j;
    memset(&c, 0, sizeof c);
    c.loop_inv = 1.0 / (1.0 + L0);
    c.nozzle_xh = xh;
    assert_int_equal(pf_nozzle_q15_make(&nz, &c, 1.0), PF_OK);
    hs = ldexp(1.0, -nz.h_sh);
    /* the operating point is a knot: exact */
    assert_int_equal(pf_nz_h(&nz, 0), 0);
    *curve = *solve = 0.0;
    for (j = 0; j <= 20000; j++) {
        /* half the points over the whole range, half within 6 x_1/2 */
        double xd = j % 2 ? -XMAX + 2.0 * XMAX * j / 20000.0 : (j - 10000) * xh / 1700.0;
        int32_t x = (int32_t)fmax(-XMAX, fmin(XMAX, xd)), h;
        double want = pf_nozzle(x, xh), w = round(exact_map(x, xh, L0)), xs, err;
        err = fabs(pf_nz_h(&nz, x) * hs - want) - 2.0;
        *curve = fmax(*curve, err / g);
        /* the solution for an integer W, against the exact one for it */
        (void)pf_nz_solve(&nz, (int64_t)w, &h);
        xs = exact_inverse(w, xh, L0, fmax(-XMAX, x - reach), fmin(XMAX, x + reach));
        err = fabs(h * hs - pf_nozzle(xs, xh)) - 4.0 - 0.5 / fmin(1.0, 1.0 + L0);
        *solve = fmax(*solve, err / g);
    }
}

/* The bound stated in docs/architecture.md for PF_Q15_NOZZLE_SEG = 32:
 * 2^-16 of the span while |L0| <= 0.02 (every default design is there),
 * 2^-13 for L0 in [-0.9, 1e4], beyond 2 units of x. */
static void test_table_within_bound(void **state)
{
    static const double L0s[] = {0.0, 1e-13, 0.0104, -0.02, 1.04, 104.0, 1e4, -0.5, -0.9};
    size_t i;
    int e;
    (void)state;
    assert_int_equal(PF_Q15_NOZZLE_SEG, 32);
    for (i = 0; i < sizeof L0s / sizeof L0s[0]; i++) {
        double bound = fabs(L0s[i]) <= 0.02 ? ldexp(1.0, -16) : ldexp(1.0, -13);
        double worst_c = 0.0, worst_s = 0.0;
        for (e = -24; e <= 6; e += 3) {
            double c, s;
            table_errors(ldexp(XMAX, e), L0s[i], &c, &s);
            worst_c = fmax(worst_c, c);
            worst_s = fmax(worst_s, s);
        }
        printf("L0 %-8g curve within 2^%.1f, loop solution within 2^%.1f of the span\n",
               L0s[i], log2(fmax(worst_c, 1e-30)), log2(fmax(worst_s, 1e-30)));
        assert_true(worst_c <= bound);
        assert_true(worst_s <= bound);
    }
}

/* ---- the controller ----------------------------------------------- */

typedef struct rig {
    pf_ctrl_design d;
    pf_ctrl_f64 f;
    pf_ctrl_coeffs_q15 cq;
    pf_nozzle_q15 nz;
    pf_ctrl_q15 q;
    double out_fs;
} rig;

/* A deterministic input of one of three shapes at amplitude amp (of
 * in_fs = 1): a step and its reversal, two sines, on/off pulses. */
static int16_t input(int shape, double amp, long n)
{
    double v = shape == 0   ? (n < NRUN / 2 ? amp : -amp)
               : shape == 1 ? amp * sin(2 * M_PI * n * 7.0 / NRUN) +
                                  0.3 * amp * sin(2 * M_PI * n * 311.0 / NRUN)
                            : ((n / 800) % 2 ? amp : 0.0);
    return (int16_t)lrint(fmax(-1.0, fmin(32767.0 / 32768.0, v)) * 32768.0);
}

/* Design with the effects, choose out_fs = 1.25 x the double run's peak
 * for this input (so the output uses its range), and init both. */
static rig *make_rig(pf_topology cfg, double k1_mul, const pf_effects *fx, int shape, double amp)
{
    rig *r = calloc(1, sizeof *r);
    pf_params p;
    pf_design_opts o;
    double peak = 0.0;
    long n;
    assert_non_null(r);
    pf_params_default(&p, cfg);
    p.k1 *= k1_mul;
    pf_design_opts_default(&o, FS);
    assert_int_equal(pf_ctrl_design_make(&r->d, &p, fx, &o), PF_OK);
    assert_int_equal(pf_ctrl_init_f64(&r->f, &r->d.rt, NULL, 0), PF_OK);
    for (n = 0; n < NRUN; n++)
        peak = fmax(peak, fabs(pf_ctrl_step_f64(&r->f, input(shape, amp, n) / 32768.0)));
    pf_ctrl_reset_f64(&r->f);
    r->out_fs = 1.25 * peak;
    assert_int_equal(pf_ctrl_coeffs_q15_make_nz(&r->cq, &r->nz, &r->d, 1.0, r->out_fs), PF_OK);
    assert_int_equal(pf_ctrl_init_q15(&r->q, &r->cq, NULL, 0), PF_OK);
    return r;
}

/* Max |Q15 - double| in LSB of out_fs over one run. */
static double run_compare(pf_topology cfg, double k1_mul, const pf_effects *fx, int shape,
                          double amp)
{
    rig *r = make_rig(cfg, k1_mul, fx, shape, amp);
    double worst = 0.0;
    long n;
    for (n = 0; n < NRUN; n++) {
        int16_t e = input(shape, amp, n);
        double ref = pf_ctrl_step_f64(&r->f, e / 32768.0) / r->out_fs * 32768.0;
        worst = fmax(worst, fabs(pf_ctrl_step_q15(&r->q, e) - ref));
    }
    free(r);
    return worst;
}

/* Every configuration, x_1/2 from lo to hi of in_fs (by decades and
 * between), each shape at a small, a middle and the full amplitude: the
 * full-scale runs drive x far onto both flat ends of the curve (gap
 * closed, and the far tail). */
static double sweep(double k1_mul, double lo, double hi)
{
    static const double xhs[] = {1e-4, 1e-3, 1e-2, 0.05, 0.2, 1.0, 3.0, 30.0};
    static const double amps[] = {0.05, 0.3, 1.0};
    double worst = 0.0;
    int cfg, shape;
    size_t i, a;
    for (cfg = 0; cfg < PF_TOPO_COUNT; cfg++) {
        for (i = 0; i < sizeof xhs / sizeof xhs[0]; i++) {
            pf_effects fx;
            double w = 0.0;
            if (xhs[i] < lo || xhs[i] > hi)
                continue;
            memset(&fx, 0, sizeof fx);
            fx.nozzle_xh = xhs[i];
            for (a = 0; a < sizeof amps / sizeof amps[0]; a++)
                for (shape = 0; shape < 3; shape++)
                    w = fmax(w, run_compare((pf_topology)cfg, k1_mul, &fx, shape, amps[a]));
            printf("%-4s k1 x %-4g x_1/2 %-6g max %.2f LSB\n",
                   pf_topology_name((pf_topology)cfg), k1_mul, xhs[i], w);
            worst = fmax(worst, w);
        }
    }
    return worst;
}

/* The paper's designs (in-sample loop gain L0 <= 0.011): within 1 LSB. */
static void test_controller_matches_double(void **state)
{
    (void)state;
    assert_true(sweep(1.0, 1e-3, 30.0) <= 1.0);
}

/* k1 x 100 (L0 about 1 for id and pid, where the solution leans on the
 * inverse table): within 1.5 LSB. */
static void test_high_loop_gain(void **state)
{
    (void)state;
    assert_true(sweep(100.0, 1e-3, 30.0) <= 1.5);
}

/* A curve 1e4 times narrower than the input's range: one unit of x (2^-28
 * of its design peak) is then about 2^-15 of x_1/2, and x's resolution,
 * not the table, limits the output: within 2 LSB. */
static void test_narrow_curve(void **state)
{
    (void)state;
    assert_true(sweep(1.0, 1e-4, 1e-4) <= 2.0);
    assert_true(sweep(100.0, 1e-4, 1e-4) <= 2.0);
}

/* The nozzle with backlash (dd), and with backlash and supply limits
 * cutting into the response (id): the play's and the limits' cases run
 * through the curve and its inverse. */
static void test_with_backlash_and_saturation(void **state)
{
    int k, shape;
    (void)state;
    for (k = 0; k < 2; k++) {
        pf_effects fx;
        double w = 0.0;
        memset(&fx, 0, sizeof fx);
        fx.nozzle_xh = 0.2;
        fx.backlash = 0.06;
        if (k == 1) {
            fx.saturate = 1;
            fx.sat_lo = -0.2;
            fx.sat_hi = 2.0;
        }
        for (shape = 0; shape < 3; shape++) {
            w = fmax(w, run_compare(k ? PF_TOPO_ID : PF_TOPO_DD, 1.0, &fx, shape, 0.3));
            w = fmax(w, run_compare(k ? PF_TOPO_ID : PF_TOPO_DD, 1.0, &fx, shape, 1.0));
        }
        printf("%s nozzle + backlash%s: max %.2f LSB\n", k ? "id" : "dd",
               k ? " + saturation" : "", w);
        assert_true(w <= 1.0);
    }
}

/* Zero in gives zero out, and any split into blocks the same output. */
static void test_zero_input_and_blocks(void **state)
{
    pf_effects fx;
    rig *r;
    static int16_t e[NRUN], y1[NRUN], y2[NRUN];
    long n;
    size_t at = 0, len = 1;
    (void)state;
    memset(&fx, 0, sizeof fx);
    fx.nozzle_xh = 0.1;
    r = make_rig(PF_TOPO_PID, 1.0, &fx, 0, 0.5);
    for (n = 0; n < NRUN; n++)
        assert_int_equal(pf_ctrl_step_q15(&r->q, 0), 0);
    for (n = 0; n < NRUN; n++)
        e[n] = input(2, 0.7, n);
    pf_ctrl_reset_q15(&r->q);
    pf_ctrl_run_q15(&r->q, e, y1, NRUN);
    pf_ctrl_reset_q15(&r->q);
    while (at < NRUN) {
        len = len * 7 % 911 + 1;
        if (len > NRUN - at)
            len = NRUN - at;
        pf_ctrl_run_q15(&r->q, e + at, y2 + at, len);
        at += len;
    }
    assert_memory_equal(y1, y2, sizeof y1);
    free(r);
}

static void test_refusals(void **state)
{
    static pf_ctrl_design d;
    static pf_ctrl_coeffs_q15 cq;
    static pf_nozzle_q15 nz, bad;
    static pf_ctrl_q15 q;
    pf_effects fx;
    pf_params p;
    pf_design_opts o;
    (void)state;
    memset(&fx, 0, sizeof fx);
    fx.nozzle_xh = 0.1;
    pf_params_default(&p, PF_TOPO_DD);
    pf_design_opts_default(&o, FS);
    assert_int_equal(pf_ctrl_design_make(&d, &p, &fx, &o), PF_OK);
    /* a nozzle needs room for its table */
    assert_int_equal(pf_ctrl_coeffs_q15_make(&cq, &d, 1.0, 1.0), PF_E_BUFFER);
    assert_int_equal(pf_ctrl_coeffs_q15_make_nz(&cq, NULL, &d, 1.0, 1.0), PF_E_BUFFER);
    /* the full scales are checked first, as without a nozzle */
    assert_int_equal(pf_ctrl_coeffs_q15_make_nz(&cq, &nz, &d, NAN, 1.0), PF_E_PARAM(PF_P_IN_FS));
    assert_int_equal(pf_ctrl_coeffs_q15_make_nz(&cq, &nz, &d, 1.0, 1.0), PF_OK);
    assert_ptr_equal(cq.nz, &nz);
    assert_int_equal(pf_ctrl_init_q15(&q, &cq, NULL, 0), PF_OK);
    /* a table that claims more knots than it holds is refused at init */
    bad = nz;
    bad.n = PF_Q15_NOZZLE_SEG + 2;
    cq.nz = &bad;
    assert_int_equal(pf_ctrl_init_q15(&q, &cq, NULL, 0), PF_E_BUFFER);
    bad.n = 2;
    assert_int_equal(pf_ctrl_init_q15(&q, &cq, NULL, 0), PF_E_BUFFER);
    /* the refined approximation stays float/double only */
    o.approx = PF_APPROX_REFINED;
    assert_int_equal(pf_ctrl_design_make(&d, &p, &fx, &o), PF_OK);
    assert_int_equal(pf_ctrl_coeffs_q15_make_nz(&cq, &nz, &d, 1.0, 1.0), PF_E_UNSUPPORTED);
    /* without a nozzle the table is not used */
    fx.nozzle_xh = 0.0;
    pf_design_opts_default(&o, FS);
    assert_int_equal(pf_ctrl_design_make(&d, &p, &fx, &o), PF_OK);
    assert_int_equal(pf_ctrl_coeffs_q15_make_nz(&cq, &nz, &d, 1.0, 1.0), PF_OK);
    assert_null(cq.nz);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_table_within_bound),
        cmocka_unit_test(test_controller_matches_double),
        cmocka_unit_test(test_high_loop_gain),
        cmocka_unit_test(test_narrow_curve),
        cmocka_unit_test(test_with_backlash_and_saturation),
        cmocka_unit_test(test_zero_input_and_blocks),
        cmocka_unit_test(test_refusals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
