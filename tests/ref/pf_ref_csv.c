/* SPDX-License-Identifier: MIT */
/* CSV loader and case table for the exact reference (see pf_ref_csv.h). */
#include "pf_ref_csv.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define LINE_MAX_LEN 4096

/* Read one line without its end-of-line; reject over-long lines rather than
 * silently splitting them into two rows.
 * @return 1 line read, 0 EOF, -1 error. */
static int read_line(FILE *f, char *buf, size_t len)
{
    size_t n;

    if (!fgets(buf, (int)len, f))
        return ferror(f) ? -1 : 0;
    n = strlen(buf);
    if (n == len - 1 && buf[n - 1] != '\n' && !feof(f))
        return -1;
    while (n > 0 && (buf[n - 1] == '\n' || buf[n - 1] == '\r'))
        buf[--n] = '\0';
    return 1;
}

static int parse_header(char *line, pf_ref_csv *out)
{
    char *tok = line;

    out->ncols = 0;
    for (;;) {
        char *comma = strchr(tok, ',');
        size_t n = comma ? (size_t)(comma - tok) : strlen(tok);

        if (out->ncols >= PF_REF_CSV_MAX_COLS || n == 0 ||
            n >= PF_REF_CSV_NAME_LEN)
            return -1;
        memcpy(out->name[out->ncols], tok, n);
        out->name[out->ncols][n] = '\0';
        out->ncols++;
        if (!comma)
            return 0;
        tok = comma + 1;
    }
}

static int parse_row(const char *line, pf_ref_csv *out)
{
    const char *s = line;
    int j;

    if (out->nrows >= PF_REF_CSV_MAX_ROWS)
        return -1;
    for (j = 0; j < out->ncols; ++j) {
        char *end;
        double v = strtod(s, &end);

        if (end == s)
            return -1; /* empty or non-numeric field */
        if (*end != (j + 1 < out->ncols ? ',' : '\0'))
            return -1; /* wrong field count or trailing junk */
        out->col[j][out->nrows] = v;
        s = end + 1;
    }
    out->nrows++;
    return 0;
}

int pf_ref_csv_load(const char *path, pf_ref_csv *out)
{
    char line[LINE_MAX_LEN];
    FILE *f;
    int rc = -1, r;

    if (!path || !out)
        return -1;
    out->ncols = out->nrows = 0;
    f = fopen(path, "r");
    if (!f)
        return -1;
    if (read_line(f, line, sizeof line) != 1 || parse_header(line, out) != 0)
        goto done;
    while ((r = read_line(f, line, sizeof line)) == 1) {
        if (line[0] == '\0')
            continue; /* tolerate a blank last line */
        if (parse_row(line, out) != 0)
            goto done;
    }
    if (r == 0 && out->nrows > 0)
        rc = 0;
done:
    fclose(f);
    return rc;
}

/* Copied from /work/shared/reference/paper_step_exact.json (the paper's
 * Examples 4, 6 and 7). Unused parameters are 0. */
typedef struct ref_case {
    const char *name;
    const char *config; /* as in the JSON: "p", "dd", "id" */
    double a, b, k1, k2, A, ks, tau, pmin, pmax, beta, q, nu, w, RC;
} ref_case;

static const ref_case cases[] = {
    /* name          cfg   a  b  k1   k2   A  ks  tau    pmin pmax beta q     nu    w     RC */
    {"ex4_q0.9",    "p",  1, 9, 0.1, 0.1, 2, 20, 0.001, 1, 10, 0.8, 0.9,  0,    0,    0},
    {"ex4_q0.99",   "p",  1, 9, 0.1, 0.1, 2, 20, 0.001, 1, 10, 0.8, 0.99, 0,    0,    0},
    {"ex4_q1.0",    "p",  1, 9, 0.1, 0.1, 2, 20, 0.001, 1, 10, 0.8, 1.0,  0,    0,    0},
    {"ex4_beta0.6", "p",  1, 9, 0.1, 0.1, 2, 20, 0.001, 1, 10, 0.6, 0.9,  0,    0,    0},
    {"ex4_beta0.8", "p",  1, 9, 0.1, 0.1, 2, 20, 0.001, 1, 10, 0.8, 0.9,  0,    0,    0},
    {"ex4_beta1.0", "p",  1, 9, 0.1, 0.1, 2, 20, 0.001, 1, 10, 1.0, 0.9,  0,    0,    0},
    {"ex6_q0.9",    "dd", 1, 9, 0.1, 0.1, 2, 20, 0.001, 1, 10, 0.8, 0.9,  0.94, 0,    0.1},
    {"ex6_q0.99",   "dd", 1, 9, 0.1, 0.1, 2, 20, 0.001, 1, 10, 0.8, 0.99, 0.94, 0,    0.1},
    {"ex6_q1.0",    "dd", 1, 9, 0.1, 0.1, 2, 20, 0.001, 1, 10, 0.8, 1.0,  0.94, 0,    0.1},
    {"ex7",         "id", 1, 9, 2,   5,   2, 20, 0.001, 1, 10, 0.8, 0,    0,    0.94, 0.1},
};

#define NCASES ((int)(sizeof cases / sizeof cases[0]))

/* The JSON names configurations by string; map them here (not through the
 * library's pf_config_lookup) to stay independent of the library. */
static int config_from_string(const char *s, pf_config *cfg)
{
    if (strcmp(s, "p") == 0)
        *cfg = PF_CFG_P;
    else if (strcmp(s, "dd") == 0)
        *cfg = PF_CFG_DD;
    else if (strcmp(s, "id") == 0)
        *cfg = PF_CFG_ID;
    else
        return -1;
    return 0;
}

int pf_ref_case(const char *name, pf_params *p)
{
    int i;

    if (!name || !p)
        return -1;
    for (i = 0; i < NCASES; ++i) {
        const ref_case *c = &cases[i];

        if (strcmp(name, c->name) != 0)
            continue;
        memset(p, 0, sizeof *p);
        if (config_from_string(c->config, &p->config) != 0)
            return -1;
        p->a = c->a;
        p->b = c->b;
        p->k1 = c->k1;
        p->k2 = c->k2;
        p->A = c->A;
        p->ks = c->ks;
        p->tau = c->tau;
        p->pmin = c->pmin;
        p->pmax = c->pmax;
        p->beta = c->beta;
        p->q = c->q;
        p->nu = c->nu;
        p->w = c->w;
        p->RC = c->RC;
        return 0;
    }
    return -1;
}

int pf_ref_case_count(void)
{
    return NCASES;
}

const char *pf_ref_case_name(int i)
{
    return (i >= 0 && i < NCASES) ? cases[i].name : NULL;
}
