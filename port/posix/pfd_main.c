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

#include "pfd_cli.h"
#include "pfd_commit.h"
#include "pfd_config.h"
#include "pfd_log.h"
#include "pfd_loop.h"
#include "pfd_modbus.h"
#include "pfd_regmap.h"

#define EXIT_USAGE 2

static void default_instances(pfd_config *c, const pfd_run *run)
{
    int i;
    c->n = run->instances;
    for (i = 0; i < run->instances; i++) {
        pfd_config_inst_default(&c->inst[i], i + 1);
        pf_params_default(&c->inst[i].ip.p, (pf_config)run->controller);
        c->inst[i].ip.fs = run->fs;
        c->inst[i].ip.arith = run->arith;
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
    pfd_cli a;
    pfd_daemon *d = &daemon_state;
    pfd_settings set;
    sigset_t sigs;
    struct timespec t0;
    char err[600];
    uint16_t last_flags[PFD_MAX_INSTANCES] = {0};
    uint32_t last_over[PFD_MAX_INSTANCES] = {0};
    int i, rc = 0;

    if (pfd_cli_parse(argc, argv, &a, err, sizeof err) != 0) {
        pfd_fatal("%s", err);
        return EXIT_USAGE;
    }
    if (a.run.help) {
        pfd_cli_help(stdout);
        return fflush(stdout) == 0 ? 0 : 1;
    }
    if (a.run.version) {
        printf("pneufracd %d.%d.%d (register map %d)\n", PFD_VERSION_MAJOR,
               PFD_VERSION_MINOR, PFD_VERSION_PATCH, PFD_REGMAP_VERSION);
        return fflush(stdout) == 0 ? 0 : 1;
    }
    if (a.run.verbose)
        pfd_log_set_level(PFD_LOG_DEBUG);
    if (a.run.print_map) {
        pfd_regmap_print_md(stdout);
        return fflush(stdout) == 0 ? 0 : 1;
    }
    if (a.run.print_config) {
        memset(&file_cfg, 0, sizeof file_cfg);
        pfd_settings_default(&file_cfg.set);
        default_instances(&file_cfg, &a.run);
        return pfd_config_print(&file_cfg, stdout) == 0 && fflush(stdout) == 0 ? 0 : 1;
    }
    if (a.run.seal != NULL)
        return seal(a.run.seal);

    /* Configuration: file (or defaults), then the command line. */
    memset(&file_cfg, 0, sizeof file_cfg);
    pfd_settings_default(&file_cfg.set);
    if (a.run.config != NULL) {
        if (pfd_config_load(a.run.config, &file_cfg, 1, err, sizeof err) != 0 ||
            design_all(a.run.config, &file_cfg, err, sizeof err) != 0) {
            if (!a.run.fallback) {
                pfd_fatal("%s", err);
                return EXIT_USAGE;
            }
            move_aside(a.run.config);
            pfd_log(PFD_LOG_WARN, "config-fallback", "using=defaults error=\"%s\"", err);
            memset(&file_cfg, 0, sizeof file_cfg);
            pfd_settings_default(&file_cfg.set);
            default_instances(&file_cfg, &a.run);
        }
    } else {
        default_instances(&file_cfg, &a.run);
    }
    set = file_cfg.set;
    pfd_settings_copy(&set, &a.set, a.given);

    if (pfd_daemon_init(d, &set) != 0) {
        pfd_fatal("out of memory");
        return 1;
    }
    d->config_path = a.run.config;
    d->config_file = &file_cfg;
    for (i = 0; i < file_cfg.n; i++) {
        pfd_fail why;
        if (pfd_inst_add(d, &file_cfg.inst[i], &why) != 0) {
            char desc[200];
            describe_fail(desc, sizeof desc, &why);
            if (a.run.config != NULL)
                pfd_fatal("config %s:%d: [instance %d]: %s", a.run.config,
                          file_cfg.inst[i].line, file_cfg.inst[i].unit, desc);
            else
                pfd_fatal("instance %d: %s", file_cfg.inst[i].unit, desc);
            pfd_daemon_free(d);
            return EXIT_USAGE;
        }
    }
    pfd_log(PFD_LOG_INFO, "start", "version=%d.%d.%d instances=%d config=%s persistence=%s",
            PFD_VERSION_MAJOR, PFD_VERSION_MINOR, PFD_VERSION_PATCH, d->n,
            a.run.config ? a.run.config : "none", a.run.config ? "on" : "off");
    for (i = 0; i < d->n; i++) {
        const pfd_iparams *ip = &d->inst[i]->committed;
        pfd_log(PFD_LOG_INFO, "instance", "unit=%d config=%s arith=%s fs=%.9g",
                d->inst[i]->unit, pf_config_name(ip->p.config),
                pfd_arith_name(ip->arith), ip->fs);
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
        if (a.run.run_for > 0 &&
            (double)(now.tv_sec - t0.tv_sec) + 1e-9 * (double)(now.tv_nsec - t0.tv_nsec) >=
                a.run.run_for) {
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
