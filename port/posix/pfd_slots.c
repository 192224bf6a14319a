/* SPDX-License-Identifier: MIT */
#include "pfd_slots.h"

static int live(const pfd_slot_view *s)
{
    return s->in_use && !s->evicted;
}

/* Eviction order: silent newcomers, then newcomers, then active ones. */
static int rank(const pfd_slot_view *s)
{
    return s->active ? 2 : s->heard ? 1 : 0;
}

/* Is @p a a better victim than @p b (-1: none yet)? Lower rank first;
 * then the one idle (or waiting for its first request) longest. */
static int better(const pfd_slot_view *v, int a, int b)
{
    if (b < 0)
        return 1;
    if (rank(&v[a]) != rank(&v[b]))
        return rank(&v[a]) < rank(&v[b]);
    return v[a].since_ns < v[b].since_ns;
}

/* The best victim among live slots neither busy nor with a request
 * pending (from @p addr only if @p same_addr); active ones only if idle
 * for protect_ns, so that an address that reconnects in a hurry cannot
 * push out its own poller. */
static int victim(const pfd_slot_view *v, int n, uint32_t addr, int same_addr,
                  int64_t now_ns, int64_t protect_ns)
{
    int i, best = -1;
    for (i = 0; i < n; i++) {
        if (!live(&v[i]) || v[i].busy || v[i].pending || (same_addr && v[i].addr != addr))
            continue;
        if (v[i].active && now_ns - v[i].since_ns < protect_ns)
            continue;
        if (better(v, i, best))
            best = i;
    }
    return best;
}

pfd_slot_choice pfd_slots_choose(const pfd_slot_view *v, int n, uint32_t addr,
                                 int max_clients, int max_per_addr,
                                 int64_t now_ns, int64_t protect_ns)
{
    pfd_slot_choice c = {-1, -1, ""};
    int i, total = 0, mine = 0;

    for (i = 0; i < n; i++)
        if (live(&v[i])) {
            total++;
            if (v[i].addr == addr)
                mine++;
        }
    if (mine >= max_per_addr) {
        c.victim = victim(v, n, addr, 1, now_ns, protect_ns);
        c.why = "max-clients-per-addr";
        if (c.victim < 0)
            return c;
    } else if (total >= max_clients) {
        c.victim = victim(v, n, addr, 0, now_ns, protect_ns);
        c.why = "max-clients";
        if (c.victim < 0)
            return c;
    }
    for (i = 0; i < n && c.slot < 0; i++)
        if (!v[i].in_use)
            c.slot = i;
    if (c.slot < 0) {
        c.victim = -1;
        c.why = "no-free-slot";
    }
    return c;
}

int pfd_slots_pending(int tls, int up, int moved, int whole, int app_data)
{
    if (!tls)
        return !moved && whole;
    return up && (moved || (whole && app_data));
}
