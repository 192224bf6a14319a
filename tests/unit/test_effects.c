/* SPDX-License-Identifier: MIT */
/*
 * Black-box tests of the effects: the play operator and the nozzle curve
 * on their own, validation of the effect parameters against the limits in
 * pf_effects.h (and the design's cap on the dead time), and then every
 * effect inside a real controller (Example 6, FrDD, f64 runtime at fs =
 * 20 kHz), checked against what the physics says it must do and against
 * the recorded loop signals (pf_ctrl_f64.sig).
 *
 * The recorded signals make the in-loop solution checkable from outside:
 * sig.e is the input as the lever sees it (the held-input mean with
 * PF_INPUT_HOLD), and whatever the solver does, the flapper lever (eq. 15)
 * must hold exactly on the recorded signals, p_b must be k1 times the
 * play/nozzle image of that x, and the saturated p_c must stay inside its
 * limits. An effect applied outside the loop, or not at all, breaks one of
 * these relations.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pneufrac/pneufrac.h"
/* soft checks: print the first few offending samples, then fail once */
#define SOFT_MAX_PRINT 8
#include "test_util.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#define FS 20000.0
#define NS 4000 /* 0.2 s: several relay and restrictor time constants */

/* ------------------------------------------------------------------ */
/* pf_play                                                              */
/* ------------------------------------------------------------------ */

static void test_play_operator(void **state)
{
    const double r = 0.25;
    const double prevs[] = {-3.0, -0.1, 0.0, 0.7, 2.0};
    size_t i;
    (void)state;
    for (i = 0; i < sizeof prevs / sizeof prevs[0]; i++) {
        const double p = prevs[i];
        double x, last = -INFINITY;
        /* inside the band the output does not move at all */
        EXPECT(pf_play(p, p, r) == p, "play(%g,%g)", p, p);
        EXPECT(pf_play(p, p + r, r) == p, "band edge +r");
        EXPECT(pf_play(p, p - r, r) == p, "band edge -r");
        EXPECT(pf_play(p, p + 0.9 * r, r) == p, "inside +");
        EXPECT(pf_play(p, p - 0.9 * r, r) == p, "inside -");
        /* beyond it the output trails the input at distance r */
        EXPECT(fabs(pf_play(p, p + 3.0, r) - (p + 3.0 - r)) <= 1e-15 * (fabs(p) + 4),
               "follow up: %g", pf_play(p, p + 3.0, r));
        EXPECT(fabs(pf_play(p, p - 3.0, r) - (p - 3.0 + r)) <= 1e-15 * (fabs(p) + 4),
               "follow down: %g", pf_play(p, p - 3.0, r));
        /* monotone non-decreasing in x, and never further than r from x */
        for (x = p - 5.0; x <= p + 5.0; x += 0.01) {
            double y = pf_play(p, x, r);
            EXPECT(y >= last, "play not monotone at x=%g (prev %g)", x, p);
            EXPECT(fabs(y - x) <= r * (1 + 1e-12), "play output %g too far from x=%g", y, x);
            last = y;
        }
    }
    /* r = 0 is the identity */
    EXPECT(pf_play(1.0, -2.5, 0.0) == -2.5, "play r=0");
    EXPECT(pf_play(-1.0, 3.0, 0.0) == 3.0, "play r=0");

    /* a sequence: up, small reversal (held), large reversal (follows) */
    {
        double y = 0.0;
        y = pf_play(y, 1.0, r);  EXPECT(y == 0.75, "seq 1: %g", y);
        y = pf_play(y, 0.6, r);  EXPECT(y == 0.75, "seq 2: %g", y);
        y = pf_play(y, 0.55, r); EXPECT(y == 0.75, "seq 3: %g", y);
        y = pf_play(y, 0.4, r);  EXPECT(fabs(y - 0.65) < 1e-15, "seq 4: %g", y);
        y = pf_play(y, 0.8, r);  EXPECT(fabs(y - 0.65) < 1e-15, "seq 5: %g", y);
    }
    END_SOFT();
}

/* ------------------------------------------------------------------ */
/* pf_nozzle                                                            */
/* ------------------------------------------------------------------ */

/* Independent oracle from the header's formula. */
static double nozzle_ref(double x, double xh)
{
    const double u0 = 1.0 / sqrt(3.0);
    double u = u0 + x / xh;
    double F0 = 1.0 / (1.0 + u0 * u0);
    double dF0 = 2.0 * u0 / ((1.0 + u0 * u0) * (1.0 + u0 * u0));
    if (u < 0.0)
        u = 0.0; /* the gap cannot close below 0 */
    return xh * (F0 - 1.0 / (1.0 + u * u)) / dF0;
}

static void test_nozzle_curve(void **state)
{
    const double xhs[] = {1e-3, 0.5, 1.0, 40.0};
    size_t i;
    (void)state;
    for (i = 0; i < sizeof xhs / sizeof xhs[0]; i++) {
        const double xh = xhs[i];
        double x, last = -INFINITY, h = 1e-6 * xh, slope;
        EXPECT(fabs(pf_nozzle(0.0, xh)) <= 1e-15 * xh, "h(0) = %g (xh %g)",
               pf_nozzle(0.0, xh), xh);
        /* unit slope at the operating point: the linear model of eq. 9 */
        slope = (pf_nozzle(h, xh) - pf_nozzle(-h, xh)) / (2 * h);
        EXPECT(fabs(slope - 1.0) < 1e-6, "slope at 0 = %.12g (xh %g)", slope, xh);
        /* u0 is the inflection point, so the curvature vanishes there too:
         * the one-sided difference quotients agree to O(h^2) */
        EXPECT(fabs(pf_nozzle(h, xh) / h - 1.0) < 1e-9, "h(x)/x near 0 (xh %g)", xh);
        for (x = -10.0 * xh; x <= 10.0 * xh; x += 0.001 * xh) {
            double y = pf_nozzle(x, xh), want = nozzle_ref(x, xh);
            EXPECT(y >= last, "nozzle not monotone at x=%g (xh %g): %g < %g", x, xh, y, last);
            EXPECT(isfinite(y), "nozzle(%g, %g) not finite", x, xh);
            EXPECT(fabs(y - want) <= 1e-12 * xh, "nozzle(%g, %g) = %.15g, formula %.15g",
                   x, xh, y, want);
            last = y;
        }
        /* the gap closed: flat at xh (F(u0) - 1)/|F'(u0)| for x < -u0 xh */
        EXPECT(pf_nozzle(-2.0 * xh, xh) == pf_nozzle(-100.0 * xh, xh),
               "not flat once the gap is closed (xh %g)", xh);
        EXPECT(fabs(pf_nozzle(-1e6 * xh, xh) - nozzle_ref(-1.0, 1.0) * xh) <= 1e-12 * xh,
               "floor %g", pf_nozzle(-1e6 * xh, xh));
        /* far open: approaches xh F(u0)/|F'(u0)| from below */
        EXPECT(pf_nozzle(1e6 * xh, xh) < xh * 0.75 / (9.0 / (8.0 * sqrt(3.0))) &&
                   pf_nozzle(1e6 * xh, xh) > 0.99 * xh * 0.75 / (9.0 / (8.0 * sqrt(3.0))),
               "ceiling %g", pf_nozzle(1e6 * xh, xh));
        EXPECT(isfinite(pf_nozzle(DBL_MAX, xh)) && isfinite(pf_nozzle(-DBL_MAX, xh)),
               "nozzle at +-DBL_MAX not finite (xh %g)", xh);
    }
    END_SOFT();
}

/* The biased curve against the header's formula with u0 = 1/sqrt(3) + bias. */
static double nozzle_biased_ref(double x, double xh, double bias)
{
    const double u0 = 1.0 / sqrt(3.0) + bias;
    double u = u0 + x / xh;
    double F0 = 1.0 / (1.0 + u0 * u0);
    double dF0 = 2.0 * u0 / ((1.0 + u0 * u0) * (1.0 + u0 * u0));
    if (u < 0.0)
        u = 0.0;
    return xh * (F0 - 1.0 / (1.0 + u * u)) / dF0;
}

static void test_nozzle_biased_curve(void **state)
{
    const double biases[] = {-0.5, -0.3, 0.0, 0.4, 2.0, 10.0};
    const double xhs[] = {0.5, 3.0};
    size_t i, j;
    (void)state;
    for (i = 0; i < sizeof biases / sizeof biases[0]; i++)
        for (j = 0; j < sizeof xhs / sizeof xhs[0]; j++) {
            const double b = biases[i], xh = xhs[j], h = 1e-6 * xh, a = 0.3 * xh;
            double x, last = -INFINITY, slope, asym;
            EXPECT(fabs(pf_nozzle_biased(0.0, xh, b)) <= 1e-13 * xh, "h(0) (bias %g)", b);
            slope = (pf_nozzle_biased(h, xh, b) - pf_nozzle_biased(-h, xh, b)) / (2 * h);
            EXPECT(fabs(slope - 1.0) < 1e-6, "slope at the bias point %.12g (bias %g)", slope, b);
            for (x = -10.0 * xh; x <= 10.0 * xh; x += 0.001 * xh) {
                double y = pf_nozzle_biased(x, xh, b), want = nozzle_biased_ref(x, xh, b);
                EXPECT(y >= last, "not monotone at x=%g (bias %g)", x, b);
                EXPECT(fabs(y - want) <= 1e-11 * fmax(xh, fabs(want)),
                       "nozzle_biased(%g, %g, %g) = %.15g, formula %.15g", x, xh, b, y, want);
                last = y;
            }
            /* off the inflection the curve is not odd: beyond it (bias > 0)
             * the gain falls for x > 0 and rises for x < 0, before it the
             * other way round; at it the even part starts at fourth order */
            asym = pf_nozzle_biased(a, xh, b) + pf_nozzle_biased(-a, xh, b);
            if (b > 0)
                EXPECT(asym < -1e-3 * a, "bias %g: h(a) + h(-a) = %g, want < 0", b, asym);
            else if (b < 0)
                EXPECT(asym > 1e-3 * a, "bias %g: h(a) + h(-a) = %g, want > 0", b, asym);
            else
                EXPECT(fabs(asym) <= 0.05 * a, "inflection: h(a) + h(-a) = %g", asym);
        }
    /* Near the bias point (x far below x_1/2: a nearly linear nozzle, as a
     * fit passes on its way to none) every digit is kept, relative to h
     * itself: F(u0) - F(u) = (u - u0)(u + u0) F(u0) F(u) exactly, the
     * reference here. A difference of the two F values keeps 1e-4 of h at
     * x = 1e-12 x_1/2, and the controller's loop solve cannot meet its
     * tolerance on such a curve (pf_ctrl_float.inc). */
    for (i = 0; i < sizeof biases / sizeof biases[0]; i++) {
        const double b = biases[i], xh = 2.0, u0 = 1.0 / sqrt(3.0) + b;
        double r;
        for (r = 1e-12; r <= 1e-2; r *= 100.0) {
            int sgn;
            for (sgn = -1; sgn <= 1; sgn += 2) {
                const double d = sgn * r, u = u0 + d;
                const double want = xh * d * (u + u0) * (1.0 + u0 * u0) /
                                    (2.0 * u0 * (1.0 + u * u));
                const double y = pf_nozzle_biased(d * xh, xh, b);
                EXPECT(fabs(y - want) <= 1e-13 * fabs(want),
                       "nozzle_biased(%g x_1/2, bias %g) = %.17g, want %.17g", d, b, y, want);
            }
        }
    }
    /* bias 0 is pf_nozzle */
    EXPECT(pf_nozzle_biased(0.37, 1.3, 0.0) == pf_nozzle(0.37, 1.3), "bias 0 != pf_nozzle");
    END_SOFT();
}

/* ------------------------------------------------------------------ */
/* pf_effects_validate                                                  */
/* ------------------------------------------------------------------ */

/* pf_effects.h: all finite; backlash, nozzle_xh and lag in [0, 1e9]; with
 * saturate, |sat_lo|, |sat_hi| <= 1e9 and sat_lo < sat_hi; dead_time in
 * [0, 3600] s (the design also caps it at 4194304 samples). */
#define FX_MAX 1e9
#define DEAD_TIME_MAX 3600.0
#define DELAY_MAX 4194304.0 /* samples */

static void expect_fx(const pf_effects *fx, pf_param_id id, const char *what)
{
    expect_names(pf_effects_validate(fx), id, what);
}

static void expect_fx_ok(const pf_effects *fx, const char *what)
{
    pf_status st = pf_effects_validate(fx);
    EXPECT(st == PF_OK && pf_effects_any(fx), "%s: status %d (%s), any %d", what, st,
           pf_param_name(pf_status_param(st)), pf_effects_any(fx));
}

/* One of the non-negative effects (backlash, nozzle_xh, lag, dead_time):
 * bad values, values beyond its upper limit, and the ends of its range
 * (each alone counts as "on"). */
static void check_nonneg_effect(pf_param_id id, double max)
{
    const double bad[] = {-1.0, -1e-300, NAN, INFINITY, -INFINITY,
                          max * (1.0 + 1e-9), max * 10.0, DBL_MAX};
    const double ok[] = {1e-300, 0.01, max};
    pf_effects fx;
    double *field = id == PF_P_BACKLASH    ? &fx.backlash
                    : id == PF_P_NOZZLE_XH ? &fx.nozzle_xh
                    : id == PF_P_LAG       ? &fx.lag
                                           : &fx.dead_time;
    size_t i;
    char what[64];
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        memset(&fx, 0, sizeof fx);
        *field = bad[i];
        snprintf(what, sizeof what, "%s = %.17g", pf_param_name(id), bad[i]);
        expect_fx(&fx, id, what);
    }
    for (i = 0; i < sizeof ok / sizeof ok[0]; i++) {
        memset(&fx, 0, sizeof fx);
        *field = ok[i];
        snprintf(what, sizeof what, "%s = %g alone", pf_param_name(id), ok[i]);
        expect_fx_ok(&fx, what);
    }
}

static void test_effects_validate(void **state)
{
    /* saturation limits; alt is a second fair name (lo >= hi), or COUNT */
    static const struct {
        double lo, hi;
        pf_param_id want, alt;
    } sat[] = {
        {NAN, 1.0, PF_P_SAT_LO, PF_P_COUNT},
        {-1.0, NAN, PF_P_SAT_HI, PF_P_COUNT},
        {-INFINITY, 1.0, PF_P_SAT_LO, PF_P_COUNT},
        {-1.0, INFINITY, PF_P_SAT_HI, PF_P_COUNT},
        {-1.000001e9, 1.0, PF_P_SAT_LO, PF_P_COUNT},
        {-1.0, 1.000001e9, PF_P_SAT_HI, PF_P_COUNT},
        {2.0, 1.0, PF_P_SAT_LO, PF_P_SAT_HI},
        {1.0, 1.0, PF_P_SAT_LO, PF_P_SAT_HI},
        /* found while |limit| <= 1e9 was enforced but undocumented */
        {-1e10, 1e10, PF_P_SAT_LO, PF_P_SAT_HI},
        /* valid */
        {-1.0, 1.0, PF_P_COUNT, PF_P_COUNT},
        {-FX_MAX, FX_MAX, PF_P_COUNT, PF_P_COUNT},
        {0.5 * FX_MAX, FX_MAX, PF_P_COUNT, PF_P_COUNT},
    };
    pf_effects fx;
    pf_status st;
    size_t i;
    char what[64];
    (void)state;

    memset(&fx, 0, sizeof fx);
    EXPECT(pf_effects_validate(&fx) == PF_OK, "zeroed effects rejected");
    EXPECT(!pf_effects_any(&fx), "zeroed effects reported on");

    check_nonneg_effect(PF_P_BACKLASH, FX_MAX);
    check_nonneg_effect(PF_P_NOZZLE_XH, FX_MAX);
    check_nonneg_effect(PF_P_LAG, FX_MAX);
    check_nonneg_effect(PF_P_DEAD_TIME, DEAD_TIME_MAX);

    for (i = 0; i < sizeof sat / sizeof sat[0]; i++) {
        memset(&fx, 0, sizeof fx);
        fx.saturate = 1;
        fx.sat_lo = sat[i].lo;
        fx.sat_hi = sat[i].hi;
        snprintf(what, sizeof what, "saturation [%g, %g]", sat[i].lo, sat[i].hi);
        if (sat[i].want == PF_P_COUNT)
            expect_fx_ok(&fx, what);
        else if (sat[i].alt == PF_P_COUNT)
            expect_fx(&fx, sat[i].want, what);
        else
            expect_names_one_of(pf_effects_validate(&fx), sat[i].want, sat[i].alt, what);
    }
    /* limits of a disabled saturation are not looked at */
    memset(&fx, 0, sizeof fx); fx.saturate = 0; fx.sat_lo = 2.0; fx.sat_hi = 1.0;
    EXPECT(pf_effects_validate(&fx) == PF_OK, "unused sat limits checked");
    fx.sat_lo = -1e300; fx.sat_hi = NAN;
    EXPECT(pf_effects_validate(&fx) == PF_OK, "unused sat limits checked (range)");

    /* found while these limits were enforced but undocumented: backlash,
     * lag and nozzle_xh all 1e10 at once; any of the three is a fair name */
    memset(&fx, 0, sizeof fx);
    fx.backlash = 1e10;
    fx.lag = 1e10;
    fx.nozzle_xh = 1e10;
    st = pf_effects_validate(&fx);
    EXPECT(st == PF_E_PARAM(PF_P_BACKLASH) || st == PF_E_PARAM(PF_P_LAG) ||
               st == PF_E_PARAM(PF_P_NOZZLE_XH),
           "backlash = lag = nozzle_xh = 1e10: %d (%s)", st, pf_param_name(pf_status_param(st)));
    EXPECT(pf_effects_validate(NULL) == PF_E_NULL, "validate(NULL)");
    END_SOFT();
}

/* ------------------------------------------------------------------ */
/* Effects inside the controller                                        */
/* ------------------------------------------------------------------ */

typedef struct trace {
    double out[NS];
    pf_ctrl_signals_f64 sig[NS];
} trace;

static pf_ctrl_design g_d;
static trace g_a, g_b, g_c;
static double g_e[NS], g_e2[NS];

/* The defaults of cfg at FS with effects fx (NULL: none). */
static pf_status try_design(pf_ctrl_design *d, pf_topology cfg, const pf_effects *fx,
                            pf_input_model in)
{
    pf_params p;
    pf_design_opts o;
    pf_params_default(&p, cfg);
    memset(&o, 0, sizeof o);
    o.fs = FS;
    o.input = in;
    return pf_ctrl_design_make(d, &p, fx, &o);
}

static void design_cfg(pf_ctrl_design *d, pf_topology cfg, const pf_effects *fx,
                       pf_input_model in)
{
    pf_status st = try_design(d, cfg, fx, in);
    if (st != PF_OK)
        fail_msg("design_make(%s) = %d (%s)", pf_topology_name(cfg), st,
                 pf_param_name(pf_status_param(st)));
}

/* Example 6 (FrDD), the controller every in-loop check runs on. */
static void design_dd(pf_ctrl_design *d, const pf_effects *fx)
{
    design_cfg(d, PF_TOPO_DD, fx, PF_INPUT_HOLD);
}

static void run(const pf_ctrl_design *d, const double *e, size_t n, trace *t)
{
    pf_ctrl_f64 in;
    double *buf = NULL;
    size_t k;
    if (d->rt.delay_len > 0) {
        buf = calloc(d->rt.delay_len, sizeof *buf);
        assert_non_null(buf);
    }
    assert_int_equal(pf_ctrl_init_f64(&in, &d->rt, buf, d->rt.delay_len), PF_OK);
    for (k = 0; k < n; k++) {
        t->out[k] = pf_ctrl_step_f64(&in, e[k]);
        t->sig[k] = in.sig;
    }
    free(buf);
}

/* A step of height amp*offset with two tones on top: reversals of every
 * size. With offset 0 the FrDD output takes both signs. */
static void make_input_off(double *e, double amp, double offset)
{
    size_t k;
    for (k = 0; k < NS; k++) {
        double t = (double)k / FS;
        e[k] = amp * (offset + 0.5 * sin(2 * M_PI * 37.0 * t) +
                      0.3 * sin(2 * M_PI * 410.0 * t + 0.3));
    }
}

static void make_input(double *e, double amp)
{
    make_input_off(e, amp, 0.6);
}

static double peak(const double *v, size_t n)
{
    double m = 0;
    size_t k;
    for (k = 0; k < n; k++)
        if (fabs(v[k]) > m)
            m = fabs(v[k]);
    return m;
}

/* Eq. 15 on the recorded signals: x = b/(a+b) e - a/(a+b) y, whatever
 * nonlinearity sits between x and p_c. This is the residual of the
 * in-loop equation, so it checks that the loop was actually solved. sig.e
 * is the input as the lever sees it (the held-input mean in PF_INPUT_HOLD). */
static void check_lever(const pf_ctrl_design *d, const trace *t, const char *what)
{
    const double ce = d->p.b / (d->p.a + d->p.b), cy = d->p.a / (d->p.a + d->p.b);
    size_t k;
    for (k = 0; k < NS; k++) {
        const pf_ctrl_signals_f64 *s = &t->sig[k];
        double want = ce * s->e - cy * s->y;
        double tol = 1e-12 * (fabs(ce * s->e) + fabs(cy * s->y)) + 1e-300;
        EXPECT(fabs(s->x - want) <= tol, "%s: k=%zu x=%.17g, ce e - cy y = %.17g (diff %.3g)",
               what, k, s->x, want, s->x - want);
        EXPECT(isfinite(s->x) && isfinite(s->pc) && isfinite(s->y), "%s: k=%zu non-finite",
               what, k);
    }
}

/* sig.e is the input as the lever sees it: the sample itself with a
 * linear input, the mean of the last two samples with a held one
 * (pf_controller.h); the state starts at rest, so e[-1] = 0. */
static void check_recorded_e(const trace *t, const double *e, int hold, const char *what)
{
    size_t k;
    for (k = 0; k < NS; k++) {
        double want = hold ? 0.5 * (e[k] + (k > 0 ? e[k - 1] : 0.0)) : e[k];
        EXPECT(fabs(t->sig[k].e - want) <= 1e-15 * fabs(want),
               "%s: k=%zu sig.e = %.17g, want %.17g", what, k, t->sig[k].e, want);
    }
}

/* The recorded signals of one sample must satisfy eq. 15 as recorded,
 * for both input models: sig is the public window on the loop. */
static void test_recorded_lever_hold(void **state)
{
    static const pf_input_model ins[] = {PF_INPUT_LINEAR, PF_INPUT_HOLD};
    pf_effects fx;
    size_t i, with_fx;
    (void)state;
    make_input(g_e, 1.0);
    memset(&fx, 0, sizeof fx);
    fx.backlash = 0.2;
    for (i = 0; i < 2; i++)
        for (with_fx = 0; with_fx < 2; with_fx++) {
            char what[64];
            snprintf(what, sizeof what, "%s input%s", i ? "held" : "linear",
                     with_fx ? ", backlash" : ", no effects");
            design_cfg(&g_d, PF_TOPO_DD, with_fx ? &fx : NULL, ins[i]);
            run(&g_d, g_e, NS, &g_a);
            check_lever(&g_d, &g_a, what);
            check_recorded_e(&g_a, g_e, ins[i] == PF_INPUT_HOLD, what);
        }
    END_SOFT();
}

/* --- dead time ---------------------------------------------------- */

static void test_dead_time_shift(void **state)
{
    const uint32_t D = 7;
    pf_effects fx;
    size_t k;
    (void)state;
    make_input(g_e, 1.0);
    design_dd(&g_d, NULL);
    run(&g_d, g_e, NS, &g_a);

    memset(&fx, 0, sizeof fx);
    fx.dead_time = D / FS;
    design_dd(&g_d, &fx);
    EXPECT(g_d.rt.delay_len == D, "delay_len %u, want %u", g_d.rt.delay_len, D);
    run(&g_d, g_e, NS, &g_b);
    /* a pure transport delay: the first D outputs are the rest state, the
     * rest is the undelayed output, bit for bit */
    for (k = 0; k < D; k++)
        EXPECT(g_b.out[k] == 0.0, "k=%zu: %g during the dead time", k, g_b.out[k]);
    for (k = D; k < NS; k++)
        EXPECT(g_b.out[k] == g_a.out[k - D], "k=%zu: %.17g != %.17g", k, g_b.out[k],
               g_a.out[k - D]);
    /* the loop itself is untouched: p_c is not delayed */
    for (k = 0; k < NS; k++)
        EXPECT(g_b.sig[k].pc == g_a.sig[k].pc, "k=%zu: p_c changed by the line delay", k);

    /* the float runtime delays by the same amount */
    {
        static pf_ctrl_coeffs_f32 c0, c1;
        pf_ctrl_design d0;
        pf_ctrl_f32 i0, i1;
        float buf[16], y0[NS];
        design_dd(&d0, NULL);
        pf_ctrl_coeffs_f32_make(&c0, &d0.rt);
        pf_ctrl_coeffs_f32_make(&c1, &g_d.rt);
        assert_int_equal(c1.delay_len, D);
        assert_int_equal(pf_ctrl_init_f32(&i0, &c0, NULL, 0), PF_OK);
        assert_int_equal(pf_ctrl_init_f32(&i1, &c1, buf, 16), PF_OK);
        for (k = 0; k < NS; k++) {
            float y1;
            y0[k] = pf_ctrl_step_f32(&i0, (float)g_e[k]);
            y1 = pf_ctrl_step_f32(&i1, (float)g_e[k]);
            if (k < D)
                EXPECT(y1 == 0.0f, "f32 k=%zu: %g during the dead time", k, (double)y1);
            else
                EXPECT(y1 == y0[k - D], "f32 k=%zu: %g != %g", k, (double)y1,
                       (double)y0[k - D]);
        }
    }

    /* the caller's buffer must be big enough */
    {
        pf_ctrl_f64 in;
        double small[6];
        EXPECT(pf_ctrl_init_f64(&in, &g_d.rt, small, 6) == PF_E_BUFFER, "short buffer accepted");
        EXPECT(pf_ctrl_init_f64(&in, &g_d.rt, NULL, 0) != PF_OK, "NULL buffer accepted");
    }
    END_SOFT();
}

/* A dead time is refused by name beyond 3600 s (pf_effects_validate) or
 * beyond 4194304 samples (the design), never wrapped into a different
 * (short) delay. The first three were found by this test: at 20 kHz they
 * exceed 2^32 samples. */
static void test_dead_time_too_long(void **state)
{
    static const struct {
        double dead_time;
        int ok;
    } cases[] = {
        {1e6, 0}, {3e5, 0}, {1e300, 0},
        {DEAD_TIME_MAX, 0},          /* valid alone; 7.2e7 samples at 20 kHz */
        {(DELAY_MAX + 1.0) / FS, 0}, /* one sample beyond the cap */
        {DELAY_MAX / FS, 1},         /* exactly the cap */
        {200.0, 1},
    };
    size_t i;
    (void)state;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const double want = floor(cases[i].dead_time * FS + 0.5);
        pf_effects fx;
        pf_status st;
        char what[64];
        memset(&fx, 0, sizeof fx);
        fx.dead_time = cases[i].dead_time;
        st = try_design(&g_d, PF_TOPO_DD, &fx, PF_INPUT_HOLD);
        snprintf(what, sizeof what, "dead_time %.17g s at %g Hz", cases[i].dead_time, FS);
        if (!cases[i].ok)
            expect_names(st, PF_P_DEAD_TIME, what);
        else
            EXPECT(st == PF_OK && (double)g_d.rt.delay_len == want,
                   "%s: status %d, delay_len %u (want %.0f samples)", what, st,
                   st == PF_OK ? g_d.rt.delay_len : 0u, want);
    }
    END_SOFT();
}

/* --- lag ---------------------------------------------------------- */

static void test_lag(void **state)
{
    const double lag = 0.01; /* 200 samples */
    const double lam = 1.0 - exp(-1.0 / (FS * lag));
    pf_effects fx;
    double f = 0, maxdiff = 0, maxlagdiff = 0, pk;
    size_t k;
    (void)state;
    make_input(g_e, 1.0);
    design_dd(&g_d, NULL);
    run(&g_d, g_e, NS, &g_a);
    pk = peak(g_a.out, NS);
    assert_true(pk > 0);

    memset(&fx, 0, sizeof fx);
    fx.lag = lag;
    design_dd(&g_d, &fx);
    run(&g_d, g_e, NS, &g_b);
    /* the lag-free output through 1/(lag s + 1), discretised by the step
     * invariant; a different but consistent discretisation differs by
     * O(T/lag) of the peak */
    for (k = 0; k < NS; k++) {
        f += lam * (g_a.out[k] - f);
        if (fabs(g_b.out[k] - f) > maxdiff)
            maxdiff = fabs(g_b.out[k] - f);
        if (fabs(g_b.out[k] - g_a.out[k]) > maxlagdiff)
            maxlagdiff = fabs(g_b.out[k] - g_a.out[k]);
        /* the lag is on the line: the loop is untouched */
        EXPECT(g_b.sig[k].pc == g_a.sig[k].pc, "k=%zu: p_c changed by the line lag", k);
    }
    EXPECT(maxdiff <= 0.02 * pk, "lagged output vs filtered lag-free output: %g (peak %g)",
           maxdiff, pk);
    EXPECT(maxlagdiff >= 0.2 * pk, "lag has little effect: %g (peak %g)", maxlagdiff, pk);

    /* a very long lag, up to the documented 1e9 s, barely lets anything
     * through; it must not collapse into "no lag". Longer ones (found by
     * this test while the limit was undocumented) are refused by name. */
    {
        const double lags[] = {1e3, FX_MAX, 1.000001e9, 1e13, 1e20};
        size_t i;
        for (i = 0; i < sizeof lags / sizeof lags[0]; i++) {
            double bound = pk * (double)NS / (FS * lags[i]) * 1.01;
            pf_status st;
            char what[32];
            memset(&fx, 0, sizeof fx);
            fx.lag = lags[i];
            st = try_design(&g_d, PF_TOPO_DD, &fx, PF_INPUT_HOLD);
            snprintf(what, sizeof what, "lag = %g s", lags[i]);
            if (lags[i] > FX_MAX) {
                expect_names(st, PF_P_LAG, what);
                continue;
            }
            EXPECT(st == PF_OK, "%s: refused (%d)", what, st);
            if (st != PF_OK)
                continue;
            run(&g_d, g_e, NS, &g_b);
            EXPECT(peak(g_b.out, NS) <= bound,
                   "%s: output peak %g, at most %g expected (lag-free peak %g)", what,
                   peak(g_b.out, NS), bound, pk);
        }
    }
    END_SOFT();
}

/* --- saturation --------------------------------------------------- */

/* With saturation as the only effect on p_c and none on the line, p_c
 * stays inside [lo, hi] from the very first sample on and is the output. */
static void check_inside(const trace *t, double lo, double hi, const char *what)
{
    size_t k;
    for (k = 0; k < NS; k++)
        EXPECT(t->sig[k].pc >= lo && t->sig[k].pc <= hi && t->out[k] == t->sig[k].pc,
               "%s, k=%zu: p_c %g, output %g, limits [%g, %g]", what, k, t->sig[k].pc,
               t->out[k], lo, hi);
}

/* Example 6 saturated at [lo, hi], run on g_e into t. */
static void run_saturated(double lo, double hi, trace *t, const char *what)
{
    pf_effects fx;
    memset(&fx, 0, sizeof fx);
    fx.saturate = 1;
    fx.sat_lo = lo;
    fx.sat_hi = hi;
    design_dd(&g_d, &fx);
    run(&g_d, g_e, NS, t);
    check_inside(t, lo, hi, what);
    check_lever(&g_d, t, what);
}

static void test_saturation(void **state)
{
    double mx = -INFINITY, mn = INFINITY, ydiff = 0, ypk = 0, lo, hi;
    int at_hi = 0, at_lo = 0;
    size_t k;
    (void)state;
    make_input_off(g_e, 1.0, 0.0);
    design_dd(&g_d, NULL);
    run(&g_d, g_e, NS, &g_a);
    for (k = 0; k < NS; k++) {
        mx = fmax(mx, g_a.sig[k].pc);
        mn = fmin(mn, g_a.sig[k].pc);
        ypk = fmax(ypk, fabs(g_a.sig[k].y));
    }
    assert_true(mx > 0 && mn < 0);

    lo = 0.4 * mn;
    hi = 0.4 * mx;
    run_saturated(lo, hi, &g_b, "saturation");
    for (k = 0; k < NS; k++) {
        at_hi += g_b.sig[k].pc == hi;
        at_lo += g_b.sig[k].pc == lo;
        ydiff = fmax(ydiff, fabs(g_b.sig[k].y - g_a.sig[k].y));
    }
    EXPECT(at_hi > 0 && at_lo > 0, "saturation never reached its limits (%d, %d)", at_hi, at_lo);
    /* In the loop the bellows sees the clipped p_c, so y must differ from
     * the unsaturated run; clipping only the output would leave y as is. */
    EXPECT(ydiff > 1e-3 * ypk, "bellows y unaffected by saturation (%g vs peak %g): "
           "saturation applied outside the loop?", ydiff, ypk);

    /* limits that exclude the rest state */
    run_saturated(0.2 * mx, 0.5 * mx, &g_b, "offset saturation");

    /* limits wider than the signal change nothing at all */
    run_saturated(2 * mn, 2 * mx, &g_b, "inactive saturation");
    for (k = 0; k < NS; k++)
        EXPECT(fabs(g_b.out[k] - g_a.out[k]) <= 1e-12 * (mx - mn),
               "inactive saturation, k=%zu: %.17g vs %.17g", k, g_b.out[k], g_a.out[k]);
    END_SOFT();
}

/* --- backlash ----------------------------------------------------- */

/* p_b / k1 must follow the play operator of half-width backlash/2 applied
 * to the recorded in-loop x, starting from rest. */
static void check_play_relation(const pf_ctrl_design *d, const trace *t, double r,
                                double xh, const char *what)
{
    const double k1 = d->p.k1;
    double xb = 0.0;
    size_t k;
    for (k = 0; k < NS; k++) {
        const pf_ctrl_signals_f64 *s = &t->sig[k];
        double want;
        xb = r > 0 ? pf_play(xb, s->x, r) : s->x;
        want = k1 * (xh > 0 ? pf_nozzle_biased(xb, xh, d->fx.nozzle_bias) : xb);
        EXPECT(fabs(s->pb - want) <= 1e-12 * k1 * (fabs(xb) + r) + 1e-300,
               "%s: k=%zu p_b=%.17g, k1*h(play(x))=%.17g", what, k, s->pb, want);
        /* continue from what the library holds, so one miss is reported once */
        if (r > 0 && xh == 0)
            xb = s->pb / k1;
    }
}

static void test_backlash_in_loop(void **state)
{
    const double backlash = 0.2, r = 0.1; /* full width, half-width */
    pf_effects fx;
    size_t k;
    (void)state;

    /* 1. from rest, an input whose lever image stays inside the band never
     *    moves the nozzle: the output is exactly zero, for ever */
    for (k = 0; k < NS; k++)
        g_e[k] = 0.1 * sin(2 * M_PI * 50.0 * (double)k / FS); /* |ce e| <= 0.09 < r */
    memset(&fx, 0, sizeof fx);
    fx.backlash = backlash;
    design_dd(&g_d, &fx);
    run(&g_d, g_e, NS, &g_b);
    EXPECT(peak(g_b.out, NS) == 0.0, "sub-band input moved the output: peak %g",
           peak(g_b.out, NS));
    design_dd(&g_d, NULL);
    run(&g_d, g_e, NS, &g_a);
    EXPECT(peak(g_a.out, NS) > 0.0, "no output without backlash either");

    /*    ... but one between the half and the full width does (the header
     *    documents backlash as the full width of the band) */
    for (k = 0; k < NS; k++)
        g_e[k] = 0.15 * sin(2 * M_PI * 50.0 * (double)k / FS); /* |ce e| <= 0.135 */
    design_dd(&g_d, &fx);
    run(&g_d, g_e, NS, &g_b);
    EXPECT(peak(g_b.out, NS) > 0.0, "input beyond the half-width gave no output");

    /* 2. the recorded p_b is the play image of the recorded x, sample by
     *    sample, for a signal full of reversals of every size */
    make_input(g_e, 1.0);
    run(&g_d, g_e, NS, &g_b);
    check_play_relation(&g_d, &g_b, r, 0.0, "backlash");
    check_lever(&g_d, &g_b, "backlash");

    /* 3. ramp up far beyond the band, then reverse by less than the full
     *    width and hold: the flapper image never leaves the band, so the
     *    output must equal that of the same ramp held at its peak. Without
     *    backlash (or with it on e, outside the loop, at the x scale) the
     *    reversal shows up at once. */
    {
        /* the ramp tops out at k = 400; the reversal starts 10 samples
         * later, once x (which the held-input mean delays by half a
         * sample) has settled at the top in both runs */
        const size_t kt = 400, kr = 410, kd = 20;
        size_t j;
        double dmax = 0, dmax_lin = 0, pk;
        for (k = 0; k < NS; k++) {
            double up = k < kt ? (double)k / kt : 1.0;
            double down = k < kr ? 0.0 : k < kr + kd ? 0.1 * (double)(k - kr) / kd : 0.1;
            g_e[k] = up;          /* held at the peak */
            g_e2[k] = up - down;  /* reversed by 0.1: |ce * 0.1| = 0.09 < 2r */
        }
        run(&g_d, g_e, NS, &g_a);
        run(&g_d, g_e2, NS, &g_b);
        pk = peak(g_a.out, NS);
        for (j = kr; j < NS; j++)
            if (fabs(g_b.out[j] - g_a.out[j]) > dmax)
                dmax = fabs(g_b.out[j] - g_a.out[j]);
        EXPECT(dmax <= 1e-12 * pk, "a reversal inside the dead band changed the output by "
               "%g (peak %g)", dmax, pk);
        /* the held p_b really is held across the reversal */
        for (j = kr; j < kr + kd; j++)
            EXPECT(g_b.sig[j].pb == g_b.sig[kr - 1].pb || g_b.sig[j].pb == g_a.sig[j].pb,
                   "p_b moved during the in-band reversal at k=%zu", j);
        check_play_relation(&g_d, &g_b, r, 0.0, "backlash reversal");

        design_dd(&g_d, NULL);
        run(&g_d, g_e, NS, &g_a);
        run(&g_d, g_e2, NS, &g_c);
        for (j = kr; j < NS; j++)
            if (fabs(g_c.out[j] - g_a.out[j]) > dmax_lin)
                dmax_lin = fabs(g_c.out[j] - g_a.out[j]);
        EXPECT(dmax_lin > 1e-3 * pk, "without backlash the reversal should show (%g)", dmax_lin);
    }
    END_SOFT();
}

/* --- nozzle curve ------------------------------------------------- */

static double max_rel_diff(const double *a, const double *b)
{
    double d = 0;
    size_t k;
    for (k = 0; k < NS; k++)
        if (fabs(a[k] - b[k]) > d)
            d = fabs(a[k] - b[k]);
    return d / peak(b, NS);
}

static void test_nozzle_in_loop(void **state)
{
    pf_effects fx;
    double dsmall, dlarge;
    (void)state;

    /* small signals: |x| <= 1e-3 xh, the curve is linear to ~1e-6 there
     * (u0 is an inflection point, so the first deviation is cubic) */
    make_input(g_e, 1e-3);
    design_dd(&g_d, NULL);
    run(&g_d, g_e, NS, &g_a);
    memset(&fx, 0, sizeof fx);
    fx.nozzle_xh = 1.0;
    design_dd(&g_d, &fx);
    run(&g_d, g_e, NS, &g_b);
    dsmall = max_rel_diff(g_b.out, g_a.out);
    EXPECT(dsmall <= 1e-4, "small signals deviate from the linear nozzle by %g", dsmall);
    check_play_relation(&g_d, &g_b, 0.0, fx.nozzle_xh, "nozzle small");
    check_lever(&g_d, &g_b, "nozzle small");

    /* large signals: |x| up to ~3 xh, far into the curve */
    make_input(g_e, 1.0);
    design_dd(&g_d, NULL);
    run(&g_d, g_e, NS, &g_a);
    fx.nozzle_xh = 0.3;
    design_dd(&g_d, &fx);
    run(&g_d, g_e, NS, &g_b);
    dlarge = max_rel_diff(g_b.out, g_a.out);
    EXPECT(dlarge >= 0.05, "large signals follow the linear nozzle (diff %g)", dlarge);
    check_play_relation(&g_d, &g_b, 0.0, fx.nozzle_xh, "nozzle large");
    check_lever(&g_d, &g_b, "nozzle large");

    /* biased away from the inflection: the loop holds p_b = k1 h_biased(x) */
    fx.nozzle_bias = 0.8;
    design_dd(&g_d, &fx);
    run(&g_d, g_e, NS, &g_b);
    check_play_relation(&g_d, &g_b, 0.0, fx.nozzle_xh, "nozzle biased");
    check_lever(&g_d, &g_b, "nozzle biased");
    EXPECT(max_rel_diff(g_b.out, g_a.out) >= 0.05, "the biased nozzle follows the linear one");
    END_SOFT();
}

/* A pid whose in-sample loop gain L0 is negative (net positive feedback
 * within a sample: fs = 0.01 Hz, a slow, strongly fractional derivative
 * restrictor against an integer integral one) and a nozzle: near its
 * inflection, and below it down to the range's end, the loop equation
 * stays monotone (slope 1 + L0 s > 0); far out on the curve's tail the
 * curve is many times steeper than at its bias point, 1 + L0 s goes
 * negative, the sample's x is not unique, and the design refuses it,
 * naming the bias. */
static void test_nozzle_loop_unique(void **state)
{
    static const struct {
        double bias;
        int ok;
    } cases[] = {{0.0, 1}, {2.0, 1}, {-0.5, 1}, {5.0, 0}, {10.0, 0}};
    pf_params p;
    pf_design_opts o;
    pf_effects fx;
    double L0;
    size_t i;
    (void)state;
    pf_params_default(&p, PF_TOPO_PID);
    p.RCd = 0.5;
    p.nu = 0.1;
    p.RCi = 1.0;
    p.w = 1.0;
    memset(&o, 0, sizeof o);
    o.fs = 0.01;
    memset(&fx, 0, sizeof fx);
    assert_int_equal(pf_ctrl_design_make(&g_d, &p, &fx, &o), PF_OK);
    L0 = 1.0 / g_d.rt.loop_inv - 1.0;
    EXPECT(L0 < -0.01 && L0 > -0.1, "the loop gain is %g, not the small negative one", L0);
    fx.nozzle_xh = 1.0;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const double u0 = 0.57735026918962576 + cases[i].bias, q = 1.0 + u0 * u0;
        /* the curve's steepest slope over its slope at the bias point */
        const double steep = (3.0 * sqrt(3.0) / 8.0) * q * q / (2.0 * u0);
        pf_status st;
        char what[64];
        fx.nozzle_bias = cases[i].bias;
        st = pf_ctrl_design_make(&g_d, &p, &fx, &o);
        snprintf(what, sizeof what, "nozzle_bias %g (1 + L0 s = %.3g)", cases[i].bias,
                 1.0 + L0 * steep);
        /* the cases sit clearly on either side of the 0.01 margin */
        EXPECT((1.0 + L0 * steep > 0.1) == cases[i].ok, "%s: case on the wrong side", what);
        if (cases[i].ok) {
            EXPECT(st == PF_OK, "%s refused: %d", what, st);
            /* the loop solve's bracket reaches as far as the smallest slope */
            if (st == PF_OK)
                EXPECT(fabs(g_d.rt.slope_inv * (1.0 + L0 * fmax(steep, 1.0)) - 1.0) < 1e-9,
                       "%s: slope_inv %.17g", what, g_d.rt.slope_inv);
        } else
            expect_names(st, PF_P_NOZZLE_BIAS, what);
    }
    END_SOFT();
}

/* --- everything at once ------------------------------------------- */

static void test_all_in_loop_effects(void **state)
{
    static const pf_topology cfgs[] = {PF_TOPO_P, PF_TOPO_DD, PF_TOPO_ID, PF_TOPO_PID};
    static const pf_input_model ins[] = {PF_INPUT_HOLD, PF_INPUT_LINEAR};
    size_t c, i, k;
    int sat;
    (void)state;
    make_input_off(g_e, 1.0, 0.0);
    for (c = 0; c < 4; c++)
        for (i = 0; i < 2; i++) {
            pf_effects fx;
            double mx = 0;
            char what[64];
            design_cfg(&g_d, cfgs[c], NULL, ins[i]);
            run(&g_d, g_e, NS, &g_a);
            for (k = 0; k < NS; k++)
                if (fabs(g_a.sig[k].pc) > mx)
                    mx = fabs(g_a.sig[k].pc);

            /* backlash and nozzle together: lever and play/nozzle chain;
             * then with saturation in the same loop */
            memset(&fx, 0, sizeof fx);
            fx.backlash = 0.1;
            fx.nozzle_xh = 0.5;
            fx.sat_lo = -0.3 * mx;
            fx.sat_hi = 0.3 * mx;
            for (sat = PF_SAT_OFF; sat <= PF_SAT_STOP; sat++) {
                fx.saturate = sat;
                design_cfg(&g_d, cfgs[c], &fx, ins[i]);
                run(&g_d, g_e, NS, &g_b);
                snprintf(what, sizeof what, "%s/%s backlash+nozzle%s", pf_topology_name(cfgs[c]),
                         i ? "linear" : "hold", sat == PF_SAT_STOP ? "+stop" : sat ? "+sat" : "");
                check_lever(&g_d, &g_b, what);
                check_play_relation(&g_d, &g_b, 0.05, 0.5, what);
                if (sat)
                    check_inside(&g_b, fx.sat_lo, fx.sat_hi, what);
            }
        }
    END_SOFT();
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_play_operator, setup_soft),
        cmocka_unit_test_setup(test_nozzle_curve, setup_soft),
        cmocka_unit_test_setup(test_nozzle_biased_curve, setup_soft),
        cmocka_unit_test_setup(test_effects_validate, setup_soft),
        cmocka_unit_test_setup(test_dead_time_shift, setup_soft),
        cmocka_unit_test_setup(test_dead_time_too_long, setup_soft),
        cmocka_unit_test_setup(test_lag, setup_soft),
        cmocka_unit_test_setup(test_saturation, setup_soft),
        cmocka_unit_test_setup(test_backlash_in_loop, setup_soft),
        cmocka_unit_test_setup(test_nozzle_in_loop, setup_soft),
        cmocka_unit_test_setup(test_nozzle_loop_unique, setup_soft),
        cmocka_unit_test_setup(test_all_in_loop_effects, setup_soft),
        cmocka_unit_test_setup(test_recorded_lever_hold, setup_soft),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
