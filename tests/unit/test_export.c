/* SPDX-License-Identifier: MIT */
/*
 * Exported coefficient headers (pneufrac design --format c), compiled back
 * in: they must be the in-process design, byte for byte, and run to the
 * same outputs bit for bit; compiled as C++ (export_cxx.cpp) they must be
 * the same bytes as compiled here.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <string.h>

#include "pneufrac/pneufrac.h"
#include "pf_example6_f32.h"
#include "pf_example6_q15.h"
#include "pf_pid_fx_f32.h"
#include "pf_nozzle_fx_q15.h"
#include "pf_pid_fx_q15.h"
#include "export_cxx.h"

static pf_ctrl_design design;

static int setup(void **state)
{
    pf_params p;
    pf_design_opts o;
    (void)state;
    pf_params_default(&p, PF_TOPO_DD);
    pf_design_opts_default(&o, 20000.0);
    return pf_ctrl_design_make(&design, &p, NULL, &o) == PF_OK ? 0 : -1;
}

static void test_q15_header(void **state)
{
    static pf_ctrl_coeffs_q15 mine;
    static pf_ctrl_q15 a, b;
    long n;
    (void)state;
    assert_int_equal(pf_ctrl_coeffs_q15_make(&mine, &design, 1.0, 0.01), PF_OK);
    assert_memory_equal(&mine, &pf_example6_q15, sizeof mine);
    pf_ctrl_init_q15(&a, &mine, NULL, 0);
    pf_ctrl_init_q15(&b, &pf_example6_q15, NULL, 0);
    for (n = 0; n < 20000; n++) {
        int16_t e = (int16_t)(n < 10000 ? 16384 : -4096);
        assert_int_equal(pf_ctrl_step_q15(&a, e), pf_ctrl_step_q15(&b, e));
    }
}

static void test_f32_header(void **state)
{
    static pf_ctrl_coeffs_f32 mine;
    static pf_ctrl_f32 a, b;
    long n;
    (void)state;
    pf_ctrl_coeffs_f32_make(&mine, &design.rt);
    assert_memory_equal(&mine, &pf_example6_f32, sizeof mine);
    pf_ctrl_init_f32(&a, &mine, NULL, 0);
    pf_ctrl_init_f32(&b, &pf_example6_f32, NULL, 0);
    for (n = 0; n < 20000; n++) {
        float e = n < 10000 ? 0.5f : -0.125f, ya = pf_ctrl_step_f32(&a, e);
        float yb = pf_ctrl_step_f32(&b, e);
        assert_memory_equal(&ya, &yb, sizeof ya);
    }
}

/* Every operator, both integer arrays, backlash, lag and dead time: a pid
 * with effects (tests/CMakeLists.txt: pf_pid_fx_*.h), designed here the
 * same. */
static void test_pid_fx_headers(void **state)
{
    static pf_ctrl_design d;
    static pf_ctrl_coeffs_q15 q;
    static pf_ctrl_coeffs_f32 f;
    pf_params p;
    pf_effects fx;
    pf_design_opts o;
    (void)state;
    pf_params_default(&p, PF_TOPO_PID);
    memset(&fx, 0, sizeof fx);
    fx.backlash = 0.01;
    fx.lag = 0.01;
    fx.dead_time = 0.001;
    pf_design_opts_default(&o, 20000.0);
    assert_int_equal(pf_ctrl_design_make(&d, &p, &fx, &o), PF_OK);
    assert_int_equal(pf_ctrl_coeffs_q15_make(&q, &d, 1.0, 20.0), PF_OK);
    assert_true(q.play_r > 0);
    pf_ctrl_coeffs_f32_make(&f, &d.rt);
    assert_memory_equal(&q, &pf_pid_fx_q15, sizeof q);
    assert_memory_equal(&f, &pf_pid_fx_f32, sizeof f);
}

/* An id with the nozzle curve and backlash: the set and the table it
 * points to, each byte for byte (but for the pointer), and the outputs. */
static void test_nozzle_header(void **state)
{
    static pf_ctrl_design d;
    static pf_ctrl_coeffs_q15 mine, theirs;
    static pf_nozzle_q15 nz;
    static pf_ctrl_q15 a, b;
    pf_params p;
    pf_design_opts o;
    pf_effects fx;
    long n;
    (void)state;
    memset(&fx, 0, sizeof fx);
    fx.nozzle_xh = 0.2;
    fx.backlash = 0.05;
    pf_params_default(&p, PF_TOPO_ID);
    pf_design_opts_default(&o, 20000.0);
    assert_int_equal(pf_ctrl_design_make(&d, &p, &fx, &o), PF_OK);
    assert_int_equal(pf_ctrl_coeffs_q15_make_nz(&mine, &nz, &d, 1.0, 20.0), PF_OK);
    assert_true(mine.nz == &nz);
    assert_memory_equal(&nz, pf_nozzle_fx_q15.nz, sizeof nz);
    theirs = pf_nozzle_fx_q15;
    theirs.nz = mine.nz;
    assert_memory_equal(&mine, &theirs, sizeof mine);
    pf_ctrl_init_q15(&a, &mine, NULL, 0);
    pf_ctrl_init_q15(&b, &pf_nozzle_fx_q15, NULL, 0);
    for (n = 0; n < 20000; n++) {
        int16_t e = (int16_t)(n % 5000 < 2500 ? 30000 - n : -8000);
        assert_int_equal(pf_ctrl_step_q15(&a, e), pf_ctrl_step_q15(&b, e));
    }
}

static void test_cxx_compiles_the_same(void **state)
{
    (void)state;
    assert_memory_equal(cxx_example6_q15(), &pf_example6_q15, sizeof pf_example6_q15);
    assert_memory_equal(cxx_example6_f32(), &pf_example6_f32, sizeof pf_example6_f32);
    assert_memory_equal(cxx_pid_fx_q15(), &pf_pid_fx_q15, sizeof pf_pid_fx_q15);
    assert_memory_equal(cxx_pid_fx_f32(), &pf_pid_fx_f32, sizeof pf_pid_fx_f32);
    {
        /* the set points to its own translation unit's table */
        pf_ctrl_coeffs_q15 cxx = *cxx_nozzle_fx_q15();
        assert_memory_equal(cxx.nz, pf_nozzle_fx_q15.nz, sizeof *cxx.nz);
        cxx.nz = pf_nozzle_fx_q15.nz;
        assert_memory_equal(&cxx, &pf_nozzle_fx_q15, sizeof cxx);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_q15_header),
        cmocka_unit_test(test_f32_header),
        cmocka_unit_test(test_pid_fx_headers),
        cmocka_unit_test(test_nozzle_header),
        cmocka_unit_test(test_cxx_compiles_the_same),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
