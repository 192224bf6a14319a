/* SPDX-License-Identifier: MIT */
/*
 * pneufracd: start-up, signals and shutdown.
 * Exit status: 0 clean stop, 1 run-time failure, 2 bad arguments or config.
 */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "pfd_cli.h"
#include "pfd_commit.h"
#include "pfd_log.h"
#include "pfd_loop.h"
#include "pfd_overrun.h"
#include "pfd_rate.h"
#include "pfd_regmap.h"
#include "pfd_server.h"
#include "pfd_start.h"
#include "pfd_tls.h"

/* What the main thread remembers between two housekeeping rounds. */
typedef struct watch {
    uint16_t flags[PFD_MAX_INSTANCES];
    pfd_overrun_report overruns;
} watch;

static int64_t mono_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

/* Log watchdog trips/recoveries, from the snapshots, and report overruns
 * (pfd_overrun.h); @p final: the loop has stopped, report what is left. */
static void housekeeping(pfd_daemon *d, watch *w, int final)
{
    int i;
    for (i = 0; i < d->n; i++) {
        pfd_inst *in = d->inst[i];
        pfd_snap s;
        pthread_mutex_lock(&d->regs_mx);
        s = *(const pfd_snap *)pfd_tbuf_latest(&in->out_tb);
        pthread_mutex_unlock(&d->regs_mx);
        if ((s.flags ^ w->flags[i]) & PFD_SNAP_TRIPPED)
            pfd_log(PFD_LOG_WARN,
                    (s.flags & PFD_SNAP_TRIPPED) ? "watchdog-tripped" : "watchdog-recovered",
                    "unit=%d samples=%lu", in->unit, (unsigned long)s.samples);
        w->flags[i] = s.flags;
        pfd_overrun_look(&w->overruns, i, in->unit, s.overruns,
                         pfd_overrun_take(&in->late_max_ns));
    }
    pfd_overrun_emit(&w->overruns, d->n, mono_ns(), final);
}

/* Refuse to start instances that the loop could not run within the
 * budget, naming the costliest; in lockstep the client's ticks set the
 * pace, and the load is only logged. @return 0, or -1 after a fatal
 * message. */
static int check_load(const pfd_daemon *d)
{
    const pfd_inst *worst = d->inst[0];
    pfd_load l;
    double load;
    int i;

    pfd_loop_load(d, NULL, 0.0, NULL, &l);
    load = pfd_load_total(&l);
    pfd_log(PFD_LOG_INFO, "loop-load", "util_pct=%.2f load_pct=%.2f budget_pct=%d wake_us=%.2f",
            100.0 * l.util, 100.0 * load, d->set.loop_budget, d->wake_ns / 1000.0);
    if (d->set.external_clock || load <= d->set.loop_budget / 100.0)
        return 0;
    for (i = 1; i < d->n; i++)
        if (d->inst[i]->committed.fs * pfd_rate_exchange_ns(&d->inst[i]->rate) >
            worst->committed.fs * pfd_rate_exchange_ns(&worst->rate))
            worst = d->inst[i];
    pfd_fatal("the instances need %.0f %% of one core, over --loop-budget %d %%; the "
              "costliest is unit %d: %.9g Hz x %u substeps at %.0f ns a step, and %.1f us "
              "a wake-up (lower fs, substeps or the number of instances)", 100.0 * load,
              d->set.loop_budget, worst->unit, worst->committed.fs, worst->rate.k,
              worst->rate.step_ns, d->wake_ns / 1000.0);
    return -1;
}

/* The instances of @p c into @p d. @return 0, or -1 after a fatal message. */
static int add_instances(pfd_daemon *d, const pfd_config *c, const char *path)
{
    int i;
    for (i = 0; i < c->n; i++) {
        pfd_fail why;
        if (pfd_inst_add(d, &c->inst[i], &why) != 0) {
            char desc[700];
            pfd_start_describe(desc, sizeof desc, path, &c->inst[i], &why);
            pfd_fatal("%s", desc);
            return -1;
        }
    }
    pfd_log(PFD_LOG_INFO, "start", "version=%d.%d.%d instances=%d config=%s persistence=%s",
            PFD_VERSION_MAJOR, PFD_VERSION_MINOR, PFD_VERSION_PATCH, d->n,
            path ? path : "none", path ? "on" : "off");
    for (i = 0; i < d->n; i++) {
        const pfd_iparams *ip = &d->inst[i]->committed;
        const pfd_rate *r = &d->inst[i]->rate;
        pfd_log(PFD_LOG_INFO, "instance",
                "unit=%d config=%s arith=%s fs=%.9g substeps=%u internal_fs=%.9g step_ns=%.0f",
                d->inst[i]->unit, pf_topology_name(ip->p.topology),
                pfd_arith_name(ip->arith), ip->fs, r->k, r->internal_fs, r->step_ns);
    }
    return check_load(d);
}

/* Until SIGINT, SIGTERM or --run-for; housekeeping every 200 ms. */
static void serve(pfd_daemon *d, watch *w, const sigset_t *sigs, double run_for)
{
    struct timespec t0;

    clock_gettime(CLOCK_MONOTONIC, &t0);
    for (;;) {
        struct timespec to = {0, 200000000L}, now;
        int sig = sigtimedwait(sigs, NULL, &to);
        if (sig == SIGINT || sig == SIGTERM) {
            pfd_log(PFD_LOG_INFO, "stopping", "signal=%s", sig == SIGINT ? "SIGINT" : "SIGTERM");
            return;
        }
        if (sig == SIGHUP)
            pfd_log(PFD_LOG_INFO, "sighup", "action=none");
        housekeeping(d, w, 0);
        clock_gettime(CLOCK_MONOTONIC, &now);
        if (run_for > 0 &&
            (double)(now.tv_sec - t0.tv_sec) + 1e-9 * (double)(now.tv_nsec - t0.tv_nsec) >=
                run_for) {
            pfd_log(PFD_LOG_INFO, "stopping", "reason=run-for");
            return;
        }
    }
}

/* The TLS context, built before the loop starts: a certificate, key or CA
 * that exists but cannot be used (a directory, a file that is not PEM) is
 * then a usage error reported before anything runs, like a missing one
 * (pfd_settings_check). pfd_server_start takes it over (pfd_server.h).
 * @return 0, or -1 (reported). */
static int tls_context(pfd_daemon *d)
{
    char err[600];

    if (d->set.tls_listen.addr[0] == '\0')
        return 0;
    d->server.tls = pfd_tls_new(&d->set, err, sizeof err);
    if (d->server.tls == NULL) {
        pfd_fatal("%s", err);
        return -1;
    }
    return 0;
}

/* Start the daemon on @p c, serve, stop. @p fallback: @p c is the
 * defaults, standing in for a file that could not be used. @return the
 * exit status. */
static int run(const pfd_cli *a, const pfd_config *c, int fallback)
{
    pfd_daemon *d = malloc(sizeof *d);
    pfd_settings set = c->set;
    sigset_t sigs;
    watch *w = calloc(1, sizeof *w); /* nothing seen yet */
    char err[600];
    int rc = 0;

    /* The file's [daemon] section (in a fallback: the defaults with the
     * security settings at their fallback values), then the command line. */
    if (fallback)
        pfd_settings_fallback(&set);
    pfd_settings_copy(&set, &a->set, a->given);
    if (d != NULL && w != NULL && pfd_settings_check(&set, err, sizeof err) != 0) {
        pfd_fatal("%s", err);
        free(w);
        free(d);
        return PFD_EXIT_USAGE;
    }
    if (d == NULL || w == NULL || pfd_daemon_init(d, &set) != 0) {
        pfd_fatal("out of memory");
        free(w);
        free(d);
        return 1;
    }
    /* Never rewrite a file that could not be used. */
    d->config_path = fallback ? NULL : a->run.config;
    d->config_file = c;
    d->wake_ns = pfd_rate_measure_wakeup();
    if (add_instances(d, c, a->run.config) != 0 || tls_context(d) != 0) {
        pfd_daemon_free(d);
        free(w);
        free(d);
        return PFD_EXIT_USAGE;
    }

    /* Every thread inherits this mask; main alone takes the signals. A
     * write past RLIMIT_FSIZE (ulimit -f) must fail with EFBIG, so that a
     * commit is answered "not persisted", instead of killing the daemon. */
    signal(SIGPIPE, SIG_IGN);
    signal(SIGXFSZ, SIG_IGN);
    sigemptyset(&sigs);
    sigaddset(&sigs, SIGINT);
    sigaddset(&sigs, SIGTERM);
    sigaddset(&sigs, SIGHUP);
    pthread_sigmask(SIG_BLOCK, &sigs, NULL);

    if (pfd_loop_start(d) != 0) {
        rc = 1;
    } else if (pfd_server_start(d) != 0) {
        pfd_loop_stop(d);
        rc = 1;
    } else {
        pfd_overrun_init(&w->overruns, d->set.overrun_report_s, mono_ns());
        serve(d, w, &sigs, a->run.run_for);
        pfd_server_stop(d);
        pfd_loop_stop(d);
        housekeeping(d, w, 1);
        pfd_loop_log_stats(d);
        if (d->config_path != NULL && pfd_persist(d) != 0)
            rc = 1;
        pfd_log(PFD_LOG_INFO, "stopped", "status=%d", rc);
    }
    pfd_tls_free(d->server.tls); /* not started: pfd_server_stop did not free it */
    pfd_daemon_free(d);
    free(w);
    free(d);
    return rc;
}

int main(int argc, char **argv)
{
    pfd_cli a;
    pfd_config *c;
    char err[600];
    int rc;

    if (pfd_cli_parse(argc, argv, &a, err, sizeof err) != 0) {
        pfd_fatal("%s", err);
        return PFD_EXIT_USAGE;
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
    if (a.run.print_config)
        return pfd_start_print_default(&a.run);
    if (a.run.seal != NULL)
        return pfd_start_seal(a.run.seal);
    if (a.run.init != NULL)
        return pfd_start_init(&a.run, a.run.init);

    c = malloc(sizeof *c);
    if (c == NULL) {
        pfd_fatal("out of memory");
        return 1;
    }
    rc = pfd_start_config(&a.run, c);
    rc = rc < 0 ? PFD_EXIT_USAGE : run(&a, c, rc == 1);
    free(c);
    return rc;
}
