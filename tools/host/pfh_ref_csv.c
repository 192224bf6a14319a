/* SPDX-License-Identifier: MIT */
/* CSV loader for the exact reference table (see pfh_ref_csv.h). */
#include "pfh_ref_csv.h"

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

static int parse_header(char *line, pfh_ref_csv *out)
{
    char *tok = line;

    out->ncols = 0;
    for (;;) {
        char *comma = strchr(tok, ',');
        size_t n = comma ? (size_t)(comma - tok) : strlen(tok);

        if (out->ncols >= PFH_REF_CSV_MAX_COLS || n == 0 ||
            n >= PFH_REF_CSV_NAME_LEN)
            return -1;
        memcpy(out->name[out->ncols], tok, n);
        out->name[out->ncols][n] = '\0';
        out->ncols++;
        if (!comma)
            return 0;
        tok = comma + 1;
    }
}

static int parse_row(const char *line, pfh_ref_csv *out)
{
    const char *s = line;
    int j;

    if (out->nrows >= PFH_REF_CSV_MAX_ROWS)
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

int pfh_ref_csv_load(const char *path, pfh_ref_csv *out)
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
