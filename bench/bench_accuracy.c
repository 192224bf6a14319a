/* SPDX-License-Identifier: MIT */
/*
 * Accuracy benchmark: every case of the exact reference (tests/ref/
 * paper_step_cases.json) against the exact
 * response (tests/ref, Talbot inverse Laplace), max |error| over
 * t in [1 ms, 2 s] relative to the peak |response|, at 5, 20 and 100 kHz,
 * in double, float and Q15, with the default band and order. Prints a
 * Markdown table; never passes or fails on anything (tests do that).
 *   bench_accuracy [--quick]     --quick: 20 kHz only
 *   bench_accuracy --grid FILE   the grid band x N x fs x arithmetic for
 *                                every case: Markdown on stdout, CSV in FILE
 *   bench_accuracy --orders      at 20 kHz with the library's band, every
 *                                case against N = 1 .. PF_MAX_ORDER in double
 *                                and Q15, and Q15's distance from double in
 *                                LSB: how few sections a target error needs
 *   bench_accuracy --exact CASE FS T0 T1
 *                                the exact step response of one case at every
 *                                sample n/fs in [T0, T1], one "n value" line
 *                                each (bench/bench_reduce.py measures the
 *                                reduced banks against it)
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pfh_accuracy.h"
#include "pfh_ref_cases.h"

static pfh_ref_cases cases;

static const double rates[] = {5000.0, 20000.0, 100000.0};

/* The bands of the grid; wh = 0 is the library's pi*fs. */
typedef struct band {
    const char *name;
    double wb, wh;
} band;

static const band bands[] = {
    {"toolbox [1e-3, 1e3]", 1e-3, 1e3},
    {"library [1e-3, pi fs]", 0.0, 0.0},
    {"wide [1e-4, pi fs]", 1e-4, 0.0},
};
static const int orders[] = {3, 5, 8};
static const char *arith_name[] = {"double", "float", "q15"};

#define NB 3
#define NN 3
#define NR 3

static void cell(double e)
{
    if (e < 0)
        printf("refused");
    else
        printf("%.3g", 100 * e);
}

/* Every case x band x N x fs x arithmetic: one Markdown table per case
 * (rows band x N, one column per rate holding double / float / Q15, in %
 * of the peak), and every value in CSV for the error-vs-cost plot. */
static int grid(const char *csv_path)
{
    static double err[NR][NB][NN][3];
    int i, r, b, n, a;
    FILE *csv = fopen(csv_path, "w");
    if (csv == NULL) {
        perror(csv_path);
        return 1;
    }
    fprintf(csv, "case,fs,band,wb,wh,N,arith,error\n");
    for (i = 0; i < cases.n; i++) {
        const pf_params *p = &cases.p[i];
        for (r = 0; r < NR; r++) {
            pfh_acc_ref ref;
            fprintf(stderr, "[bench] grid: %s at %.0f Hz\n", cases.name[i], rates[r]);
            if (pfh_acc_ref_make(&ref, p, rates[r], 1e-3, 2.0) != 0)
                return 1;
            for (b = 0; b < NB; b++)
                for (n = 0; n < NN; n++) {
                    pf_design_opts o;
                    pf_design_opts_default(&o, rates[r]);
                    o.wb = bands[b].wb;
                    o.wh = bands[b].wh;
                    o.order = orders[n];
                    for (a = 0; a < 3; a++) {
                        pf_design_opts res;
                        double e = pfh_acc_error(&ref, &o, (pf_arith)a, NULL);
                        err[r][b][n][a] = e;
                        if (pf_design_opts_resolve(&o, &res) != PF_OK)
                            res.wb = res.wh = 0.0;
                        fprintf(csv, "%s,%.0f,\"%s\",%.6g,%.6g,%d,%s,%.6g\n",
                                cases.name[i], rates[r], bands[b].name, res.wb,
                                res.wh, orders[n], arith_name[a], e);
                    }
                }
            pfh_acc_ref_free(&ref);
        }
        printf("\n### %s\n\n| band | N | 5 kHz | 20 kHz | 100 kHz |\n"
               "|---|---|---|---|---|\n", cases.name[i]);
        for (b = 0; b < NB; b++)
            for (n = 0; n < NN; n++) {
                printf("| %s | %d |", bands[b].name, orders[n]);
                for (r = 0; r < NR; r++) {
                    printf(" ");
                    for (a = 0; a < 3; a++) {
                        cell(err[r][b][n][a]);
                        printf("%s", a < 2 ? " / " : " |");
                    }
                }
                printf("\n");
            }
    }
    return fclose(csv) == 0 ? 0 : 1;
}

/* Q15 against double, max |difference| in LSB of out_fs, over the run. */
typedef struct lsb_ctx {
    double *y;
    long n;
    double worst, lsb;
} lsb_ctx;

static void keep_f64(void *ctx, long n, double y)
{
    lsb_ctx *c = ctx;
    if (n < c->n)
        c->y[n] = y;
}

static void cmp_q15(void *ctx, long n, double y)
{
    lsb_ctx *c = ctx;
    if (n < c->n && fabs(y - c->y[n]) / c->lsb > c->worst)
        c->worst = fabs(y - c->y[n]) / c->lsb;
}

static int order_sweep(void)
{
    const double fs = 20000.0;
    static double ybuf[40001];
    int i, n;
    printf("| case |");
    for (n = 1; n <= PF_MAX_ORDER; n++)
        printf(" N = %d (%d sections per operator) |", n, 2 * n + 1);
    printf("\n|---|");
    for (n = 1; n <= PF_MAX_ORDER; n++)
        printf("---|");
    printf("\n");
    for (i = 0; i < cases.n; i++) {
        const pf_params *p = &cases.p[i];
        pfh_acc_ref ref;
        fprintf(stderr, "[bench] orders: %s\n", cases.name[i]);
        if (pfh_acc_ref_make(&ref, p, fs, 1e-3, 2.0) != 0)
            return 1;
        printf("| %s |", cases.name[i]);
        for (n = 1; n <= PF_MAX_ORDER; n++) {
            pf_design_opts o;
            double e64, eq;
            /* Q15 as pfh_acc_error runs it: half-scale step, out_fs = 1.25 peak */
            lsb_ctx c = {ybuf, 40001, 0.0, 1.25 * ref.peak / 32768.0};
            pf_design_opts_default(&o, fs);
            o.order = n;
            e64 = pfh_acc_error(&ref, &o, PF_ARITH_F64, NULL);
            eq = pfh_acc_error(&ref, &o, PF_ARITH_Q15, NULL);
            if (pfh_acc_run(p, &o, PF_ARITH_F64, 0.0, c.n - 1, keep_f64, &c) != 0 ||
                pfh_acc_run(p, &o, PF_ARITH_Q15, 1.25 * ref.peak, c.n - 1, cmp_q15, &c) != 0)
                c.worst = -1.0;
            printf(" %.3g %% / %.3g %% / %.2f LSB |", 100 * e64, 100 * eq, c.worst);
        }
        printf("\n");
        pfh_acc_ref_free(&ref);
    }
    return 0;
}

/* The paper's likely setting: a toolbox-default band at 10 kHz, N = 5, in
 * double, for Example 4 (beta = 0.8, q = 0.9); the error at t = 1 ms
 * relative to the local value, and the worst over [1 ms, 2 s] relative to
 * the peak. */
static void toolbox_example(void)
{
    static pf_ctrl_design d;
    static pf_ctrl_f64 c;
    pf_params p;
    pf_design_opts o;
    pfh_acc_ref ref;
    long n;
    double y = 0.0, ex, worst;
    pf_params_default(&p, PF_TOPO_P);
    pf_design_opts_default(&o, 10000.0);
    o.wb = 1e-3;
    o.wh = 1e3;
    o.order = 5;
    if (pf_ctrl_design_make(&d, &p, NULL, &o) != PF_OK ||
        pfh_acc_ref_make(&ref, &p, 10000.0, 1e-3, 2.0) != 0)
        return;
    pf_ctrl_init_f64(&c, &d.rt, NULL, 0);
    for (n = 0; n <= 10; n++) /* t = 1 ms is sample 10 */
        y = pf_ctrl_step_f64(&c, 1.0);
    ex = ref.y[0];
    worst = pfh_acc_error(&ref, &o, PF_ARITH_F64, NULL);
    printf("toolbox band [1e-3, 1e3] rad/s, N = 5, 10 kHz, Example 4 (beta 0.8, "
           "q 0.9), double: %.2f %% of the local value at t = 1 ms; worst %.2f %% "
           "of the peak over [1 ms, 2 s]\n", 100 * fabs(y - ex) / fabs(ex), 100 * worst);
    pfh_acc_ref_free(&ref);
}

/* The exact response of case @p name at the samples of [t0, t1]. */
static int exact(const char *name, double fs, double t0, double t1)
{
    const pf_params *p = pfh_ref_cases_find(&cases, name);
    pfh_acc_ref ref;
    long n;
    if (p == NULL || !(fs > 0 && t0 >= 0 && t1 > t0 && t1 * fs <= 1e8)) {
        fprintf(stderr, "bench_accuracy --exact: no case '%s', or a bad window\n", name);
        return 2;
    }
    if (pfh_acc_ref_make(&ref, p, fs, t0, t1) != 0)
        return 1;
    for (n = ref.n0; n <= ref.n1; n++)
        printf("%ld %.17g\n", n, ref.y[n - ref.n0]);
    pfh_acc_ref_free(&ref);
    return 0;
}

int main(int argc, char **argv)
{
    int quick = argc > 1 && strcmp(argv[1], "--quick") == 0;
    if (pfh_ref_cases_load(REF_DATA_DIR "/paper_step_cases.json", &cases) != 0) {
        fprintf(stderr, "bench_accuracy: cannot read %s\n",
                REF_DATA_DIR "/paper_step_cases.json");
        return 1;
    }
    if (argc > 1 && strcmp(argv[1], "--orders") == 0)
        return order_sweep();
    if (argc > 5 && strcmp(argv[1], "--exact") == 0)
        return exact(argv[2], atof(argv[3]), atof(argv[4]), atof(argv[5]));
    if (argc > 2 && strcmp(argv[1], "--grid") == 0) {
        toolbox_example();
        return grid(argv[2]);
    }
    int i, r, a;
    double worst[3][3] = {{0}};

    printf("| case | fs | band (rad/s) | N | double | float | Q15 |\n");
    printf("|---|---|---|---|---|---|---|\n");
    for (r = quick ? 1 : 0; r < (quick ? 2 : 3); r++) {
        for (i = 0; i < cases.n; i++) {
            pf_design_opts o, res;
            pfh_acc_ref ref;
            double e[3];
            fprintf(stderr, "[bench] %s at %.0f Hz\n", cases.name[i], rates[r]);
            if (pfh_acc_ref_make(&ref, &cases.p[i], rates[r], 1e-3, 2.0) != 0)
                return 1;
            pf_design_opts_default(&o, rates[r]);
            pf_design_opts_resolve(&o, &res);
            for (a = 0; a < 3; a++) {
                e[a] = pfh_acc_error(&ref, &o, (pf_arith)a, NULL);
                if (e[a] > worst[r][a])
                    worst[r][a] = e[a];
            }
            printf("| %s | %.0f kHz | [%.3g, %.3g] | %d | %.4f %% | %.4f %% | %.4f %% |\n",
                   cases.name[i], rates[r] / 1000, res.wb, res.wh, res.order,
                   100 * e[0], 100 * e[1], 100 * e[2]);
            pfh_acc_ref_free(&ref);
        }
    }
    printf("\n| fs | worst double | worst float | worst Q15 |\n|---|---|---|---|\n");
    for (r = quick ? 1 : 0; r < (quick ? 2 : 3); r++)
        printf("| %.0f kHz | %.4f %% | %.4f %% | %.4f %% |\n", rates[r] / 1000,
               100 * worst[r][0], 100 * worst[r][1], 100 * worst[r][2]);
    return 0;
}
