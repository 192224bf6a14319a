/* SPDX-License-Identifier: MIT */
/*
 * Command-line options shared by the commands that design a controller
 * (simulate, design): one parser, one set of messages, each command
 * accepting the subset it names in cli_command.allowed.
 */
#include "cli_options.h"

#include <stdio.h>
#include <string.h>

#include "cli_args.h"

typedef struct opt_desc {
    const char *name;
    unsigned seen;
} opt_desc;

static const opt_desc options[] = {
    {"--config", CLI_OPT_CONFIG},     {"--fs", CLI_OPT_FS},
    {"--duration", CLI_OPT_DURATION}, {"--arith", CLI_OPT_ARITH},
    {"--in-fs", CLI_OPT_IN_FS},       {"--out-fs", CLI_OPT_OUT_FS},
    {"--band", CLI_OPT_BAND},         {"--order", CLI_OPT_ORDER},
    {"--approx", CLI_OPT_APPROX},     {"--input-model", CLI_OPT_INPUT_MODEL},
    {"--t-slow", CLI_OPT_TSLOW},      {"--input", CLI_OPT_INPUT},
    {"--format", CLI_OPT_FORMAT},     {"--name", CLI_OPT_NAME},
    {"--set", CLI_OPT_SET},           {"--effect", CLI_OPT_EFFECT},
    {"--omega", CLI_OPT_OMEGA},       {"--points", CLI_OPT_POINTS},
    {"--plot", CLI_OPT_PLOT},
};
#define N_OPTIONS (sizeof options / sizeof options[0])

static int opts_parse(int argc, char **argv, const cli_command *cmd, cli_opts *a)
{
    char q[48];
    int i;

    for (i = 1; i < argc; i++) {
        const char *arg = argv[i];
        const char *val = NULL;
        const opt_desc *o = NULL;
        size_t nlen;
        size_t k;

        if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0) {
            cmd->usage(stdout);
            return 1;
        }
        if (strncmp(arg, "--", 2) != 0) {
            cli_error("%s: unexpected argument '%s' (options start "
                      "with --; see pneufrac %s --help)", cmd->name,
                      cli_quote(q, sizeof q, arg), cmd->name);
            return -1;
        }
        nlen = strcspn(arg, "=");
        for (k = 0; k < N_OPTIONS; k++)
            if (strlen(options[k].name) == nlen &&
                strncmp(arg, options[k].name, nlen) == 0)
                o = &options[k];
        if (o != NULL && !(cmd->allowed & o->seen))
            o = NULL;
        if (o == NULL) {
            cli_error("%s: unknown option '%s' (see pneufrac %s --help)",
                      cmd->name, cli_quote_n(q, sizeof q, arg, nlen), cmd->name);
            return -1;
        }
        if (arg[nlen] == '=') {
            val = arg + nlen + 1;
        } else if (i + 1 < argc && strncmp(argv[i + 1], "--", 2) != 0) {
            /* A value never starts with "--": "--fs --duration 1" is a
             * forgotten value, not an fs of "--duration". */
            val = argv[++i];
        } else {
            cli_error("%s needs a value", o->name);
            return -1;
        }
        if (!(o->seen & (CLI_OPT_SET | CLI_OPT_EFFECT))) {
            if (a->seen & o->seen) {
                cli_error("%s given more than once", o->name);
                return -1;
            }
            a->seen |= o->seen;
        }

        switch (o->seen) {
        case CLI_OPT_CONFIG:
            a->topology = pf_topology_lookup(val);
            if (a->topology == PF_TOPO_COUNT) {
                cli_error("--config: unknown configuration '%s' (valid: p, "
                          "dd, id, pid)", cli_quote(q, sizeof q, val));
                return -1;
            }
            break;
        case CLI_OPT_FS:
            if (cli_parse_positive("--fs", val, &a->fs) != 0)
                return -1;
            break;
        case CLI_OPT_DURATION:
            if (cli_parse_positive("--duration", val, &a->duration) != 0)
                return -1;
            break;
        case CLI_OPT_ARITH:
            a->arith = pf_arith_lookup(val);
            if (a->arith == PF_ARITH_COUNT) {
                cli_error("--arith: unknown arithmetic '%s' (valid: double, "
                          "float, q15)", cli_quote(q, sizeof q, val));
                return -1;
            }
            break;
        case CLI_OPT_IN_FS:
            if (cli_parse_positive("--in-fs", val, &a->in_fs) != 0)
                return -1;
            break;
        case CLI_OPT_OUT_FS:
            if (cli_parse_positive("--out-fs", val, &a->out_fs) != 0)
                return -1;
            break;
        case CLI_OPT_BAND:
            if (cli_parse_range("--band", "WB", "WH", val, &a->wb, &a->wh) != 0)
                return -1;
            break;
        case CLI_OPT_OMEGA:
            if (cli_parse_range("--omega", "WMIN", "WMAX", val, &a->w_lo, &a->w_hi) != 0)
                return -1;
            break;
        case CLI_OPT_POINTS:
            if (cli_parse_int(val, &a->points) != 0 || a->points < 2 ||
                a->points > CLI_MAX_POINTS) {
                cli_error("--points: '%s' is not an integer in 2..%d",
                          cli_quote(q, sizeof q, val), CLI_MAX_POINTS);
                return -1;
            }
            break;
        case CLI_OPT_PLOT:
            if (*val == '\0') {
                cli_error("--plot needs a file name");
                return -1;
            }
            a->plot = val;
            break;
        case CLI_OPT_ORDER:
            if (cli_parse_int(val, &a->order) != 0 || a->order < 1 ||
                a->order > PF_MAX_ORDER) {
                cli_error("--order: '%s' is not an integer in 1..%d",
                          cli_quote(q, sizeof q, val), PF_MAX_ORDER);
                return -1;
            }
            break;
        case CLI_OPT_APPROX:
            if (strcmp(val, "oustaloup") == 0) {
                a->approx = PF_APPROX_OUSTALOUP;
            } else if (strcmp(val, "refined") == 0) {
                a->approx = PF_APPROX_REFINED;
            } else {
                cli_error("--approx: unknown method '%s' (valid: oustaloup, "
                          "refined)", cli_quote(q, sizeof q, val));
                return -1;
            }
            break;
        case CLI_OPT_INPUT_MODEL:
            if (strcmp(val, "hold") == 0) {
                a->input_model = PF_INPUT_HOLD;
            } else if (strcmp(val, "linear") == 0) {
                a->input_model = PF_INPUT_LINEAR;
            } else {
                cli_error("--input-model: unknown model '%s' (valid: hold, "
                          "linear)", cli_quote(q, sizeof q, val));
                return -1;
            }
            break;
        case CLI_OPT_TSLOW:
            if (cli_parse_positive("--t-slow", val, &a->t_slow) != 0)
                return -1;
            break;
        case CLI_OPT_INPUT:
            if (*val == '\0') {
                cli_error("--input needs a file name");
                return -1;
            }
            a->input = val;
            break;
        case CLI_OPT_FORMAT:
            a->format = val;
            break;
        case CLI_OPT_NAME:
            a->name = val;
            break;
        default:
            if (o->seen == CLI_OPT_SET) {
                cli_set s;
                if (cli_parse_set(val, &s) != 0)
                    return -1;
                if (a->set_mask & (1u << s.id)) {
                    cli_error("--set %s given more than once",
                              pf_param_name(s.id));
                    return -1;
                }
                a->set_mask |= 1u << s.id;
                a->set_val[s.id] = s.value;
            } else if (cli_parse_effect(val, &a->fx) != 0) {
                return -1;
            }
            break;
        }
    }
    return 0;
}

static int opts_build(const cli_opts *a, const cli_command *cmd, cli_run *run)
{
    int id;

    if (!(a->seen & CLI_OPT_CONFIG)) {
        cli_error("%s: missing --config (p, dd, id or pid)", cmd->name);
        return -1;
    }
    if (!(a->seen & CLI_OPT_FS)) {
        cli_error("%s: missing --fs HZ", cmd->name);
        return -1;
    }
    if ((cmd->allowed & CLI_OPT_DURATION) && !(a->seen & CLI_OPT_DURATION)) {
        cli_error("%s: missing --duration S", cmd->name);
        return -1;
    }
    if (!(a->duration * a->fs <= CLI_MAX_SAMPLES)) {
        cli_error("--duration %.10g at --fs %.10g is %.6g samples; at most "
                  "%.0f are allowed", a->duration, a->fs, a->duration * a->fs,
                  CLI_MAX_SAMPLES);
        return -1;
    }
    if (a->arith == PF_ARITH_Q15) {
        if (!(a->seen & CLI_OPT_IN_FS) || !(a->seen & CLI_OPT_OUT_FS)) {
            cli_error("--arith q15 needs --in-fs and --out-fs (the physical "
                      "full scales of e and p_c)");
            return -1;
        }
    } else if (a->seen & (CLI_OPT_IN_FS | CLI_OPT_OUT_FS)) {
        cli_error("%s is allowed only with --arith q15",
                  (a->seen & CLI_OPT_IN_FS) ? "--in-fs" : "--out-fs");
        return -1;
    }

    memset(run, 0, sizeof *run);
    pf_params_default(&run->p, a->topology);
    for (id = 0; id < (int)PF_P_CONFIG; id++) {
        if (!(a->set_mask & (1u << id)))
            continue;
        /* A parameter the configuration ignores would silently change
         * nothing; that is almost always a mistaken name or config. */
        if (!pf_param_used(a->topology, (pf_param_id)id)) {
            cli_error("--set %s: configuration %s does not use '%s'",
                      pf_param_name((pf_param_id)id),
                      pf_topology_name(a->topology),
                      pf_param_name((pf_param_id)id));
            return -1;
        }
        if (pf_params_set(&run->p, (pf_param_id)id, a->set_val[id]) != PF_OK) {
            cli_error("--set %s: not a settable parameter",
                      pf_param_name((pf_param_id)id));
            return -1;
        }
    }
    run->fx = a->fx.fx;
    /* Zero fields ask the library for its defaults, which it derives from
     * fs and t_slow when it resolves the options. */
    run->opt.fs = a->fs;
    run->opt.wb = a->wb;
    run->opt.wh = a->wh;
    run->opt.order = a->order;
    run->opt.approx = a->approx;
    run->opt.t_slow = a->t_slow;
    run->opt.input = a->input_model;
    run->arith = a->arith;
    run->in_fs = a->in_fs;
    run->out_fs = a->out_fs;
    run->duration = a->duration;
    return 0;
}

int cli_opts_read(int argc, char **argv, const cli_command *cmd, cli_opts *a,
                  cli_run *run)
{
    int rc;
    memset(a, 0, sizeof *a);
    a->topology = PF_TOPO_COUNT; /* --config is required */
    rc = opts_parse(argc, argv, cmd, a);
    if (rc != 0)
        return rc;
    return opts_build(a, cmd, run);
}
