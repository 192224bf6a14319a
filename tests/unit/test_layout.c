/* SPDX-License-Identifier: MIT */
/*
 * The binding seam (pf_layout.h) against the compiler that builds this
 * test: every size, every member's offset, size and kind, the names the
 * parameter table gives them, and the limits it reports.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <string.h>

#include "pneufrac/pneufrac.h"

static void test_sizes(void **state)
{
    static const struct {
        pf_type t;
        const char *name;
        size_t size;
    } want[] = {
        {PF_TYPE_PARAMS, "pf_params", sizeof(pf_params)},
        {PF_TYPE_EFFECTS, "pf_effects", sizeof(pf_effects)},
        {PF_TYPE_DESIGN_OPTS, "pf_design_opts", sizeof(pf_design_opts)},
        {PF_TYPE_CTRL_DESIGN, "pf_ctrl_design", sizeof(pf_ctrl_design)},
        {PF_TYPE_CTRL_COEFFS_F64, "pf_ctrl_coeffs_f64", sizeof(pf_ctrl_coeffs_f64)},
        {PF_TYPE_CTRL_COEFFS_F32, "pf_ctrl_coeffs_f32", sizeof(pf_ctrl_coeffs_f32)},
        {PF_TYPE_CTRL_COEFFS_Q15, "pf_ctrl_coeffs_q15", sizeof(pf_ctrl_coeffs_q15)},
        {PF_TYPE_CTRL_F64, "pf_ctrl_f64", sizeof(pf_ctrl_f64)},
        {PF_TYPE_CTRL_F32, "pf_ctrl_f32", sizeof(pf_ctrl_f32)},
        {PF_TYPE_CTRL_Q15, "pf_ctrl_q15", sizeof(pf_ctrl_q15)},
        {PF_TYPE_RUNTIME, "pf_runtime", sizeof(pf_runtime)},
        {PF_TYPE_PARAM_SPEC, "pf_param_spec", sizeof(pf_param_spec)},
    };
    size_t i;
    (void)state;
    assert_int_equal(sizeof want / sizeof want[0], PF_TYPE_COUNT);
    for (i = 0; i < sizeof want / sizeof want[0]; i++) {
        assert_string_equal(pf_type_name(want[i].t), want[i].name);
        assert_int_equal(pf_sizeof(want[i].t), want[i].size);
    }
    assert_string_equal(pf_type_name(PF_TYPE_COUNT), "?");
    assert_int_equal(pf_sizeof(PF_TYPE_COUNT), 0);
    assert_int_equal(pf_max_order(), PF_MAX_ORDER);
}

typedef struct want_field {
    const char *name;
    size_t offset, size;
    pf_field_kind kind;
} want_field;

#define F(S, m, k) {#m, offsetof(S, m), sizeof(((S *)0)->m), k}

/* Every member, in order, and nothing after the last. */
static void expect_fields(pf_type t, const want_field *w, int n)
{
    pf_field f;
    int i;
    for (i = 0; i < n; i++) {
        assert_int_equal(pf_field_get(t, i, &f), 0);
        assert_string_equal(f.name, w[i].name);
        assert_int_equal(f.offset, w[i].offset);
        assert_int_equal(f.size, w[i].size);
        assert_int_equal(f.kind, w[i].kind);
    }
    assert_int_equal(pf_field_get(t, n, &f), -1);
    assert_int_equal(pf_field_get(t, -1, &f), -1);
    assert_int_equal(pf_field_get(t, 0, NULL), -1);
}

static void test_members(void **state)
{
    static const want_field params[] = {
        F(pf_params, topology, PF_FIELD_INT), F(pf_params, a, PF_FIELD_DOUBLE),
        F(pf_params, b, PF_FIELD_DOUBLE),   F(pf_params, k1, PF_FIELD_DOUBLE),
        F(pf_params, k2, PF_FIELD_DOUBLE),  F(pf_params, A, PF_FIELD_DOUBLE),
        F(pf_params, ks, PF_FIELD_DOUBLE),  F(pf_params, tau, PF_FIELD_DOUBLE),
        F(pf_params, pmin, PF_FIELD_DOUBLE), F(pf_params, pmax, PF_FIELD_DOUBLE),
        F(pf_params, beta, PF_FIELD_DOUBLE), F(pf_params, q, PF_FIELD_DOUBLE),
        F(pf_params, nu, PF_FIELD_DOUBLE),  F(pf_params, w, PF_FIELD_DOUBLE),
        F(pf_params, RC, PF_FIELD_DOUBLE),  F(pf_params, RCd, PF_FIELD_DOUBLE),
        F(pf_params, RCi, PF_FIELD_DOUBLE),
    };
    static const want_field effects[] = {
        F(pf_effects, backlash, PF_FIELD_DOUBLE), F(pf_effects, nozzle_xh, PF_FIELD_DOUBLE),
        F(pf_effects, saturate, PF_FIELD_INT),    F(pf_effects, sat_lo, PF_FIELD_DOUBLE),
        F(pf_effects, sat_hi, PF_FIELD_DOUBLE),   F(pf_effects, dead_time, PF_FIELD_DOUBLE),
        F(pf_effects, lag, PF_FIELD_DOUBLE),      F(pf_effects, nozzle_bias, PF_FIELD_DOUBLE),
    };
    static const want_field opts[] = {
        F(pf_design_opts, fs, PF_FIELD_DOUBLE),     F(pf_design_opts, wb, PF_FIELD_DOUBLE),
        F(pf_design_opts, wh, PF_FIELD_DOUBLE),     F(pf_design_opts, order, PF_FIELD_INT),
        F(pf_design_opts, approx, PF_FIELD_INT),    F(pf_design_opts, prewarp, PF_FIELD_DOUBLE),
        F(pf_design_opts, t_slow, PF_FIELD_DOUBLE), F(pf_design_opts, input, PF_FIELD_INT),
    };
    static const want_field design[] = {
        F(pf_ctrl_design, p, PF_FIELD_STRUCT),   F(pf_ctrl_design, fx, PF_FIELD_STRUCT),
        F(pf_ctrl_design, opt, PF_FIELD_STRUCT), F(pf_ctrl_design, rt, PF_FIELD_STRUCT),
    };
    static const pf_type parts[] = {PF_TYPE_PARAMS, PF_TYPE_EFFECTS,
                                     PF_TYPE_DESIGN_OPTS, PF_TYPE_CTRL_COEFFS_F64};
    pf_field f;
    int i;
    (void)state;
    expect_fields(PF_TYPE_PARAMS, params, (int)(sizeof params / sizeof params[0]));
    expect_fields(PF_TYPE_EFFECTS, effects, (int)(sizeof effects / sizeof effects[0]));
    expect_fields(PF_TYPE_DESIGN_OPTS, opts, (int)(sizeof opts / sizeof opts[0]));
    expect_fields(PF_TYPE_CTRL_DESIGN, design, (int)(sizeof design / sizeof design[0]));
    for (i = 0; i < 4; i++) {
        assert_int_equal(pf_field_get(PF_TYPE_CTRL_DESIGN, i, &f), 0);
        assert_int_equal(f.type, parts[i]);
        assert_int_equal(f.size, pf_sizeof(parts[i]));
    }
    /* opaque types list no members */
    assert_int_equal(pf_field_get(PF_TYPE_CTRL_F64, 0, &f), -1);
    assert_int_equal(pf_field_get(PF_TYPE_COUNT, 0, &f), -1);
}

static void test_delay_len(void **state)
{
    static pf_ctrl_design d;
    pf_params p;
    pf_effects fx;
    pf_design_opts o;
    (void)state;
    pf_params_default(&p, PF_TOPO_DD);
    memset(&fx, 0, sizeof fx);
    fx.dead_time = 0.0125;
    pf_design_opts_default(&o, 1000.0);
    assert_int_equal(pf_ctrl_design_make(&d, &p, &fx, &o), PF_OK);
    assert_int_equal(pf_ctrl_design_delay_len(&d), d.rt.delay_len);
    assert_int_equal(pf_ctrl_design_delay_len(&d), 13); /* round(12.5) up */
    assert_int_equal(pf_ctrl_design_delay_len(NULL), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sizes),
        cmocka_unit_test(test_members),
        cmocka_unit_test(test_delay_len),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
