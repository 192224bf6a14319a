/* SPDX-License-Identifier: MIT */
/*
 * Who gets a client slot: the policy that keeps idle, half-open and
 * slowloris connections from starving real clients (docs/pneufracd.md,
 * "Security"). Pure: the server passes a snapshot of its table.
 *
 *  - One address holds at most max_per_addr connections. One more from
 *    that address replaces that address's own best victim (in the order
 *    below), so an address competes only with itself, and a client that
 *    reconnects is not locked out by its own stale connections.
 *  - A full table replaces its best victim: first the connections that
 *    have not completed a request and have sent nothing at all, then
 *    those that have not completed a request (each oldest first), then
 *    the connection idle longest, but only once it has been idle for at
 *    least `protect_ns`, so that a flood of new connections cannot push
 *    out a client that polls.
 *  - A connection in the middle of a request, or holding a lock, is never
 *    a victim; nor is one with a complete request waiting unread in its
 *    socket: it has done all a client must, and only its thread, not yet
 *    scheduled, is late. Evicting it would charge the client for time the
 *    scheduler took from the daemon: under load, a poller's first request
 *    (oldest among those that have sent something) went to a flood of
 *    half-open sockets.
 */
#ifndef PFD_SLOTS_H
#define PFD_SLOTS_H

#include <stdint.h>

/** What the policy needs to know of one slot. */
typedef struct pfd_slot_view {
    int in_use;          /**< taken (also while an evicted one winds down) */
    int evicted;         /**< told to go, or its thread has ended: counts
                              for nothing */
    int active;          /**< has completed a request */
    int heard;           /**< has sent at least one byte */
    int busy;            /**< a request is being served, or it holds a lock */
    int pending;         /**< a complete request waits unread */
    uint32_t addr;       /**< IPv4, host order */
    int64_t since_ns;    /**< last completed request, or accepted if none */
} pfd_slot_view;

/** A decision for a new connection from @p addr at @p now_ns. */
typedef struct pfd_slot_choice {
    int slot;   /**< the free slot to use, or -1: refuse */
    int victim; /**< the slot to evict first, or -1 */
    const char *why; /**< refusal or eviction reason */
} pfd_slot_choice;

pfd_slot_choice pfd_slots_choose(const pfd_slot_view *v, int n, uint32_t addr,
                                 int max_clients, int max_per_addr,
                                 int64_t now_ns, int64_t protect_ns);

/** Whether a look at a slot's socket (pfd_server.c, unread()) finds a
 *  request waiting unread. @p whole: a whole unit is first in the socket
 *  (plain TCP: a frame; TLS: a record, @p app_data if its outer type is
 *  application data); @p moved: the thread's unit count moved during the
 *  look; @p up: TLS, the handshake was done before the look. Plain TCP: a
 *  whole frame, if the count did not move (if it did, the thread is
 *  serving and says busy). TLS: nothing during the handshake; past it, a
 *  whole application-data record, or a count that moved (the thread took
 *  a record that may have left it with part of a frame, the rest whole
 *  behind it: it runs, it is not late). */
int pfd_slots_pending(int tls, int up, int moved, int whole, int app_data);

#endif
