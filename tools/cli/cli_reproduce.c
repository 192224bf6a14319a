/* SPDX-License-Identifier: MIT */
/*
 * "pneufrac reproduce --out DIR": the paper's Figs. 8-10 (step responses of
 * Examples 4, 6 and 7) run in float and Q15 beside the exact response (the
 * host library's Talbot inverse Laplace, tools/host/pfh_ref.c, which knows nothing of
 * Oustaloup), and the frequency responses of the Oustaloup and refined
 * approximants of s^beta, s^q and s^nu against the ideal. CSV only; the
 * plots are drawn by tools/reproduce/plot.py (scripts/reproduce.sh runs
 * both).
 */
#include "cli_reproduce.h"

#include <complex.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pneufrac/pneufrac.h"
#include "cli_args.h"
#include "pfh_accuracy.h"
#include "pfh_ref.h"

#define T_END 10.0
#define MAX_T 1200
#define MAX_CASES 10

/* Example 4 is swept over the full grid the issue asks for, not only the
 * two one-dimensional sweeps of the shared reference. */
static const double ex4_beta[] = {0.6, 0.8, 1.0};
static const double qs[] = {0.9, 0.99, 1.0};

typedef struct series {
    char name[32];
    pf_params p;
} series;

void cli_reproduce_usage(FILE *f)
{
    fprintf(f,
"usage: pneufrac reproduce --out DIR [--fs HZ]\n"
"\n"
"Writes the data of the paper's figures as CSV into DIR (which must exist):\n"
"  fig8_ex4.csv    Example 4 (eq. 17), beta in {0.6, 0.8, 1} x q in {0.9, 0.99, 1},\n"
"                  plus a toolbox-default band ([1e-3, 1e3] rad/s, N = 5) run\n"
"  fig9_ex6.csv    Example 6 (eq. 18, FrDD), q in {0.9, 0.99, 1}\n"
"  fig10_ex7.csv   Example 7 (eq. 20, FrID)\n"
"  freq_oustaloup.csv  Oustaloup and refined approximants of s^0.8, s^0.9,\n"
"                  s^0.94 (beta, q, nu) at 20 kHz against the ideal\n"
"Step responses: columns t and, per case, <case>_exact, _float, _q15, on a\n"
"log time grid (10 us .. 10 s) merged with a linear one; simulated at\n"
"--fs HZ (default 100000) with the default band and order. Q15 runs a\n"
"half-scale step with out_fs = 1.25 x the peak of the exact response.\n"
"Plots: tools/reproduce/plot.py DIR, or scripts/reproduce.sh for both.\n"
"\n");
    cli_exit_status_help(f, 0);
}

/* Sample indices of the merged grid: 40 points per decade from 10 us and
 * 200 linear points up to T_END, each rounded to a sample and deduplicated. */
static int time_grid(double fs, long *n)
{
    long tmp[MAX_T];
    int i, k = 0, m = 0;
    for (i = 0; i <= 240 && k < MAX_T; i++)
        tmp[k++] = lround(1e-5 * pow(10.0, i / 40.0) * fs);
    for (i = 1; i <= 200 && k < MAX_T; i++)
        tmp[k++] = lround(T_END * i / 200.0 * fs);
    for (i = 0; i < k; i++) {
        long v = tmp[i], j;
        for (j = i + 1; j < k; j++)
            if (tmp[j] < v) {
                long t = tmp[j];
                tmp[j] = v;
                v = t;
            }
        if (v >= 1 && (m == 0 || v != n[m - 1]))
            n[m++] = v;
    }
    return m;
}

/* Records a run at the grid's samples. */
typedef struct grid_ctx {
    const long *n;
    double *y;
    int i;
} grid_ctx;

static void record_grid(void *ctx, long s, double v)
{
    grid_ctx *g = ctx;
    if (s == g->n[g->i])
        g->y[g->i++] = v;
}

/* One run in float or Q15 (q15 != 0), recorded at the grid's samples. */
static int simulate(const pf_params *p, const pf_design_opts *o, int q15,
                    double out_fs, const long *n, int nt, double *y)
{
    grid_ctx g = {NULL, NULL, 0};
    g.n = n;
    g.y = y;
    return pfh_acc_run(p, o, q15 ? PF_ARITH_Q15 : PF_ARITH_F32, out_fs, n[nt - 1], record_grid, &g);
}

/* The toolbox default the paper's Simulink blocks likely used, in double. */
static int simulate_toolbox(const pf_params *p, double fs, const long *n, int nt,
                            double *y)
{
    grid_ctx g = {NULL, NULL, 0};
    pf_design_opts o;
    pf_design_opts_default(&o, fs);
    o.wb = 1e-3;
    o.wh = 1e3;
    o.order = 5;
    g.n = n;
    g.y = y;
    return pfh_acc_run(p, &o, PF_ARITH_F64, 1.0, n[nt - 1], record_grid, &g);
}

static int write_steps(const char *dir, const char *file, const series *cs,
                       int ncase, int toolbox, double fs)
{
    static long n[MAX_T];
    static double ex[MAX_CASES][MAX_T], yf[MAX_CASES][MAX_T], yq[MAX_CASES][MAX_T],
        tb[MAX_T];
    char path[1024];
    pf_design_opts o;
    FILE *f;
    int nt = time_grid(fs, n), c, i;

    pf_design_opts_default(&o, fs);
    for (c = 0; c < ncase; c++) {
        double peak = 0.0;
        fprintf(stderr, "[reproduce] %s: %s\n", file, cs[c].name);
        for (i = 0; i < nt; i++) {
            ex[c][i] = pfh_ref_step(&cs[c].p, n[i] / fs);
            if (fabs(ex[c][i]) > peak)
                peak = fabs(ex[c][i]);
        }
        if (simulate(&cs[c].p, &o, 0, 0.0, n, nt, yf[c]) != 0 ||
            simulate(&cs[c].p, &o, 1, 1.25 * peak, n, nt, yq[c]) != 0) {
            cli_error("reproduce: case %s: design refused", cs[c].name);
            return CLI_EXIT_USAGE;
        }
    }
    if (toolbox && simulate_toolbox(&cs[toolbox - 1].p, fs, n, nt, tb) != 0) {
        cli_error("reproduce: toolbox band refused");
        return CLI_EXIT_USAGE;
    }
    snprintf(path, sizeof path, "%s/%s", dir, file);
    f = fopen(path, "w");
    if (f == NULL) {
        cli_error("reproduce: cannot write %s: %s", path, strerror(errno));
        return CLI_EXIT_IO;
    }
    fprintf(f, "t");
    for (c = 0; c < ncase; c++)
        fprintf(f, ",%s_exact,%s_float,%s_q15", cs[c].name, cs[c].name, cs[c].name);
    if (toolbox)
        fprintf(f, ",%s_toolbox", cs[toolbox - 1].name);
    fprintf(f, "\n");
    for (i = 0; i < nt; i++) {
        fprintf(f, "%.9g", n[i] / fs);
        for (c = 0; c < ncase; c++)
            fprintf(f, ",%.12g,%.9g,%.9g", ex[c][i], yf[c][i], yq[c][i]);
        if (toolbox)
            fprintf(f, ",%.12g", tb[i]);
        fprintf(f, "\n");
    }
    if (fclose(f) != 0) {
        cli_error("reproduce: error writing %s: %s", path, strerror(errno));
        return CLI_EXIT_IO;
    }
    return CLI_EXIT_OK;
}

static int write_freq(const char *dir)
{
    static const double orders[] = {0.8, 0.9, 0.94};
    static const char *names[] = {"beta", "q", "nu"};
    pf_fracop_design od[3][2];
    pf_design_opts o;
    char path[1024];
    FILE *f;
    int i, k, a;
    const double fs = 20000.0;

    for (k = 0; k < 3; k++)
        for (a = 0; a < 2; a++) {
            pf_design_opts_default(&o, fs);
            o.approx = a ? PF_APPROX_REFINED : PF_APPROX_OUSTALOUP;
            if (pf_fracop_design_make(&od[k][a], orders[k], 1.0, &o) != PF_OK) {
                cli_error("reproduce: s^%g refused", orders[k]);
                return CLI_EXIT_USAGE;
            }
        }
    snprintf(path, sizeof path, "%s/freq_oustaloup.csv", dir);
    f = fopen(path, "w");
    if (f == NULL) {
        cli_error("reproduce: cannot write %s: %s", path, strerror(errno));
        return CLI_EXIT_IO;
    }
    fprintf(f, "w");
    for (k = 0; k < 3; k++)
        fprintf(f, ",%s_ideal_db,%s_ideal_deg,%s_oustaloup_db,%s_oustaloup_deg,"
                   "%s_refined_db,%s_refined_deg",
                names[k], names[k], names[k], names[k], names[k], names[k]);
    fprintf(f, "\n");
    /* From two decades below the band to just under Nyquist. */
    for (i = 0; i <= 400; i++) {
        double w = 1e-5 * pow(0.995 * M_PI * fs / 1e-5, i / 400.0);
        fprintf(f, "%.9g", w);
        for (k = 0; k < 3; k++) {
            fprintf(f, ",%.9g,%.9g", 20.0 * orders[k] * log10(w), 90.0 * orders[k]);
            for (a = 0; a < 2; a++) {
                double re, im;
                pf_fracop_freqresp(&od[k][a], w, &re, &im);
                fprintf(f, ",%.9g,%.9g", 20.0 * log10(hypot(re, im)),
                        atan2(im, re) * 180.0 / M_PI);
            }
        }
        fprintf(f, "\n");
    }
    if (fclose(f) != 0) {
        cli_error("reproduce: error writing %s: %s", path, strerror(errno));
        return CLI_EXIT_IO;
    }
    return CLI_EXIT_OK;
}

int cli_reproduce_main(int argc, char **argv)
{
    series cs[MAX_CASES];
    const char *dir = NULL;
    double fs = 100000.0;
    char q[48];
    int i, j, rc;

    for (i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            cli_reproduce_usage(stdout);
            return CLI_EXIT_OK;
        }
        if (i + 1 >= argc) {
            cli_error("reproduce: '%s' needs a value or is unknown (see pneufrac "
                      "reproduce --help)", cli_quote(q, sizeof q, argv[i]));
            return CLI_EXIT_USAGE;
        }
        if (strcmp(argv[i], "--out") == 0) {
            dir = argv[++i];
        } else if (strcmp(argv[i], "--fs") == 0) {
            if (cli_parse_positive("--fs", argv[++i], &fs) != 0)
                return CLI_EXIT_USAGE;
        } else {
            cli_error("reproduce: unknown option '%s' (see pneufrac reproduce "
                      "--help)", cli_quote(q, sizeof q, argv[i]));
            return CLI_EXIT_USAGE;
        }
    }
    if (dir == NULL || *dir == '\0') {
        cli_error("reproduce: missing --out DIR");
        return CLI_EXIT_USAGE;
    }

    /* Fig. 8: beta x q; the toolbox run is beta = 0.8, q = 0.9 (case 3, passed
     * 1-based so that 0 means none). */
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) {
            series *s = &cs[3 * i + j];
            pf_params_default(&s->p, PF_TOPO_P);
            s->p.beta = ex4_beta[i];
            s->p.q = qs[j];
            snprintf(s->name, sizeof s->name, "ex4_b%g_q%g", ex4_beta[i], qs[j]);
        }
    rc = write_steps(dir, "fig8_ex4.csv", cs, 9, 4, fs);
    if (rc != CLI_EXIT_OK)
        return rc;
    for (j = 0; j < 3; j++) {
        pf_params_default(&cs[j].p, PF_TOPO_DD);
        cs[j].p.q = qs[j];
        snprintf(cs[j].name, sizeof cs[j].name, "ex6_q%g", qs[j]);
    }
    rc = write_steps(dir, "fig9_ex6.csv", cs, 3, 0, fs);
    if (rc != CLI_EXIT_OK)
        return rc;
    pf_params_default(&cs[0].p, PF_TOPO_ID);
    snprintf(cs[0].name, sizeof cs[0].name, "ex7");
    rc = write_steps(dir, "fig10_ex7.csv", cs, 1, 0, fs);
    if (rc != CLI_EXIT_OK)
        return rc;
    return write_freq(dir);
}
