/* SPDX-License-Identifier: MIT */
/*
 * The LTI exports, one JSON object each (numbers in shortest round-trip
 * form, so reading them back gives the exported doubles exactly):
 *   ss   {"A": n x n, "B": n x 1, "C": 1 x n, "D": 1 x 1, "dt"}
 *        for control.ss(A, B, C, D, dt) or scipy.signal.dlti(A, B, C, D, dt=dt)
 *   zpk  {"z": [[re, im], ...], "p": [[re, im], ...], "k", "dt"}
 *        H(z) = k prod(z - z_i)/prod(z - p_i), roots as roots
 *   sos  {"sos": [[b0, b1, b2, 1, a1, a2], ...], "dt"}   (scipy's layout)
 * Every one also carries "format", "config" and "fs".
 */
#include "cli_lti.h"

#include <string.h>

#include "cli_args.h"
#include "pfh_fmt.h"
#include "pfh_lti.h"

int cli_lti_is_format(const char *format)
{
    return strcmp(format, "ss") == 0 || strcmp(format, "zpk") == 0 ||
           strcmp(format, "sos") == 0;
}

static void num(FILE *f, double v)
{
    pfh_fput_double(f, v);
}

static void row(FILE *f, const double *v, int n, int stride)
{
    int i;
    fputc('[', f);
    for (i = 0; i < n; i++) {
        if (i)
            fputs(", ", f);
        num(f, v[(size_t)i * (size_t)stride]);
    }
    fputc(']', f);
}

static void roots(FILE *f, const char *key, const double complex *r, int n)
{
    int i;
    fprintf(f, ",\n  \"%s\": [", key);
    for (i = 0; i < n; i++) {
        fputs(i ? ",\n    [" : "\n    [", f);
        num(f, creal(r[i]));
        fputs(", ", f);
        num(f, cimag(r[i]));
        fputc(']', f);
    }
    fputs("]", f);
}

static void write_ss(FILE *f, const pfh_lti_ss *ss)
{
    int i;
    fputs(",\n  \"A\": [", f);
    for (i = 0; i < ss->n; i++) {
        fputs(i ? ",\n    " : "\n    ", f);
        row(f, ss->A + (size_t)i * (size_t)ss->n, ss->n, 1);
    }
    fputs("],\n  \"B\": [", f);
    for (i = 0; i < ss->n; i++) {
        fputs(i ? ", " : "", f);
        row(f, ss->B + i, 1, 1);
    }
    fputs("],\n  \"C\": [", f);
    row(f, ss->C, ss->n, 1);
    fputs("],\n  \"D\": [[", f);
    num(f, ss->D);
    fputs("]]", f);
}

static void write_sos(FILE *f, const pfh_lti_sos *sos)
{
    int k;
    fputs(",\n  \"sos\": [", f);
    for (k = 0; k < sos->n; k++) {
        fputs(k ? ",\n    " : "\n    ", f);
        row(f, sos->s[k], 6, 1);
    }
    fputs("]", f);
}

int cli_lti_write(FILE *f, const char *format, const pf_ctrl_design *d)
{
    pfh_lti_ss ss;
    pfh_lti_zpk zpk;
    pfh_lti_sos sos;
    int err, rc = CLI_EXIT_OK;

    memset(&zpk, 0, sizeof zpk);
    memset(&sos, 0, sizeof sos);
    err = pfh_lti_ss_make(&ss, d);
    if (err == PFH_LTI_OK && strcmp(format, "ss") != 0)
        err = pfh_lti_zpk_make(&zpk, &ss);
    if (err == PFH_LTI_OK && strcmp(format, "sos") == 0)
        err = pfh_lti_sos_make(&sos, &zpk);
    if (err != PFH_LTI_OK) {
        cli_error("design --format %s: %s", format, pfh_lti_strerror(err));
        rc = err == PFH_LTI_NOMEM || err == PFH_LTI_NUMERIC ? CLI_EXIT_IO : CLI_EXIT_USAGE;
    } else {
        fprintf(f, "{\"format\": \"%s\", \"config\": \"%s\", \"fs\": ", format,
                pf_topology_name(d->p.topology));
        num(f, d->opt.fs);
        fputs(", \"dt\": ", f);
        num(f, 1.0 / d->opt.fs);
        if (strcmp(format, "ss") == 0) {
            write_ss(f, &ss);
        } else if (strcmp(format, "zpk") == 0) {
            roots(f, "z", zpk.z, zpk.nz);
            roots(f, "p", zpk.p, zpk.np);
            fputs(",\n  \"k\": ", f);
            num(f, zpk.k);
        } else {
            write_sos(f, &sos);
        }
        fputs("}\n", f);
        if (ferror(f))
            rc = CLI_EXIT_IO;
    }
    pfh_lti_sos_free(&sos);
    pfh_lti_zpk_free(&zpk);
    pfh_lti_ss_free(&ss);
    return rc;
}
