/* SPDX-License-Identifier: MIT */
/*
 * Black-box tests of the parameter layer against the contract written in
 * the public headers: the paper's example values as defaults; validation
 * that names exactly the offending parameter (ranges, pmin <= pmax, the
 * bellows ratio A/ks, the pid rules nu <= w and RCd < RCi); the name/id
 * tables; design option resolution and its limits; the operator's gain and
 * order limits; the Q15 full scales; that validation and design agree and
 * an accepted design runs finite; and that a failed controller design
 * leaves the caller's struct untouched.
 *
 * Only the public API (pneufrac/pneufrac.h) is used. Table-driven checks
 * report every mismatch before failing, so one run shows the whole picture.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "pneufrac/pneufrac.h"
#include "test_util.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* Documented limits (pf_params.h, pf_fracop.h, pf_controller.h). */
#define PARAM_MIN 1e-9      /* every positive model parameter ... */
#define PARAM_MAX 1e9       /* ... lies in [PARAM_MIN, PARAM_MAX] */
#define GAIN_MAX 1e12       /* operator: 0 < |gain| <= GAIN_MAX */
#define FULL_SCALE_MAX 1e12 /* Q15: in_fs, out_fs in (0, FULL_SCALE_MAX] */
#define FS 20000.0          /* the sample rate of the fixed cases */
#define NRUN 400            /* samples an accepted design is run for */

/* pf_fracop.h: a defaulted wb is max(0.01/t_slow, 2e-9*fs), t_slow 0 = 10 s */
static double default_wb(double fs, double t_slow)
{
    return fmax(0.01 / (t_slow != 0.0 ? t_slow : PF_DEFAULT_TSLOW), 2e-9 * fs);
}

static const char *pname(pf_param_id id)
{
    return pf_param_name(id);
}

static const char *cname(int c)
{
    return pf_topology_name((pf_topology)c);
}

/* Which parameters each configuration uses, from the block diagram in
 * pf_controller.h and the field comments of pf_params.h. */
static int uses(pf_topology c, pf_param_id id)
{
    switch (id) {
    case PF_P_A: case PF_P_B: case PF_P_K1: case PF_P_K2: case PF_P_AREA:
    case PF_P_KS: case PF_P_TAU: case PF_P_PMIN: case PF_P_PMAX:
    case PF_P_BETA: case PF_P_Q:
        return 1;
    case PF_P_NU: return c == PF_TOPO_DD || c == PF_TOPO_PID;
    case PF_P_W: return c == PF_TOPO_ID || c == PF_TOPO_PID;
    case PF_P_RC: return c == PF_TOPO_DD || c == PF_TOPO_ID;
    case PF_P_RCD: case PF_P_RCI: return c == PF_TOPO_PID;
    default: return 0;
    }
}

static int is_positive_param(pf_param_id id)
{
    return id <= PF_P_PMAX || id == PF_P_RC || id == PF_P_RCD || id == PF_P_RCI;
}

/* A change to a configuration's defaults (up to three parameters) and the
 * parameter its refusal must name (PF_P_COUNT: the result is valid). It
 * applies to the configurations in cfgs that use every parameter it sets. */
#define CFG_ALL 0xFu
#define CFG_BIT(c) (1u << (c))
#define CFG_DD_ID (CFG_BIT(PF_TOPO_DD) | CFG_BIT(PF_TOPO_ID))
#define CFG_ID_PID (CFG_BIT(PF_TOPO_ID) | CFG_BIT(PF_TOPO_PID))
#define CFG_PID CFG_BIT(PF_TOPO_PID)
#define VALID PF_P_COUNT

typedef struct mutation {
    const char *what;
    unsigned cfgs;
    int n;
    pf_param_id id[3];
    double v[3];
    pf_param_id want;
} mutation;

/* The defaults of cfg with m applied; 0 if m does not apply to cfg. */
static int apply_mutation(pf_params *p, int cfg, const mutation *m)
{
    int i;
    if (!(m->cfgs & CFG_BIT(cfg)))
        return 0;
    pf_params_default(p, (pf_topology)cfg);
    for (i = 0; i < m->n; i++) {
        if (!uses((pf_topology)cfg, m->id[i]))
            return 0;
        pf_params_set(p, m->id[i], m->v[i]);
    }
    return 1;
}

/* Set one parameter to a valid value and keep the pair rules met (pmin <=
 * pmax; pid: nu <= w, RCd < RCi) by moving the partner, so that only the
 * value itself is under test. 0 if no partner in range can do that. */
static int set_keep_pairs(pf_params *p, pf_param_id id, double v)
{
    pf_params_set(p, id, v);
    switch (id) {
    case PF_P_PMIN: if (p->pmax < v) p->pmax = v; break;
    case PF_P_PMAX: if (p->pmin > v) p->pmin = v; break;
    case PF_P_NU: if (p->w < v) p->w = v; break;
    case PF_P_W: if (p->nu > v) p->nu = v; break;
    case PF_P_RCD:
        if (p->RCi <= v) p->RCi = fmin(10.0 * v, PARAM_MAX);
        return v < p->RCi;
    case PF_P_RCI:
        if (p->RCd >= v) p->RCd = fmax(0.1 * v, PARAM_MIN);
        return p->RCd < v;
    default: break;
    }
    return 1;
}

/* ------------------------------------------------------------------ */
/* Defaults                                                             */
/* ------------------------------------------------------------------ */

/* The paper's values in pf_param_id order: a b k1 k2 A ks tau pmin pmax
 * beta q nu w RC RCd RCi (0 where the configuration does not use one). */
static const struct example {
    pf_topology cfg;
    const char *source;
    double v[PF_P_RCI + 1];
} k_examples[] = {
    {PF_TOPO_P, "Example 4 (eq. 17)",
     {1, 9, 0.1, 0.1, 2, 20, 0.001, 1, 10, 0.8, 0.9, 0, 0, 0, 0, 0}},
    {PF_TOPO_DD, "Example 6 (eq. 18)",
     {1, 9, 0.1, 0.1, 2, 20, 0.001, 1, 10, 0.8, 0.9, 0.94, 0, 0.1, 0, 0}},
    {PF_TOPO_ID, "Example 7 (eq. 20)",
     {1, 9, 2, 5, 2, 20, 0.001, 1, 10, 0.8, 0, 0, 0.94, 0.1, 0, 0}},
    /* no example in the paper: Example 7's values with nu = w = 0.94,
     * RCd = 0.01 s, RCi = 0.1 s (pf_params.h) */
    {PF_TOPO_PID, "pid defaults",
     {1, 9, 2, 5, 2, 20, 0.001, 1, 10, 0.8, 0, 0.94, 0.94, 0, 0.01, 0.1}},
};

static void test_defaults_match_paper(void **state)
{
    size_t i;
    int id;
    (void)state;
    for (i = 0; i < sizeof k_examples / sizeof k_examples[0]; i++) {
        const struct example *ex = &k_examples[i];
        pf_params p;
        pf_status st;
        memset(&p, 0x5a, sizeof p);
        pf_params_default(&p, ex->cfg);
        EXPECT(p.topology == ex->cfg, "%s: config = %d", ex->source, (int)p.topology);
        for (id = PF_P_A; id <= PF_P_RCI; id++) {
            double got = pf_params_get(&p, (pf_param_id)id);
            if (uses(ex->cfg, (pf_param_id)id))
                EXPECT(got == ex->v[id], "%s: %s = %g, want %g", ex->source,
                       pname((pf_param_id)id), got, ex->v[id]);
        }
        st = pf_params_validate(&p);
        EXPECT(st == PF_OK, "%s: default rejected (%d, %s)", ex->source, st,
               pname(pf_status_param(st)));
    }
    END_SOFT();
}

/* ------------------------------------------------------------------ */
/* Validation                                                           */
/* ------------------------------------------------------------------ */

static void test_param_used_table(void **state)
{
    int c, id;
    (void)state;
    for (c = 0; c < PF_TOPO_COUNT; c++)
        for (id = PF_P_A; id <= PF_P_RCI; id++)
            EXPECT(!pf_param_used((pf_topology)c, (pf_param_id)id) ==
                       !uses((pf_topology)c, (pf_param_id)id),
                   "pf_param_used(%s, %s) = %d", cname(c), pname((pf_param_id)id),
                   pf_param_used((pf_topology)c, (pf_param_id)id));
    END_SOFT();
}

/* Every positive parameter, in every configuration that uses it, refuses
 * zero (both signs), negatives, NaN, both infinities and finite values
 * outside [1e-9, 1e9], by its own name: before any pair rule (pmin <= pmax,
 * A/ks, RCd < RCi) that the value also breaks, since the range check of a
 * parameter comes first in pf_params_validate's list. The ends of the
 * range and values just inside are legal on their own (the partner of a
 * pair is moved so that only the single value is tested). */
static void test_validate_positive(void **state)
{
    const double bad[] = {0.0, -0.0, -1.0, -1e-300, -DBL_MAX, NAN, -NAN,
                          INFINITY, -INFINITY, DBL_MIN, 1e-10, 0.99999999e-9,
                          1.00000001e9, 1e10, DBL_MAX};
    const double ok[] = {PARAM_MIN, PARAM_MAX, 1.0000001e-9, 0.9999999e9};
    int c, id;
    size_t i;
    (void)state;
    for (c = 0; c < PF_TOPO_COUNT; c++) {
        for (id = PF_P_A; id <= PF_P_RCI; id++) {
            if (!uses((pf_topology)c, (pf_param_id)id) ||
                !is_positive_param((pf_param_id)id))
                continue;
            for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
                pf_params p;
                char what[96];
                pf_params_default(&p, (pf_topology)c);
                assert_int_equal(pf_params_set(&p, (pf_param_id)id, bad[i]), PF_OK);
                snprintf(what, sizeof what, "cfg %s, %s = %.17g", cname(c),
                         pname((pf_param_id)id), bad[i]);
                expect_names(pf_params_validate(&p), (pf_param_id)id, what);
            }
            for (i = 0; i < sizeof ok / sizeof ok[0]; i++) {
                pf_params p;
                pf_status st;
                pf_params_default(&p, (pf_topology)c);
                if (!set_keep_pairs(&p, (pf_param_id)id, ok[i]))
                    continue;
                st = pf_params_validate(&p);
                EXPECT(st == PF_OK, "cfg %s, %s = %g rejected with %d (%s)", cname(c),
                       pname((pf_param_id)id), ok[i], st, pname(pf_status_param(st)));
            }
        }
    }
    END_SOFT();
}

/* Orders: beta, nu, w in (0, 1]; q in [0, 1]. A bad order is named by
 * itself, also where it breaks the pid rule nu <= w too. */
static void test_validate_orders(void **state)
{
    const double bad_open[] = {0.0, -0.0, -0.5, 1.0 + 2 * DBL_EPSILON, 1.5,
                               NAN, INFINITY, -INFINITY};
    const double ok_open[] = {1e-9, 0.5, 0.94, 1.0};
    const double bad_q[] = {-DBL_MIN, -1e-12, -0.5, 1.0 + 2 * DBL_EPSILON, 2.0,
                            NAN, INFINITY, -INFINITY};
    const double ok_q[] = {0.0, 1e-9, 0.5, 1.0};
    const pf_param_id ids[] = {PF_P_BETA, PF_P_NU, PF_P_W, PF_P_Q};
    int c;
    size_t i, j;
    (void)state;
    for (c = 0; c < PF_TOPO_COUNT; c++) {
        for (j = 0; j < sizeof ids / sizeof ids[0]; j++) {
            const pf_param_id id = ids[j];
            const double *bad = id == PF_P_Q ? bad_q : bad_open;
            const double *ok = id == PF_P_Q ? ok_q : ok_open;
            if (!uses((pf_topology)c, id))
                continue;
            /* bad_q and bad_open have the same length, ok_q and ok_open too */
            for (i = 0; i < sizeof bad_open / sizeof bad_open[0]; i++) {
                pf_params p;
                char what[96];
                pf_params_default(&p, (pf_topology)c);
                pf_params_set(&p, id, bad[i]);
                snprintf(what, sizeof what, "cfg %s, %s = %.17g", cname(c), pname(id), bad[i]);
                expect_names(pf_params_validate(&p), id, what);
            }
            for (i = 0; i < sizeof ok_open / sizeof ok_open[0]; i++) {
                pf_params p;
                pf_status st;
                pf_params_default(&p, (pf_topology)c);
                set_keep_pairs(&p, id, ok[i]);
                st = pf_params_validate(&p);
                EXPECT(st == PF_OK, "cfg %s, %s = %g rejected (%d, %s)", cname(c), pname(id),
                       ok[i], st, pname(pf_status_param(st)));
            }
        }
    }
    END_SOFT();
}

/* The rules between parameters (pf_params.h): pmin <= pmax, else pmax is
 * named; A/ks in [1e-12, 1e12], else ks; for pid, nu <= w, else w, and
 * then RCd < RCi, else RCd. */
static const mutation k_pair_rules[] = {
    {"pmax < pmin", CFG_ALL, 2, {PF_P_PMIN, PF_P_PMAX}, {10.0, 9.999999}, PF_P_PMAX},
    {"pmax = 0.5 < pmin = 1", CFG_ALL, 1, {PF_P_PMAX}, {0.5}, PF_P_PMAX},
    {"pmin == pmax (a plain spring relay)", CFG_ALL, 2, {PF_P_PMIN, PF_P_PMAX}, {3.0, 3.0}, VALID},
    {"A/ks = 9.9e11", CFG_ALL, 2, {PF_P_AREA, PF_P_KS}, {1e9, 1.01e-3}, VALID},
    {"A/ks = 1.01e12", CFG_ALL, 2, {PF_P_AREA, PF_P_KS}, {1e9, 0.99e-3}, PF_P_KS},
    {"A/ks = 1.01e-12", CFG_ALL, 2, {PF_P_AREA, PF_P_KS}, {1e-9, 0.99e3}, VALID},
    {"A/ks = 9.9e-13", CFG_ALL, 2, {PF_P_AREA, PF_P_KS}, {1e-9, 1.01e3}, PF_P_KS},
    {"A/ks = 1e18", CFG_ALL, 2, {PF_P_AREA, PF_P_KS}, {1e9, 1e-9}, PF_P_KS},
    {"A/ks = 1e-18", CFG_ALL, 2, {PF_P_AREA, PF_P_KS}, {1e-9, 1e9}, PF_P_KS},
    {"A = 2e9 (its own range first)", CFG_ALL, 2, {PF_P_AREA, PF_P_KS}, {2e9, 1e-9}, PF_P_AREA},
    {"nu == w", CFG_PID, 2, {PF_P_NU, PF_P_W}, {0.5, 0.5}, VALID},
    {"nu < w", CFG_PID, 2, {PF_P_NU, PF_P_W}, {0.3, 1.0}, VALID},
    {"nu just above w", CFG_PID, 2, {PF_P_NU, PF_P_W}, {0.5000001, 0.5}, PF_P_W},
    {"nu = 1 > w = 0.94", CFG_PID, 1, {PF_P_NU}, {1.0}, PF_P_W},
    {"nu = 0.94 > w = 0.01", CFG_PID, 1, {PF_P_W}, {0.01}, PF_P_W},
    {"RCd == RCi", CFG_PID, 1, {PF_P_RCD}, {0.1}, PF_P_RCD},
    {"RCd > RCi", CFG_PID, 2, {PF_P_RCD, PF_P_RCI}, {1.0, 0.5}, PF_P_RCD},
    {"RCd just below RCi", CFG_PID, 1, {PF_P_RCD}, {0.0999999}, VALID},
    {"nu > w and RCd == RCi: nu <= w comes first", CFG_PID, 3,
     {PF_P_NU, PF_P_W, PF_P_RCD}, {1.0, 0.5, 0.1}, PF_P_W},
    /* the pid rules mean nothing where a partner is unused */
    {"nu = 1, w = 0.01, one of them unused", CFG_DD_ID, 2, {PF_P_NU, PF_P_W}, {1.0, 0.01}, VALID},
};

static void expect_validate(const pf_params *p, pf_param_id want, const char *what)
{
    pf_status st = pf_params_validate(p);
    if (want == VALID)
        EXPECT(st == PF_OK, "%s: rejected with %d (%s)", what, st, pname(pf_status_param(st)));
    else
        expect_names(st, want, what);
}

/* The rule a refusal within every range came from is the one
 * pf_params_broken_rule names (what a message tells the user to change);
 * none when the set is valid. */
static void expect_broken_rule(const pf_params *p, pf_param_id want, const char *what)
{
    const pf_param_rule *r = pf_params_broken_rule(p);
    if (want == VALID)
        EXPECT(r == NULL, "%s: valid, yet rule '%s' named", what, r ? r->text : "");
    else if (pf_param_check(want, pf_params_get(p, want)) == PF_OK)
        EXPECT(r != NULL && r->refused == want && r->other != want && r->text[0] != '\0',
               "%s: broken rule %s, want one refusing %s", what,
               r ? r->text : "none", pname(want));
}

static void test_validate_pairs(void **state)
{
    int c;
    size_t i;
    (void)state;
    for (c = 0; c < PF_TOPO_COUNT; c++)
        for (i = 0; i < sizeof k_pair_rules / sizeof k_pair_rules[0]; i++) {
            pf_params p;
            char what[96];
            if (!apply_mutation(&p, c, &k_pair_rules[i]))
                continue;
            snprintf(what, sizeof what, "cfg %s, %s", cname(c), k_pair_rules[i].what);
            expect_validate(&p, k_pair_rules[i].want, what);
            expect_broken_rule(&p, k_pair_rules[i].want, what);
        }
    /* the pid ordering rules mean nothing to the other configurations */
    for (c = 0; c < PF_TOPO_PID; c++) {
        pf_params p;
        pf_params_default(&p, (pf_topology)c);
        p.RCd = 1.0;
        p.RCi = 0.5;
        p.nu = 1.0;
        p.w = 0.01;
        expect_validate(&p, VALID, cname(c));
    }
    END_SOFT();
}

/* A parameter the configuration does not use is ignored, however bad. */
static void test_validate_unused_ignored(void **state)
{
    const double junk[] = {NAN, INFINITY, -1.0, 0.0, 7.0};
    int c, id;
    size_t i;
    (void)state;
    for (c = 0; c < PF_TOPO_COUNT; c++)
        for (id = PF_P_A; id <= PF_P_RCI; id++) {
            if (uses((pf_topology)c, (pf_param_id)id))
                continue;
            for (i = 0; i < sizeof junk / sizeof junk[0]; i++) {
                pf_params p;
                pf_status st;
                pf_params_default(&p, (pf_topology)c);
                pf_params_set(&p, (pf_param_id)id, junk[i]);
                st = pf_params_validate(&p);
                EXPECT(st == PF_OK, "cfg %s: unused %s = %g gives %d (%s)",
                       cname(c), pname((pf_param_id)id),
                       junk[i], st, pname(pf_status_param(st)));
            }
        }
    END_SOFT();
}

static void test_validate_config_and_null(void **state)
{
    pf_params p;
    (void)state;
    pf_params_default(&p, PF_TOPO_DD);
    p.topology = PF_TOPO_COUNT;
    expect_names(pf_params_validate(&p), PF_P_CONFIG, "config = PF_TOPO_COUNT");
    p.topology = (pf_topology)-1;
    expect_names(pf_params_validate(&p), PF_P_CONFIG, "config = -1");
    EXPECT(pf_params_validate(NULL) == PF_E_NULL, "validate(NULL) = %d",
           pf_params_validate(NULL));
    EXPECT(pf_params_broken_rule(NULL) == NULL, "broken_rule(NULL) is not NULL");
    END_SOFT();
}

/* set/get address the field the id names, and refuse non-model ids
 * without touching the struct. */
static void test_params_set_get(void **state)
{
    int id;
    (void)state;
    for (id = PF_P_A; id <= PF_P_RCI; id++) {
        pf_params p, before;
        double v = 0.125 + id;
        double *field[PF_P_RCI + 1];
        memset(&p, 0, sizeof p);
        field[PF_P_A] = &p.a; field[PF_P_B] = &p.b; field[PF_P_K1] = &p.k1;
        field[PF_P_K2] = &p.k2; field[PF_P_AREA] = &p.A; field[PF_P_KS] = &p.ks;
        field[PF_P_TAU] = &p.tau; field[PF_P_PMIN] = &p.pmin;
        field[PF_P_PMAX] = &p.pmax; field[PF_P_BETA] = &p.beta;
        field[PF_P_Q] = &p.q; field[PF_P_NU] = &p.nu; field[PF_P_W] = &p.w;
        field[PF_P_RC] = &p.RC; field[PF_P_RCD] = &p.RCd; field[PF_P_RCI] = &p.RCi;
        before = p;
        EXPECT(pf_params_set(&p, (pf_param_id)id, v) == PF_OK, "set %s", pname((pf_param_id)id));
        EXPECT(*field[id] == v, "set %s wrote the wrong field", pname((pf_param_id)id));
        EXPECT(pf_params_get(&p, (pf_param_id)id) == v, "get %s", pname((pf_param_id)id));
        *field[id] = 0.0;
        EXPECT(memcmp(&p, &before, sizeof p) == 0, "set %s touched other fields",
               pname((pf_param_id)id));
    }
    for (id = PF_P_CONFIG; id <= PF_P_COUNT; id++) {
        pf_params p, before;
        pf_status st;
        pf_params_default(&p, PF_TOPO_PID);
        before = p;
        st = pf_params_set(&p, (pf_param_id)id, 1.0);
        EXPECT(st == PF_E_PARAM(id), "set non-model id %d gives %d", id, st);
        EXPECT(memcmp(&p, &before, sizeof p) == 0, "set non-model id %d changed p", id);
    }
    END_SOFT();
}

/* ------------------------------------------------------------------ */
/* Names                                                                */
/* ------------------------------------------------------------------ */

static void test_param_names_roundtrip(void **state)
{
    int id, j;
    (void)state;
    for (id = 0; id < PF_P_COUNT; id++) {
        const char *n = pf_param_name((pf_param_id)id);
        EXPECT(n != NULL && n[0] != '\0' && strcmp(n, "?") != 0,
               "id %d has no name", id);
        if (n == NULL)
            continue;
        EXPECT(pf_param_lookup(n) == (pf_param_id)id, "lookup(\"%s\") = %d, want %d",
               n, (int)pf_param_lookup(n), id);
        for (j = 0; j < id; j++) {
            const char *m = pf_param_name((pf_param_id)j);
            EXPECT(m == NULL || strcmp(m, n) != 0, "ids %d and %d share name %s", j, id, n);
        }
        /* a status built from the id decodes back to it */
        EXPECT(pf_status_param(PF_E_PARAM(id)) == (pf_param_id)id, "status of %s", n);
        EXPECT(pf_status_str(PF_E_PARAM(id)) != NULL, "status_str of %s", n);
    }
    /* the paper's spelling, as documented */
    EXPECT(strcmp(pf_param_name(PF_P_BETA), "beta") == 0, "beta is \"%s\"",
           pf_param_name(PF_P_BETA));
    EXPECT(strcmp(pf_param_name(PF_P_COUNT), "?") == 0, "name(COUNT)");
    EXPECT(strcmp(pf_param_name((pf_param_id)-1), "?") == 0, "name(-1)");
    EXPECT(strcmp(pf_param_name((pf_param_id)1000), "?") == 0, "name(1000)");
    EXPECT(pf_param_lookup("no-such-parameter") == PF_P_COUNT, "lookup(junk)");
    EXPECT(pf_param_lookup("") == PF_P_COUNT, "lookup(\"\")");
    EXPECT(pf_param_lookup("?") == PF_P_COUNT, "lookup(\"?\")");
    EXPECT(pf_param_lookup("betaa") == PF_P_COUNT, "lookup(prefix-extended)");
    EXPECT(pf_param_lookup("bet") == PF_P_COUNT, "lookup(prefix)");

    /* non-parameter statuses name no parameter */
    EXPECT(pf_status_param(PF_OK) == PF_P_COUNT, "status_param(OK)");
    EXPECT(pf_status_param(PF_E_NULL) == PF_P_COUNT, "status_param(E_NULL)");
    EXPECT(pf_status_param(PF_E_SCALE) == PF_P_COUNT, "status_param(E_SCALE)");
    EXPECT(pf_status_param(PF_E_PARAM(PF_P_COUNT)) == PF_P_COUNT, "status_param(base+COUNT)");
    EXPECT(pf_status_param(PF_E_PARAM_BASE - 1) == PF_P_COUNT, "status_param(base-1)");
    EXPECT(pf_status_param(INT_MAX) == PF_P_COUNT, "status_param(INT_MAX)");
    EXPECT(pf_status_param(INT_MIN) == PF_P_COUNT, "status_param(INT_MIN)");
    EXPECT(pf_status_str(PF_OK) != NULL && pf_status_str(INT_MIN) != NULL &&
               pf_status_str(INT_MAX) != NULL && pf_status_str(PF_E_BUFFER) != NULL,
           "status_str returns NULL");
    END_SOFT();
}

/* The parameter table (pf_param_info.h): a row per id, the limits the
 * headers document, and pf_param_check against each row's own bounds. */
static void test_param_table(void **state)
{
    int id;
    (void)state;
    EXPECT(pf_param_count() == (int)PF_P_COUNT, "count %d", pf_param_count());
    EXPECT(pf_param_info(PF_P_COUNT) == NULL, "info(COUNT)");
    EXPECT(pf_param_info((pf_param_id)-1) == NULL, "info(-1)");
    EXPECT(pf_param_check(PF_P_COUNT, 1.0) == PF_E_PARAM(PF_P_COUNT), "check(COUNT)");
    for (id = 0; id < PF_P_COUNT; id++) {
        const pf_param_spec *s = pf_param_info((pf_param_id)id);
        double in_lo, in_hi;
        EXPECT(s != NULL, "id %d has no row", id);
        if (s == NULL)
            continue;
        EXPECT(strcmp(s->name, pname((pf_param_id)id)) == 0, "%s: name", s->name);
        EXPECT(s->desc[0] != '\0' && s->unit != NULL, "%s: desc/unit", s->name);
        EXPECT(s->lo < s->hi, "%s: [%g, %g]", s->name, s->lo, s->hi);
        EXPECT(id <= PF_P_RCI ? s->topologies != 0 : s->topologies == 0,
               "%s: topologies %#x", s->name, s->topologies);
        /* the ends: in exactly when closed (a finite one) */
        EXPECT((pf_param_check((pf_param_id)id, s->lo) == PF_OK) ==
                   !(s->flags & PF_PARAM_LO_OPEN),
               "%s: lo %g", s->name, s->lo);
        if (isfinite(s->hi))
            EXPECT((pf_param_check((pf_param_id)id, s->hi) == PF_OK) ==
                       !(s->flags & PF_PARAM_HI_OPEN),
                   "%s: hi %g", s->name, s->hi);
        /* just outside: out, with the status naming the parameter */
        expect_names(pf_param_check((pf_param_id)id, nextafter(s->lo, -INFINITY)),
                     (pf_param_id)id, "below lo");
        if (isfinite(s->hi))
            expect_names(pf_param_check((pf_param_id)id, nextafter(s->hi, INFINITY)),
                         (pf_param_id)id, "above hi");
        expect_names(pf_param_check((pf_param_id)id, NAN), (pf_param_id)id, "NaN");
        expect_names(pf_param_check((pf_param_id)id, INFINITY), (pf_param_id)id, "inf");
        /* inside: a whole number for integers, not 0 where 0 is out */
        in_lo = (s->flags & PF_PARAM_INTEGER) ? ceil(s->lo + 0.5)
                : nextafter(s->lo, INFINITY);
        if (in_lo == 0.0 && (s->flags & PF_PARAM_NONZERO))
            in_lo = nextafter(0.0, INFINITY);
        EXPECT(pf_param_check((pf_param_id)id, in_lo) == PF_OK, "%s: %g", s->name, in_lo);
        in_hi = isfinite(s->hi) ? s->hi : 1e300;
        if (s->flags & PF_PARAM_INTEGER) {
            EXPECT(pf_param_check((pf_param_id)id, s->lo + 0.5) != PF_OK,
                   "%s: %g is not whole", s->name, s->lo + 0.5);
        } else if (s->flags & PF_PARAM_HI_OPEN) {
            in_hi = nextafter(s->hi, -INFINITY);
        }
        EXPECT(pf_param_check((pf_param_id)id, in_hi) == PF_OK, "%s: %g", s->name, in_hi);
        if (s->flags & PF_PARAM_NONZERO)
            expect_names(pf_param_check((pf_param_id)id, 0.0), (pf_param_id)id, "0");
    }
    /* the limits the headers document (pf_params.h, pf_fracop.h,
     * pf_controller.h) */
    for (id = PF_P_A; id <= PF_P_RCI; id++) {
        const pf_param_spec *s = pf_param_info((pf_param_id)id);
        if (!is_positive_param((pf_param_id)id))
            continue;
        EXPECT(s->lo == PARAM_MIN && s->hi == PARAM_MAX && s->flags == 0,
               "%s: [%g, %g] flags %#x", s->name, s->lo, s->hi, s->flags);
    }
    EXPECT(pf_param_info(PF_P_Q)->lo == 0.0 && pf_param_info(PF_P_Q)->flags == 0, "q");
    EXPECT(pf_param_info(PF_P_BETA)->flags == PF_PARAM_LO_OPEN &&
               pf_param_info(PF_P_BETA)->hi == 1.0, "beta");
    EXPECT(pf_param_info(PF_P_GAIN)->hi == GAIN_MAX, "gain");
    EXPECT(pf_param_info(PF_P_IN_FS)->hi == FULL_SCALE_MAX &&
               pf_param_info(PF_P_OUT_FS)->hi == FULL_SCALE_MAX, "full scales");
    EXPECT(pf_param_info(PF_P_ORDER)->hi == PF_MAX_ORDER, "order");
    EXPECT(pf_param_info(PF_P_CONFIG)->hi == PF_TOPO_COUNT - 1, "config");
    EXPECT(strcmp(pf_param_info(PF_P_FS)->unit, "Hz") == 0 &&
               strcmp(pf_param_info(PF_P_TAU)->unit, "s") == 0, "units");
    END_SOFT();
}

static void test_config_names(void **state)
{
    static const char *const names[] = {"p", "dd", "id", "pid"};
    static const char *const bad[] = {"", "x", "pd", "ddd", "pi", "pid ", " p",
                                      "?", "PIDX"};
    int c;
    size_t i;
    (void)state;
    for (c = 0; c < PF_TOPO_COUNT; c++) {
        EXPECT(strcmp(pf_topology_name((pf_topology)c), names[c]) == 0,
               "config_name(%d) = %s", c, pf_topology_name((pf_topology)c));
        EXPECT(pf_topology_lookup(names[c]) == (pf_topology)c, "lookup(%s) = %d",
               names[c], (int)pf_topology_lookup(names[c]));
    }
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++)
        EXPECT(pf_topology_lookup(bad[i]) == PF_TOPO_COUNT, "lookup(\"%s\") = %d",
               bad[i], (int)pf_topology_lookup(bad[i]));
    EXPECT(strcmp(pf_topology_name(PF_TOPO_COUNT), "?") == 0, "config_name(COUNT)");
    EXPECT(strcmp(pf_topology_name((pf_topology)-1), "?") == 0, "config_name(-1)");
    END_SOFT();
}

/* ------------------------------------------------------------------ */
/* Design options                                                       */
/* ------------------------------------------------------------------ */

static pf_design_opts bare(double fs)
{
    pf_design_opts o;
    memset(&o, 0, sizeof o);
    o.fs = fs;
    return o;
}

static void expect_opts(const pf_design_opts *in, pf_param_id id, const char *what)
{
    pf_design_opts out;
    expect_names(pf_design_opts_resolve(in, &out), id, what);
}

static void expect_opts_either(const pf_design_opts *in, pf_param_id a, pf_param_id b,
                               const char *what)
{
    pf_design_opts out;
    expect_names_one_of(pf_design_opts_resolve(in, &out), a, b, what);
}

static void expect_opts_ok(const pf_design_opts *in, const char *what)
{
    pf_design_opts out;
    pf_status st = pf_design_opts_resolve(in, &out);
    EXPECT(st == PF_OK, "%s: rejected with %d (%s)", what, st, pname(pf_status_param(st)));
}

static int close_rel(double a, double b)
{
    return fabs(a - b) <= 1e-15 * fabs(b);
}

/* Defaults as documented: wb = max(0.01/t_slow, 2e-9 fs), wh = pi fs,
 * N = ceil(log10(wh/wb)) capped at PF_MAX_ORDER. */
static void expect_defaults(double fs, double t_slow)
{
    pf_design_opts in = bare(fs), out;
    pf_status st;
    int n;
    in.t_slow = t_slow;
    st = pf_design_opts_resolve(&in, &out);
    EXPECT(st == PF_OK, "fs %g, t_slow %g: defaults refused (%d, %s)", fs, t_slow, st,
           pname(pf_status_param(st)));
    if (st != PF_OK)
        return;
    n = (int)ceil(log10(out.wh / out.wb));
    if (n > PF_MAX_ORDER)
        n = PF_MAX_ORDER;
    EXPECT(out.fs == fs && out.t_slow == (t_slow != 0.0 ? t_slow : PF_DEFAULT_TSLOW),
           "fs %g, t_slow %g: resolved fs %g, t_slow %g", fs, t_slow, out.fs, out.t_slow);
    EXPECT(close_rel(out.wb, default_wb(fs, t_slow)), "fs %g, t_slow %g: wb %.17g, want %.17g",
           fs, t_slow, out.wb, default_wb(fs, t_slow));
    EXPECT(close_rel(out.wh, M_PI * fs), "fs %g: wh %.17g, want pi fs", fs, out.wh);
    EXPECT(out.order == n, "fs %g, t_slow %g: order %d, want %d", fs, t_slow, out.order, n);
    EXPECT(out.approx == PF_APPROX_OUSTALOUP && out.input == PF_INPUT_HOLD &&
               out.prewarp == 0.0,
           "fs %g: approx %d input %d prewarp %g", fs, (int)out.approx, (int)out.input,
           out.prewarp);
}

static void test_opts_defaults(void **state)
{
    /* fs, t_slow: the 0.01/t_slow branch, then the 2e-9 fs floor */
    static const double cases[][2] = {
        {FS, 0.0}, {FS, 1.0}, {1.0, 0.0}, {1e7, 0.0}, {1e6, 1e3}, {1.0, 1e9}, {FS, 1e9}};
    pf_design_opts in, out, dflt, again;
    size_t i;
    (void)state;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++)
        expect_defaults(cases[i][0], cases[i][1]);

    /* pf_design_opts_default leaves wb, wh and order at 0, so that they
     * follow t_slow when resolved; it resolves like a bare struct */
    in = bare(FS);
    assert_int_equal(pf_design_opts_resolve(&in, &out), PF_OK);
    memset(&dflt, 0x5a, sizeof dflt);
    pf_design_opts_default(&dflt, FS);
    EXPECT(dflt.fs == FS && dflt.wb == 0.0 && dflt.wh == 0.0 && dflt.order == 0,
           "opts_default: fs %g wb %g wh %g N %d, want fs and zeros", dflt.fs, dflt.wb,
           dflt.wh, dflt.order);
    assert_int_equal(pf_design_opts_resolve(&dflt, &again), PF_OK);
    EXPECT(again.wb == out.wb && again.wh == out.wh && again.order == out.order &&
               again.t_slow == out.t_slow && again.approx == out.approx &&
               again.input == out.input && again.prewarp == out.prewarp,
           "opts_default resolves differently from a bare struct");
    dflt.t_slow = 1.0;
    assert_int_equal(pf_design_opts_resolve(&dflt, &again), PF_OK);
    EXPECT(close_rel(again.wb, 0.01), "opts_default, t_slow = 1: wb %g, want 0.01", again.wb);
    /* resolving a resolved struct changes nothing */
    assert_int_equal(pf_design_opts_resolve(&out, &again), PF_OK);
    EXPECT(again.wb == out.wb && again.wh == out.wh && again.order == out.order &&
               again.t_slow == out.t_slow && again.prewarp == out.prewarp,
           "resolve is not idempotent");

    /* An explicit band keeps its values; the order follows the band. */
    in = bare(1000.0);
    in.wb = 10.0;
    in.wh = 500.0; /* 1.7 decades -> 2 */
    assert_int_equal(pf_design_opts_resolve(&in, &out), PF_OK);
    EXPECT(out.wb == 10.0 && out.wh == 500.0, "band %g..%g", out.wb, out.wh);
    EXPECT(out.order == 2, "order for 1.7 decades: %d", out.order);
    in.wh = 50.0; /* 0.7 decade -> 1 */
    assert_int_equal(pf_design_opts_resolve(&in, &out), PF_OK);
    EXPECT(out.order == 1, "order for 0.7 decade: %d", out.order);
    in = bare(1e6); /* 8.5 decades: capped */
    in.wb = 0.01;
    assert_int_equal(pf_design_opts_resolve(&in, &out), PF_OK);
    EXPECT(out.order == PF_MAX_ORDER, "order for 8.5 decades: %d", out.order);
    /* an explicit order is kept */
    in = bare(FS);
    in.order = 3;
    assert_int_equal(pf_design_opts_resolve(&in, &out), PF_OK);
    EXPECT(out.order == 3, "explicit order: %d", out.order);

    EXPECT(pf_design_opts_resolve(NULL, &out) == PF_E_NULL, "resolve(NULL, out)");
    EXPECT(pf_design_opts_resolve(&in, NULL) == PF_E_NULL, "resolve(in, NULL)");
    END_SOFT();
}

static void test_opts_fs(void **state)
{
    const double bad[] = {0.0, -0.0, -1.0, NAN, INFINITY, -INFINITY, 1.0000001e7,
                          1e8, 1e300, DBL_MAX};
    pf_design_opts o;
    size_t i;
    (void)state;
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char what[48];
        o = bare(bad[i]);
        snprintf(what, sizeof what, "fs = %g", bad[i]);
        expect_opts(&o, PF_P_FS, what);
    }
    /* the ends of (0, 1e7]; at 1e7 the default wb is raised to 2e-9 fs
     * (checked in test_opts_defaults) */
    o = bare(1e7);          expect_opts_ok(&o, "fs = 1e7 (defaults)");
    o = bare(1e7); o.wb = 0.05; expect_opts_ok(&o, "fs = 1e7, wb = 0.05");
    o = bare(1.0);          expect_opts_ok(&o, "fs = 1 (defaults)");
    END_SOFT();
}

static void test_opts_band(void **state)
{
    const double ny = M_PI * FS;
    pf_design_opts o, out;
    (void)state;

    o = bare(FS); o.wb = -1.0;       expect_opts(&o, PF_P_WB, "wb = -1");
    o = bare(FS); o.wb = NAN;        expect_opts(&o, PF_P_WB, "wb = NaN");
    o = bare(FS); o.wb = INFINITY;   expect_opts(&o, PF_P_WB, "wb = inf");
    o = bare(FS); o.wh = -1.0;       expect_opts(&o, PF_P_WH, "wh = -1");
    o = bare(FS); o.wh = NAN;        expect_opts(&o, PF_P_WH, "wh = NaN");
    o = bare(FS); o.wh = INFINITY;   expect_opts(&o, PF_P_WH, "wh = inf");

    /* above Nyquist, beyond the documented 1e-12 relative slack */
    o = bare(FS); o.wh = ny * (1.0 + 1e-9);  expect_opts(&o, PF_P_WH, "wh = pi fs (1 + 1e-9)");
    o = bare(FS); o.wh = ny * (1.0 + 1e-11); expect_opts(&o, PF_P_WH, "wh = pi fs (1 + 1e-11)");
    o = bare(FS); o.wh = 2.0 * ny;           expect_opts(&o, PF_P_WH, "wh = 2 pi fs");
    o = bare(FS); o.wh = ny;                 expect_opts_ok(&o, "wh = pi fs");
    o = bare(FS); o.wh = ny * (1.0 + 5e-13); expect_opts_ok(&o, "wh = pi fs (1 + 5e-13)");

    /* empty or inverted band: either edge is a fair name */
    o = bare(FS); o.wb = 1000.0; o.wh = 1000.0;
    expect_opts_either(&o, PF_P_WB, PF_P_WH, "wb == wh");
    o = bare(FS); o.wb = 2000.0; o.wh = 1000.0;
    expect_opts_either(&o, PF_P_WB, PF_P_WH, "wb > wh");
    o = bare(FS); o.wb = ny * 1.5;
    expect_opts_either(&o, PF_P_WB, PF_P_WH, "wb > default wh");

    /* wb / fs below 1e-9: a pole the Q15 runtime cannot resolve */
    o = bare(1e6); o.wb = 0.5e-3;   expect_opts(&o, PF_P_WB, "wb/fs = 5e-10");
    o = bare(1e6); o.wb = 2e-3;     expect_opts_ok(&o, "wb/fs = 2e-9");
    o = bare(1e7); o.wb = 1e-6;     expect_opts(&o, PF_P_WB, "wb/fs = 1e-13");
    /* the default wb never falls below that floor: it is raised to 2e-9 fs */
    o = bare(1e7);
    o.t_slow = 1e3;
    assert_int_equal(pf_design_opts_resolve(&o, &out), PF_OK);
    EXPECT(close_rel(out.wb, 0.02), "t_slow = 1e3 s at fs = 1e7: wb %g, want 0.02", out.wb);

    /* t_slow in [0, 1e9], whether or not wb is defaulted */
    o = bare(FS); o.t_slow = -1.0;       expect_opts(&o, PF_P_TSLOW, "t_slow = -1");
    o = bare(FS); o.t_slow = NAN;        expect_opts(&o, PF_P_TSLOW, "t_slow = NaN");
    o = bare(FS); o.t_slow = INFINITY;   expect_opts(&o, PF_P_TSLOW, "t_slow = inf");
    o = bare(FS); o.t_slow = 1.000001e9; expect_opts(&o, PF_P_TSLOW, "t_slow = 1.000001e9");
    o = bare(FS); o.t_slow = 1e9;        expect_opts_ok(&o, "t_slow = 1e9");
    o = bare(FS); o.wb = 1.0; o.t_slow = -1.0;
    expect_opts(&o, PF_P_TSLOW, "wb given, t_slow = -1");
    o = bare(FS); o.wb = 1.0; o.t_slow = 1e10;
    expect_opts(&o, PF_P_TSLOW, "wb given, t_slow = 1e10");
    END_SOFT();
}

/* The refined method needs wh >= 2 rad/s. Which option the refusal names
 * (the band edge or the method) is not documented; either is fair. */
static void test_opts_refined(void **state)
{
    pf_design_opts o;
    (void)state;
    o = bare(1000.0); o.wb = 0.01; o.wh = 2.0; o.approx = PF_APPROX_REFINED;
    expect_opts_ok(&o, "refined, wh = 2");
    o.wh = 1.999;
    expect_opts_either(&o, PF_P_WH, PF_P_APPROX, "refined, wh = 1.999");
    o.approx = PF_APPROX_OUSTALOUP;
    expect_opts_ok(&o, "oustaloup, wh = 1.999");
    /* the default wh = pi fs is below 2 rad/s for fs < 2/pi Hz */
    o = bare(0.5); o.approx = PF_APPROX_REFINED;
    expect_opts_either(&o, PF_P_WH, PF_P_APPROX, "refined, fs = 0.5 Hz (default wh)");
    o.approx = PF_APPROX_OUSTALOUP;
    expect_opts_ok(&o, "oustaloup, fs = 0.5 Hz");
    END_SOFT();
}

static void test_opts_enums_order_prewarp(void **state)
{
    const double ny = M_PI * FS;
    const int bad_order[] = {-1, PF_MAX_ORDER + 1, 1000, INT_MAX, INT_MIN};
    const double bad_prewarp[] = {0.99 * ny, 0.995 * ny, 0.999 * ny, ny, 2.0 * ny, -1.0,
                                  NAN, INFINITY};
    pf_design_opts o, out;
    size_t i;
    (void)state;

    for (i = 0; i < sizeof bad_order / sizeof bad_order[0]; i++) {
        char what[40];
        o = bare(FS);
        o.order = bad_order[i];
        snprintf(what, sizeof what, "order = %d", bad_order[i]);
        expect_opts(&o, PF_P_ORDER, what);
    }
    o = bare(FS); o.order = 1;            expect_opts_ok(&o, "order = 1");
    o = bare(FS); o.order = PF_MAX_ORDER; expect_opts_ok(&o, "order = PF_MAX_ORDER");
    /* 0 after the default: filled in, never left at 0 */
    o = bare(FS); o.order = 0;
    assert_int_equal(pf_design_opts_resolve(&o, &out), PF_OK);
    EXPECT(out.order >= 1 && out.order <= PF_MAX_ORDER, "order 0 resolved to %d", out.order);

    o = bare(FS); o.approx = (pf_approx)2;  expect_opts(&o, PF_P_APPROX, "approx = 2");
    o = bare(FS); o.approx = (pf_approx)-1; expect_opts(&o, PF_P_APPROX, "approx = -1");
    o = bare(FS); o.approx = PF_APPROX_REFINED; expect_opts_ok(&o, "approx = refined");
    o = bare(FS); o.input = (pf_input_model)2;  expect_opts(&o, PF_P_INPUT, "input = 2");
    o = bare(FS); o.input = (pf_input_model)-1; expect_opts(&o, PF_P_INPUT, "input = -1");
    o = bare(FS); o.input = PF_INPUT_LINEAR;    expect_opts_ok(&o, "input = linear");

    /* prewarp in [0, 0.99 pi fs) */
    for (i = 0; i < sizeof bad_prewarp / sizeof bad_prewarp[0]; i++) {
        char what[48];
        o = bare(FS);
        o.prewarp = bad_prewarp[i];
        snprintf(what, sizeof what, "prewarp = %.6g pi fs", bad_prewarp[i] / ny);
        expect_opts(&o, PF_P_PREWARP, what);
    }
    o = bare(FS); o.prewarp = 0.989 * ny;  expect_opts_ok(&o, "prewarp = 0.989 pi fs");
    o = bare(FS); o.prewarp = 100.0;
    assert_int_equal(pf_design_opts_resolve(&o, &out), PF_OK);
    EXPECT(out.prewarp == 100.0, "prewarp kept: %g", out.prewarp);
    END_SOFT();
}

/* ------------------------------------------------------------------ */
/* The operator and the Q15 full scales                                 */
/* ------------------------------------------------------------------ */

static int same_design(const pf_fracop_design *a, const pf_fracop_design *b)
{
    int k;
    if (a->n_sec != b->n_sec || a->n_int != b->n_int || a->d != b->d || a->D != b->D ||
        a->int_d != b->int_d || a->int_k != b->int_k || a->c != b->c)
        return 0;
    for (k = 0; k < a->n_sec; k++)
        if (a->lam[k] != b->lam[k] || a->G[k] != b->G[k])
            return 0;
    return 1;
}

/* pf_fracop_design_make: 0 < |alpha| < 2, finite 0 < |gain| <= 1e12; the
 * refined method falls back to Oustaloup's within 1e-3 of an integer. */
static void test_operator_limits(void **state)
{
    const double bad_gain[] = {0.0, -0.0, NAN, INFINITY, -INFINITY, 1.000001e12,
                               -1.000001e12, DBL_MAX};
    const double ok_gain[] = {GAIN_MAX, -GAIN_MAX, 1.0, -0.5, 1e-300};
    const double bad_alpha[] = {0.0, -0.0, 2.0, -2.0, 2.5, -3.0, NAN, INFINITY, -INFINITY};
    const double ok_alpha[] = {0.5, -0.5, 1.0, -1.0, 1.5, -1.5, 1.999, -1.999, 1e-9};
    const double near_int[] = {0.0005, -0.0005, 0.9995, 1.0009, -1.0009, 1.9995};
    static pf_fracop_design op, ref;
    pf_design_opts o = bare(FS), refined = bare(FS);
    pf_status st;
    size_t i;
    char what[64];
    (void)state;
    refined.approx = PF_APPROX_REFINED;

    for (i = 0; i < sizeof bad_gain / sizeof bad_gain[0]; i++) {
        snprintf(what, sizeof what, "gain = %g", bad_gain[i]);
        expect_names(pf_fracop_design_make(&op, 0.5, bad_gain[i], &o), PF_P_GAIN, what);
    }
    for (i = 0; i < sizeof ok_gain / sizeof ok_gain[0]; i++) {
        st = pf_fracop_design_make(&op, 0.5, ok_gain[i], &o);
        EXPECT(st == PF_OK, "gain = %g refused (%d, %s)", ok_gain[i], st,
               pname(pf_status_param(st)));
    }
    for (i = 0; i < sizeof bad_alpha / sizeof bad_alpha[0]; i++) {
        snprintf(what, sizeof what, "alpha = %g", bad_alpha[i]);
        expect_names(pf_fracop_design_make(&op, bad_alpha[i], 1.0, &o), PF_P_ALPHA, what);
    }
    for (i = 0; i < sizeof ok_alpha / sizeof ok_alpha[0]; i++) {
        st = pf_fracop_design_make(&op, ok_alpha[i], 1.0, &o);
        EXPECT(st == PF_OK, "alpha = %g refused (%d, %s)", ok_alpha[i], st,
               pname(pf_status_param(st)));
        st = pf_fracop_design_make(&op, ok_alpha[i], 1.0, &refined);
        EXPECT(st == PF_OK, "refined, alpha = %g refused (%d, %s)", ok_alpha[i], st,
               pname(pf_status_param(st)));
    }
    for (i = 0; i < sizeof near_int / sizeof near_int[0]; i++) {
        pf_status s1 = pf_fracop_design_make(&op, near_int[i], 2.0, &refined);
        pf_status s2 = pf_fracop_design_make(&ref, near_int[i], 2.0, &o);
        EXPECT(s1 == PF_OK && s2 == PF_OK, "alpha = %g: refined %d, oustaloup %d",
               near_int[i], s1, s2);
        EXPECT(s1 != PF_OK || s2 != PF_OK || same_design(&op, &ref),
               "alpha = %g (within 1e-3 of an integer): refined did not fall back to "
               "Oustaloup's design", near_int[i]);
    }
    END_SOFT();
}

/* pf_ctrl_coeffs_q15_make: in_fs and out_fs finite, in (0, 1e12], else
 * PF_E_PARAM naming the one that is not. Inside the range a refusal can
 * only be PF_E_SCALE. */
static void test_q15_full_scales(void **state)
{
    const double bad[] = {0.0, -0.0, -1.0, NAN, INFINITY, -INFINITY, 1.000001e12, 1e300};
    static pf_ctrl_design d;
    static pf_ctrl_coeffs_q15 cq;
    pf_params p;
    pf_design_opts o = bare(FS);
    pf_status st;
    size_t i;
    char what[48];
    (void)state;
    pf_params_default(&p, PF_TOPO_DD);
    assert_int_equal(pf_ctrl_design_make(&d, &p, NULL, &o), PF_OK);
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        snprintf(what, sizeof what, "in_fs = %g", bad[i]);
        expect_names(pf_ctrl_coeffs_q15_make(&cq, &d, bad[i], 0.01), PF_P_IN_FS, what);
        snprintf(what, sizeof what, "out_fs = %g", bad[i]);
        expect_names(pf_ctrl_coeffs_q15_make(&cq, &d, 1.0, bad[i]), PF_P_OUT_FS, what);
    }
    st = pf_ctrl_coeffs_q15_make(&cq, &d, 1.0, 0.01);
    EXPECT(st == PF_OK, "Example 6, in_fs = 1, out_fs = 0.01 (the README's): %d", st);
    st = pf_ctrl_coeffs_q15_make(&cq, &d, FULL_SCALE_MAX, FULL_SCALE_MAX);
    EXPECT(st == PF_OK || st == PF_E_SCALE, "in_fs = out_fs = 1e12: %d (%s)", st,
           pname(pf_status_param(st)));
    st = pf_ctrl_coeffs_q15_make(&cq, &d, 1e-300, 1e-300);
    EXPECT(st == PF_OK || st == PF_E_SCALE, "in_fs = out_fs = 1e-300: %d (%s)", st,
           pname(pf_status_param(st)));
    END_SOFT();
}

/* ------------------------------------------------------------------ */
/* pf_ctrl_design_make: all or nothing                                  */
/* ------------------------------------------------------------------ */

/* One failing call: the caller's struct, filled with a pattern, must come
 * back byte for byte, so a half-made design can never be mistaken for one.
 * alt is a second fair name, or PF_P_COUNT. */
static void check_make_untouched(const char *cfg, const char *what, const pf_params *p,
                                 const pf_effects *fx, const pf_design_opts *o,
                                 pf_status want, pf_param_id alt)
{
    static pf_ctrl_design d, ref;
    pf_status st;
    memset(&d, 0xA5, sizeof d);
    memset(&ref, 0xA5, sizeof ref);
    st = pf_ctrl_design_make(&d, p, fx, o);
    EXPECT(st == want || (alt != PF_P_COUNT && st == PF_E_PARAM(alt)),
           "%s: %s: status %d (%s), want %d (or %s)", cfg, what, st,
           pname(pf_status_param(st)), want, pname(alt));
    EXPECT(memcmp(&d, &ref, sizeof d) == 0,
           "%s: %s: failed design_make modified the output struct", cfg, what);
}

static const mutation k_bad_params[] = {
    {"a = NaN", CFG_ALL, 1, {PF_P_A}, {NAN}, PF_P_A},
    {"a = 1e-10", CFG_ALL, 1, {PF_P_A}, {1e-10}, PF_P_A},
    {"beta = 0", CFG_ALL, 1, {PF_P_BETA}, {0.0}, PF_P_BETA},
    {"q = 1.5", CFG_ALL, 1, {PF_P_Q}, {1.5}, PF_P_Q},
    {"pmax < pmin", CFG_ALL, 1, {PF_P_PMAX}, {0.5}, PF_P_PMAX},
    {"A/ks = 1e18", CFG_ALL, 2, {PF_P_AREA, PF_P_KS}, {1e9, 1e-9}, PF_P_KS},
    /* the last parameter each configuration uses */
    {"RC = -1", CFG_DD_ID, 1, {PF_P_RC}, {-1.0}, PF_P_RC},
    {"w = 2", CFG_ID_PID, 1, {PF_P_W}, {2.0}, PF_P_W},
    {"RCi = inf", CFG_PID, 1, {PF_P_RCI}, {INFINITY}, PF_P_RCI},
    {"nu > w", CFG_PID, 1, {PF_P_W}, {0.5}, PF_P_W},
    {"RCd == RCi", CFG_PID, 1, {PF_P_RCD}, {0.1}, PF_P_RCD},
};

/* Good parameters, bad options: fs, wb, wh, order, approx, prewarp, t_slow, input. */
static const struct {
    const char *what;
    pf_design_opts o;
    pf_param_id want, alt;
} k_bad_opts[] = {
    {"fs = 0", {0.0, 0, 0, 0, PF_APPROX_OUSTALOUP, 0, 0, PF_INPUT_HOLD}, PF_P_FS, PF_P_COUNT},
    {"order too high", {FS, 0, 0, PF_MAX_ORDER + 1, PF_APPROX_OUSTALOUP, 0, 0, PF_INPUT_HOLD},
     PF_P_ORDER, PF_P_COUNT},
    {"wh above Nyquist", {FS, 0, 10.0 * M_PI * FS, 0, PF_APPROX_OUSTALOUP, 0, 0, PF_INPUT_HOLD},
     PF_P_WH, PF_P_COUNT},
    {"prewarp = 0.995 pi fs",
     {FS, 0, 0, 0, PF_APPROX_OUSTALOUP, 0.995 * M_PI * FS, 0, PF_INPUT_HOLD}, PF_P_PREWARP,
     PF_P_COUNT},
    {"t_slow = 2e9", {FS, 0, 0, 0, PF_APPROX_OUSTALOUP, 0, 2e9, PF_INPUT_HOLD}, PF_P_TSLOW,
     PF_P_COUNT},
    {"refined, wh = 1 rad/s", {FS, 0.01, 1.0, 0, PF_APPROX_REFINED, 0, 0, PF_INPUT_HOLD},
     PF_P_WH, PF_P_APPROX},
};

/* Good parameters and options, bad effects: backlash, nozzle_xh, saturate,
 * sat_lo, sat_hi, dead_time, lag, nozzle_bias. */
static const struct {
    const char *what;
    pf_effects fx;
    pf_param_id want, alt;
} k_bad_fx[] = {
    {"backlash < 0", {-1.0, 0, 0, 0, 0, 0, 0, 0}, PF_P_BACKLASH, PF_P_COUNT},
    {"lag NaN", {0, 0, 0, 0, 0, 0, NAN, 0}, PF_P_LAG, PF_P_COUNT},
    {"nozzle_xh = 2e9", {0, 2e9, 0, 0, 0, 0, 0, 0}, PF_P_NOZZLE_XH, PF_P_COUNT},
    {"sat_lo == sat_hi", {0, 0, 1, 1.0, 1.0, 0, 0, 0}, PF_P_SAT_LO, PF_P_SAT_HI},
    {"dead_time = 3601 s", {0, 0, 0, 0, 0, 3601.0, 0, 0}, PF_P_DEAD_TIME, PF_P_COUNT},
    {"nozzle_bias = -0.6", {0, 1.0, 0, 0, 0, 0, 0, -0.6}, PF_P_NOZZLE_BIAS, PF_P_COUNT},
    {"nozzle_bias = 11", {0, 1.0, 0, 0, 0, 0, 0, 11.0}, PF_P_NOZZLE_BIAS, PF_P_COUNT},
    /* valid for pf_effects_validate; the design caps it at 4194304 samples */
    {"dead_time = 300 s (6e6 samples)", {0, 0, 0, 0, 0, 300.0, 0, 0}, PF_P_DEAD_TIME, PF_P_COUNT},
};

static void test_design_make_atomic(void **state)
{
    pf_params p;
    pf_design_opts o = bare(FS);
    int c;
    size_t i;
    (void)state;

    for (c = 0; c < PF_TOPO_COUNT; c++) {
        for (i = 0; i < sizeof k_bad_params / sizeof k_bad_params[0]; i++)
            if (apply_mutation(&p, c, &k_bad_params[i]))
                check_make_untouched(cname(c), k_bad_params[i].what, &p, NULL, &o,
                                     PF_E_PARAM(k_bad_params[i].want), PF_P_COUNT);
        pf_params_default(&p, (pf_topology)c);
        for (i = 0; i < sizeof k_bad_opts / sizeof k_bad_opts[0]; i++)
            check_make_untouched(cname(c), k_bad_opts[i].what, &p, NULL, &k_bad_opts[i].o,
                                 PF_E_PARAM(k_bad_opts[i].want), k_bad_opts[i].alt);
        for (i = 0; i < sizeof k_bad_fx / sizeof k_bad_fx[0]; i++)
            check_make_untouched(cname(c), k_bad_fx[i].what, &p, &k_bad_fx[i].fx, &o,
                                 PF_E_PARAM(k_bad_fx[i].want), k_bad_fx[i].alt);
    }

    pf_params_default(&p, PF_TOPO_DD);
    p.topology = PF_TOPO_COUNT;
    check_make_untouched("?", "config = COUNT", &p, NULL, &o, PF_E_PARAM(PF_P_CONFIG),
                         PF_P_COUNT);
    pf_params_default(&p, PF_TOPO_DD);
    check_make_untouched("dd", "p = NULL", NULL, NULL, &o, PF_E_NULL, PF_P_COUNT);
    check_make_untouched("dd", "opt = NULL", &p, NULL, NULL, PF_E_NULL, PF_P_COUNT);
    EXPECT(pf_ctrl_design_make(NULL, &p, NULL, &o) == PF_E_NULL, "d = NULL");
    END_SOFT();
}

/* A successful make records what was asked and resolves the options; a
 * NULL effects pointer means no effects at all. */
static void test_design_make_ok(void **state)
{
    static pf_ctrl_design d;
    pf_params p;
    pf_design_opts o = bare(FS), r;
    int c;
    (void)state;
    assert_int_equal(pf_design_opts_resolve(&o, &r), PF_OK);
    for (c = 0; c < PF_TOPO_COUNT; c++) {
        pf_params_default(&p, (pf_topology)c);
        memset(&d, 0xA5, sizeof d);
        assert_int_equal(pf_ctrl_design_make(&d, &p, NULL, &o), PF_OK);
        EXPECT(d.p.topology == p.topology && d.p.a == p.a && d.p.beta == p.beta &&
                   d.p.q == p.q && d.p.k1 == p.k1,
               "%s: design does not record its parameters", cname(c));
        EXPECT(d.fx.backlash == 0.0 && d.fx.nozzle_xh == 0.0 && d.fx.saturate == 0 &&
                   d.fx.dead_time == 0.0 && d.fx.lag == 0.0,
               "%s: NULL effects not recorded as off", cname(c));
        EXPECT(!pf_effects_any(&d.fx), "%s: effects_any on NULL fx", cname(c));
        EXPECT(d.opt.wb == r.wb && d.opt.wh == r.wh && d.opt.order == r.order &&
                   d.opt.fs == r.fs,
               "%s: options not resolved in the design", cname(c));
        EXPECT(d.rt.delay_len == 0 && d.rt.in_loop_fx == 0 && d.rt.saturate == 0,
               "%s: runtime effect fields set without effects", cname(c));
        EXPECT(fabs(d.rt.ce - p.b / (p.a + p.b)) <= 1e-15 &&
                   fabs(d.rt.cy - p.a / (p.a + p.b)) <= 1e-15,
               "%s: lever ratios ce=%g cy=%g", cname(c), d.rt.ce, d.rt.cy);
    }
    END_SOFT();
}

/* ------------------------------------------------------------------ */
/* Validation and design agree                                          */
/* ------------------------------------------------------------------ */

/* An accepted design runs finite in f64 and f32 (a step), and in Q15 if
 * its coefficient set can be made (full scale: twice the f64 peak). */
static void expect_runs_finite(const pf_ctrl_design *d, const char *what)
{
    static pf_ctrl_coeffs_f32 c32;
    static pf_ctrl_coeffs_q15 cq;
    pf_ctrl_f64 i64;
    pf_ctrl_f32 i32;
    pf_ctrl_q15 iq;
    double pk = 0.0;
    pf_status st;
    int k;
    pf_ctrl_coeffs_f32_make(&c32, &d->rt);
    assert_int_equal(pf_ctrl_init_f64(&i64, &d->rt, NULL, 0), PF_OK);
    assert_int_equal(pf_ctrl_init_f32(&i32, &c32, NULL, 0), PF_OK);
    for (k = 0; k < NRUN; k++) {
        double y = pf_ctrl_step_f64(&i64, 1.0);
        float yf = pf_ctrl_step_f32(&i32, 1.0f);
        if (!isfinite(y) || !isfinite(yf)) {
            EXPECT(0, "%s: step response not finite at k=%d: f64 %g, f32 %g", what, k, y,
                   (double)yf);
            return;
        }
        pk = fmax(pk, fabs(y));
    }
    st = pf_ctrl_coeffs_q15_make(&cq, d, 1.0, pk > 0.0 ? fmin(2.0 * pk, FULL_SCALE_MAX) : 1.0);
    EXPECT(st == PF_OK || st == PF_E_SCALE, "%s: q15_make(1, %g) = %d (%s)", what, 2.0 * pk,
           st, pname(pf_status_param(st)));
    if (st != PF_OK)
        return;
    assert_int_equal(pf_ctrl_init_q15(&iq, &cq, NULL, 0), PF_OK);
    for (k = 0; k < NRUN; k++)
        (void)pf_ctrl_step_q15(&iq, 16384);
}

/* validate and design agree: what validate refuses, the design refuses
 * with the same status; what it accepts is designed (or refused as above)
 * and runs finite. */
static void expect_design_agrees(const pf_params *p, pf_param_id want, const char *what)
{
    static pf_ctrl_design d;
    pf_design_opts o = bare(FS);
    pf_status sv = pf_params_validate(p), sd = pf_ctrl_design_make(&d, p, NULL, &o);
    pf_param_id id = pf_status_param(sd);
    expect_validate(p, want, what);
    if (sv != PF_OK) {
        EXPECT(sd == sv, "%s: validate says %d (%s), design_make %d (%s)", what, sv,
               pname(pf_status_param(sv)), sd, pname(id));
        return;
    }
    EXPECT(sd == PF_OK || design_may_name(p->topology, o.fs, id),
           "%s: validate OK but design_make = %d (%s)", what, sd, pname(id));
    if (sd == PF_OK)
        expect_runs_finite(&d, what);
}

static const mutation k_agree[] = {
    /* found by this test: the design refused what validate accepted, with
     * A/ks = 1e15 and with a pid whose nu > w; validate now refuses both */
    {"A = 1e9, ks = 1e-6", CFG_ALL, 2, {PF_P_AREA, PF_P_KS}, {1e9, 1e-6}, PF_P_KS},
    {"w = 0.01", CFG_PID, 1, {PF_P_W}, {0.01}, PF_P_W},
    {"w = 0.2", CFG_PID, 1, {PF_P_W}, {0.2}, PF_P_W},
    /* valid at the documented edges */
    {"nu = w = 0.2", CFG_PID, 2, {PF_P_NU, PF_P_W}, {0.2, 0.2}, VALID},
    {"nu = 1e-9, w = 1", CFG_PID, 2, {PF_P_NU, PF_P_W}, {1e-9, 1.0}, VALID},
    {"A/ks = 9.9e11", CFG_ALL, 2, {PF_P_AREA, PF_P_KS}, {1e9, 1.01e-3}, VALID},
    {"A/ks = 1.01e-12", CFG_ALL, 2, {PF_P_AREA, PF_P_KS}, {1e-9, 0.99e3}, VALID},
    {"beta = 1e-6", CFG_ALL, 1, {PF_P_BETA}, {1e-6}, VALID},
    {"beta = 1e-9", CFG_ALL, 1, {PF_P_BETA}, {1e-9}, VALID},
    {"q = 1e-9", CFG_ALL, 1, {PF_P_Q}, {1e-9}, VALID},
    {"q = 1", CFG_ALL, 1, {PF_P_Q}, {1.0}, VALID},
    {"k1 = k2 = 1e9", CFG_ALL, 2, {PF_P_K1, PF_P_K2}, {1e9, 1e9}, VALID},
    {"k1 = k2 = 1e-9", CFG_ALL, 2, {PF_P_K1, PF_P_K2}, {1e-9, 1e-9}, VALID},
    {"tau = 1e-9", CFG_ALL, 1, {PF_P_TAU}, {1e-9}, VALID},
    {"tau = 1e9", CFG_ALL, 1, {PF_P_TAU}, {1e9}, VALID},
    {"pmin = pmax = 1e-9", CFG_ALL, 2, {PF_P_PMIN, PF_P_PMAX}, {1e-9, 1e-9}, VALID},
    {"pmin = 1e-9, pmax = 1e9", CFG_ALL, 2, {PF_P_PMIN, PF_P_PMAX}, {1e-9, 1e9}, VALID},
    {"a = 1e9, b = 1e-9", CFG_ALL, 2, {PF_P_A, PF_P_B}, {1e9, 1e-9}, VALID},
    {"RC = 1e-9", CFG_DD_ID, 1, {PF_P_RC}, {1e-9}, VALID},
    {"RC = 1e9", CFG_DD_ID, 1, {PF_P_RC}, {1e9}, VALID},
    {"RCd = 1e-9, RCi = 1e9", CFG_PID, 2, {PF_P_RCD, PF_P_RCI}, {1e-9, 1e9}, VALID},
};

static void test_validate_matches_design(void **state)
{
    pf_params p;
    int c;
    size_t i;
    (void)state;
    for (c = 0; c < PF_TOPO_COUNT; c++)
        for (i = 0; i < sizeof k_agree / sizeof k_agree[0]; i++) {
            char what[96];
            if (!apply_mutation(&p, c, &k_agree[i]))
                continue;
            snprintf(what, sizeof what, "%s: %s", cname(c), k_agree[i].what);
            expect_design_agrees(&p, k_agree[i].want, what);
        }
    END_SOFT();
}

/* Found by this suite while these limits were enforced but undocumented
 * (the headers said only "> 0" and "[wb, wh] ... <= pi fs"). pf_params.h
 * and pf_fracop.h now document them, so each input is refused by name.
 * The effect limits found at the same time are in test_effects. */
static void test_formerly_hidden_limits(void **state)
{
    pf_params p;
    pf_design_opts o;
    int id;
    (void)state;
    for (id = PF_P_A; id <= PF_P_RCI; id++) {
        char what[48];
        if (!is_positive_param((pf_param_id)id) || !uses(PF_TOPO_PID, (pf_param_id)id))
            continue;
        pf_params_default(&p, PF_TOPO_PID);
        pf_params_set(&p, (pf_param_id)id, 1e10);
        if (id == PF_P_PMIN) p.pmax = 1e10;
        if (id == PF_P_RCD) p.RCi = 2e10;
        snprintf(what, sizeof what, "pid, %s = 1e10", pname((pf_param_id)id));
        expect_names(pf_params_validate(&p), (pf_param_id)id, what);
    }
    /* the refined approximation on a low band: wb = 0.01, wh = 1 rad/s */
    o = bare(1000.0);
    o.approx = PF_APPROX_REFINED;
    o.wb = 0.01;
    o.wh = 1.0;
    expect_opts_either(&o, PF_P_WH, PF_P_APPROX, "refined, band 0.01..1 rad/s");
    END_SOFT();
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_defaults_match_paper, setup_soft),
        cmocka_unit_test_setup(test_param_used_table, setup_soft),
        cmocka_unit_test_setup(test_validate_positive, setup_soft),
        cmocka_unit_test_setup(test_validate_orders, setup_soft),
        cmocka_unit_test_setup(test_validate_pairs, setup_soft),
        cmocka_unit_test_setup(test_validate_unused_ignored, setup_soft),
        cmocka_unit_test_setup(test_validate_config_and_null, setup_soft),
        cmocka_unit_test_setup(test_params_set_get, setup_soft),
        cmocka_unit_test_setup(test_param_names_roundtrip, setup_soft),
        cmocka_unit_test_setup(test_param_table, setup_soft),
        cmocka_unit_test_setup(test_config_names, setup_soft),
        cmocka_unit_test_setup(test_opts_defaults, setup_soft),
        cmocka_unit_test_setup(test_opts_fs, setup_soft),
        cmocka_unit_test_setup(test_opts_band, setup_soft),
        cmocka_unit_test_setup(test_opts_refined, setup_soft),
        cmocka_unit_test_setup(test_opts_enums_order_prewarp, setup_soft),
        cmocka_unit_test_setup(test_operator_limits, setup_soft),
        cmocka_unit_test_setup(test_q15_full_scales, setup_soft),
        cmocka_unit_test_setup(test_design_make_atomic, setup_soft),
        cmocka_unit_test_setup(test_design_make_ok, setup_soft),
        cmocka_unit_test_setup(test_validate_matches_design, setup_soft),
        cmocka_unit_test_setup(test_formerly_hidden_limits, setup_soft),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
