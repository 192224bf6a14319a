/* SPDX-License-Identifier: MIT */
/*
 * The relay's diaphragm at its stop (pf_effects.saturate = PF_SAT_STOP)
 * against the physics it claims, from outside the library:
 *  - the range of "saturate" is the parameter table's, and validation
 *    refuses anything else, naming it;
 *  - the diaphragm's material law (eq. 11, with I = (tau s)^-beta), driven
 *    by the recorded strain z = p_c/k2 alone (its memory is its own
 *    history, the held z included), gives a stress equal to the recorded
 *    p_b wherever the diaphragm is free, and on a seat a stress that the
 *    seat's push completes (p_b above it on the upper seat, below it on
 *    the lower). The operator I is stepped by this test on the recorded
 *    signal (the design's relay operator, not the controller's instance).
 *    The clip model (PF_SAT_CLIP) remembers the unclipped z, so the same
 *    check fails on it after a saturated stretch: the check can fail, and
 *    tells the two placements apart;
 *  - after a saturated stretch the diaphragm lifts off its seat with the
 *    input; the clip model's output stays at the limit longer;
 *  - the wound-on relay (PF_SAT_WIND) obeys eq. 11 with the whole p_b and
 *    the held z in its memory (a check that fails on the clip and the
 *    seat), and recovers last: seat < clip < wind;
 *  - p_c never leaves the limits, in every arithmetic, for every placement
 *    (Q15 refuses PF_SAT_WIND: its memory outgrows any fixed scale).
 * f32 against f64 for every placement: here; Q15 for clip and seat: test_runtime,
 * test_ctrl_q15 (their stated tolerances).
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
#define SOFT_MAX_PRINT 8
#include "test_util.h"

#define FS 20000.0
#define NS 12000 /* 0.6 s: saturated stretches of 0.2 s either way */

static pf_ctrl_design g_d;
static pf_ctrl_f64 g_c;
static pf_ctrl_signals_f64 g_sig[NS];
static double g_e[NS];

/* up into the upper limit, back to rest, down into the lower one, rest */
static void make_input(void)
{
    size_t k;
    for (k = 0; k < NS; k++)
        g_e[k] = k < NS / 12 ? 0.0 : k < 5 * NS / 12 ? 1.0 : k < 6 * NS / 12 ? 0.0
               : k < 10 * NS / 12 ? -1.0 : 0.0;
}

static void design(pf_topology topo, int kind, double lo, double hi)
{
    pf_params p;
    pf_design_opts o;
    pf_effects fx;
    memset(&fx, 0, sizeof fx);
    fx.saturate = kind;
    fx.sat_lo = lo;
    fx.sat_hi = hi;
    pf_params_default(&p, topo);
    pf_design_opts_default(&o, FS);
    assert_int_equal(pf_ctrl_design_make(&g_d, &p, kind ? &fx : NULL, &o), PF_OK);
}

static void run(void)
{
    size_t k;
    assert_int_equal(pf_ctrl_init_f64(&g_c, &g_d.rt, NULL, 0), PF_OK);
    for (k = 0; k < NS; k++) {
        (void)pf_ctrl_step_f64(&g_c, g_e[k]);
        g_sig[k] = g_c.sig;
    }
}

/* Peak |p_c| of the linear loop on the input: the limits are set from it. */
static double linear_peak(pf_topology topo)
{
    double pk = 0;
    size_t k;
    design(topo, PF_SAT_OFF, 0, 0);
    run();
    for (k = 0; k < NS; k++)
        pk = fmax(pk, fabs(g_sig[k].pc));
    return pk;
}

/* The diaphragm's material law (eq. 11, a Zener model: stress ~ p_b,
 * strain ~ z) driven by the recorded strain z alone: z = (1 + I) v with
 * w = I v, solved sample by sample (S, what I's state contributes, from a
 * copy stepped with 0), and the material's stress s = pmin w + pmax v.
 * Free diaphragm: s = p_b. On the upper seat the seat pushes back, so
 * p_b >= s; on the lower one p_b <= s. Returns the largest |s - p_b| off
 * the seats relative to the largest |p_b|, and in *wrong_side the largest
 * violation of the seats' sign, likewise; *on_seat counts seat samples. */
static double material_residual(double lo, double hi, double *wrong_side, int *on_seat)
{
    pf_fracop_design I = g_d.rt.P;
    pf_fracop_f64 op, probe;
    const double pmin = g_d.p.pmin, pmax = g_d.p.pmax;
    double worst = 0, scale = 1e-300;
    size_t k;
    I.hold = 0; /* the relay's operator takes v as it is (the loop holds e) */
    assert_int_equal(pf_fracop_init_f64(&op, &I), PF_OK);
    *wrong_side = 0;
    *on_seat = 0;
    for (k = 0; k < NS; k++)
        scale = fmax(scale, fabs(g_sig[k].pb));
    for (k = 0; k < NS; k++) {
        const double pb = g_sig[k].pb, z = g_sig[k].z;
        double S, v, w, stress;
        probe = op;
        S = pf_fracop_step_f64(&probe, 0.0);
        v = (z - S) / (1.0 + I.D);
        w = pf_fracop_step_f64(&op, v);
        stress = pmin * w + pmax * v;
        if (g_sig[k].pc >= hi) {
            ++*on_seat;
            *wrong_side = fmax(*wrong_side, (stress - pb) / scale);
        } else if (g_sig[k].pc <= lo) {
            ++*on_seat;
            *wrong_side = fmax(*wrong_side, (pb - stress) / scale);
        } else {
            worst = fmax(worst, fabs(stress - pb) / scale);
        }
    }
    return worst;
}

/* Samples from the input's fall (k0) until p_c leaves the upper limit. */
static int lift_off(size_t k0, double hi)
{
    size_t k = k0;
    while (k < NS && g_sig[k].pc >= hi)
        k++;
    return (int)(k - k0);
}

static void test_saturate_range(void **state)
{
    const pf_param_spec *s = pf_param_info(PF_P_SATURATE);
    static const int bad[] = {-1, 4, 100};
    pf_effects fx;
    int i;
    (void)state;
    assert_non_null(s);
    EXPECT(pf_param_lookup("saturate") == PF_P_SATURATE, "lookup");
    EXPECT(s->lo == PF_SAT_OFF && s->hi == PF_SAT_WIND && (s->flags & PF_PARAM_INTEGER),
           "range [%g, %g] flags %u", s->lo, s->hi, (unsigned)s->flags);
    memset(&fx, 0, sizeof fx);
    fx.sat_lo = -1.0;
    fx.sat_hi = 1.0;
    for (i = PF_SAT_OFF; i <= PF_SAT_WIND; i++) {
        fx.saturate = i;
        EXPECT(pf_effects_validate(&fx) == PF_OK, "saturate = %d refused", i);
    }
    for (i = 0; i < (int)(sizeof bad / sizeof bad[0]); i++) {
        fx.saturate = bad[i];
        EXPECT(pf_effects_validate(&fx) == PF_E_PARAM(PF_P_SATURATE),
               "saturate = %d: status %d", bad[i], pf_effects_validate(&fx));
    }
    END_SOFT();
}

/* Design and run one placement; p_c must stay within the limits. */
static void run_within(pf_topology topo, int kind, double lo, double hi)
{
    size_t k;
    design(topo, kind, lo, hi);
    run();
    for (k = 0; k < NS; k++)
        EXPECT(g_sig[k].pc >= lo && g_sig[k].pc <= hi, "%s kind %d, k=%zu: p_c %g outside "
               "[%g, %g]", pf_topology_name(topo), kind, k, g_sig[k].pc, lo, hi);
}

static void wind_checks(pf_topology topo, double lo, double hi);

static void test_diaphragm_on_its_seat(void **state)
{
    int c;
    (void)state;
    make_input();
    for (c = 0; c < PF_TOPO_COUNT; c++) {
        const pf_topology topo = (pf_topology)c;
        const char *name = pf_topology_name(topo);
        const double pk = linear_peak(topo), lo = -0.3 * pk, hi = 0.4 * pk;
        double stop, clip, side_stop, side_clip;
        int n_stop, n_clip, up_stop, up_clip;
        run_within(topo, PF_SAT_STOP, lo, hi);
        stop = material_residual(lo, hi, &side_stop, &n_stop);
        up_stop = lift_off(5 * NS / 12, hi);
        run_within(topo, PF_SAT_CLIP, lo, hi);
        clip = material_residual(lo, hi, &side_clip, &n_clip);
        up_clip = lift_off(5 * NS / 12, hi);
        print_message("%s: material law off the seats %.2e (stop), %.2e (clip); wrong side "
                      "%.2e (stop); %d, %d samples on a limit; off the upper limit %d (stop), "
                      "%d (clip) samples after the input falls\n", name, stop, clip,
                      side_stop, n_stop, n_clip, up_stop, up_clip);
        EXPECT(n_stop > NS / 10 && n_clip > NS / 10, "%s: the limits were hardly reached "
               "(%d, %d samples)", name, n_stop, n_clip);
        /* rounding only */
        EXPECT(stop <= 1e-9, "%s: the free diaphragm breaks its law (%.3g)", name, stop);
        EXPECT(side_stop <= 1e-9, "%s: a seat pulls the diaphragm (%.3g)", name, side_stop);
        /* the clip's relay remembers the unclipped z: the law on the
         * recorded (clipped) strain fails by far more than rounding */
        EXPECT(clip >= 1e-3, "%s: the clip model obeys the seat's law (%.3g)", name, clip);
        /* on the seat the diaphragm lifts off with the input (the held
         * input's mean and the loop's own sample: 2 samples); the clip's
         * memory holds the output at the limit for longer */
        EXPECT(up_stop <= 2, "%s: the diaphragm stayed %d samples on its seat", name,
               up_stop);
        EXPECT(up_clip > up_stop, "%s: the clip recovered as fast (%d samples)", name,
               up_clip);
        wind_checks(topo, lo, hi);
    }
    END_SOFT();
}

/* The wound-on relay's law (pf_effects.h, PF_SAT_WIND), from outside:
 * with v = (p_b - pmin z)/(pmax - pmin) taken from the recorded p_b and
 * z = p_c/k2 at every sample (the diaphragm loaded by the whole p_b, the
 * stroke z held at a limit) and w = I v stepped by this test, z = w + v
 * holds wherever the output is free; largest |w + v - z| off the limits
 * over the largest |z|. The clip's relay remembers its unclipped z and
 * the seat's a relaxed stress, so the check fails on both. */
static double wind_residual(double lo, double hi)
{
    pf_fracop_design I = g_d.rt.P;
    pf_fracop_f64 op;
    const double pmin = g_d.p.pmin, pmax = g_d.p.pmax;
    double worst = 0, scale = 1e-300;
    size_t k;
    I.hold = 0;
    assert_int_equal(pf_fracop_init_f64(&op, &I), PF_OK);
    for (k = 0; k < NS; k++)
        scale = fmax(scale, fabs(g_sig[k].z));
    for (k = 0; k < NS; k++) {
        const double v = (g_sig[k].pb - pmin * g_sig[k].z) / (pmax - pmin);
        const double w = pf_fracop_step_f64(&op, v);
        if (g_sig[k].pc < hi && g_sig[k].pc > lo)
            worst = fmax(worst, fabs(w + v - g_sig[k].z) / scale);
    }
    return worst;
}

/* The wound-on relay against its law and the others (called for every
 * topology by test_diaphragm_on_its_seat, on its limits). */
static void wind_checks(pf_topology topo, double lo, double hi)
{
    const char *name = pf_topology_name(topo);
    double res[4];
    int up[4], kind;
    for (kind = PF_SAT_CLIP; kind <= PF_SAT_WIND; kind++) {
        run_within(topo, kind, lo, hi);
        res[kind] = wind_residual(lo, hi);
        up[kind] = lift_off(5 * NS / 12, hi);
    }
    print_message("%s: wound-on law off the limits %.2e (wind), %.2e (clip), %.2e "
                  "(seat); off the upper limit after %d (wind), %d (clip), %d (seat) "
                  "samples\n", name, res[PF_SAT_WIND], res[PF_SAT_CLIP], res[PF_SAT_STOP],
                  up[PF_SAT_WIND], up[PF_SAT_CLIP], up[PF_SAT_STOP]);
    EXPECT(res[PF_SAT_WIND] <= 1e-9, "%s: the wound-on relay breaks its law (%.3g)", name,
           res[PF_SAT_WIND]);
    EXPECT(res[PF_SAT_CLIP] >= 1e-3 && res[PF_SAT_STOP] >= 1e-3, "%s: clip or seat obey "
           "the wound-on law (%.3g, %.3g)", name, res[PF_SAT_CLIP], res[PF_SAT_STOP]);
    /* the excess the memory took on must fade first: the longest recovery */
    EXPECT(up[PF_SAT_WIND] > up[PF_SAT_CLIP] && up[PF_SAT_CLIP] > up[PF_SAT_STOP],
           "%s: recoveries %d (wind), %d (clip), %d (seat) not in the memory's order", name,
           up[PF_SAT_WIND], up[PF_SAT_CLIP], up[PF_SAT_STOP]);
}

/* p_c inside the limits in f32 and Q15 too, for every placement. */
static void test_limits_every_arithmetic(void **state)
{
    static pf_ctrl_coeffs_f32 cf;
    static pf_ctrl_f32 f;
    static pf_ctrl_coeffs_q15 cq;
    static pf_ctrl_q15 q;
    int kind;
    (void)state;
    make_input();
    for (kind = PF_SAT_CLIP; kind <= PF_SAT_WIND; kind++) {
        const double pk = linear_peak(PF_TOPO_PID), lo = -0.3 * pk, hi = 0.4 * pk;
        const double out_fs = 1.25 * pk, lsb = out_fs / 32768.0;
        size_t k;
        /* the wound-on memory outgrows any fixed scale: refused in Q15 */
        const int q15 = kind != PF_SAT_WIND;
        design(PF_TOPO_PID, kind, lo, hi);
        pf_ctrl_coeffs_f32_make(&cf, &g_d.rt);
        assert_int_equal(pf_ctrl_init_f32(&f, &cf, NULL, 0), PF_OK);
        assert_int_equal(pf_ctrl_coeffs_q15_make(&cq, &g_d, 1.25, out_fs),
                         q15 ? PF_OK : PF_E_UNSUPPORTED);
        if (q15)
            assert_int_equal(pf_ctrl_init_q15(&q, &cq, NULL, 0), PF_OK);
        double dev = 0;
        assert_int_equal(pf_ctrl_init_f64(&g_c, &g_d.rt, NULL, 0), PF_OK);
        for (k = 0; k < NS; k++) {
            const float of = pf_ctrl_step_f32(&f, (float)g_e[k]);
            dev = fmax(dev, fabs(of - pf_ctrl_step_f64(&g_c, g_e[k])) / (hi - lo));
            EXPECT(of >= (float)lo && of <= (float)hi, "kind %d f32, k=%zu: %g", kind, k,
                   (double)of);
            if (q15) {
                const double oq = pf_ctrl_step_q15(&q, pf_q15_quantize(g_e[k], 1.25)) * lsb;
                /* the limits are rounded to the internal scale, the output to Q15 */
                EXPECT(oq >= lo - lsb && oq <= hi + lsb, "kind %d Q15, k=%zu: %g", kind, k,
                       oq);
            }
        }
        /* float's rounding, carried by a state the limits leave unbounded */
        print_message("kind %d: f32 within %.2e of f64 (of the limits' span)\n", kind, dev);
        EXPECT(dev <= 1e-4, "kind %d: f32 off f64 by %.3g of the span", kind, dev);
    }
    END_SOFT();
}

/* pf_ctrl_f64.limited counts the samples on which a limit acted on the
 * relay, and before the first of them the three placements have given the
 * same output bit for bit (the fits share those runs between placements:
 * pneufrac_fit.placement_share). The input of make_input with its upper
 * stretch only reaching the upper limit: every sample before the limit is
 * reached is compared, and the placements must part after it (the check
 * can fail). Limits beyond the output count nothing; reset clears it. */
static void test_limited_count(void **state)
{
    static double out[PF_SAT_WIND + 1][NS];
    static uint32_t count[PF_SAT_WIND + 1][NS];
    static pf_ctrl_coeffs_f32 cf;
    static pf_ctrl_f32 f;
    static const pf_topology topos[] = {PF_TOPO_P, PF_TOPO_DD, PF_TOPO_ID, PF_TOPO_PID};
    size_t t, k;
    (void)state;
    make_input();
    for (t = 0; t < sizeof topos / sizeof topos[0]; t++) {
        const double pk = linear_peak(topos[t]);
        size_t first = NS;
        int kind, parted = 0;
        for (kind = PF_SAT_CLIP; kind <= PF_SAT_WIND; kind++) {
            design(topos[t], kind, -2.0 * pk, 0.5 * pk);
            assert_int_equal(pf_ctrl_init_f64(&g_c, &g_d.rt, NULL, 0), PF_OK);
            for (k = 0; k < NS; k++) {
                out[kind][k] = pf_ctrl_step_f64(&g_c, g_e[k]);
                count[kind][k] = g_c.limited;
            }
            EXPECT(g_c.limited > 0 && pf_ctrl_limited_f64(&g_c) == g_c.limited,
                   "%s kind %d: %u samples limited", pf_topology_name(topos[t]), kind,
                   (unsigned)g_c.limited);
            pf_ctrl_reset_f64(&g_c);
            EXPECT(g_c.limited == 0, "reset leaves %u", (unsigned)g_c.limited);
            pf_ctrl_coeffs_f32_make(&cf, &g_d.rt);
            assert_int_equal(pf_ctrl_init_f32(&f, &cf, NULL, 0), PF_OK);
            for (k = 0; k < NS; k++)
                (void)pf_ctrl_step_f32(&f, (float)g_e[k]);
            EXPECT(f.limited > 0, "%s kind %d f32: nothing counted", pf_topology_name(topos[t]),
                   kind);
            /* limits beyond the output: nothing counted */
            design(topos[t], kind, -2.0 * pk, 2.0 * pk);
            run();
            EXPECT(g_c.limited == 0, "%s kind %d, wide limits: %u samples limited",
                   pf_topology_name(topos[t]), kind, (unsigned)g_c.limited);
        }
        for (k = 0; k < NS && count[PF_SAT_CLIP][k] == 0; k++)
            ;
        first = k;
        EXPECT(first > NS / 12 && first < NS, "%s: first limited sample %zu",
               pf_topology_name(topos[t]), first);
        for (kind = PF_SAT_STOP; kind <= PF_SAT_WIND; kind++) {
            for (k = 0; k < first; k++) {
                EXPECT(count[kind][k] == 0, "%s kind %d counts at k=%zu, clip first at %zu",
                       pf_topology_name(topos[t]), kind, k, first);
                EXPECT(out[kind][k] == out[PF_SAT_CLIP][k], "%s kind %d, k=%zu (before the "
                       "first limited sample %zu): %.17g vs clip %.17g",
                       pf_topology_name(topos[t]), kind, k, first, out[kind][k],
                       out[PF_SAT_CLIP][k]);
            }
            for (k = first; k < NS; k++)
                parted |= out[kind][k] != out[PF_SAT_CLIP][k];
        }
        EXPECT(parted, "%s: the placements never part after the limit", pf_topology_name(topos[t]));
    }
    END_SOFT();
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_saturate_range, setup_soft),
        cmocka_unit_test_setup(test_diaphragm_on_its_seat, setup_soft),
        cmocka_unit_test_setup(test_limits_every_arithmetic, setup_soft),
        cmocka_unit_test_setup(test_limited_count, setup_soft),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
