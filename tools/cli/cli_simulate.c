/* SPDX-License-Identifier: MIT */
#include "cli_simulate.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli_args.h"
#include "cli_csv.h"
#include "cli_options.h"
#include "pfh_fmt.h"
#include "pfh_ref.h"

void cli_simulate_usage(FILE *f)
{
    fprintf(f,
"usage: pneufrac simulate --config {p,dd,id,pid} --fs HZ --duration S [options]\n"
"\n"
"Runs one of the paper's controllers (p: eq. 17, dd: eq. 18, id: eq. 20,\n"
"pid: Remark 3) and writes CSV to standard output: a header t,e,pc, a\n"
"'#' line with the units (pandas: read_csv(f, comment='#')), and one row per\n"
"sample n = 0 .. round(duration*fs), t = n/fs, numbers in the shortest form\n"
"that reads back exactly. The input e is a unit step at n = 0 unless --input\n"
"is given.\n"
"\n"
"required:\n"
"  --config NAME        p, dd, id or pid\n"
"  --fs HZ              sample rate, Hz\n"
"  --duration S         length of the run, s (at most 1e9 samples)\n"
"\n"
"model and design:\n"
"  --set NAME=VALUE     model parameter by the paper's name, repeatable:\n"
"                       a b k1 k2 A ks tau pmin pmax beta q nu w RC RCd RCi\n"
"                       (defaults: the paper's examples for each config)\n"
"  --band WB:WH         Oustaloup band, rad/s (default: derived from\n"
"                       --t-slow below and pi*fs above)\n"
"  --order N            Oustaloup order, 2N+1 sections per operator\n"
"  --approx NAME        oustaloup (default) or refined\n"
"  --input-model NAME   hold (default: samples held, as by a DAC) or linear\n"
"  --t-slow S           slowest time scale of interest, s (default 10)\n"
"\n"
"arithmetic:\n"
"  --arith NAME         double (default), float or q15\n"
"  --in-fs X            q15 only, required: e = X maps to Q15 +1.0\n"
"  --out-fs Y           q15 only, required: p_c = Y maps to Q15 +1.0\n"
"                       q15 adds a column pc_q15 (raw output) and writes\n"
"                       pc = pc_q15*Y/32768; e is quantised with round half\n"
"                       up and saturation, the e column shows it unquantised\n"
"\n"
"input and effects:\n"
"  --input FILE.csv     input sequence: columns t and e (others ignored), t\n"
"                       uniform at 1/fs; '#' comments and blank lines allowed;\n"
"                       '-' reads standard input; a short file holds its\n"
"                       last value\n"
"  --effect NAME:K=V[,K=V]  repeatable: backlash:width=W  nozzle:xh=X\n"
"                       saturation:lo=L,hi=H[,kind=K]  deadtime:t=S  lag:tau=S\n"
"                       (kind 1: p_c clipped after the relay, the default;\n"
"                       2: the relay's diaphragm stops at the limits;\n"
"                       3: the relay's output stops, its memory winds on)\n"
"\n"
"Options take their value as the next argument or after '='.\n");
    cli_exit_status_help(f, 0);
}

size_t cli_run_samples(const cli_run *run)
{
    return (size_t)round(run->duration * run->opt.fs) + 1;
}

/* What the user should change to fix a rejected parameter. */
static void describe_param(const cli_run *run, pf_param_id id, char *buf,
                           size_t n)
{
    const pf_effects *fx = &run->fx;
    double fs = run->opt.fs;
    char range[64];

    cli_param_range(id, range, sizeof range);

    if (id < PF_P_CONFIG) {
        const pf_params *p = &run->p;
        const pf_param_rule *rule = pf_params_broken_rule(p);
        double v = pf_params_get(p, id);

        /* Outside its own range, the range says what to give. Inside it,
         * either a rule between two parameters refused it (the library
         * says which, and the user may change either), or the design did
         * at this rate (pf_ctrl_design_make, pf_controller.h). */
        if (pf_param_check(id, v) != PF_OK) {
            snprintf(buf, n, "value %.10g for config %s, outside %s; change it with "
                     "--set %s=VALUE", v, pf_topology_name(p->topology), range,
                     pf_param_name(id));
        } else if (rule != NULL && rule->refused == id) {
            snprintf(buf, n, "value %.10g for config %s breaks %s, with %s = %.10g; change "
                     "--set %s=VALUE or --set %s=VALUE", v, pf_topology_name(p->topology),
                     rule->text, pf_param_name(rule->other),
                     pf_params_get(p, rule->other), pf_param_name(id),
                     pf_param_name(rule->other));
        } else {
            snprintf(buf, n, "value %.10g for config %s, which the design cannot realise "
                     "at --fs %.10g (an order the approximation cannot reach, or an "
                     "in-sample loop that is nearly singular); change it with --set "
                     "%s=VALUE, or --fs", v, pf_topology_name(p->topology), fs,
                     pf_param_name(id));
        }
        return;
    }
    switch (id) {
    case PF_P_FS:
        snprintf(buf, n, "--fs %.10g; it must be in %s", fs, range);
        break;
    case PF_P_WB:
    case PF_P_WH:
        snprintf(buf, n, "the band (--band, or its default from --t-slow) "
                 "needs WB < WH <= pi*fs = %.10g and WB >= %g*fs = %.10g",
                 M_PI * fs, PF_WB_MIN_PER_FS, PF_WB_MIN_PER_FS * fs);
        break;
    case PF_P_ORDER:
        snprintf(buf, n, "--order must be in 1..%d", PF_MAX_ORDER);
        break;
    case PF_P_TSLOW:
        snprintf(buf, n, "--t-slow %.10g; it must be in %s", run->opt.t_slow,
                 range);
        break;
    case PF_P_IN_FS:
        snprintf(buf, n, "--in-fs %.10g", run->in_fs);
        break;
    case PF_P_OUT_FS:
        snprintf(buf, n, "--out-fs %.10g", run->out_fs);
        break;
    case PF_P_BACKLASH:
        snprintf(buf, n, "--effect backlash:width=%.10g", fx->backlash);
        break;
    case PF_P_NOZZLE_XH:
        snprintf(buf, n, "--effect nozzle:xh=%.10g", fx->nozzle_xh);
        break;
    case PF_P_SAT_LO:
    case PF_P_SAT_HI:
        snprintf(buf, n, "--effect saturation:lo=%.10g,hi=%.10g; needs lo < hi",
                 fx->sat_lo, fx->sat_hi);
        break;
    case PF_P_SATURATE:
        /* 0 is the library's "off"; the top placement is the table's. */
        snprintf(buf, n, "--effect saturation:kind=%d; needs a whole number from 1 to %g",
                 fx->saturate, pf_param_info(PF_P_SATURATE)->hi);
        break;
    case PF_P_DEAD_TIME:
        snprintf(buf, n, "--effect deadtime:t=%.10g", fx->dead_time);
        break;
    case PF_P_LAG:
        snprintf(buf, n, "--effect lag:tau=%.10g", fx->lag);
        break;
    default:
        snprintf(buf, n, "%s", pf_status_str(PF_E_PARAM(id)));
        break;
    }
}

static void report_status(const cli_run *run, pf_status st)
{
    pf_param_id id = pf_status_param(st);
    char why[256];

    if (id != PF_P_COUNT) {
        describe_param(run, id, why, sizeof why);
        cli_error("invalid parameter '%s' (%s)", pf_param_name(id), why);
    } else if (st == PF_E_UNSUPPORTED) {
        cli_error("--arith q15 does not support the refined approximation, a "
                  "relay whose memory winds on at its limits (saturation "
                  "kind=3), nor a nozzle curve whose in-sample loop is not "
                  "monotone (%s); use --arith double or float", pf_status_str(st));
    } else if (st == PF_E_SCALE) {
        cli_error("--arith q15: %s; try other --in-fs/--out-fs or a "
                  "narrower --band", pf_status_str(st));
    } else {
        cli_error("design failed: %s", pf_status_str(st));
    }
}

int cli_run_design(const cli_run *run, pf_ctrl_design *d)
{
    pf_status st = pf_ctrl_design_make(d, &run->p, &run->fx, &run->opt);
    if (st != PF_OK) {
        report_status(run, st);
        return CLI_EXIT_USAGE;
    }
    return CLI_EXIT_OK;
}

static int write_error(const char *out_name)
{
    cli_error("error writing %s: %s", out_name, strerror(errno));
    return CLI_EXIT_IO;
}

int cli_run_write(const cli_run *run, const pf_ctrl_design *d, FILE *out,
                  const char *out_name, cli_sample_fn fn, void *ctx)
{
    const size_t total = cli_run_samples(run);
    const size_t dlen = d->rt.delay_len;
    const double fs = run->opt.fs;
    /* static: the runtime holds a coefficient set of every arithmetic;
     * the CLI runs one simulation per process. */
    static pf_runtime rt;
    char cols[64], units[128];
    void *dbuf = NULL;
    pf_status st;
    size_t n;
    int rc = CLI_EXIT_OK;

    if (dlen > 0) {
        dbuf = calloc(dlen, pf_arith_sample_size(run->arith));
        if (dbuf == NULL) {
            cli_error("out of memory for a dead time of %lu samples",
                      (unsigned long)dlen);
            return CLI_EXIT_USAGE;
        }
    }
    st = pf_runtime_init(&rt, d, run->arith, run->in_fs, run->out_fs, dbuf,
                         dlen);
    if (st != PF_OK) {
        report_status(run, st);
        free(dbuf);
        return CLI_EXIT_USAGE;
    }

    snprintf(cols, sizeof cols, "t,e,pc%s%s", run->arith == PF_ARITH_Q15 ? ",pc_q15" : "",
             run->exact ? ",pc_exact" : "");
    snprintf(units, sizeof units, "s,input units,output units%s%s",
             run->arith == PF_ARITH_Q15 ? ",counts of out_fs/32768" : "",
             run->exact ? ",output units" : "");
    if (cli_csv_head(out, cols, units) != 0) {
        free(dbuf);
        return write_error(out_name);
    }
    for (n = 0; n < total; n++) {
        double e = run->input == NULL ? 1.0
                   : run->input[n < run->n_input ? n : run->n_input - 1];
        double pc = pf_runtime_step(&rt, e);
        char row[5 * PFH_FMT_LEN + 8];
        int k = 0;
        /* Shortest round-trip text: the values read back exactly; a float
         * run's output is written as the float it is ("0.1", not
         * "0.100000001"). */
        k += pfh_fmt_double(row + k, (double)n / fs);
        row[k++] = ',';
        k += pfh_fmt_double(row + k, e);
        row[k++] = ',';
        if (run->arith == PF_ARITH_F32)
            k += pfh_fmt_float(row + k, (float)pc);
        else
            k += pfh_fmt_double(row + k, pc);
        if (run->arith == PF_ARITH_Q15)
            k += sprintf(row + k, ",%d", (int)rt.out_q15);
        if (run->exact) {
            /* NaN at t = 0 (and within a dead time): the exact response
             * jumps there and has no value of its own. */
            row[k++] = ',';
            k += pfh_fmt_double(row + k, pfh_ref_step_fx(&run->p, &run->fx, (double)n / fs));
        }
        row[k++] = '\n';
        if (fwrite(row, 1, (size_t)k, out) != (size_t)k) {
            rc = write_error(out_name);
            break;
        }
        if (fn != NULL)
            fn(ctx, n, pc);
    }
    if (rc == CLI_EXIT_OK && fflush(out) != 0)
        rc = write_error(out_name);
    free(dbuf);
    return rc;
}

static const cli_command simulate_cmd = {
    "simulate", cli_simulate_usage,
    CLI_OPTS_DESIGN | CLI_OPTS_ARITH | CLI_OPT_DURATION | CLI_OPT_INPUT};

int cli_simulate_main(int argc, char **argv)
{
    cli_opts a;
    cli_run run;
    pf_ctrl_design d;
    double *input = NULL;
    int rc;

    rc = cli_opts_read(argc, argv, &simulate_cmd, &a, &run);
    if (rc != 0)
        return rc > 0 ? CLI_EXIT_OK : CLI_EXIT_USAGE;
    rc = cli_run_design(&run, &d);
    if (rc != CLI_EXIT_OK)
        return rc;
    if (a.input != NULL) {
        if (cli_csv_read_input(a.input, run.opt.fs, cli_run_samples(&run),
                               &input, &run.n_input) != 0)
            return CLI_EXIT_USAGE;
        run.input = input;
    }
    rc = cli_run_write(&run, &d, stdout, "standard output", NULL, NULL);
    free(input);
    return rc;
}
