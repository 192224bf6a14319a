/* SPDX-License-Identifier: MIT */
/*
 * pneufracd's model at its own rate (port/posix/pfd_rate.c): the substep
 * rule, the accuracy it gives against the exact response at the exchange
 * instants, the exchange as the internal-rate simulation decimated, the
 * cost measurement and the load arithmetic.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pfh_accuracy.h"
#include "pfh_ref_cases.h"
#include "pfd_accuracy.h"
#include "pfd_commit.h"
#include "pfd_rate.h"
#include "pfd_sample.h"
#include "pneufrac/pneufrac.h"
#include "test_util.h"

static const pf_params *paper_case(pfh_ref_cases *cs, const char *name)
{
    const pf_params *p;
    assert_int_equal(pfh_ref_cases_load(REF_DATA_DIR "/paper_step_cases.json", cs), 0);
    p = pfh_ref_cases_find(cs, name);
    assert_non_null(p);
    return p;
}

/* The requirement of issue 12: within 0.1 % of the peak of the exact
 * response at the exchange instants over [1 ms, 2 s], at any exchange
 * rate from 100 Hz up; here 100 Hz, 1 kHz, 3 kHz (not a divisor of the
 * rule's 20 kHz) and 10 kHz, every case of the reference table, float and
 * Q15, with the substeps the daemon chooses. */
static void paper_cases_within_0p1_percent(void **state)
{
    static const double rates[] = {100.0, 1000.0, 3000.0, 10000.0};
    pfh_ref_cases cs;
    unsigned i, c;
    (void)state;

    assert_int_equal(pfh_ref_cases_load(REF_DATA_DIR "/paper_step_cases.json", &cs), 0);
    for (c = 0; c < (unsigned)cs.n; c++)
        for (i = 0; i < sizeof rates / sizeof rates[0]; i++) {
            pfh_acc_ref r;
            pfd_acc_result f, q;
            assert_int_equal(pfh_acc_ref_make(&r, &cs.p[c], rates[i], 1e-3, 2.0), 0);
            assert_int_equal(pfd_acc_error(&r, PFD_ARITH_FLOAT, 0, &f), 0);
            assert_int_equal(pfd_acc_error(&r, PFD_ARITH_Q15, 0, &q), 0);
            EXPECT(f.err <= 1e-3, "%s at %g Hz, float, k = %u: %.4f %% at t = %g s",
                   cs.name[c], rates[i], f.k, 100.0 * f.err, f.t_worst);
            EXPECT(q.err <= 1e-3, "%s at %g Hz, q15, k = %u: %.4f %% at t = %g s",
                   cs.name[c], rates[i], q.k, 100.0 * q.err, q.t_worst);
            pfh_acc_ref_free(&r);
        }
    END_SOFT();
}

/* One step per exchange, as before substeps: the same measurement fails
 * at 1 kHz (0.89 % of the peak) and 100 Hz, so the check above can fail. */
static void one_step_per_exchange_is_not_enough(void **state)
{
    pfh_ref_cases cs;
    const pf_params *p = paper_case(&cs, "ex6_q0.9");
    pfh_acc_ref r;
    pfd_acc_result f;
    (void)state;

    assert_int_equal(pfh_acc_ref_make(&r, p, 1000.0, 1e-3, 2.0), 0);
    assert_int_equal(pfd_acc_error(&r, PFD_ARITH_FLOAT, 1, &f), 0);
    assert_int_equal(f.k, 1);
    assert_true(f.err > 5e-3);
    assert_int_equal(pfd_acc_error(&r, PFD_ARITH_FLOAT, 0, &f), 0);
    assert_int_equal(f.k, 20);
    assert_true(f.err < 5e-4);
    pfh_acc_ref_free(&r);
}

/* Example 6: the relay (tau = 1 ms) is the fastest; 20 kHz internally. */
static void rule_for_the_paper_relay(void **state)
{
    static const struct {
        double fs;
        unsigned k;
    } want[] = {{100.0, 200}, {1000.0, 20}, {3000.0, 7}, {10000.0, 2},
                {15000.0, 2}, {20000.0, 1}, {50000.0, 1}};
    pf_params p;
    unsigned i;
    (void)state;

    pf_params_default(&p, PF_TOPO_DD);
    assert_true(fabs(pfd_rate_fastest(&p) - p.tau) <= 1e-15);
    for (i = 0; i < sizeof want / sizeof want[0]; i++)
        assert_int_equal(pfd_rate_substeps(&p, want[i].fs), want[i].k);
    /* 1 Hz would need 20000: the register's limit holds it. */
    assert_int_equal(pfd_rate_substeps(&p, 1.0), PFD_SUBSTEPS_MAX);
}

/* A restrictor faster than the relay; a loop whose crossover is known in
 * closed form; a loop with q = 0, which adds no faster time constant. */
static void rule_restrictor_and_loop(void **state)
{
    pf_params p;
    (void)state;

    pf_params_default(&p, PF_TOPO_DD);
    p.RC = 1e-4;
    p.nu = 1.0;
    assert_true(fabs(pfd_rate_fastest(&p) - 1e-4) <= 1e-12);
    p.nu = 0.5; /* RC s^0.5 = 1 at w = 1e8: 1e-8 s */
    assert_true(fabs(pfd_rate_fastest(&p) - 1e-8) <= 1e-16);

    /* pmin = pmax makes the relay exactly 1; with q = 1 the loop gain is
     * a/(a+b) k1 k2 (A/ks) / w, 1e4/w here: w_c = 1e4 rad/s. */
    pf_params_default(&p, PF_TOPO_P);
    p.pmin = p.pmax = 1.0;
    p.k1 = p.k2 = 1000.0;
    p.q = 1.0;
    assert_true(fabs(pfd_rate_fastest(&p) - 1e-4) <= 1e-4 * 1e-9);
    p.q = 0.5; /* (1e4/w^0.5) = 1 at w = 1e8 */
    assert_true(fabs(pfd_rate_fastest(&p) - 1e-8) <= 1e-8 * 1e-9);
    /* Capped at 200 kHz internally. */
    assert_int_equal(pfd_rate_substeps(&p, 1000.0), 200);
    assert_int_equal(pfd_rate_substeps(&p, 50000.0), 4);
    assert_int_equal(pfd_rate_substeps(&p, 30000.0), 6);
    p.q = 0.0; /* a static loop gain of 1e4 */
    assert_true(fabs(pfd_rate_fastest(&p) - p.tau) <= 1e-15);
}

static void substeps_are_checked(void **state)
{
    pf_ctrl_design *scratch = malloc(sizeof *scratch);
    pfd_slot *s = malloc(sizeof *s);
    pfd_iparams ip;
    pfd_fail why;
    (void)state;

    assert_non_null(scratch);
    assert_non_null(s);
    pfd_iparams_default(&ip);
    assert_int_equal(pfd_slot_build(s, &ip, scratch, &why), 0);
    assert_int_equal(s->rate.k, 20);
    assert_true(s->rate.internal_fs == 20000.0);
    assert_true(s->rate.wanted_fs == 20000.0);
    assert_true(s->rate.step_ns == 0.0);
    ip.substeps = 200; /* 200 kHz: the limit */
    assert_int_equal(pfd_slot_build(s, &ip, scratch, &why), 0);
    assert_int_equal(s->rate.k, 200);
    assert_true(s->rate.wanted_fs == 0.0); /* given, not chosen */
    ip.substeps = 201;
    assert_int_equal(pfd_slot_build(s, &ip, scratch, &why), -1);
    assert_int_equal(why.param, PFD_P_SUBSTEPS);
    ip.substeps = 1;
    ip.fs = 50000.0;
    assert_int_equal(pfd_slot_build(s, &ip, scratch, &why), 0);
    ip.substeps = 0;
    assert_int_equal(pfd_slot_build(s, &ip, scratch, &why), 0);
    assert_int_equal(s->rate.k, 1);
    /* An invalid set is refused before the rule reads it. */
    ip.p.tau = -1.0;
    assert_int_equal(pfd_slot_build(s, &ip, scratch, &why), -1);
    assert_int_equal(why.param, PF_P_TAU);
    free(s);
    free(scratch);
}

/* An exchange is the internal-rate run with the input held for k steps,
 * sampled at its first: bit for bit, float and Q15, with an input that
 * changes at every exchange. The reference is the library's runtime, as
 * `pneufrac simulate` runs it. */
static void exchange_is_the_internal_run_decimated(void **state)
{
    enum { K = 5, N = 400 };
    const double fs = 1000.0;
    int arith;
    (void)state;

    for (arith = 0; arith < PFD_ARITH_COUNT; arith++) {
        pfd_daemon *d = malloc(sizeof *d);
        pf_ctrl_design *des = malloc(sizeof *des);
        pf_runtime *rt = malloc(sizeof *rt);
        pf_design_opts o;
        pfd_settings set;
        pfd_config_inst ci;
        pfd_fail why;
        pfd_inst *in;
        int n, j;

        assert_non_null(d);
        assert_non_null(des);
        assert_non_null(rt);
        pfd_settings_default(&set);
        assert_int_equal(pfd_daemon_init(d, &set), 0);
        pfd_config_inst_default(&ci, 1);
        ci.ip.fs = fs;
        ci.ip.substeps = K;
        ci.ip.arith = arith;
        assert_int_equal(pfd_inst_add(d, &ci, &why), 0);
        in = d->inst[0];

        memset(&o, 0, sizeof o);
        o.fs = fs * K;
        assert_int_equal(pf_ctrl_design_make(des, &ci.ip.p, NULL, &o), PF_OK);
        assert_int_equal(pf_runtime_init(rt, des, pfd_arith_lib(arith), ci.ip.in_fs,
                                         ci.ip.out_fs, NULL, 0), PF_OK);

        for (n = 0; n < N; n++) {
            const float e = (float)(0.6 * sin(0.05 * n) + (n % 7 == 0 ? 0.3 : 0.0));
            const pfd_snap *s;
            float first;
            in->live.e = e;
            in->live.refresh++;
            pfd_publish_live(in);
            pfd_sample_run(in, &d->loop.jitter, 0, -1);
            s = (const pfd_snap *)pfd_tbuf_latest(&in->out_tb);
            first = (float)pf_runtime_step(rt, (double)e);
            if (arith == PFD_ARITH_Q15)
                assert_int_equal(s->sig.pc_q15, rt->out_q15);
            assert_memory_equal(&s->sig.pc, &first, sizeof first);
            for (j = 1; j < K; j++)
                (void)pf_runtime_step(rt, (double)e);
        }
        assert_int_equal(((const pfd_snap *)pfd_tbuf_latest(&in->out_tb))->samples, N);
        pfd_daemon_free(d);
        free(d);
        free(des);
        free(rt);
    }
}

/* The measurement leaves the slot as built: the same outputs follow. */
static void measure_leaves_the_slot_at_rest(void **state)
{
    pf_ctrl_design *scratch = malloc(sizeof *scratch);
    pfd_slot *a = malloc(sizeof *a), *b = malloc(sizeof *b);
    pfd_iparams ip;
    pfd_fail why;
    int arith, n;
    (void)state;

    assert_non_null(scratch);
    assert_non_null(a);
    assert_non_null(b);
    for (arith = 0; arith < PFD_ARITH_COUNT; arith++) {
        pfd_iparams_default(&ip);
        ip.arith = arith;
        assert_int_equal(pfd_slot_build(a, &ip, scratch, &why), 0);
        assert_int_equal(pfd_slot_build(b, &ip, scratch, &why), 0);
        pfd_rate_measure(a);
        assert_true(a->rate.step_ns > 0.0 && isfinite(a->rate.step_ns));
        for (n = 0; n < 200; n++) {
            pfd_sig sa, sb;
            pfd_slot_step(a, 1.0f, &sa);
            pfd_slot_step(b, 1.0f, &sb);
            assert_memory_equal(&sa.pc, &sb.pc, sizeof sa.pc);
            assert_int_equal(sa.pc_q15, sb.pc_q15);
        }
    }
    free(a);
    free(b);
    free(scratch);
}

/* Load: the sum of fs x (k + 1) x step, one wake-up per period of each
 * distinct rate, plus the longest exchange over the shortest period. */
static void load_is_utilisation_plus_blocking(void **state)
{
    const pfd_rate slow = {200, 20000.0, 50.0, 0.0}; /* 100 Hz: 10.05 us an exchange */
    const pfd_rate fast = {1, 50000.0, 100.0, 0.0};  /* 50 kHz: 200 ns an exchange */
    const double wake = 10e-6;                        /* 10 us a wake-up */
    pfd_load l;
    (void)state;

    assert_true(fabs(pfd_rate_exchange_ns(&slow) - 10050.0) < 1e-9);
    pfd_load_init(&l, 1e9 * wake);
    pfd_load_add(&l, 100.0, &slow);
    assert_true(fabs(pfd_load_total(&l) - (2.0 * 100.0 * 10050e-9 + 100.0 * wake)) < 1e-12);
    /* A second instance at the same rate shares the wake-ups. */
    pfd_load_add(&l, 100.0, &slow);
    assert_true(fabs(pfd_load_total(&l) - (3.0 * 100.0 * 10050e-9 + 100.0 * wake)) < 1e-12);
    pfd_load_add(&l, 50000.0, &fast);
    /* 0.201 % + 0.1 % of exchanges at 100 Hz, 1 % + 50 % at 50 kHz, and
     * 10.05 us against 20 us: 50.25 % */
    assert_true(fabs(pfd_load_total(&l) - (2.0 * 100.0 * 10050e-9 + 100.0 * wake +
                                           50000.0 * 200e-9 + 50000.0 * wake +
                                           10050e-9 * 50000.0)) < 1e-12);
}

/* A wake-up costs something, and far less than the 200 us it sleeps. */
static void wakeup_is_measured(void **state)
{
    double w = pfd_rate_measure_wakeup();
    (void)state;
    assert_true(w > 0.0 && w < 200000.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(paper_cases_within_0p1_percent, setup_soft),
        cmocka_unit_test(one_step_per_exchange_is_not_enough),
        cmocka_unit_test(rule_for_the_paper_relay),
        cmocka_unit_test(rule_restrictor_and_loop),
        cmocka_unit_test(substeps_are_checked),
        cmocka_unit_test(exchange_is_the_internal_run_decimated),
        cmocka_unit_test(measure_leaves_the_slot_at_rest),
        cmocka_unit_test(load_is_utilisation_plus_blocking),
        cmocka_unit_test(wakeup_is_measured),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
