/* SPDX-License-Identifier: MIT */
#include "cli_demo.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli_args.h"
#include "cli_simulate.h"

#define DEMO_FS 20000.0
#define DEMO_DURATION 2.0
#define DEMO_OUT "example6.csv"

static const double table_t[] = {0.0, 1e-3, 1e-2, 1e-1, 1.0, 2.0};
static const char *const table_label[] = {"0 s", "1 ms", "10 ms",
                                          "100 ms", "1 s", "2 s"};
#define N_TABLE (sizeof table_t / sizeof table_t[0])

typedef struct demo_stats {
    size_t idx[N_TABLE];
    double at[N_TABLE];
    double peak, final_pc;
    size_t peak_n;
} demo_stats;

static void observe(void *ctx, size_t n, double pc)
{
    demo_stats *s = ctx;
    size_t k;
    for (k = 0; k < N_TABLE; k++)
        if (s->idx[k] == n)
            s->at[k] = pc;
    if (n == 0 || pc > s->peak) {
        s->peak = pc;
        s->peak_n = n;
    }
    s->final_pc = pc;
}

void cli_demo_usage(FILE *f)
{
    fprintf(f,
"usage: pneufrac demo [--out FILE.csv]\n"
"\n"
"Runs the paper's Example 6 (config dd, eq. 18, default parameters) on a\n"
"unit step at fs = 20 kHz for 2 s in double precision, writes the response\n"
"as CSV (t,e,pc) to FILE.csv (default " DEMO_OUT ") and prints a summary:\n"
"parameters, design, and p_c at a few instants.\n"
"It is the same as: pneufrac simulate --config dd --fs 20000 --duration 2\n"
"\n");
    cli_exit_status_help(f, 0);
}

static void print_op(const char *label, const char *expr,
                     const pf_fracop_design *op)
{
    printf("  %-22s %-16s alpha = %-6g %2d sections", label, expr, op->alpha,
           op->n_sec);
    if (op->n_int != 0)
        printf(" + %d %s%s", abs(op->n_int),
               op->n_int < 0 ? "integrator" : "differentiator",
               abs(op->n_int) > 1 ? "s" : "");
    printf("\n");
}

static void print_summary(const cli_run *run, const pf_ctrl_design *d,
                          const demo_stats *s, const char *out, size_t rows)
{
    const pf_ctrl_coeffs_f64 *c = &d->rt;
    const int pid = run->p.topology == PF_TOPO_PID;
    int id, col = 0;
    size_t k;

    printf("pneufrac demo: Example 6 of the paper, the fractional derivative\n"
           "controller (config %s, eq. 18), answering a unit step in e at "
           "t = 0.\n\n", pf_topology_name(run->p.topology));
    printf("parameters:");
    for (id = 0; id < (int)PF_P_CONFIG; id++) {
        if (!pf_param_used(run->p.topology, (pf_param_id)id))
            continue;
        if (col == 7) {
            printf("\n           ");
            col = 0;
        }
        printf(" %s=%g", pf_param_name((pf_param_id)id),
               pf_params_get(&run->p, (pf_param_id)id));
        col++;
    }
    printf("\ndesign:     fs = %g Hz, double; %s band %g .. %g rad/s, "
           "order N = %d, %s input\n",
           d->opt.fs,
           d->opt.approx == PF_APPROX_REFINED ? "refined Oustaloup"
                                              : "Oustaloup",
           d->opt.wb, d->opt.wh, d->opt.order,
           d->opt.input == PF_INPUT_HOLD ? "held" : "linear");
    print_op("relay", "(tau s)^-beta", &c->P);
    if (c->has_q)
        print_op("bellows", "(A/ks) s^-q", &c->Q);
    if (c->has_v)
        print_op(pid ? "derivative restrictor" : "restrictor",
                 pid ? "(1/RCd) s^-nu" : "(1/RC) s^-nu", &c->V);
    if (c->has_w)
        print_op(pid ? "reset restrictor" : "restrictor",
                 pid ? "(1/RCi) s^-w" : "(1/RC) s^-w", &c->W);

    printf("\n  %8s   %s\n", "t", "p_c(t)");
    for (k = 0; k < N_TABLE; k++)
        printf("  %8s   %.6g\n", table_label[k], s->at[k]);
    printf("  %8s   %.6g at t = %g s\n", "peak", s->peak,
           (double)s->peak_n / run->opt.fs);
    printf("  %8s   %.6g at t = %g s\n", "final", s->final_pc,
           (double)(rows - 1) / run->opt.fs);
    printf("\nwrote %s (%lu rows: t,e,pc)\n", out, (unsigned long)rows);
}

int cli_demo_main(int argc, char **argv)
{
    const char *out = DEMO_OUT;
    int have_out = 0;
    char q[48];
    cli_run run;
    pf_ctrl_design d;
    demo_stats s;
    FILE *f;
    size_t k;
    int i, rc;

    for (i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0) {
            cli_demo_usage(stdout);
            return CLI_EXIT_OK;
        }
        if (strcmp(arg, "--out") == 0 || strncmp(arg, "--out=", 6) == 0) {
            if (have_out) {
                cli_error("--out given more than once");
                return CLI_EXIT_USAGE;
            }
            if (arg[5] == '=') {
                out = arg + 6;
            } else if (i + 1 < argc && strncmp(argv[i + 1], "--", 2) != 0) {
                out = argv[++i];
            } else {
                cli_error("--out needs a value");
                return CLI_EXIT_USAGE;
            }
            if (*out == '\0') {
                cli_error("--out needs a file name");
                return CLI_EXIT_USAGE;
            }
            have_out = 1;
            continue;
        }
        cli_error("demo: unexpected argument '%s' (see pneufrac demo --help)",
                  cli_quote(q, sizeof q, arg));
        return CLI_EXIT_USAGE;
    }

    memset(&run, 0, sizeof run);
    pf_params_default(&run.p, PF_TOPO_DD);
    run.opt.fs = DEMO_FS;
    run.arith = PF_ARITH_F64;
    run.duration = DEMO_DURATION;
    rc = cli_run_design(&run, &d);
    if (rc != CLI_EXIT_OK)
        return rc;

    memset(&s, 0, sizeof s);
    for (k = 0; k < N_TABLE; k++)
        s.idx[k] = (size_t)round(table_t[k] * DEMO_FS);

    f = fopen(out, "w");
    if (f == NULL) {
        cli_error("cannot create %s: %s", out, strerror(errno));
        return CLI_EXIT_IO;
    }
    setvbuf(f, NULL, _IOFBF, 1 << 16);
    rc = cli_run_write(&run, &d, f, out, observe, &s);
    if (fclose(f) != 0 && rc == CLI_EXIT_OK) {
        cli_error("error writing %s: %s", out, strerror(errno));
        rc = CLI_EXIT_IO;
    }
    if (rc != CLI_EXIT_OK) {
        /* A truncated CSV looks like a valid shorter run; do not leave it. */
        remove(out);
        return rc;
    }
    print_summary(&run, &d, &s, out, cli_run_samples(&run));
    return CLI_EXIT_OK;
}
