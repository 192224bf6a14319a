/* SPDX-License-Identifier: MIT */
#include "pfd_commit.h"

#include <modbus/modbus.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "pfd_audit.h"
#include "pfd_log.h"
#include "pfd_plausible.h"

int pfd_daemon_init(pfd_daemon *d, const pfd_settings *set)
{
    pthread_condattr_t ca;

    memset(d, 0, sizeof *d);
    d->set = *set;
    d->server.listen_fd = d->server.tls_fd = d->server.reserve_fd = -1;
    d->scratch = malloc(sizeof *d->scratch);
    d->persist_buf = malloc(sizeof *d->persist_buf);
    d->check = malloc(sizeof *d->check);
    if (d->scratch == NULL || d->persist_buf == NULL || d->check == NULL) {
        pfd_daemon_free(d);
        return -1;
    }
    pthread_mutex_init(&d->regs_mx, NULL);
    pthread_mutex_init(&d->server.clients_mx, NULL);
    pthread_mutex_init(&d->commit_mx, NULL);
    pthread_mutex_init(&d->tick_mx, NULL);
    /* Timed waits use CLOCK_MONOTONIC, immune to clock steps. */
    pthread_condattr_init(&ca);
    pthread_condattr_setclock(&ca, CLOCK_MONOTONIC);
    pthread_cond_init(&d->work_cv, &ca);
    pthread_cond_init(&d->done_cv, &ca);
    pthread_condattr_destroy(&ca);
    return 0;
}

int pfd_inst_add(pfd_daemon *d, const pfd_config_inst *ci, pfd_fail *why)
{
    pfd_iparams ref;
    pfd_inst *in;
    pfd_snap s0;
    int k;

    if (d->n >= PFD_MAX_INSTANCES || d->by_unit[ci->unit] != NULL) {
        why->st = PF_E_NULL;
        why->param = PF_P_COUNT;
        return -1;
    }
    in = calloc(1, sizeof *in);
    if (in == NULL) {
        why->st = PF_E_NULL;
        why->param = PF_P_COUNT;
        return -1;
    }
    for (k = 0; k < PFD_NSLOTS; k++) {
        in->slot[k] = calloc(1, sizeof *in->slot[k]);
        if (in->slot[k] == NULL) {
            while (k-- > 0)
                free(in->slot[k]);
            free(in);
            why->st = PF_E_NULL;
            why->param = PF_P_COUNT;
            return -1;
        }
    }
    pfd_plausible_ref(&ci->ip, NULL, &ref);
    if (pfd_slot_prepare(in->slot[0], &ci->ip, &ref, d->scratch, d->check, why) != 0) {
        for (k = 0; k < PFD_NSLOTS; k++)
            free(in->slot[k]);
        free(in);
        return -1;
    }
    pfd_rate_measure(in->slot[0]);
    in->rate = in->slot[0]->rate;
    in->unit = ci->unit;
    in->slot_state[0] = PFD_SLOT_ACTIVE;
    in->rt.active = in->slot[0];
    in->rt.active_idx = 0;
    in->live = ci->live;
    in->param_lock = (uint16_t)(d->set.param_lock ? 1 : 0);
    in->lock_holder = 0;
    in->committed = ci->ip;
    in->err_addr = 0xFFFFu;
    in->err_param = 0xFFFFu;
    pfd_tbuf_init(&in->in_tb, &in->in_buf[0], &in->in_buf[1], &in->in_buf[2],
                  sizeof(pfd_live), &ci->live);
    memset(&s0, 0, sizeof s0);
    pfd_tbuf_init(&in->out_tb, &in->out_buf[0], &in->out_buf[1], &in->out_buf[2],
                  sizeof(pfd_snap), &s0);
    d->inst[d->n++] = in;
    d->by_unit[ci->unit] = in;
    return 0;
}

void pfd_daemon_free(pfd_daemon *d)
{
    int i, k;
    for (i = 0; i < d->n; i++) {
        for (k = 0; k < PFD_NSLOTS; k++)
            free(d->inst[i]->slot[k]);
        free(d->inst[i]);
    }
    d->n = 0;
    free(d->scratch);
    d->scratch = NULL;
    free(d->persist_buf);
    d->persist_buf = NULL;
    free(d->check);
    d->check = NULL;
}

void pfd_publish_live(pfd_inst *in)
{
    pfd_live *b = (pfd_live *)pfd_tbuf_back(&in->in_tb);
    *b = in->live;
    pfd_tbuf_publish(&in->in_tb);
}

void pfd_apply_settings(pfd_inst *in, const pfd_who *w, const pfd_wlist *wl)
{
    pfd_hold before, after;
    unsigned i;

    memset(&before, 0, sizeof before);
    before.live = in->live;
    before.param_lock = in->param_lock;
    after = before;
    pfd_regmap_apply(&after, &in->committed, wl);
    for (i = 0; i < wl->n; i++)
        if (!strcmp(wl->w[i].r->name, "param_lock"))
            in->lock_holder = wl->w[i].v != 0.0 ? w->id : 0;
    pfd_audit_settings(w, in->unit, &before, &after, &in->committed, "ok");
    in->live = after.live;
    in->param_lock = after.param_lock;
    if (wl->live)
        pfd_publish_live(in);
}

void pfd_release_lock(pfd_inst *in, const pfd_who *w, const char *why)
{
    pfd_hold before, after;

    memset(&before, 0, sizeof before);
    before.live = in->live;
    before.param_lock = in->param_lock;
    after = before;
    after.param_lock = 0;
    pfd_audit_settings(w, in->unit, &before, &after, &in->committed, why);
    in->param_lock = 0;
    in->lock_holder = 0;
}

static int iparams_equal(const pfd_iparams *a, const pfd_iparams *b)
{
    int k;
    if (a->p.topology != b->p.topology || a->arith != b->arith || a->fs != b->fs ||
        a->substeps != b->substeps || a->in_fs != b->in_fs || a->out_fs != b->out_fs ||
        a->bump_tau != b->bump_tau)
        return 0;
    for (k = PF_P_A; k <= PF_P_RCI; k++)
        if (pf_params_get(&a->p, (pf_param_id)k) != pf_params_get(&b->p, (pf_param_id)k))
            return 0;
    return 1;
}

uint16_t pfd_status_bits(const pfd_daemon *d, const pfd_inst *in,
                         const pfd_snap *s, const pfd_iparams *staged)
{
    uint16_t b = 0;
    if (!pfd_stopping(d))
        b |= 1u << 0;
    if (s->flags & PFD_SNAP_TRIPPED)
        b |= 1u << 1;
    if (in->commit_result != PFD_COMMIT_OK)
        b |= 1u << 2;
    if (s->flags & PFD_SNAP_MANUAL)
        b |= 1u << 3;
    if (in->param_lock)
        b |= 1u << 4;
    if (d->set.read_only)
        b |= 1u << 5;
    if (d->set.external_clock)
        b |= 1u << 6;
    if (!iparams_equal(staged, &in->committed))
        b |= 1u << 7;
    /* The set the loop ran last is not the one committed last. */
    if (s->gen != in->gen)
        b |= 1u << 8;
    if (in->committed.arith == PFD_ARITH_Q15)
        b |= 1u << 9;
    if (s->flags & PFD_SNAP_TRANSFER)
        b |= 1u << 10;
    if (__atomic_load_n(&d->persist_failed, __ATOMIC_RELAXED))
        b |= 1u << 11;
    return b;
}

unsigned pfd_settle_samples(double internal_fs)
{
    /* One second of held input, at most 20000 steps: long enough for the
     * fast part of a new set's step response (the derivative kick of dd
     * and pid) to die out, short enough to keep a commit in milliseconds. */
    double n = internal_fs < 20000.0 ? internal_fs : 20000.0;
    return (unsigned)n;
}

void pfd_loop_load(const pfd_daemon *d, const pfd_inst *in, double fs, const pfd_rate *r,
                   pfd_load *out)
{
    int i;

    pfd_load_init(out, d->wake_ns);
    for (i = 0; i < d->n; i++) {
        if (d->inst[i] == in)
            pfd_load_add(out, fs, r);
        else
            pfd_load_add(out, d->inst[i]->committed.fs, &d->inst[i]->rate);
    }
}

/* Under commit_mx: whether the loop could run @p s in place of @p in's
 * committed set within the budget. In lockstep nothing runs in real
 * time: the client's ticks set the pace, so the budget does not apply. */
static int affordable(const pfd_daemon *d, const pfd_inst *in, const pfd_slot *s,
                      double *load)
{
    pfd_load l;
    pfd_loop_load(d, in, s->ip.fs, &s->rate, &l);
    *load = pfd_load_total(&l);
    return d->set.external_clock || *load <= d->set.loop_budget / 100.0;
}

static int refuse(pfd_daemon *d, pfd_inst *in, uint16_t result, int param)
{
    /* An unstable set names the parameter, like an invalid one. */
    pthread_mutex_lock(&d->regs_mx);
    in->commit_result = result;
    /* The library's pf_param_id; the daemon's own settings (bump_tau,
     * arith, substeps) have none, and err_addr names them. */
    in->err_param = param >= (int)PF_P_COUNT ? 0xFFFFu : (uint16_t)param;
    in->err_addr = param == PF_P_COUNT ? 0xFFFFu : pfd_regmap_staged_addr(param);
    pthread_mutex_unlock(&d->regs_mx);
    return result == PFD_COMMIT_BUSY     ? MODBUS_EXCEPTION_SLAVE_OR_SERVER_BUSY
           : result == PFD_COMMIT_FAILED ? MODBUS_EXCEPTION_SLAVE_OR_SERVER_FAILURE
                                         : MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE;
}

/* Under commit_mx: a slot to build into, neither the loop's active one nor
 * the pending one (which must survive a build that fails). With three
 * slots one is always free, except in the few instructions between the
 * loop taking a pending set and marking its old slot free; a commit that
 * lands there waits for it, a bounded time, and is refused as busy only
 * if the loop stalls right there. @return the index, or -1. */
static int free_slot(const pfd_inst *in)
{
    const struct timespec pause = {0, 50000L};
    int k, tries;

    for (tries = 0; tries < 200; tries++) {
        for (k = 0; k < PFD_NSLOTS; k++)
            if (__atomic_load_n(&in->slot_state[k], __ATOMIC_ACQUIRE) == PFD_SLOT_FREE)
                return k;
        nanosleep(&pause, NULL);
    }
    return -1;
}

static int persist_locked(pfd_daemon *d);

int pfd_commit(pfd_daemon *d, pfd_inst *in, const pfd_who *w, const pfd_stage *st,
               const pfd_wlist *wl)
{
    pfd_iparams ip, old_set, ref;
    const pfd_reg *bad;
    pfd_slot *slot, *old;
    pfd_fail why;
    float e_hold;
    double load;
    int k, j;

    pthread_mutex_lock(&d->commit_mx);

    /* `committed` changes only under commit_mx, which we hold. */
    pthread_mutex_lock(&d->regs_mx);
    /* The int16 mirrors convert with the committed in_fs, which another
     * commit may have changed since the request was checked; checked again
     * here, before any work, as in_fs cannot change while commit_mx is
     * held (unlike the lock, checked again where the commit applies). */
    bad = pfd_regmap_check_mirrors(wl, &in->committed);
    if (bad != NULL) {
        pthread_mutex_unlock(&d->regs_mx);
        pthread_mutex_unlock(&d->commit_mx);
        pfd_audit_refused(w, in->unit, bad->addr, 1, MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE,
                          "value");
        return MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE;
    }
    old_set = in->committed;
    pfd_stage_compose(st, wl, &in->committed, &ip);
    e_hold = ((const pfd_snap *)pfd_tbuf_latest(&in->out_tb))->e_used;
    pthread_mutex_unlock(&d->regs_mx);

    k = free_slot(in);
    if (k < 0) {
        int rc = refuse(d, in, PFD_COMMIT_BUSY, PF_P_COUNT);
        pthread_mutex_unlock(&d->commit_mx);
        return rc;
    }
    slot = in->slot[k];
    pfd_plausible_ref(&ip, &old_set, &ref);
    if (pfd_slot_prepare(slot, &ip, &ref, d->scratch, d->check, &why) != 0) {
        uint16_t res = why.st == PF_E_SCALE         ? PFD_COMMIT_SCALE
                       : why.st == PFD_E_UNSTABLE   ? PFD_COMMIT_UNSTABLE
                       : why.st == PFD_E_RATE       ? PFD_COMMIT_RATE
                       : why.param != PF_P_COUNT    ? PFD_COMMIT_INVALID
                                                    : PFD_COMMIT_FAILED;
        int rc;
        pfd_audit_params(w, in->unit, &old_set, &ip, "refused");
        pfd_log(PFD_LOG_WARN, "commit-refused",
                "peer=%s role=%s unit=%d result=%u param=%s status=\"%s\"", w->peer, w->role,
                in->unit, (unsigned)res, pfd_param_name(why.param),
                why.st == PFD_E_DAEMON     ? "out of range"
                : why.st == PFD_E_UNSTABLE ? "unstable sampled loop"
                : why.st == PFD_E_RATE     ? "the substep rule's rate is beyond the limits"
                                           : pf_status_str(why.st));
        /* The slot was free and stays free: a pending set, if any, is
         * still what `committed` and the config file describe. */
        rc = refuse(d, in, res, why.param);
        pthread_mutex_unlock(&d->commit_mx);
        return rc;
    }
    pfd_rate_measure(slot);
    if (!affordable(d, in, slot, &load)) {
        /* With one step per exchange the exchange rate is what costs;
         * with more, the substeps are. */
        const int param = slot->rate.k > 1 ? PFD_P_SUBSTEPS : PF_P_FS;
        int rc;
        pfd_audit_params(w, in->unit, &old_set, &ip, "refused");
        pfd_log(PFD_LOG_WARN, "commit-refused",
                "peer=%s role=%s unit=%d result=%u param=%s load_pct=%.1f budget_pct=%d "
                "fs=%.9g substeps=%u step_ns=%.0f", w->peer, w->role, in->unit,
                (unsigned)PFD_COMMIT_LOAD, pfd_param_name(param), 100.0 * load,
                d->set.loop_budget, ip.fs, slot->rate.k, slot->rate.step_ns);
        rc = refuse(d, in, PFD_COMMIT_LOAD, param);
        pthread_mutex_unlock(&d->commit_mx);
        return rc;
    }
    if (e_hold != 0.0f)
        pfd_slot_hold(slot, e_hold, pfd_settle_samples(slot->rate.internal_fs));
    /* in->gen changes only under commit_mx, which we hold. */
    slot->gen = in->gen + 1u;

    pthread_mutex_lock(&d->regs_mx);
    /* The request was checked against the lock, but another client may
     * have taken it since; checked again where the commit takes effect,
     * so that no commit is applied after the lock write was answered. */
    if (in->param_lock && in->lock_holder != w->id) {
        pthread_mutex_unlock(&d->regs_mx);
        pthread_mutex_unlock(&d->commit_mx);
        pfd_audit_refused(w, in->unit, 0, 0, MODBUS_EXCEPTION_ILLEGAL_FUNCTION, "locked");
        return MODBUS_EXCEPTION_ILLEGAL_FUNCTION;
    }
    pfd_apply_settings(in, w, wl);
    pfd_audit_params(w, in->unit, &old_set, &ip, "committed");
    in->committed = ip;
    in->rate = slot->rate;
    in->commit_result = PFD_COMMIT_OK;
    in->err_addr = 0xFFFFu;
    in->err_param = 0xFFFFu;
    in->gen = slot->gen;
    __atomic_store_n(&in->slot_state[k], PFD_SLOT_PENDING, __ATOMIC_RELEASE);
    /* Swap: a set the loop has not taken yet is replaced, and its slot is
     * ours again. The exchange decides who gets it, the loop or us. */
    old = __atomic_exchange_n(&in->pending, slot, __ATOMIC_ACQ_REL);
    for (j = 0; j < PFD_NSLOTS && old != NULL; j++)
        if (in->slot[j] == old)
            __atomic_store_n(&in->slot_state[j], PFD_SLOT_FREE, __ATOMIC_RELEASE);
    pthread_mutex_unlock(&d->regs_mx);

    pfd_log(PFD_LOG_INFO, "commit",
            "peer=%s role=%s unit=%d config=%s arith=%s fs=%.9g substeps=%u internal_fs=%.9g "
            "load_pct=%.1f", w->peer, w->role, in->unit, pf_topology_name(ip.p.topology),
            pfd_arith_name(ip.arith), ip.fs, slot->rate.k, slot->rate.internal_fs, 100.0 * load);
    /* Answered only once the file is on disk; if it cannot be written the
     * set still runs (it was switched in above), and the client learns
     * that it would not survive a restart. */
    if (persist_locked(d) != 0) {
        pthread_mutex_lock(&d->regs_mx);
        in->commit_result = PFD_COMMIT_UNSAVED;
        pthread_mutex_unlock(&d->regs_mx);
        pthread_mutex_unlock(&d->commit_mx);
        return MODBUS_EXCEPTION_SLAVE_OR_SERVER_FAILURE;
    }
    pthread_mutex_unlock(&d->commit_mx);
    return 0;
}

/* Under commit_mx. */
static int persist_locked(pfd_daemon *d)
{
    pfd_config *c = d->persist_buf;
    char err[512];
    int i, rc;

    if (d->config_path == NULL)
        return 0;
    pthread_mutex_lock(&d->regs_mx);
    *c = *d->config_file;
    c->n = d->n;
    for (i = 0; i < d->n; i++) {
        const pfd_inst *in = d->inst[i];
        pfd_config_inst_default(&c->inst[i], in->unit);
        c->inst[i].ip = in->committed;
        c->inst[i].live = in->live;
    }
    pthread_mutex_unlock(&d->regs_mx);
    rc = pfd_config_write(d->config_path, c, err, sizeof err);
    if (rc != 0) {
        __atomic_store_n(&d->persist_failed, 1, __ATOMIC_RELAXED);
        pfd_log(PFD_LOG_ERROR, "persist-failed", "error=\"%s\"", err);
        return -1;
    }
    __atomic_store_n(&d->persist_failed, 0, __ATOMIC_RELAXED);
    pfd_log(PFD_LOG_DEBUG, "persisted", "file=%s", d->config_path);
    return 0;
}

int pfd_persist(pfd_daemon *d)
{
    int rc;
    pthread_mutex_lock(&d->commit_mx);
    rc = persist_locked(d);
    pthread_mutex_unlock(&d->commit_mx);
    return rc;
}
