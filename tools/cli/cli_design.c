/* SPDX-License-Identifier: MIT */
/*
 * "pneufrac design": the design step on its own, for firmware that runs
 * only the runtime. --format c writes the float or Q15 coefficient set as a
 * C header (static const, no libm or FPU needed to use it); --format json
 * describes the double design: resolved band and order, every operator's
 * sections and the loop constants; --format cmsis-f32 / cmsis-q15 write
 * each operator as a biquad cascade for CMSIS-DSP's DF1 functions.
 */
#include "cli_design.h"

#include <ctype.h>
#include <stdlib.h>
#include <string.h>

#include "cli_args.h"
#include "cli_export.h"
#include "cli_lti.h"
#include "cli_options.h"
#include "pfh_fmt.h"

static const cli_command design_cmd = {
    "design", cli_design_usage,
    CLI_OPTS_DESIGN | CLI_OPTS_ARITH | CLI_OPT_FORMAT | CLI_OPT_NAME};

void cli_design_usage(FILE *f)
{
    fprintf(f,
"usage: pneufrac design --config {p,dd,id,pid} --fs HZ\n"
"                       --format {c,cmsis-f32,cmsis-q15,json,ss,zpk,sos}\n"
"                       [--arith double|float|q15] [--in-fs X --out-fs Y]\n"
"                       [--name IDENT] [--set NAME=VALUE ...]\n"
"                       [--band WB:WH] [--order N] [--approx oustaloup|refined]\n"
"                       [--input-model hold|linear] [--t-slow S]\n"
"                       [--effect NAME:K=V[,K=V] ...]\n"
"\n"
"Designs a controller and writes it to standard output.\n"
"  --format c     a C header defining 'static const pf_ctrl_coeffs_q15 IDENT'\n"
"                 (--arith q15, needs --in-fs/--out-fs) or pf_ctrl_coeffs_f32\n"
"                 (--arith float), for pf_ctrl_init_q15/_f32 in firmware\n"
"  --format json  the double design: resolved band and order, each\n"
"                 operator's parallel sections, the loop constants\n"
"  --format ss, --format zpk, --format sos\n"
"                 the whole realised controller (double, at fs, held input\n"
"                 and lag included) as a discrete system in scipy's\n"
"                 conventions, one JSON object with dt = 1/fs:\n"
"                 ss: A, B, C, D in the runtime's own coordinates (one state\n"
"                 per parallel section: keeps every digit, use this one);\n"
"                 zpk: zeros z and poles p as [re, im] roots, gain k;\n"
"                 sos: rows [b0, b1, b2, 1, a1, a2]. Linear designs only:\n"
"                 no backlash, nozzle, saturation or dead time\n"
"  --format cmsis-f32, --format cmsis-q15\n"
"                 each fractional operator alone as coefficient arrays for\n"
"                 CMSIS-DSP arm_biquad_cascade_df1_f32 / _q15 (5 or 6 values\n"
"                 per stage, CMSIS sign: y += a1 y[n-1] + a2 y[n-2]; q15\n"
"                 with postShift). cmsis-q15 takes --arith q15 --in-fs X\n"
"                 --out-fs Y to scale each operator by X/Y (default 1)\n"
"  --name IDENT   the C identifier of the coefficient set (default pf_coeffs)\n"
"\n");
    cli_exit_status_help(f, 0);
}

static int valid_ident(const char *s)
{
    if (!(isalpha((unsigned char)*s) || *s == '_'))
        return 0;
    for (; *s; s++)
        if (!(isalnum((unsigned char)*s) || *s == '_'))
            return 0;
    return 1;
}

/* JSON numbers in shortest round-trip form: they read back exactly. */
static void json_num(FILE *f, const char *key, double v, const char *after)
{
    fprintf(f, "\"%s\": ", key);
    pfh_fput_double(f, v);
    fputs(after, f);
}

static void json_array(FILE *f, const char *key, const double *v, int n)
{
    int i;
    fprintf(f, "\"%s\": [", key);
    for (i = 0; i < n; i++) {
        fputs(i ? ", " : "", f);
        pfh_fput_double(f, v[i]);
    }
    fprintf(f, "]");
}

static void json_op(FILE *f, const char *role, const pf_fracop_design *op, int last)
{
    fprintf(f, "    {\"role\": \"%s\", ", role);
    json_num(f, "alpha", op->alpha, ", ");
    json_num(f, "gain", op->gain, ", ");
    fprintf(f, "\"n_int\": %d, \"n_sec\": %d, ", op->n_int, op->n_sec);
    json_num(f, "d", op->d, ", ");
    json_num(f, "D", op->D, ",\n      ");
    json_array(f, "lam", op->lam, op->n_sec);
    fprintf(f, ",\n      ");
    json_array(f, "G", op->G, op->n_sec);
    fprintf(f, "}%s\n", last ? "" : ",");
}

static void write_json(FILE *f, const pf_ctrl_design *d)
{
    const pf_ctrl_coeffs_f64 *c = &d->rt;
    int id, first = 1;
    fprintf(f, "{\n  \"config\": \"%s\",\n  \"params\": {", pf_topology_name(d->p.topology));
    for (id = 0; id <= (int)PF_P_RCI; id++) {
        if (!pf_param_used(d->p.topology, (pf_param_id)id))
            continue;
        fputs(first ? "" : ", ", f);
        json_num(f, pf_param_name((pf_param_id)id), pf_params_get(&d->p, (pf_param_id)id), "");
        first = 0;
    }
    fprintf(f, "},\n  \"design\": {");
    json_num(f, "fs", d->opt.fs, ", ");
    json_num(f, "wb", d->opt.wb, ", ");
    json_num(f, "wh", d->opt.wh, ", ");
    fprintf(f, "\"order\": %d, \"approx\": \"%s\", \"input\": \"%s\", ", d->opt.order,
            d->opt.approx == PF_APPROX_REFINED ? "refined" : "oustaloup",
            d->opt.input == PF_INPUT_LINEAR ? "linear" : "hold");
    json_num(f, "prewarp", d->opt.prewarp, "},\n");
    fprintf(f, "  \"operators\": [\n");
    json_op(f, "relay (tau s)^-beta", &c->P, !c->has_q && !c->has_v && !c->has_w);
    if (c->has_q)
        json_op(f, "bellows (A/ks) s^-q", &c->Q, !c->has_v && !c->has_w);
    if (c->has_v)
        json_op(f, "restrictor (1/RC) s^-nu", &c->V, !c->has_w);
    if (c->has_w)
        json_op(f, "restrictor (1/RC) s^-w", &c->W, 1);
    fprintf(f, "  ],\n  \"loop\": {");
    json_num(f, "ce", c->ce, ", ");
    json_num(f, "cy", c->cy, ", ");
    json_num(f, "alpha_z", c->alpha_z, ", ");
    json_num(f, "alpha_y", c->alpha_y, ", ");
    json_num(f, "loop_inv", c->loop_inv, "}\n}\n");
}

/* --format cmsis-*: the arithmetic is the format's; --arith may only
 * repeat it (q15 then brings the full scales that scale each operator). */
static int write_cmsis(const cli_run *run, pf_ctrl_design *d, const char *name,
                       int q15)
{
    char note[160];
    double scale = 1.0;
    pf_status st;
    int rc;
    if (run->arith != PF_ARITH_F64 &&
        run->arith != (q15 ? PF_ARITH_Q15 : PF_ARITH_F32)) {
        cli_error("--format cmsis-%s takes no --arith %s (the format sets "
                  "the arithmetic)", q15 ? "q15" : "f32",
                  run->arith == PF_ARITH_Q15 ? "q15" : "float");
        return CLI_EXIT_USAGE;
    }
    if (run->arith == PF_ARITH_Q15)
        scale = run->in_fs / run->out_fs;
    if (cli_run_design(run, d) != CLI_EXIT_OK)
        return CLI_EXIT_USAGE;
    snprintf(note, sizeof note, "config %s, fs = %g Hz, band [%g, %g] rad/s, N = %d",
             pf_topology_name(d->p.topology), d->opt.fs, d->opt.wb, d->opt.wh, d->opt.order);
    rc = cli_export_cmsis(stdout, name, note, d, q15, scale, &st);
    if (rc == -2) {
        cli_error("design: no CMSIS %s cascade: %s", q15 ? "q15" : "f32",
                  pf_status_str(st));
        return CLI_EXIT_USAGE;
    }
    return rc == 0 ? CLI_EXIT_OK : CLI_EXIT_IO;
}

int cli_design_main(int argc, char **argv)
{
    static pf_ctrl_design d;
    cli_opts a;
    cli_run run;
    char q[48];
    const char *name;
    int rc;

    rc = cli_opts_read(argc, argv, &design_cmd, &a, &run);
    if (rc != 0)
        return rc > 0 ? CLI_EXIT_OK : CLI_EXIT_USAGE;
    if (a.format == NULL) {
        cli_error("design: missing --format (c, cmsis-f32, cmsis-q15, json, ss, "
                  "zpk or sos)");
        return CLI_EXIT_USAGE;
    }
    name = a.name != NULL ? a.name : "pf_coeffs";
    if (!valid_ident(name)) {
        cli_error("--name: '%s' is not a C identifier", cli_quote(q, sizeof q, name));
        return CLI_EXIT_USAGE;
    }
    if (strcmp(a.format, "json") == 0) {
        if (cli_run_design(&run, &d) != CLI_EXIT_OK)
            return CLI_EXIT_USAGE;
        write_json(stdout, &d);
    } else if (strcmp(a.format, "c") == 0) {
        char note[160];
        if (run.arith == PF_ARITH_F64) {
            cli_error("--format c needs --arith float or q15 (firmware runs "
                      "float or Q15, not double)");
            return CLI_EXIT_USAGE;
        }
        if (cli_run_design(&run, &d) != CLI_EXIT_OK)
            return CLI_EXIT_USAGE;
        snprintf(note, sizeof note, "config %s, fs = %g Hz, band [%g, %g] rad/s, N = %d",
                 pf_topology_name(d.p.topology), d.opt.fs, d.opt.wb, d.opt.wh, d.opt.order);
        if (run.arith == PF_ARITH_Q15) {
            static pf_ctrl_coeffs_q15 cq;
            static pf_nozzle_q15 nz;
            pf_status st = pf_ctrl_coeffs_q15_make_nz(&cq, &nz, &d, run.in_fs, run.out_fs);
            if (st != PF_OK) {
                cli_error("design: no Q15 coefficient set: %s", pf_status_str(st));
                return CLI_EXIT_USAGE;
            }
            rc = cli_export_c_q15(stdout, name, note, &cq);
        } else {
            static pf_ctrl_coeffs_f32 cf;
            pf_ctrl_coeffs_f32_make(&cf, &d.rt);
            rc = cli_export_c_f32(stdout, name, note, &cf);
        }
        if (rc != 0)
            return CLI_EXIT_IO;
    } else if (cli_lti_is_format(a.format)) {
        if (run.arith != PF_ARITH_F64) {
            cli_error("--format %s describes the double design; it takes no "
                      "--arith", a.format);
            return CLI_EXIT_USAGE;
        }
        if (cli_run_design(&run, &d) != CLI_EXIT_OK)
            return CLI_EXIT_USAGE;
        return cli_lti_write(stdout, a.format, &d);
    } else if (strcmp(a.format, "cmsis-f32") == 0 ||
               strcmp(a.format, "cmsis-q15") == 0) {
        rc = write_cmsis(&run, &d, name, a.format[6] == 'q');
        if (rc != CLI_EXIT_OK)
            return rc;
    } else {
        cli_error("--format: unknown format '%s' (valid: c, cmsis-f32, "
                  "cmsis-q15, json, ss, zpk, sos)",
                  cli_quote(q, sizeof q, a.format));
        return CLI_EXIT_USAGE;
    }
    return CLI_EXIT_OK;
}
