/* SPDX-License-Identifier: MIT */
#include "pfd_sample.h"

/* Reset and clear-statistics requests: counters the Modbus side bumps. */
static void take_commands(pfd_inst *in)
{
    uint32_t req = __atomic_load_n(&in->reset_req, __ATOMIC_ACQUIRE);
    if (req != in->rt.reset_seen) {
        in->rt.reset_seen = req;
        pfd_slot_reset(in->rt.active);
        in->rt.offset = 0.0;
    }
    req = __atomic_load_n(&in->stats_req, __ATOMIC_ACQUIRE);
    if (req != in->rt.stats_seen) {
        in->rt.stats_seen = req;
        in->rt.s.overruns = 0;
        in->rt.s.jit_max_us = 0;
        in->rt.s.wd_trips = 0;
    }
}

/* Bumpless switch to the committed set @p p: the old set runs this sample
 * once more, and the offset makes the output exactly what it would have
 * given. Then hand the slots over. */
static void switch_to(pfd_inst *in, pfd_slot *p, float e, pfd_sig *sig)
{
    pfd_slot *old = in->rt.active;
    int old_idx = in->rt.active_idx, k;
    pfd_sig so;
    double out_old;

    pfd_slot_step(old, e, &so);
    in->rt.offset *= old->decay;
    out_old = (double)so.pc + in->rt.offset;
    pfd_slot_step(p, e, sig);
    in->rt.offset = out_old - (double)sig->pc;
    for (k = 0; k < PFD_NSLOTS; k++)
        if (in->slot[k] == p)
            in->rt.active_idx = k;
    in->rt.active = p;
    __atomic_store_n(&in->slot_state[in->rt.active_idx], PFD_SLOT_ACTIVE, __ATOMIC_RELEASE);
    __atomic_store_n(&in->slot_state[old_idx], PFD_SLOT_FREE, __ATOMIC_RELEASE);
}

/* The controller's step: on the set a commit left pending, if any. */
static void step_controller(pfd_inst *in, float e, pfd_sig *sig)
{
    pfd_slot *p = __atomic_exchange_n(&in->pending, (pfd_slot *)NULL, __ATOMIC_ACQ_REL);
    if (p != NULL) {
        switch_to(in, p, e, sig);
    } else {
        pfd_slot_step(in->rt.active, e, sig);
        in->rt.offset *= in->rt.active->decay;
    }
}

/* Watchdog, counted in samples so that lockstep runs are exact. */
static void watchdog(pfd_inst *in, const pfd_live *l, uint32_t missed)
{
    if (l->refresh != in->rt.last_refresh) {
        in->rt.last_refresh = l->refresh;
        in->rt.wd_count = 0;
        in->rt.tripped = 0;
    } else {
        uint32_t add = missed + 1;
        in->rt.wd_count = in->rt.wd_count > UINT32_MAX - add ? UINT32_MAX
                                                             : in->rt.wd_count + add;
    }
    if (l->watchdog_ms > 0 && !in->rt.tripped) {
        double lim = (double)l->watchdog_ms * in->rt.active->ip.fs / 1000.0;
        if ((double)in->rt.wd_count >= (lim < 1.0 ? 1.0 : lim)) {
            in->rt.tripped = 1;
            in->rt.s.wd_trips++;
        }
    }
}

/* Output: fail-safe, manual, or the controller plus the transfer offset,
 * which tracks the difference while overridden. @return the PFD_SNAP_*
 * flags that say which. */
static uint16_t select_output(pfd_inst *in, const pfd_live *l, pfd_sig *sig)
{
    const double y = (double)sig->pc;
    const double tiny = 1e-9 * in->rt.active->ip.out_fs;
    uint16_t flags = 0;
    double out;

    if (in->rt.tripped) {
        out = (double)l->failsafe_out;
        in->rt.offset = out - y;
        flags |= PFD_SNAP_TRIPPED;
    } else if (l->mode == 1) {
        out = (double)l->manual_out;
        in->rt.offset = out - y;
        flags |= PFD_SNAP_MANUAL;
    } else {
        if (in->rt.offset < tiny && in->rt.offset > -tiny)
            in->rt.offset = 0.0;
        out = y + in->rt.offset;
    }
    if (in->rt.offset != 0.0 || (flags & (PFD_SNAP_TRIPPED | PFD_SNAP_MANUAL))) {
        /* Without an offset the controller's output goes out untouched, so
         * lockstep runs match `pneufrac simulate` bit for bit. */
        sig->pc = (float)out;
        sig->pc_q15 = pf_q15_quantize(out, in->rt.active->ip.out_fs);
        if (in->rt.offset != 0.0)
            flags |= PFD_SNAP_TRANSFER;
    }
    return flags;
}

static uint32_t ns_to_us(int64_t ns)
{
    int64_t us = (ns + 500) / 1000;
    return us > (int64_t)UINT32_MAX ? UINT32_MAX : (uint32_t)us;
}

/* Samples, overruns and period jitter: the instance's and the loop's. */
static void count(pfd_inst *in, pfd_jitter *jit, uint32_t missed, int64_t jitter_ns)
{
    in->rt.s.samples++;
    in->rt.s.overruns += missed;
    if (jitter_ns >= 0) {
        uint32_t us = ns_to_us(jitter_ns);
        in->rt.s.jit_last_us = us;
        if (us > in->rt.s.jit_max_us)
            in->rt.s.jit_max_us = us;
        jit->bin[us < PFD_JITTER_BINS ? us : PFD_JITTER_BINS]++;
        jit->total++;
        if (jitter_ns > jit->max_ns)
            jit->max_ns = jitter_ns;
    }
    jit->overruns += missed;
}

static void publish(pfd_inst *in, const pfd_sig *sig, float e, uint16_t flags)
{
    pfd_snap *s;
    in->rt.s.sig = *sig;
    in->rt.s.gen = in->rt.active->gen;
    in->rt.s.e_used = e;
    in->rt.s.flags = flags;
    s = (pfd_snap *)pfd_tbuf_back(&in->out_tb);
    *s = in->rt.s;
    pfd_tbuf_publish(&in->out_tb);
}

void pfd_sample_run(pfd_inst *in, pfd_jitter *jit, uint32_t missed, int64_t jitter_ns)
{
    const pfd_live *l = (const pfd_live *)pfd_tbuf_latest(&in->in_tb);
    const float e = l->input_sel ? l->sp - l->pv : l->e;
    pfd_sig sig;
    uint16_t flags;

    take_commands(in);
    step_controller(in, e, &sig);
    watchdog(in, l, missed);
    flags = select_output(in, l, &sig);
    count(in, jit, missed, jitter_ns);
    publish(in, &sig, e, flags);
    /* The rest of the exchange, input held: the output went out after the
     * first step, the model's response at the exchange instant. */
    pfd_slot_hold(in->rt.active, e, in->rt.active->rate.k - 1u);
}

uint32_t pfd_jitter_percentile(const pfd_jitter *jit, double q)
{
    uint64_t want = (uint64_t)(q * (double)jit->total), acc = 0;
    uint32_t i;
    if (want >= jit->total && jit->total > 0)
        want = jit->total - 1;
    for (i = 0; i <= PFD_JITTER_BINS; i++) {
        acc += jit->bin[i];
        if (acc > want)
            return i;
    }
    return PFD_JITTER_BINS;
}
