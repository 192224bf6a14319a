/* SPDX-License-Identifier: MIT */
/*
 * Helpers shared by the black-box unit tests (test_params, test_effects,
 * test_robust): soft checks, "this status names that parameter", and which
 * parameters a design refusal of validated input may name.
 *
 * Soft checks: a table-driven test should list every wrong row, not just
 * the first, so EXPECT counts its failures and END_SOFT() asserts zero at
 * the end of the test. Register the test with cmocka_unit_test_setup(...,
 * setup_soft). Define SOFT_MAX_PRINT before the include to print only
 * the first few failures (all are still counted).
 *
 * Include after <cmocka.h> and "pneufrac/pneufrac.h".
 */
#ifndef TEST_UTIL_H
#define TEST_UTIL_H

#ifndef SOFT_MAX_PRINT
#define SOFT_MAX_PRINT 1000000
#endif

static int g_fails;

/* Counts a failure; says whether to print it (the caller prints the why). */
static inline int soft_fail(const char *file, int line, const char *cond)
{
    if (++g_fails > SOFT_MAX_PRINT)
        return 0;
    print_error("%s:%d: EXPECT(%s) failed: ", file, line, cond);
    return 1;
}

#define EXPECT(cond, ...)                                                     \
    do {                                                                      \
        if (!(cond) && soft_fail(__FILE__, __LINE__, #cond)) {                \
            print_error(__VA_ARGS__);                                         \
            print_error("\n");                                                \
        }                                                                     \
    } while (0)
#define END_SOFT() assert_int_equal(g_fails, 0)

static inline int setup_soft(void **state)
{
    (void)state;
    g_fails = 0;
    return 0;
}

/* The status must be exactly PF_E_PARAM(id) and decode back to id. */
static inline void expect_names(pf_status st, pf_param_id id, const char *what)
{
    EXPECT(st == PF_E_PARAM(id) && pf_status_param(st) == id,
           "%s: got status %d (param %s), want PF_E_PARAM(%s) = %d", what, st,
           pf_param_name(pf_status_param(st)), pf_param_name(id), PF_E_PARAM(id));
}

/* Where the headers leave open which of two parameters a refusal names
 * (wb >= wh, sat_lo >= sat_hi, the refined method's wh >= 2 rad/s), either
 * is fair; anything else is wrong. */
static inline void expect_names_one_of(pf_status st, pf_param_id a, pf_param_id b,
                                       const char *what)
{
    pf_param_id got = pf_status_param(st);
    EXPECT(st != PF_OK && (got == a || got == b) && st == PF_E_PARAM(got),
           "%s: got status %d (param %s), want %s or %s", what, st, pf_param_name(got),
           pf_param_name(a), pf_param_name(b));
}

/* pf_ctrl_design_make names the user's parameter behind an operator
 * (tau, ks, RC/RCd/RCi for its gain, beta/q/nu/w for its order), never the
 * internal PF_P_GAIN or PF_P_ALPHA. For parameters pf_params_validate
 * accepts, every operator gain lies inside the operator's 0 < |gain| <=
 * 1e12 (tau^-beta and 1/RC in [1e-9, 1e9], A/ks in [1e-12, 1e12]), so the
 * documented refusals left are an order whose section would leave the
 * representable range (pf_fracop.h), naming beta, q, nu or w, and a pid
 * whose restrictors make the in-sample loop equation (nearly) singular at
 * an extreme rate or band, naming RCd (pf_ctrl_design_make). */
static inline int design_may_name(pf_topology c, double fs, pf_param_id id)
{
    switch (id) {
    case PF_P_BETA: case PF_P_Q: case PF_P_NU: case PF_P_W:
        return pf_param_used(c, id);
    case PF_P_RCD: /* documented: a pid whose in-sample loop is singular */
        (void)fs;
        return c == PF_TOPO_PID;
    default:
        return 0;
    }
}

#endif /* TEST_UTIL_H */
