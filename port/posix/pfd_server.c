/* SPDX-License-Identifier: MIT */
/* POLLRDHUP (Linux): the peer's close behind bytes still waiting
 * (take_unit()); without it, the byte gap ends such a connection. */
#define _GNU_SOURCE
#include "pfd_server.h"

#include <arpa/inet.h>
#include <errno.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include "pfd_conn.h"
#include "pfd_log.h"
#include "pfd_modbus.h"
#include "pfd_slots.h"
#include "pfd_tls.h"

#define CLIENT_STACK (256 * 1024)
#define POLL_MS 200       /* how often threads look at the stop flag */
#define SEND_TIMEOUT_MS 1000 /* a client that does not read its answers */
#define SEQ __ATOMIC_SEQ_CST /* the slot flags below: see unread() */
/* TLS: records that bring no byte of a request (TLS 1.3 key updates,
 * empty records) allowed between two requests. A client needs a key
 * update only after some millions of records under one key (RFC 8446,
 * 5.5), and never an empty record; each such record waiting keeps the
 * slot pending (unread()), and with no idle timeout nothing else would
 * end a client that sends them without end. */
#define TLS_EMPTY_MAX 32

/* One slot of pfd_daemon.server.clients. */
typedef struct pfd_client {
    pfd_daemon *d;
    pthread_t th;
    pfd_conn conn;
    int tls;          /* came in on the TLS listener */
    int in_use;       /* slot taken (under clients_mx) */
    int done;         /* thread finished, join pending (atomic) */
    uint32_t addr;    /* IPv4, host order */
    uint64_t id;
    char peer[48];
    /* what the slot policy reads (atomic) */
    int64_t since_ns; /* last completed request, or accepted */
    int active, heard, busy, evicted;
    int frames;       /* frames (TLS: records) its thread has taken (atomic,
                         see unread()) */
    int tls_up;       /* TLS: handshake done, client authenticated (atomic) */
    /* TLS, the client thread's own: decrypted bytes of the next frame(s) */
    uint8_t held[PFD_ADU_MAX];
    int n_held;
    int empty; /* records that brought nothing since the last frame */
} pfd_client;

static pfd_ratelimit rl_refused = PFD_RATELIMIT("client-refused");
static pfd_ratelimit rl_evicted = PFD_RATELIMIT("client-evicted");
static pfd_ratelimit rl_accept = PFD_RATELIMIT("accept-failed");
static pfd_ratelimit rl_tls = PFD_RATELIMIT("tls-refused");

/* ---- client thread ----------------------------------------------------- */

/* When the client must have completed its next request. */
static int64_t deadline_of(const pfd_client *c)
{
    const pfd_settings *set = &c->d->set;
    int64_t since = __atomic_load_n(&c->since_ns, __ATOMIC_ACQUIRE);
    if (!__atomic_load_n(&c->active, __ATOMIC_ACQUIRE))
        return since + (int64_t)set->first_request_ms * 1000000;
    return set->idle_timeout_s > 0 ? since + (int64_t)set->idle_timeout_s * 1000000000 : 0;
}

/* The reason a connection ends at deadline_of(): the first request, or
 * the next one, did not come (whole) in time. */
static const char *deadline_why(const pfd_client *c)
{
    return __atomic_load_n(&c->active, __ATOMIC_ACQUIRE) ? "idle-timeout" : "first-request-timeout";
}

/* The TLS handshake and the client's role. @return 0, or -1 with @p why. */
static int tls_start(pfd_client *c, pfd_session *s, char *role, size_t n, const char **why)
{
    pfd_daemon *d = c->d;
    char reason[160];
    int rc;

    c->conn.ssl = pfd_tls_session(d->server.tls, c->conn.fd);
    if (c->conn.ssl == NULL) {
        *why = "out-of-memory";
        return -1;
    }
    rc = pfd_conn_handshake(&c->conn, deadline_of(c), reason, sizeof reason);
    if (rc == 0) {
        s->who.access = pfd_tls_peer(d->server.tls, c->conn.ssl, role, n);
        if (s->who.access >= 0 && pfd_conn_records_only(&c->conn) == 0) {
            __atomic_store_n(&c->tls_up, 1, SEQ);
            return 0;
        }
        snprintf(reason, sizeof reason, s->who.access >= 0 ? "out of memory" : "no role");
    }
    if (!pfd_stopping(d) && pfd_log_ratelimit(&rl_tls))
        pfd_log(PFD_LOG_WARN, "tls-refused", "peer=%s reason=\"%s\"", c->peer, reason);
    *why = "tls-refused";
    return -1;
}

/* Peek at the start of what waits in socket @p fd: up to @p n bytes into
 * @p buf, their number in *got (only those are this peek's: the rest of
 * @p buf is older). @return the bytes waiting (at least those peeked), 0
 * none, -2 the peer closed or the socket failed. */
static ssize_t peek_fd(int fd, uint8_t *buf, size_t n, ssize_t *got)
{
    int avail = 0;
    ssize_t k = recv(fd, buf, n, MSG_PEEK | MSG_DONTWAIT);
    *got = k > 0 ? k : 0;
    if (k < 0)
        return errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR ? 0 : -2;
    if (k == 0)
        return -2;
    if (ioctl(fd, FIONREAD, &avail) == 0 && avail > k)
        k = avail;
    return k;
}

/* The unit first in socket @p fd: an MBAP frame (plain TCP), or a TLS
 * record (@p tls), its header into @p h. @return its whole length (0: the
 * header has not all come; -1: not a frame, or no record TLS allows),
 * with the bytes waiting in *k (as peek_fd()). */
static int peek_unit(int tls, int fd, uint8_t *h, ssize_t *k)
{
    const ssize_t hl = tls ? PFD_TLS_HDR : PFD_MBAP_LEN;
    ssize_t got;
    *k = peek_fd(fd, h, (size_t)hl, &got);
    /* the header from this peek's own bytes: the rest of the header may
     * come between the peek and FIONREAD, and h beyond them is older */
    if (got < hl)
        return 0;
    return tls ? pfd_tls_record_length(h) : pfd_mbap_length(h);
}

/* Why the stream of @p fd can bring no more of a unit, with bytes possibly
 * still waiting (recv() then returns them, not 0): the peer closed its
 * side, or sent TCP urgent data, which no Modbus client sends and which
 * stops every peek and FIONREAD at its mark, so the unit would stay short
 * to the end of the byte gap. NULL while it can. */
static const char *stream_stuck(const pfd_client *c)
{
#ifdef POLLRDHUP
    struct pollfd p = {c->conn.fd, POLLRDHUP | POLLPRI, 0};
#else /* POLLHUP and POLLERR are always reported: a reset, or both sides shut */
    struct pollfd p = {c->conn.fd, POLLPRI, 0};
#endif
    if (poll(&p, 1, 0) <= 0 || p.revents == 0)
        return NULL;
    if (p.revents == POLLPRI)
        return c->tls ? "bad-record" : "bad-frame";
    return "peer-closed";
}

/* Take the unit first in the socket (peek_unit(): a plain client's
 * request, a TLS client's record) into @p buf, only once all of it is in
 * the socket, and say busy (and count the unit) before taking it. The
 * thread so never holds part of a unit, and what has come is always
 * either in the socket, whole units from the first byte, or taken: what
 * unread() needs. SO_RCVLOWAT makes poll() wait for the bytes the unit
 * lacks rather than wake at each; byte_timeout_ms without a new byte ends
 * the connection, and the whole unit has until the deadline. poll() may
 * say readable while the unit is still short, with no new byte and no
 * end of stream: Linux caps SO_RCVLOWAT (at half of tcp_rmem[2], or of a
 * locked SO_RCVBUF) and wakes readers below the mark under memory
 * pressure. That is one more wait (a short nap, as poll() would return at
 * once), still bounded by the byte gap and the deadline, unless the peer
 * has closed its side (stream_stuck(); recv() 0, peek_fd(), once nothing
 * waits): a client that sends part of a unit and closes must free its
 * slot at once, or a flood of such connections holds the table.
 * @return its length, or a PFD_CONN_* code with @p why set. */
static int take_unit(pfd_client *c, uint8_t *buf, const char **why)
{
    const int fd = c->conn.fd, one = 1;
    const int64_t gap_ns = (int64_t)c->d->set.byte_timeout_ms * 1000000;
    ssize_t k, had = -1;
    int len, lowat, ready = 0;
    int64_t now, gap_end = 0, deadline;

    for (;;) {
        len = peek_unit(c->tls, fd, buf, &k);
        if (len < 0 || k < 0) {
            *why = len < 0 ? (c->tls ? "bad-record" : "bad-frame") : "peer-closed";
            return PFD_CONN_CLOSED;
        }
        if (len > 0 && k >= len) {
            __atomic_store_n(&c->busy, 1, SEQ);
            __atomic_add_fetch(&c->frames, 1, SEQ);
            if (recv(fd, buf, (size_t)len, MSG_DONTWAIT) == len)
                return len;
            *why = "peer-closed";
            return PFD_CONN_CLOSED;
        }
        now = pfd_now_ns();
        deadline = deadline_of(c);
        if (k > had) {
            had = k;
            gap_end = now + gap_ns;
        } else if (deadline > 0 && now >= deadline) { /* the deadline's own reason */
            *why = deadline_why(c);
            return PFD_CONN_TIMEOUT;
        } else if (now >= gap_end) {
            *why = "byte-timeout";
            return PFD_CONN_TIMEOUT;
        } else if (ready) { /* readable, no new byte: see above */
            int64_t nap_ns = 10 * 1000000;
            struct timespec nap = {0, 0};
            /* an eviction's or a stop's shutdown() ends the thread at once:
             * where no POLLRDHUP tells the peer's close from it, the nap
             * would otherwise hold the slot to the end of the gap */
            const char *stuck = stream_stuck(c);
            if (stuck != NULL || __atomic_load_n(&c->evicted, SEQ) || pfd_stopping(c->d)) {
                /* client_main names an eviction or a stop */
                *why = stuck != NULL ? stuck : "peer-closed";
                return PFD_CONN_CLOSED;
            }
            if (gap_end - now < nap_ns)
                nap_ns = gap_end - now;
            if (deadline > 0 && deadline - now < nap_ns)
                nap_ns = deadline - now;
            nap.tv_nsec = (long)nap_ns;
            nanosleep(&nap, NULL);
            now = pfd_now_ns();
        }
        lowat = len > 0 ? len : c->tls ? PFD_TLS_HDR : PFD_MBAP_LEN;
        setsockopt(fd, SOL_SOCKET, SO_RCVLOWAT, &lowat, sizeof lowat);
        /* never negative: poll() would wait without end (a nap can end
         * past the gap; the next pass then ends the connection) */
        ready = pfd_conn_wait_until(&c->conn,
                                    now < gap_end ? (int)((gap_end - now + 999999) / 1000000) : 0,
                                    deadline);
        setsockopt(fd, SOL_SOCKET, SO_RCVLOWAT, &one, sizeof one);
        if (ready < 0) {
            *why = "poll-error";
            return PFD_CONN_CLOSED;
        }
    }
}

/* TLS: decrypt what the session was given into c->held, up to the end of
 * the frame it starts with (a record may hold part of a frame, or more
 * than one). @return that frame's length once all of it is held, 0 if not
 * yet, or PFD_CONN_CLOSED with @p why. */
static int tls_held(pfd_client *c, const char **why)
{
    for (;;) {
        int need = c->n_held < PFD_MBAP_LEN ? PFD_MBAP_LEN : pfd_mbap_length(c->held);
        long k;
        if (need < 0) {
            *why = "bad-frame";
            return PFD_CONN_CLOSED;
        }
        if (c->n_held >= PFD_MBAP_LEN && c->n_held >= need)
            return need;
        k = pfd_conn_take(&c->conn, c->held + c->n_held, (size_t)(need - c->n_held));
        if (k < 0) {
            *why = k == PFD_CONN_BAD ? "bad-record" : k == PFD_CONN_SEND ? "send-failed" : "peer-closed";
            return PFD_CONN_CLOSED;
        }
        if (k == 0)
            return 0;
        c->n_held += (int)k;
    }
}

/* TLS: read one request ADU into @p req, and say busy. Records are taken
 * whole (take_unit()), so the session never holds part of one; the
 * thread says busy whenever it holds a whole frame, so that a request
 * that has come is always whole records in the socket, or held and busy.
 * A record that brings no byte of a frame (an empty one, a key update)
 * after the first-request or idle deadline ends the connection: a client
 * that sends such records without end must not keep its slot past them,
 * while one whose thread comes late still has every byte of its request
 * read; and more than TLS_EMPTY_MAX of them between two requests end it
 * at once (an idle timeout may be none). Such a record before any byte of a request is no request begun:
 * the thread goes back to its idle wait (byte_timeout_ms is for the rest
 * of a request). @return its length, 0 for no request yet, or a
 * PFD_CONN_* code with @p why set. */
static int read_tls(pfd_client *c, uint8_t *req, const char **why)
{
    uint8_t rec[PFD_TLS_HDR + PFD_TLS_BODY_MAX];
    int len, before = -1; /* bytes held before the last record given */

    for (;;) {
        int64_t deadline;
        len = tls_held(c, why);
        if (len > 0) {
            __atomic_store_n(&c->busy, 1, SEQ);
            c->empty = 0;
            memcpy(req, c->held, (size_t)len);
            c->n_held -= len;
            memmove(c->held, c->held + len, (size_t)c->n_held);
            return len;
        }
        if (len < 0)
            return len;
        __atomic_store_n(&c->busy, 0, SEQ); /* holds no whole frame */
        if (c->n_held == before) { /* the last record brought nothing */
            if (++c->empty > TLS_EMPTY_MAX) {
                *why = "empty-records";
                return PFD_CONN_CLOSED;
            }
            deadline = deadline_of(c);
            if (deadline > 0 && pfd_now_ns() >= deadline) {
                *why = deadline_why(c);
                return PFD_CONN_TIMEOUT;
            }
            /* no request begun: back to the idle wait, not the byte gap */
            if (c->n_held == 0)
                return 0;
        }
        len = take_unit(c, rec, why);
        if (len < 0)
            return len;
        if (pfd_conn_give(&c->conn, rec, (size_t)len) != 0) {
            *why = "out-of-memory";
            return PFD_CONN_CLOSED;
        }
        before = c->n_held;
    }
}

static void *client_main(void *arg)
{
    pfd_client *c = (pfd_client *)arg;
    pfd_daemon *d = c->d;
    pfd_session *s = calloc(1, sizeof *s);
    uint8_t req[PFD_ADU_MAX], rsp[PFD_ADU_MAX];
    char role[PFD_ROLE_NAME_MAX] = "plain";
    const char *why = "closed";

    if (s == NULL) {
        why = "out-of-memory";
        goto out;
    }
    s->who.id = c->id;
    s->who.peer = c->peer;
    s->who.role = role;
    s->who.access = d->set.plain_access;
    if (c->tls && tls_start(c, s, role, sizeof role, &why) != 0)
        goto out;
    pfd_log(PFD_LOG_DEBUG, "client-connected", "peer=%s role=%s access=%s", c->peer, role,
            pfd_access_name(s->who.access));

    while (!pfd_stopping(d)) {
        int64_t deadline;
        int rc, len, next;

        /* a TLS thread may hold the start of its next request already */
        rc = c->n_held > 0 ? 1 : pfd_conn_wait(&c->conn, POLL_MS);
        if (rc > 0)
            __atomic_store_n(&c->heard, 1, __ATOMIC_RELEASE);
        if (__atomic_load_n(&c->evicted, __ATOMIC_ACQUIRE)) {
            why = "evicted";
            break;
        }
        if (rc < 0) {
            why = "poll-error";
            break;
        }
        if (rc == 0) {
            deadline = deadline_of(c);
            /* Look once more: the thread may have slept past the deadline
             * after a poll that found nothing, while bytes came in time. */
            if (deadline > 0 && pfd_now_ns() >= deadline && pfd_conn_wait(&c->conn, 0) == 0) {
                why = deadline_why(c);
                break;
            }
            continue;
        }
        len = c->tls ? read_tls(c, req, &why) : take_unit(c, req, &why);
        if (len < 0)
            break;
        if (len == 0)
            continue;
        rc = pfd_request(d, s, req, len, rsp);
        if (rc < 0) {
            why = pfd_stopping(d) ? "shutdown" : "bad-frame";
        } else if (pfd_conn_write(&c->conn, rsp, (size_t)rc, SEND_TIMEOUT_MS) != 0) {
            why = "send-failed";
            rc = -1;
        }
        /* in this order: see slot_view() */
        __atomic_store_n(&c->since_ns, pfd_now_ns(), SEQ);
        __atomic_store_n(&c->active, 1, SEQ);
        /* still busy if a TLS thread holds its next request whole; what
         * it holds may instead end the connection (a bad frame, a record
         * that does not decrypt): then with that reason */
        next = rc >= 0 && c->tls ? tls_held(c, &why) : 0;
        if (next < 0)
            rc = -1;
        __atomic_store_n(&c->busy, next > 0, SEQ);
        if (rc < 0)
            break;
    }
    if (pfd_stopping(d))
        why = "shutdown";
    /* an eviction is why, whichever read or write its shutdown() broke */
    if (__atomic_load_n(&c->evicted, SEQ))
        why = "evicted";
out:
    if (s != NULL) {
        pfd_session_end(d, s);
        free(s);
    }
    pfd_log(PFD_LOG_DEBUG, "client-closed", "peer=%s reason=%s", c->peer, why);
    pfd_conn_end_tls(&c->conn);
    /* reap() closes the fd after the join, so that pfd_server_stop() and
     * an eviction can shutdown() any fd of a slot in use without racing a
     * reuse of its number. */
    __atomic_store_n(&c->done, 1, __ATOMIC_RELEASE);
    return NULL;
}

/* ---- accept thread ----------------------------------------------------- */

/* Under clients_mx. */
static void reap(pfd_daemon *d, int all)
{
    int i;
    for (i = 0; i < d->server.n_slots; i++) {
        pfd_client *c = &d->server.clients[i];
        if (c->in_use && (all || __atomic_load_n(&c->done, __ATOMIC_ACQUIRE))) {
            pthread_join(c->th, NULL);
            close(c->conn.fd);
            c->in_use = 0;
        }
    }
}

static void refuse(int fd, const char *peer, const char *why)
{
    if (pfd_log_ratelimit(&rl_refused))
        pfd_log(PFD_LOG_WARN, "client-refused", "peer=%s reason=%s", peer, why);
    close(fd);
}

/* Under clients_mx: tell @p v to go; its thread ends within a poll. */
static void evict(pfd_client *v, const char *for_peer, const char *why)
{
    __atomic_store_n(&v->evicted, 1, __ATOMIC_RELEASE);
    shutdown(v->conn.fd, SHUT_RDWR);
    if (pfd_log_ratelimit(&rl_evicted))
        pfd_log(PFD_LOG_WARN, "client-evicted", "peer=%s active=%d idle_ms=%lld for=%s reason=%s",
                v->peer, __atomic_load_n(&v->active, __ATOMIC_ACQUIRE),
                (long long)((pfd_now_ns() - __atomic_load_n(&v->since_ns, __ATOMIC_ACQUIRE)) /
                            1000000),
                for_peer, why);
}

/* What waits unread in the socket of @p c, a slot in use, because its
 * thread has not got round to it (under load, or before it first runs):
 * *heard if any byte, *pending if a whole request (pfd_slots.h: such a
 * client is late only by the daemon's fault). Its thread never holds part
 * of a unit (take_unit()), so the first bytes waiting are a unit's start:
 * on plain TCP a frame, whole or not; on TLS, past the handshake, a
 * record. A whole application-data record waiting is judged a request: it
 * may hold only part of one, or none (TLS 1.3 gives alerts and key updates
 * the same outer type), but only an authenticated client gets that far, a
 * record that does not decrypt or holds a bad frame ends the connection,
 * and read_tls() bounds records that bring nothing by a count and the
 * deadlines. The thread counts each unit, after saying busy, before it
 * takes it: a count that moved during the look means the look may have
 * seen the socket after the thread took from it. On plain TCP the look
 * then judges nothing (busy, loaded after, tells: the request is being
 * served); on TLS the thread may have taken a record that did not complete
 * its request, with the rest whole behind it, so the slot counts as
 * pending for this look: its thread is running, not late. During the
 * handshake nothing is pending: anyone can send a ClientHello, and
 * first_request_timeout_ms bounds that wait. tls_up is loaded before the
 * look: its thread sets it only once the handshake has read its last
 * record, the client's Finished, which TLS 1.3 sends with the outer type
 * of application data; a flag loaded after the look could be set while the
 * look saw that Finished waiting, and judge it a request. */
static void unread(const pfd_client *c, int *heard, int *pending)
{
    uint8_t h[PFD_MBAP_LEN]; /* a record's header is shorter */
    ssize_t k;
    int frames, len, moved, up, whole;

    up = c->tls && __atomic_load_n(&c->tls_up, SEQ);
    frames = __atomic_load_n(&c->frames, SEQ);
    len = peek_unit(c->tls, c->conn.fd, h, &k);
    moved = __atomic_load_n(&c->frames, SEQ) != frames;
    if (k > 0)
        *heard = 1;
    whole = len > 0 && k >= len; /* then h holds this look's header */
    *pending = pfd_slots_pending(c->tls, up, moved, whole,
                                 whole && c->tls && h[0] == PFD_TLS_APP_DATA);
}

/* Whether client @p id holds a lock: a holder is never evicted, or a
 * flood of connections could take the lock from it (its disconnect
 * releases it). */
static int holds_lock(pfd_daemon *d, uint64_t id)
{
    int i, held = 0;
    pthread_mutex_lock(&d->regs_mx);
    for (i = 0; i < d->n && !held; i++)
        held = d->inst[i]->param_lock && d->inst[i]->lock_holder == id;
    pthread_mutex_unlock(&d->regs_mx);
    return held;
}

/* Under clients_mx: what the slot policy knows of @p c, in the reverse
 * order of its thread's stores (pending, then busy, active, since_ns), so
 * that a request that ends between two loads never shows a client that
 * has just been served as a newcomer. The socket is looked at only if
 * @p look (unread() costs two system calls). */
static void slot_view(pfd_daemon *d, const pfd_client *c, int look, pfd_slot_view *v)
{
    v->in_use = c->in_use;
    v->evicted = __atomic_load_n(&c->evicted, SEQ) || __atomic_load_n(&c->done, SEQ);
    v->heard = __atomic_load_n(&c->heard, SEQ);
    v->pending = 0;
    if (look && c->in_use && !v->evicted)
        unread(c, &v->heard, &v->pending);
    v->busy = __atomic_load_n(&c->busy, SEQ) || (c->in_use && holds_lock(d, c->id));
    v->active = __atomic_load_n(&c->active, SEQ);
    v->since_ns = __atomic_load_n(&c->since_ns, SEQ);
    v->addr = c->addr;
}

/* Under clients_mx: a slot for a client from @p addr, evicting one if
 * the policy says so. @return the slot, or NULL with @p why. The sockets
 * are looked at only when the policy picks a victim, and only the
 * victim's: what a look adds (bytes came, a request waits) only makes a
 * slot a worse victim, so a victim that a look confirms is the one a look
 * at every slot would have picked. At most one look per slot. */
static pfd_client *take_slot(pfd_daemon *d, uint32_t addr, const char *peer, const char **why)
{
    pfd_slot_view v[512];
    char looked[512] = {0};
    pfd_slot_choice ch;
    int i, n = d->server.n_slots;

    for (i = 0; i < n; i++)
        slot_view(d, &d->server.clients[i], 0, &v[i]);
    for (;;) {
        ch = pfd_slots_choose(v, n, addr, d->set.max_clients, d->set.max_per_addr, pfd_now_ns(),
                              (int64_t)d->set.first_request_ms * 1000000);
        if (ch.victim < 0 || looked[ch.victim])
            break;
        looked[ch.victim] = 1;
        slot_view(d, &d->server.clients[ch.victim], 1, &v[ch.victim]);
    }
    *why = ch.why;
    if (ch.slot < 0)
        return NULL;
    if (ch.victim >= 0)
        evict(&d->server.clients[ch.victim], peer, ch.why);
    return &d->server.clients[ch.slot];
}

/* Out of fds: accept the waiting connection on the spare fd and close it,
 * so the client learns at once instead of timing out, and the listener
 * does not stay readable (which made the accept loop spin). */
static void shed(pfd_daemon *d, int lfd)
{
    int fd;
    if (d->server.reserve_fd >= 0) {
        close(d->server.reserve_fd);
        fd = accept(lfd, NULL, NULL);
        if (fd >= 0)
            close(fd);
        d->server.reserve_fd = open("/dev/null", O_RDONLY | O_CLOEXEC);
    }
}

/* Accept one connection on @p lfd (the TLS listener if @p tls). */
static void accept_one(pfd_daemon *d, int lfd, int tls)
{
    struct sockaddr_in sa;
    socklen_t sl = sizeof sa;
    char peer[48], ip[INET_ADDRSTRLEN];
    pthread_attr_t attr;
    pfd_client *c;
    const char *why;
    uint32_t addr;
    int fd, one = 1;

    fd = accept(lfd, (struct sockaddr *)&sa, &sl);
    if (fd >= 0 && (fcntl(fd, F_SETFD, FD_CLOEXEC) != 0 ||
                    fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK) != 0)) {
        close(fd);
        return;
    }
    if (fd < 0) {
        if (errno == EMFILE || errno == ENFILE || errno == ENOBUFS || errno == ENOMEM) {
            if (pfd_log_ratelimit(&rl_accept))
                pfd_log(PFD_LOG_ERROR, "accept-failed", "error=\"%s\" action=refused",
                        strerror(errno));
            shed(d, lfd);
            /* No fd was freed: do not come back at once. */
            if (d->server.reserve_fd < 0)
                poll(NULL, 0, 100);
        }
        return;
    }
    if (sa.sin_family != AF_INET || inet_ntop(AF_INET, &sa.sin_addr, ip, sizeof ip) == NULL)
        strcpy(ip, "?");
    snprintf(peer, sizeof peer, "%s:%u", ip, (unsigned)ntohs(sa.sin_port));
    addr = ntohl(sa.sin_addr.s_addr);
    if (sa.sin_family != AF_INET || !pfd_allow_match(&d->server.allow, addr)) {
        refuse(fd, peer, "not-in-allow-list");
        return;
    }
    pthread_mutex_lock(&d->server.clients_mx);
    reap(d, 0);
    c = take_slot(d, addr, peer, &why);
    if (c == NULL) {
        pthread_mutex_unlock(&d->server.clients_mx);
        refuse(fd, peer, why);
        return;
    }
    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    memset(c, 0, sizeof *c);
    c->d = d;
    c->conn.fd = fd;
    c->tls = tls;
    c->addr = addr;
    c->id = ++d->server.next_id;
    c->since_ns = pfd_now_ns();
    strcpy(c->peer, peer);
    pthread_attr_init(&attr);
    pthread_attr_setstacksize(&attr, CLIENT_STACK);
    if (pthread_create(&c->th, &attr, client_main, c) != 0) {
        pthread_attr_destroy(&attr);
        pthread_mutex_unlock(&d->server.clients_mx);
        refuse(fd, peer, "thread-create-failed");
        return;
    }
    pthread_attr_destroy(&attr);
    c->in_use = 1;
    pthread_mutex_unlock(&d->server.clients_mx);
}

static void *accept_main(void *arg)
{
    pfd_daemon *d = (pfd_daemon *)arg;

    while (!pfd_stopping(d)) {
        struct pollfd p[2];
        int n = 0, i;

        pthread_mutex_lock(&d->server.clients_mx);
        reap(d, 0);
        pthread_mutex_unlock(&d->server.clients_mx);
        if (d->server.listen_fd >= 0) {
            p[n].fd = d->server.listen_fd;
            p[n].events = POLLIN;
            p[n++].revents = 0;
        }
        if (d->server.tls_fd >= 0) {
            p[n].fd = d->server.tls_fd;
            p[n].events = POLLIN;
            p[n++].revents = 0;
        }
        if (poll(p, (nfds_t)n, POLL_MS) <= 0)
            continue;
        for (i = 0; i < n; i++)
            if (p[i].revents & POLLIN)
                accept_one(d, p[i].fd, p[i].fd == d->server.tls_fd);
    }
    return NULL;
}

/* ---- start and stop ---------------------------------------------------- */

static void close_fd(int *fd)
{
    if (*fd >= 0) {
        close(*fd);
        *fd = -1;
    }
}

/* A listening socket on @p ep. @return the fd (its port in @p port), or
 * -1 after a fatal message. */
static int listen_on(const pfd_endpoint *ep, const char *what, unsigned *port)
{
    struct sockaddr_in sa;
    socklen_t sl = sizeof sa;
    int one = 1, fd;

    memset(&sa, 0, sizeof sa);
    sa.sin_family = AF_INET;
    sa.sin_port = htons((uint16_t)ep->port);
    if (inet_pton(AF_INET, ep->addr, &sa.sin_addr) != 1) {
        pfd_fatal("%s: '%s' is not an IPv4 address", what, ep->addr);
        return -1;
    }
    fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
    if (fd < 0) {
        pfd_fatal("socket: %s", strerror(errno));
        return -1;
    }
    setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    if (bind(fd, (struct sockaddr *)&sa, sizeof sa) != 0 || listen(fd, 64) != 0) {
        pfd_fatal("cannot listen on %s:%d: %s", ep->addr, ep->port, strerror(errno));
        close(fd);
        return -1;
    }
    getsockname(fd, (struct sockaddr *)&sa, &sl);
    *port = ntohs(sa.sin_port);
    return fd;
}

/* Room for every client, both listeners and the spare: raise the soft fd
 * limit as far as the hard one allows, and say so if that is not enough
 * (clients beyond it are refused, see shed()). */
static void fd_budget(const pfd_daemon *d)
{
    struct rlimit rl;
    rlim_t need = (rlim_t)d->server.n_slots + 32;
    if (getrlimit(RLIMIT_NOFILE, &rl) != 0 || rl.rlim_cur >= need)
        return;
    rl.rlim_cur = rl.rlim_max == RLIM_INFINITY || rl.rlim_max >= need ? need : rl.rlim_max;
    (void)setrlimit(RLIMIT_NOFILE, &rl);
    if (getrlimit(RLIMIT_NOFILE, &rl) == 0 && rl.rlim_cur < need)
        pfd_log(PFD_LOG_WARN, "fd-limit", "limit=%llu wanted=%llu",
                (unsigned long long)rl.rlim_cur, (unsigned long long)need);
}

int pfd_server_start(pfd_daemon *d)
{
    char err[400];
    unsigned port = 0, tls_port = 0;

    d->server.listen_fd = d->server.tls_fd = d->server.reserve_fd = -1;
    if (pfd_allow_parse(d->set.allow, &d->server.allow, err, sizeof err) != 0) {
        pfd_fatal("allow: %s", err);
        return -1;
    }
    d->server.n_slots = 2 * d->set.max_clients;
    d->server.clients = calloc((size_t)d->server.n_slots, sizeof *d->server.clients);
    if (d->server.clients == NULL) {
        pfd_fatal("out of memory");
        pfd_server_stop(d);
        return -1;
    }
    fd_budget(d);
    if ((d->set.plain_access != PFD_ACCESS_NONE &&
         (d->server.listen_fd = listen_on(&d->set.listen, "--listen", &port)) < 0) ||
        (d->server.tls != NULL &&
         (d->server.tls_fd = listen_on(&d->set.tls_listen, "--tls-listen", &tls_port)) < 0)) {
        pfd_server_stop(d);
        return -1;
    }
    d->server.reserve_fd = open("/dev/null", O_RDONLY | O_CLOEXEC);
    if (pthread_create(&d->server.accept_th, NULL, accept_main, d) != 0) {
        pfd_fatal("cannot start the accept thread");
        pfd_server_stop(d);
        return -1;
    }
    d->server.accept_running = 1;
    if (d->server.tls_fd >= 0)
        pfd_log(PFD_LOG_INFO, "listening-tls", "addr=%s port=%u roles=\"%s\"",
                d->set.tls_listen.addr, tls_port, d->set.tls_roles);
    /* Last: tests and scripts wait for this line. */
    pfd_log(PFD_LOG_INFO, "listening",
            "addr=%s port=%u max_clients=%d max_clients_per_addr=%d allow=\"%s\" "
            "read_only=%d plain_access=%s",
            d->server.listen_fd >= 0 ? d->set.listen.addr : "none", port, d->set.max_clients,
            d->set.max_per_addr, d->set.allow[0] ? d->set.allow : PFD_ALLOW_DEFAULT,
            d->set.read_only, pfd_access_name(d->set.plain_access));
    return 0;
}

void pfd_server_stop(pfd_daemon *d)
{
    int i;
    pfd_request_stop(d);
    if (d->server.accept_running) {
        pthread_join(d->server.accept_th, NULL);
        d->server.accept_running = 0;
    }
    close_fd(&d->server.listen_fd);
    close_fd(&d->server.tls_fd);
    close_fd(&d->server.reserve_fd);
    if (d->server.clients != NULL) {
        pthread_mutex_lock(&d->server.clients_mx);
        for (i = 0; i < d->server.n_slots; i++)
            if (d->server.clients[i].in_use)
                shutdown(d->server.clients[i].conn.fd, SHUT_RDWR);
        reap(d, 1);
        pthread_mutex_unlock(&d->server.clients_mx);
        free(d->server.clients);
        d->server.clients = NULL;
    }
    pfd_tls_free(d->server.tls);
    d->server.tls = NULL;
}
