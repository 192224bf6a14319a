/* SPDX-License-Identifier: MIT */
#include "pfd_start.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pfd_log.h"
#include "pfd_plausible.h"

static void default_instances(pfd_config *c, const pfd_run *run)
{
    int i;
    memset(c, 0, sizeof *c);
    pfd_settings_default(&c->set);
    c->n = run->instances;
    for (i = 0; i < run->instances; i++) {
        pfd_config_inst_default(&c->inst[i], i + 1);
        pf_params_default(&c->inst[i].ip.p, (pf_topology)run->controller);
        c->inst[i].ip.fs = run->fs;
        c->inst[i].ip.substeps = (unsigned)run->substeps;
        c->inst[i].ip.arith = run->arith;
    }
}

void pfd_start_describe(char *buf, size_t n, const char *path,
                        const pfd_config_inst *ci, const pfd_fail *why)
{
    char d[200];

    if (why->st == PF_E_NULL)
        snprintf(d, sizeof d, "out of memory");
    else if (why->st == PFD_E_UNSTABLE && why->param != (int)PF_P_COUNT)
        snprintf(d, sizeof d, "the sampled loop is unstable (its output would grow without "
                 "bound); '%s' makes it so", pfd_param_name(why->param));
    else if (why->st == PFD_E_UNSTABLE)
        snprintf(d, sizeof d, "the sampled loop is unstable (its output would grow without "
                 "bound)");
    else if (why->st == PFD_E_RATE)
        snprintf(d, sizeof d, "the substep rule needs an internal rate beyond the limits "
                 "(%d substeps, %.0f Hz)%s%s%s; give substeps to choose the rate",
                 PFD_SUBSTEPS_MAX, PFD_INTERNAL_FS_MAX,
                 why->param != (int)PF_P_COUNT ? ": '" : "",
                 why->param != (int)PF_P_COUNT ? pfd_param_name(why->param) : "",
                 why->param != (int)PF_P_COUNT ? "' makes it so" : "");
    else if (why->st == PF_E_SCALE)
        snprintf(d, sizeof d, "q15: a coefficient does not fit (change in_fs/out_fs)");
    else if (why->param != (int)PF_P_COUNT && why->st == PFD_E_DAEMON)
        snprintf(d, sizeof d, "invalid parameter '%s' (out of range)",
                 pfd_param_name(why->param));
    else if (why->param != (int)PF_P_COUNT)
        /* pf_status_str() would only say "invalid parameter" again. */
        snprintf(d, sizeof d, "invalid parameter '%s'", pfd_param_name(why->param));
    else
        snprintf(d, sizeof d, "%s", pf_status_str(why->st));
    if (path != NULL)
        snprintf(buf, n, "config %s:%d: [instance %d]: %s", path, ci->line, ci->unit, d);
    else
        snprintf(buf, n, "instance %d: %s", ci->unit, d);
}

/* Design every instance of @p c, as pfd_inst_add() will: a file that
 * parses but cannot be designed is as unusable as a corrupt one, and must
 * be found out before the daemon commits to it (or seals it). @p path:
 * the file @p c was read from, named in messages; NULL for instances that
 * are not from a file. @return 0, or -1 with the reason in @p err. */
static int design_all(const char *path, const pfd_config *c, char *err, size_t n)
{
    pf_ctrl_design *scratch = malloc(sizeof *scratch);
    pf_ctrl_check_work *work = malloc(sizeof *work);
    pfd_slot *slot = malloc(sizeof *slot);
    int i, rc = 0;

    if (scratch == NULL || slot == NULL || work == NULL) {
        snprintf(err, n, "out of memory");
        rc = -1;
    }
    for (i = 0; i < c->n && rc == 0; i++) {
        pfd_fail why;
        pfd_iparams ref;
        pfd_plausible_ref(&c->inst[i].ip, NULL, &ref);
        if (pfd_slot_prepare(slot, &c->inst[i].ip, &ref, scratch, work, &why) != 0) {
            pfd_start_describe(err, n, path, &c->inst[i], &why);
            rc = -1;
        }
    }
    free(slot);
    free(work);
    free(scratch);
    return rc;
}

static int load_and_design(const char *path, pfd_config *c, int need_checksum,
                           char *err, size_t n)
{
    if (pfd_config_load(path, c, need_checksum, err, n) != 0)
        return -1;
    return design_all(path, c, err, n);
}

int pfd_start_config(const pfd_run *run, pfd_config *c)
{
    char err[600];

    if (run->config == NULL) {
        default_instances(c, run);
        return 0;
    }
    if (load_and_design(run->config, c, 1, err, sizeof err) == 0)
        return 0;
    if (!run->fallback) {
        pfd_fatal("%s", err);
        return -1;
    }
    /* The file cannot be trusted, so neither can anything it might have
     * said about security: the run is read-only, and the file is never
     * moved or rewritten, so that its instances and settings are there
     * again once it is repaired. */
    pfd_log(PFD_LOG_WARN, "config-fallback",
            "using=defaults mode=read-only persistence=off file=%s error=\"%s\"", run->config,
            err);
    default_instances(c, run);
    return 1;
}

int pfd_start_seal(const char *path)
{
    pfd_config *c = malloc(sizeof *c);
    char err[600];
    int rc = 0;

    if (c == NULL) {
        pfd_fatal("out of memory");
        return 1;
    }
    if (load_and_design(path, c, 0, err, sizeof err) != 0) {
        pfd_fatal("%s", err);
        rc = PFD_EXIT_USAGE;
    } else if (pfd_config_write(path, c, err, sizeof err) != 0) {
        pfd_fatal("%s", err);
        rc = 1;
    } else {
        fprintf(stderr, "pneufracd: %s: sealed (%d instance%s)\n", path, c->n,
                c->n == 1 ? "" : "s");
    }
    free(c);
    return rc;
}

int pfd_start_print_default(const pfd_run *run)
{
    pfd_config *c = malloc(sizeof *c);
    int rc = 1;

    if (c != NULL) {
        default_instances(c, run);
        rc = pfd_config_print(c, stdout) == 0 && fflush(stdout) == 0 ? 0 : 1;
    }
    free(c);
    return rc;
}

int pfd_start_init(const pfd_run *run, const char *path)
{
    pfd_config *c = malloc(sizeof *c);
    char err[600];
    int rc;

    if (c == NULL) {
        pfd_fatal("out of memory");
        return 1;
    }
    default_instances(c, run);
    /* What the daemon would refuse to start from is not written. */
    if (design_all(NULL, c, err, sizeof err) != 0) {
        pfd_fatal("%s", err);
        free(c);
        return PFD_EXIT_USAGE;
    }
    rc = pfd_config_create(path, c, err, sizeof err);
    if (rc < 0)
        pfd_fatal("%s", err);
    else
        fprintf(stderr, "pneufracd: %s: %s\n", path,
                rc == 0 ? "created for the default instances" : "exists, left as it is");
    free(c);
    return rc < 0 ? 1 : 0;
}
