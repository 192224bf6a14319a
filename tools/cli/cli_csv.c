/* SPDX-License-Identifier: MIT */
#include "cli_csv.h"

#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli_args.h"

#define CHUNK 65536

/* A line reader over fread chunks rather than fgets or getline: it sees
 * NUL bytes (fgets hides them), and never holds more than one bounded line
 * (getline would swallow a newline-free multi-gigabyte file whole). */
typedef struct reader {
    FILE *f;
    const char *name;
    unsigned long lineno;
    size_t start, end;
    int eof;
    char chunk[CHUNK];
    char line[CLI_CSV_MAX_LINE + 1];
} reader;

/* @return 1 with r->line holding the next line (NUL-terminated, no newline),
 *         0 at end of file, -1 after printing an error. */
static int read_line(reader *r, size_t *len_out)
{
    size_t len = 0;
    int any = 0;

    for (;;) {
        if (r->start == r->end) {
            if (r->eof)
                break;
            r->start = 0;
            r->end = fread(r->chunk, 1, sizeof r->chunk, r->f);
            if (r->end == 0) {
                if (ferror(r->f)) {
                    cli_error("%s:%lu: read error: %s", r->name,
                              r->lineno + 1, strerror(errno));
                    return -1;
                }
                r->eof = 1;
                break;
            }
        }
        {
            const char *from = r->chunk + r->start;
            size_t avail = r->end - r->start;
            const char *nl = memchr(from, '\n', avail);
            size_t take = nl != NULL ? (size_t)(nl - from) : avail;

            any = 1;
            if (take > CLI_CSV_MAX_LINE - len) {
                cli_error("%s:%lu: line longer than %d bytes", r->name,
                          r->lineno + 1, CLI_CSV_MAX_LINE);
                return -1;
            }
            memcpy(r->line + len, from, take);
            len += take;
            r->start += take;
            if (nl != NULL) {
                r->start++;
                break;
            }
        }
    }
    if (!any)
        return 0;
    r->lineno++;
    r->line[len] = '\0';
    if (memchr(r->line, '\0', len) != NULL) {
        cli_error("%s:%lu: NUL byte in line (not a text file?)", r->name,
                  r->lineno);
        return -1;
    }
    if (len > 0 && r->line[len - 1] == '\r')
        r->line[--len] = '\0';
    *len_out = len;
    return 1;
}

static int is_blank(char c)
{
    return c == ' ' || c == '\t';
}

/* Split s at the next comma in place; returns the trimmed field and sets
 * *next to the rest, or NULL after the last field. */
static char *next_field(char *s, char **next)
{
    char *comma = strchr(s, ',');
    char *end;
    if (comma != NULL) {
        *comma = '\0';
        *next = comma + 1;
    } else {
        *next = NULL;
    }
    while (is_blank(*s))
        s++;
    end = s + strlen(s);
    while (end > s && is_blank(end[-1]))
        *--end = '\0';
    return s;
}

static int skip_line(const char *s)
{
    while (is_blank(*s))
        s++;
    return *s == '\0' || *s == '#';
}

/* Column positions from the header line. */
static int parse_header(reader *r, char *s, long *tcol, long *ecol,
                        long *nfields)
{
    char q[48];
    char *next = s;
    long i = 0;

    *tcol = *ecol = -1;
    /* Spreadsheet exports often start with a UTF-8 byte order mark. */
    if ((unsigned char)next[0] == 0xEF && (unsigned char)next[1] == 0xBB &&
        (unsigned char)next[2] == 0xBF)
        next += 3;
    while (next != NULL) {
        char *f = next_field(next, &next);
        long *col = strcmp(f, "t") == 0 ? tcol : strcmp(f, "e") == 0 ? ecol : NULL;
        if (col != NULL) {
            if (*col >= 0) {
                cli_error("%s:%lu: column '%s' appears twice in the header",
                          r->name, r->lineno, cli_quote(q, sizeof q, f));
                return -1;
            }
            *col = i;
        }
        i++;
    }
    /* One field holding ';' or a tab: a spreadsheet export with another
     * separator (and decimal commas); say so instead of "no column t". */
    if (i == 1 && strpbrk(s, ";\t") != NULL) {
        cli_error("%s:%lu: the header's fields are separated by '%s', not commas; "
                  "--input reads comma-separated values with '.' as the decimal point",
                  r->name, r->lineno, strchr(s, ';') != NULL ? ";" : "\\t");
        return -1;
    }
    if (*tcol < 0 || *ecol < 0) {
        cli_error("%s:%lu: header has no column '%s' (need columns t and e)",
                  r->name, r->lineno, *tcol < 0 ? "t" : "e");
        return -1;
    }
    *nfields = i;
    return 0;
}

static int parse_field(reader *r, const char *col, const char *f, double *v)
{
    char q[48];
    if (*f == '\0') {
        cli_error("%s:%lu: empty field '%s'", r->name, r->lineno, col);
        return -1;
    }
    if (cli_parse_double(f, v) != 0) {
        cli_error("%s:%lu: field '%s' is not a finite number: '%s'", r->name,
                  r->lineno, col, cli_quote(q, sizeof q, f));
        return -1;
    }
    return 0;
}

static int read_all(reader *r, double fs, size_t keep, double **e_out,
                    size_t *n_out)
{
    const double step = 1.0 / fs;
    long tcol = -1, ecol = -1, nfields = 0;
    double *e = NULL;
    size_t cap = 0, stored = 0;
    unsigned long rows = 0;
    double tprev = 0.0;
    size_t len;
    int rc;

    while ((rc = read_line(r, &len)) == 1) {
        char *next = r->line;
        double t = 0.0, ev = 0.0;
        long i = 0;

        if (skip_line(r->line))
            continue;
        if (nfields == 0) {
            if (parse_header(r, r->line, &tcol, &ecol, &nfields) != 0)
                goto fail;
            continue;
        }
        while (next != NULL) {
            char *f = next_field(next, &next);
            if (i == tcol && parse_field(r, "t", f, &t) != 0)
                goto fail;
            if (i == ecol && parse_field(r, "e", f, &ev) != 0)
                goto fail;
            i++;
        }
        if (i != nfields) {
            cli_error("%s:%lu: %ld fields, the header has %ld", r->name,
                      r->lineno, i, nfields);
            goto fail;
        }
        if (rows > 0) {
            /* The rounding allowance lets t written with %.17g (an exact
             * n/fs) pass at any t, however far from 0. */
            double dt = t - tprev;
            double tol = 1e-6 * step + 4.0 * DBL_EPSILON * (fabs(t) + fabs(tprev));
            if (!(dt > 0.0)) {
                cli_error("%s:%lu: t is not increasing (%.17g after %.17g)",
                          r->name, r->lineno, t, tprev);
                goto fail;
            }
            if (!(fabs(dt - step) <= tol)) {
                cli_error("%s:%lu: t steps by %.9g, not 1/fs = %.9g (the "
                          "input must be sampled uniformly at --fs)",
                          r->name, r->lineno, dt, step);
                goto fail;
            }
        }
        if (rows >= CLI_CSV_MAX_ROWS) {
            cli_error("%s:%lu: more than %lu data rows", r->name, r->lineno,
                      CLI_CSV_MAX_ROWS);
            goto fail;
        }
        rows++;
        tprev = t;
        if (stored < keep) {
            if (stored == cap) {
                size_t ncap = cap == 0 ? 4096 : 2 * cap;
                double *ne;
                if (ncap > keep)
                    ncap = keep;
                ne = realloc(e, ncap * sizeof *e);
                if (ne == NULL) {
                    cli_error("%s:%lu: out of memory", r->name, r->lineno);
                    goto fail;
                }
                e = ne;
                cap = ncap;
            }
            e[stored++] = ev;
        }
    }
    if (rc < 0)
        goto fail;
    if (r->lineno == 0) {
        cli_error("%s: empty file (need a header with columns t and e)",
                  r->name);
        goto fail;
    }
    if (nfields == 0) {
        cli_error("%s:%lu: no header line (need columns t and e)", r->name,
                  r->lineno);
        goto fail;
    }
    if (rows == 0) {
        cli_error("%s:%lu: no data rows after the header", r->name,
                  r->lineno);
        goto fail;
    }
    *e_out = e;
    *n_out = stored;
    return 0;
fail:
    free(e);
    return -1;
}

int cli_csv_read_input(const char *path, double fs, size_t keep, double **e,
                       size_t *n)
{
    reader *r;
    int rc;
    int use_stdin = strcmp(path, "-") == 0;

    *e = NULL;
    *n = 0;
    r = malloc(sizeof *r);
    if (r == NULL) {
        cli_error("out of memory");
        return -1;
    }
    r->name = use_stdin ? "<stdin>" : path;
    r->lineno = 0;
    r->start = r->end = 0;
    r->eof = 0;
    r->f = use_stdin ? stdin : fopen(path, "rb");
    if (r->f == NULL) {
        cli_error("%s: cannot open: %s", path, strerror(errno));
        free(r);
        return -1;
    }
    rc = read_all(r, fs, keep, e, n);
    if (!use_stdin)
        fclose(r->f);
    free(r);
    return rc;
}

int cli_csv_head(FILE *f, const char *columns, const char *units)
{
    return fprintf(f, "%s\n# units: %s\n", columns, units) < 0 ? -1 : 0;
}
