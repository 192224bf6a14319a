/* SPDX-License-Identifier: MIT */
/*
 * Reader for paper_step_cases.json (see pfh_ref_cases.h). The file's shape is
 * fixed (an object of cases, each an object with "config" and "params"), so
 * this is a small recursive-descent reader of exactly that shape, not a
 * general JSON parser: strings without escapes, numbers by strtod.
 * Parameter names map to pf_params fields here, not through the library's
 * name table, so that a mistake there cannot hide in the reference.
 */
#include "pfh_ref_cases.h"

#include <ctype.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct field {
    const char *name;
    size_t offset;
} field;

static const field fields[] = {
    {"a", offsetof(pf_params, a)},       {"b", offsetof(pf_params, b)},
    {"k1", offsetof(pf_params, k1)},     {"k2", offsetof(pf_params, k2)},
    {"A", offsetof(pf_params, A)},       {"ks", offsetof(pf_params, ks)},
    {"tau", offsetof(pf_params, tau)},   {"pmin", offsetof(pf_params, pmin)},
    {"pmax", offsetof(pf_params, pmax)}, {"beta", offsetof(pf_params, beta)},
    {"q", offsetof(pf_params, q)},       {"nu", offsetof(pf_params, nu)},
    {"w", offsetof(pf_params, w)},       {"RC", offsetof(pf_params, RC)},
    {"RCd", offsetof(pf_params, RCd)},   {"RCi", offsetof(pf_params, RCi)},
};

static const char *const configs[] = {"p", "dd", "id", "pid"};

typedef struct reader {
    const char *s;
} reader;

static void skip_ws(reader *r)
{
    while (isspace((unsigned char)*r->s))
        r->s++;
}

/* Consumes character c after optional white space. */
static int eat(reader *r, char c)
{
    skip_ws(r);
    if (*r->s != c)
        return -1;
    r->s++;
    return 0;
}

/* A string without escapes into buf (len bytes). */
static int string(reader *r, char *buf, size_t len)
{
    const char *end;

    if (eat(r, '"') != 0)
        return -1;
    end = strchr(r->s, '"');
    if (end == NULL || (size_t)(end - r->s) >= len ||
        memchr(r->s, '\\', (size_t)(end - r->s)) != NULL)
        return -1;
    memcpy(buf, r->s, (size_t)(end - r->s));
    buf[end - r->s] = '\0';
    r->s = end + 1;
    return 0;
}

static int number(reader *r, double *v)
{
    char *end;

    skip_ws(r);
    *v = strtod(r->s, &end);
    if (end == r->s)
        return -1;
    r->s = end;
    return 0;
}

/* Members of an object: calls member(r, key, ctx) for each; "{}" is allowed. */
static int object(reader *r, int (*member)(reader *, const char *, void *),
                  void *ctx)
{
    char key[PFH_REF_CASE_NAME_LEN];

    if (eat(r, '{') != 0)
        return -1;
    if (eat(r, '}') == 0)
        return 0;
    for (;;) {
        if (string(r, key, sizeof key) != 0 || eat(r, ':') != 0 ||
            member(r, key, ctx) != 0)
            return -1;
        if (eat(r, '}') == 0)
            return 0;
        if (eat(r, ',') != 0)
            return -1;
    }
}

static int param_member(reader *r, const char *key, void *ctx)
{
    size_t i;

    for (i = 0; i < sizeof fields / sizeof fields[0]; i++)
        if (strcmp(key, fields[i].name) == 0)
            /* offsetof of a double member: the cast lands on that double */
            /* cppcheck-suppress invalidPointerCast */
            return number(r, (double *)((char *)ctx + fields[i].offset));
    return -1;
}

static int case_member(reader *r, const char *key, void *ctx)
{
    pf_params *p = ctx;
    char cfg[8];
    size_t i;

    if (strcmp(key, "params") == 0)
        return object(r, param_member, p);
    if (strcmp(key, "config") != 0 || string(r, cfg, sizeof cfg) != 0)
        return -1;
    for (i = 0; i < sizeof configs / sizeof configs[0]; i++)
        if (strcmp(cfg, configs[i]) == 0) {
            p->topology = (pf_topology)i;
            return 0;
        }
    return -1;
}

static int top_member(reader *r, const char *key, void *ctx)
{
    pfh_ref_cases *c = ctx;
    pf_params *p;

    if (c->n >= PFH_REF_MAX_CASES || pfh_ref_cases_find(c, key) != NULL)
        return -1;
    p = &c->p[c->n];
    memset(p, 0, sizeof *p);
    p->topology = PF_TOPO_COUNT; /* "config" is required */
    if (object(r, case_member, p) != 0 || p->topology == PF_TOPO_COUNT)
        return -1;
    strcpy(c->name[c->n], key); /* fits: string() bounded it */
    c->n++;
    return 0;
}

int pfh_ref_cases_parse(const char *text, pfh_ref_cases *out)
{
    reader r;

    if (text == NULL || out == NULL)
        return -1;
    out->n = 0;
    r.s = text;
    if (object(&r, top_member, out) != 0 || out->n == 0)
        return -1;
    skip_ws(&r);
    return *r.s == '\0' ? 0 : -1;
}

int pfh_ref_cases_load(const char *path, pfh_ref_cases *out)
{
    static char text[PFH_REF_CASES_MAX_BYTES + 1];
    FILE *f;
    size_t n;

    if (path == NULL || out == NULL || (f = fopen(path, "rb")) == NULL)
        return -1;
    n = fread(text, 1, sizeof text, f);
    fclose(f);
    if (n == 0 || n > PFH_REF_CASES_MAX_BYTES || memchr(text, '\0', n))
        return -1;
    text[n] = '\0';
    return pfh_ref_cases_parse(text, out);
}

const pf_params *pfh_ref_cases_find(const pfh_ref_cases *c, const char *name)
{
    int i;

    if (c == NULL || name == NULL)
        return NULL;
    for (i = 0; i < c->n; i++)
        if (strcmp(c->name[i], name) == 0)
            return &c->p[i];
    return NULL;
}
