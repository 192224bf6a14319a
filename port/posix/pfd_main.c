/* SPDX-License-Identifier: MIT */
/*
 * pneufracd: command line, start-up, signals and shutdown.
 * Exit status: 0 clean stop, 1 run-time failure, 2 bad arguments or config.
 */
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "pfd_allow.h"
#include "pfd_commit.h"
#include "pfd_config.h"
#include "pfd_log.h"
#include "pfd_loop.h"
#include "pfd_modbus.h"
#include "pfd_regmap.h"

#define EXIT_USAGE 2

static void usage(FILE *f)
{
    fputs(
"usage: pneufracd [options]\n"
"\n"
"Runs the paper's controllers in real time and serves them over Modbus TCP.\n"
"With no options: one instance, unit id 1, Example 6 (FrDD) at 1 kHz in\n"
"float, on 127.0.0.1:1502. Register map: docs/register-map.md.\n"
"\n"
"  --listen ADDR:PORT       IPv4 address and port (default 127.0.0.1:1502;\n"
"                           port 0 picks a free one, logged as msg=listening)\n"
"  --config FILE            instances and settings (docs/pneufracd.md); commits\n"
"                           and the state at shutdown are written back to it\n"
"  --config-fallback-defaults  run the defaults (and log why) if FILE is\n"
"                           missing, corrupt or invalid (a set that cannot\n"
"                           be designed included); it is renamed to\n"
"                           FILE.corrupt (FILE.corrupt.N if that exists)\n"
"  --clock internal|external   external: the tick register advances samples\n"
"  --allow CIDR[,CIDR...]   client networks allowed to connect (default\n"
"                           127.0.0.0/8)\n"
"  --max-clients N          simultaneous clients, 1..256 (default 16)\n"
"  --read-only              refuse every write (exception 01)\n"
"  --param-lock             lock staged parameters and commit for this run\n"
"  --instances N            N default instances, unit ids 1..N (no --config)\n"
"  --controller p|dd|id|pid  configuration of those instances (default dd)\n"
"  --fs HZ                  their sample rate, 1..50000 (default 1000)\n"
"  --arith float|q15        their arithmetic (default float)\n"
"  --rt-priority N          SCHED_FIFO priority of the loop, 0 = none (default 80)\n"
"  --no-mlock               do not mlockall()\n"
"  --byte-timeout-ms N      drop a client that stalls this long mid-frame (100)\n"
"  --idle-timeout-s N       drop a client silent this long, 0 = never (300)\n"
"  --run-for S              stop by itself after S seconds (tests)\n"
"  --verbose                also log debug lines (client connects and drops)\n"
"\n"
"  --print-register-map     print the register table (Markdown) and exit\n"
"  --print-default-config   print a config file for the defaults and exit\n"
"  --seal-config FILE       check FILE and rewrite its checksum, then exit\n"
"  --version, --help\n", f);
}

static int parse_num(const char *opt, const char *v, double lo, double hi, double *out)
{
    char *e;
    double x;
    errno = 0;
    x = strtod(v, &e);
    if (errno != 0 || e == v || *e != '\0' || !(x >= lo && x <= hi)) {
        pfd_fatal("%s: '%s' is not a number in %g..%g", opt, v, lo, hi);
        return -1;
    }
    *out = x;
    return 0;
}

static int parse_int(const char *opt, const char *v, long lo, long hi, int *out)
{
    char *e;
    long x;
    errno = 0;
    x = strtol(v, &e, 10);
    if (errno != 0 || e == v || *e != '\0' || x < lo || x > hi) {
        pfd_fatal("%s: '%s' is not an integer in %ld..%ld", opt, v, lo, hi);
        return -1;
    }
    *out = (int)x;
    return 0;
}

typedef struct cli {
    const char *config, *seal;
    int fallback, print_map, print_config;
    double run_for;
    int verbose;
    /* daemon settings given on the command line override the file */
    pfd_settings set;
    unsigned set_mask;
    /* default instances (without --config) */
    int instances, have_inst_opts;
    pf_config controller;
    double fs;
    int arith;
} cli;

static int parse_args(int argc, char **argv, cli *a)
{
    int i;

    memset(a, 0, sizeof *a);
    pfd_settings_default(&a->set);
    a->instances = 1;
    a->controller = PF_CFG_DD;
    a->fs = 1000.0;
    a->arith = PFD_ARITH_FLOAT;
    for (i = 1; i < argc; i++) {
        const char *o = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        int takes = 1;

#define NEED_VALUE()                                                           \
    do {                                                                       \
        if (v == NULL) {                                                       \
            pfd_fatal("%s needs a value", o);                                  \
            return -1;                                                         \
        }                                                                      \
    } while (0)

        if (!strcmp(o, "--help") || !strcmp(o, "-h")) {
            usage(stdout);
            exit(0);
        } else if (!strcmp(o, "--version")) {
            printf("pneufracd %d.%d.%d (register map %d)\n", PFD_VERSION_MAJOR,
                   PFD_VERSION_MINOR, PFD_VERSION_PATCH, PFD_REGMAP_VERSION);
            exit(0);
        } else if (!strcmp(o, "--print-register-map")) {
            a->print_map = 1;
            takes = 0;
        } else if (!strcmp(o, "--print-default-config")) {
            a->print_config = 1;
            takes = 0;
        } else if (!strcmp(o, "--seal-config")) {
            NEED_VALUE();
            a->seal = v;
        } else if (!strcmp(o, "--config")) {
            NEED_VALUE();
            a->config = v;
        } else if (!strcmp(o, "--config-fallback-defaults")) {
            a->fallback = 1;
            takes = 0;
        } else if (!strcmp(o, "--listen")) {
            NEED_VALUE();
            if (pfd_parse_listen(v, &a->set) != 0) {
                pfd_fatal("--listen: '%s' is not IPV4ADDR:PORT (e.g. 127.0.0.1:1502)", v);
                return -1;
            }
            a->set_mask |= PFD_K_LISTEN;
        } else if (!strcmp(o, "--clock")) {
            NEED_VALUE();
            if (!strcmp(v, "internal") || !strcmp(v, "external")) {
                a->set.external_clock = !strcmp(v, "external");
            } else {
                pfd_fatal("--clock: '%s' is not internal or external", v);
                return -1;
            }
            a->set_mask |= PFD_K_CLOCK;
        } else if (!strcmp(o, "--allow")) {
            char err[200];
            pfd_allow al;
            NEED_VALUE();
            if (strlen(v) >= sizeof a->set.allow ||
                pfd_allow_parse(v, &al, err, sizeof err) != 0) {
                pfd_fatal("--%s", strlen(v) >= sizeof a->set.allow ? "allow: list too long" : err);
                return -1;
            }
            strcpy(a->set.allow, v);
            a->set_mask |= PFD_K_ALLOW;
        } else if (!strcmp(o, "--max-clients")) {
            NEED_VALUE();
            if (parse_int(o, v, 1, 256, &a->set.max_clients) != 0)
                return -1;
            a->set_mask |= PFD_K_MAX_CLIENTS;
        } else if (!strcmp(o, "--read-only")) {
            a->set.read_only = 1;
            a->set_mask |= PFD_K_READ_ONLY;
            takes = 0;
        } else if (!strcmp(o, "--param-lock")) {
            a->set.param_lock = 1;
            a->set_mask |= PFD_K_PARAM_LOCK;
            takes = 0;
        } else if (!strcmp(o, "--rt-priority")) {
            NEED_VALUE();
            if (parse_int(o, v, 0, 99, &a->set.rt_priority) != 0)
                return -1;
            a->set_mask |= PFD_K_RT_PRIORITY;
        } else if (!strcmp(o, "--no-mlock")) {
            a->set.mlock = 0;
            a->set_mask |= PFD_K_MLOCK;
            takes = 0;
        } else if (!strcmp(o, "--byte-timeout-ms")) {
            NEED_VALUE();
            if (parse_int(o, v, 1, 10000, &a->set.byte_timeout_ms) != 0)
                return -1;
            a->set_mask |= PFD_K_BYTE_TIMEOUT;
        } else if (!strcmp(o, "--idle-timeout-s")) {
            NEED_VALUE();
            if (parse_int(o, v, 0, 86400, &a->set.idle_timeout_s) != 0)
                return -1;
            a->set_mask |= PFD_K_IDLE_TIMEOUT;
        } else if (!strcmp(o, "--instances")) {
            NEED_VALUE();
            if (parse_int(o, v, 1, PFD_MAX_INSTANCES, &a->instances) != 0)
                return -1;
            a->have_inst_opts = 1;
        } else if (!strcmp(o, "--controller")) {
            NEED_VALUE();
            a->controller = pf_config_lookup(v);
            if (a->controller == PF_CFG_COUNT) {
                pfd_fatal("--controller: '%s' is not p, dd, id or pid", v);
                return -1;
            }
            a->have_inst_opts = 1;
        } else if (!strcmp(o, "--fs")) {
            NEED_VALUE();
            if (parse_num(o, v, PFD_FS_MIN, PFD_FS_MAX, &a->fs) != 0)
                return -1;
            a->have_inst_opts = 1;
        } else if (!strcmp(o, "--arith")) {
            NEED_VALUE();
            if (!strcmp(v, "float") || !strcmp(v, "q15")) {
                a->arith = !strcmp(v, "q15") ? PFD_ARITH_Q15 : PFD_ARITH_FLOAT;
            } else {
                pfd_fatal("--arith: '%s' is not float or q15", v);
                return -1;
            }
            a->have_inst_opts = 1;
        } else if (!strcmp(o, "--run-for")) {
            NEED_VALUE();
            if (parse_num(o, v, 0.001, 1e7, &a->run_for) != 0)
                return -1;
        } else if (!strcmp(o, "--verbose")) {
            a->verbose = 1;
            takes = 0;
        } else {
            pfd_fatal("unknown option '%s' (see pneufracd --help)", o);
            return -1;
        }
#undef NEED_VALUE
        i += takes;
    }
    if (a->config != NULL && a->have_inst_opts) {
        pfd_fatal("--instances, --controller, --fs and --arith describe the "
                  "default instances; with --config set them in the file");
        return -1;
    }
    if (a->fallback && a->config == NULL) {
        pfd_fatal("--config-fallback-defaults needs --config FILE");
        return -1;
    }
    return 0;
}

static void apply_overrides(pfd_settings *s, const cli *a)
{
    const pfd_settings *o = &a->set;
    unsigned m = a->set_mask;
    if (m & PFD_K_LISTEN) {
        strcpy(s->listen_addr, o->listen_addr);
        s->listen_port = o->listen_port;
    }
    if (m & PFD_K_CLOCK)
        s->external_clock = o->external_clock;
    if (m & PFD_K_ALLOW)
        strcpy(s->allow, o->allow);
    if (m & PFD_K_MAX_CLIENTS)
        s->max_clients = o->max_clients;
    if (m & PFD_K_READ_ONLY)
        s->read_only = o->read_only;
    if (m & PFD_K_PARAM_LOCK)
        s->param_lock = o->param_lock;
    if (m & PFD_K_RT_PRIORITY)
        s->rt_priority = o->rt_priority;
    if (m & PFD_K_MLOCK)
        s->mlock = o->mlock;
    if (m & PFD_K_BYTE_TIMEOUT)
        s->byte_timeout_ms = o->byte_timeout_ms;
    if (m & PFD_K_IDLE_TIMEOUT)
        s->idle_timeout_s = o->idle_timeout_s;
}

static void default_instances(pfd_config *c, const cli *a)
{
    int i;
    c->n = a->instances;
    for (i = 0; i < a->instances; i++) {
        pfd_config_inst_default(&c->inst[i], i + 1);
        pf_params_default(&c->inst[i].ip.p, a->controller);
        c->inst[i].ip.fs = a->fs;
        c->inst[i].ip.arith = a->arith;
    }
}

static void describe_fail(char *buf, size_t n, const pfd_fail *why)
{
    if (why->st == PF_E_NULL)
        snprintf(buf, n, "out of memory");
    else if (why->st == PF_E_SCALE)
        snprintf(buf, n, "q15: a coefficient does not fit (change in_fs/out_fs)");
    else if (why->param != (int)PF_P_COUNT && why->st == PFD_E_DAEMON)
        snprintf(buf, n, "invalid parameter '%s' (out of range)", pfd_param_name(why->param));
    else if (why->param != (int)PF_P_COUNT)
        /* pf_status_str() would only say "invalid parameter" again. */
        snprintf(buf, n, "invalid parameter '%s'", pfd_param_name(why->param));
    else
        snprintf(buf, n, "%s", pf_status_str(why->st));
}

/* Design every instance of @p c, as pfd_inst_add() will: a file that
 * parses but cannot be designed is as unusable as a corrupt one, and must
 * be found out before the daemon commits to it (or seals it).
 * @return 0, or -1 with "config FILE:LINE: [instance U]: why" in @p err. */
static int design_all(const char *path, const pfd_config *c, char *err, size_t n)
{
    static pf_ctrl_design scratch;
    static pfd_slot slot;
    int i;

    for (i = 0; i < c->n; i++) {
        pfd_fail why;
        if (pfd_slot_build(&slot, &c->inst[i].ip, &scratch, &why) != 0) {
            char d[200];
            describe_fail(d, sizeof d, &why);
            snprintf(err, n, "config %s:%d: [instance %d]: %s", path, c->inst[i].line,
                     c->inst[i].unit, d);
            return -1;
        }
    }
    return 0;
}

/* --seal-config: accept a hand-edited file once it parses and designs. */
static int seal(const char *path)
{
    static pfd_config c;
    char err[600];

    if (pfd_config_load(path, &c, 0, err, sizeof err) != 0 ||
        design_all(path, &c, err, sizeof err) != 0) {
        pfd_fatal("%s", err);
        return EXIT_USAGE;
    }
    if (pfd_config_write(path, &c, err, sizeof err) != 0) {
        pfd_fatal("%s", err);
        return 1;
    }
    fprintf(stderr, "pneufracd: %s: sealed (%d instance%s)\n", path, c.n,
            c.n == 1 ? "" : "s");
    return 0;
}

/* --config-fallback-defaults: move an unusable FILE aside, to FILE.corrupt,
 * or FILE.corrupt.N if that exists already: an earlier bad file may be
 * the one someone still wants to look at. */
static void move_aside(const char *path)
{
    char aside[4200];
    int k;

    if (access(path, F_OK) != 0)
        return;
    for (k = 0; k < 1000; k++) {
        if (k == 0)
            snprintf(aside, sizeof aside, "%s.corrupt", path);
        else
            snprintf(aside, sizeof aside, "%s.corrupt.%d", path, k);
        if (access(aside, F_OK) != 0)
            break;
    }
    if (k < 1000 && rename(path, aside) == 0)
        pfd_log(PFD_LOG_WARN, "config-fallback", "moved=%s", aside);
    else
        pfd_log(PFD_LOG_WARN, "config-fallback", "moved=none error=\"cannot move %s aside\"",
                path);
}

static pfd_config file_cfg; /* as read: persistence writes its [daemon] back */
static pfd_daemon daemon_state;

/* Log watchdog trips/recoveries and new overruns, from the snapshots. */
static void housekeeping(pfd_daemon *d, uint16_t *last_flags, uint32_t *last_over)
{
    int i;
    for (i = 0; i < d->n; i++) {
        pfd_inst *in = d->inst[i];
        pfd_snap s;
        pthread_mutex_lock(&d->regs_mx);
        s = *(const pfd_snap *)pfd_tbuf_latest(&in->out_tb);
        pthread_mutex_unlock(&d->regs_mx);
        if ((s.flags ^ last_flags[i]) & PFD_SNAP_TRIPPED)
            pfd_log(PFD_LOG_WARN,
                    (s.flags & PFD_SNAP_TRIPPED) ? "watchdog-tripped" : "watchdog-recovered",
                    "unit=%d samples=%lu", in->unit, (unsigned long)s.samples);
        if (s.overruns > last_over[i])
            pfd_log(PFD_LOG_WARN, "overruns", "unit=%d overruns=%lu jitter_max_us=%lu",
                    in->unit, (unsigned long)s.overruns, (unsigned long)s.jit_max_us);
        last_flags[i] = s.flags;
        last_over[i] = s.overruns;
    }
}

int main(int argc, char **argv)
{
    cli a;
    pfd_daemon *d = &daemon_state;
    pfd_settings set;
    sigset_t sigs;
    struct timespec t0;
    char err[600];
    uint16_t last_flags[PFD_MAX_INSTANCES] = {0};
    uint32_t last_over[PFD_MAX_INSTANCES] = {0};
    int i, rc = 0;

    if (parse_args(argc, argv, &a) != 0)
        return EXIT_USAGE;
    if (a.verbose)
        pfd_log_set_level(PFD_LOG_DEBUG);
    if (a.print_map) {
        pfd_regmap_print_md(stdout);
        return fflush(stdout) == 0 ? 0 : 1;
    }
    if (a.print_config) {
        memset(&file_cfg, 0, sizeof file_cfg);
        pfd_settings_default(&file_cfg.set);
        default_instances(&file_cfg, &a);
        return pfd_config_print(&file_cfg, stdout) == 0 && fflush(stdout) == 0 ? 0 : 1;
    }
    if (a.seal != NULL)
        return seal(a.seal);

    /* Configuration: file (or defaults), then the command line. */
    memset(&file_cfg, 0, sizeof file_cfg);
    pfd_settings_default(&file_cfg.set);
    if (a.config != NULL) {
        if (pfd_config_load(a.config, &file_cfg, 1, err, sizeof err) != 0 ||
            design_all(a.config, &file_cfg, err, sizeof err) != 0) {
            if (!a.fallback) {
                pfd_fatal("%s", err);
                return EXIT_USAGE;
            }
            move_aside(a.config);
            pfd_log(PFD_LOG_WARN, "config-fallback", "using=defaults error=\"%s\"", err);
            memset(&file_cfg, 0, sizeof file_cfg);
            pfd_settings_default(&file_cfg.set);
            default_instances(&file_cfg, &a);
        }
    } else {
        default_instances(&file_cfg, &a);
    }
    set = file_cfg.set;
    apply_overrides(&set, &a);

    if (pfd_daemon_init(d, &set) != 0) {
        pfd_fatal("out of memory");
        return 1;
    }
    d->config_path = a.config;
    d->config_file = &file_cfg;
    for (i = 0; i < file_cfg.n; i++) {
        pfd_fail why;
        if (pfd_inst_add(d, &file_cfg.inst[i], &why) != 0) {
            char desc[200];
            describe_fail(desc, sizeof desc, &why);
            if (a.config != NULL)
                pfd_fatal("config %s:%d: [instance %d]: %s", a.config,
                          file_cfg.inst[i].line, file_cfg.inst[i].unit, desc);
            else
                pfd_fatal("instance %d: %s", file_cfg.inst[i].unit, desc);
            pfd_daemon_free(d);
            return EXIT_USAGE;
        }
    }
    pfd_log(PFD_LOG_INFO, "start", "version=%d.%d.%d instances=%d config=%s persistence=%s",
            PFD_VERSION_MAJOR, PFD_VERSION_MINOR, PFD_VERSION_PATCH, d->n,
            a.config ? a.config : "none", a.config ? "on" : "off");
    for (i = 0; i < d->n; i++) {
        const pfd_iparams *ip = &d->inst[i]->committed;
        pfd_log(PFD_LOG_INFO, "instance", "unit=%d config=%s arith=%s fs=%.9g",
                d->inst[i]->unit, pf_config_name(ip->p.config),
                ip->arith == PFD_ARITH_Q15 ? "q15" : "float", ip->fs);
    }

    /* Every thread inherits this mask; main alone takes the signals. */
    signal(SIGPIPE, SIG_IGN);
    sigemptyset(&sigs);
    sigaddset(&sigs, SIGINT);
    sigaddset(&sigs, SIGTERM);
    sigaddset(&sigs, SIGHUP);
    pthread_sigmask(SIG_BLOCK, &sigs, NULL);

    if (pfd_loop_start(d) != 0) {
        pfd_daemon_free(d);
        return 1;
    }
    if (pfd_server_start(d) != 0) {
        pfd_loop_stop(d);
        pfd_daemon_free(d);
        return 1;
    }

    clock_gettime(CLOCK_MONOTONIC, &t0);
    for (;;) {
        struct timespec to = {0, 200000000L}, now;
        int sig = sigtimedwait(&sigs, NULL, &to);
        if (sig == SIGINT || sig == SIGTERM) {
            pfd_log(PFD_LOG_INFO, "stopping", "signal=%s", sig == SIGINT ? "SIGINT" : "SIGTERM");
            break;
        }
        if (sig == SIGHUP)
            pfd_log(PFD_LOG_INFO, "sighup", "action=none");
        housekeeping(d, last_flags, last_over);
        clock_gettime(CLOCK_MONOTONIC, &now);
        if (a.run_for > 0 &&
            (double)(now.tv_sec - t0.tv_sec) + 1e-9 * (double)(now.tv_nsec - t0.tv_nsec) >= a.run_for) {
            pfd_log(PFD_LOG_INFO, "stopping", "reason=run-for");
            break;
        }
    }

    pfd_server_stop(d);
    pfd_loop_stop(d);
    pfd_loop_log_stats(d);
    if (d->config_path != NULL && pfd_persist(d) != 0)
        rc = 1;
    pfd_daemon_free(d);
    pfd_log(PFD_LOG_INFO, "stopped", "status=%d", rc);
    return rc;
}
