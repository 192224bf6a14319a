/* SPDX-License-Identifier: MIT */
#include "pfd_modbus.h"

#include <arpa/inet.h>
#include <errno.h>
#include <modbus/modbus.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <stdlib.h>
#include <string.h>
#include <sys/select.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include "pfd_addr.h"
#include "pfd_commit.h"
#include "pfd_log.h"
#include "pfd_loop.h"
#include "pfd_regmap.h"

#define MBAP_LEN 7
#define CLIENT_STACK (256 * 1024)

/* One slot of pfd_daemon.server.clients. */
typedef struct pfd_client {
    pfd_daemon *d;
    pthread_t th;
    int fd;
    int in_use; /* slot taken (under clients_mx) */
    int done;   /* thread finished, join pending (atomic) */
    char peer[48];
} pfd_client;

static unsigned be16(const uint8_t *p) { return ((unsigned)p[0] << 8) | p[1]; }

/* ---- one request ------------------------------------------------------- */

typedef struct reqctx {
    pfd_daemon *d;
    modbus_t *ctx;
    modbus_mapping_t *map;
    const uint8_t *req;
    int len;
} reqctx;

static int reply_exc(reqctx *r, int code)
{
    return modbus_reply_exception(r->ctx, r->req, (unsigned)code) < 0 ? -1 : 0;
}

/* Render every register of @p space into the scratch mapping that
 * modbus_reply() reads from. */
static void fill(reqctx *r, pfd_inst *in, int space)
{
    uint16_t img[PFD_INPUT_SIZE > PFD_HOLD_SIZE ? PFD_INPUT_SIZE : PFD_HOLD_SIZE];
    pfd_view v;

    pthread_mutex_lock(&r->d->regs_mx);
    v.inst = in;
    v.snap = (const pfd_snap *)pfd_tbuf_latest(&in->out_tb);
    v.status = pfd_status_bits(r->d, in, v.snap);
    v.n_instances = (uint16_t)r->d->n;
    pfd_regmap_render(space, &v, img);
    pthread_mutex_unlock(&r->d->regs_mx);
    memcpy(space == PFD_HOLD ? r->map->tab_registers : r->map->tab_input_registers,
           img, (space == PFD_HOLD ? PFD_HOLD_SIZE : PFD_INPUT_SIZE) * sizeof img[0]);
}

/* Validated writes: state checks, then data, commit, command, tick.
 * @return 0 done, > 0 MODBUS_EXCEPTION_* code, -1 drop the connection. */
static int execute(reqctx *r, pfd_inst *in, const pfd_wlist *wl)
{
    pfd_daemon *d = r->d;
    int rc;

    pthread_mutex_lock(&d->regs_mx);
    rc = 0;
    /* Discarding the staged set changes staged registers too, so the lock
     * refuses it like a staged write. */
    if ((wl->staged || wl->commit || wl->command == 1) && in->hold.param_lock)
        rc = MODBUS_EXCEPTION_ILLEGAL_FUNCTION;
    if (wl->lock && d->set.param_lock) {
        unsigned i;
        for (i = 0; i < wl->n; i++)
            if (!strcmp(wl->w[i].r->name, "param_lock") && wl->w[i].v != 1.0)
                rc = MODBUS_EXCEPTION_ILLEGAL_FUNCTION;
    }
    if (wl->tick && !d->set.external_clock)
        rc = MODBUS_EXCEPTION_ILLEGAL_FUNCTION;
    if (rc != 0 || wl->commit) {
        pthread_mutex_unlock(&d->regs_mx);
        if (rc != 0)
            return rc;
        rc = pfd_commit(d, in, wl);
        if (rc != 0)
            return rc;
    } else {
        pfd_regmap_apply(&in->hold, &in->committed, wl);
        if (wl->live)
            pfd_publish_live(in);
        if (wl->command == 1)
            in->hold.staged = in->committed;
        pthread_mutex_unlock(&d->regs_mx);
    }
    if (wl->command == 2)
        __atomic_add_fetch(&in->reset_req, 1u, __ATOMIC_ACQ_REL);
    else if (wl->command == 3)
        __atomic_add_fetch(&in->stats_req, 1u, __ATOMIC_ACQ_REL);
    if (wl->tick && pfd_loop_tick(d, in, wl->tick) != 0)
        return -1;
    return 0;
}

/* Decode and apply a write of @p cnt registers from @p addr, whose values
 * start at @p payload. @return 0, > 0 MODBUS_EXCEPTION_* (already
 * answered) or -1 (drop the connection). */
static int write_regs(reqctx *r, pfd_inst *in, unsigned addr, unsigned cnt,
                      const uint8_t *payload)
{
    uint16_t vals[MODBUS_MAX_WRITE_REGISTERS];
    pfd_wlist wl;
    unsigned i;
    int rc;

    for (i = 0; i < cnt; i++)
        vals[i] = (uint16_t)be16(payload + 2 * i);
    rc = pfd_regmap_decode(addr, cnt, vals, &wl);
    if (rc == 0)
        rc = execute(r, in, &wl);
    if (rc > 0 && reply_exc(r, rc) != 0)
        return -1;
    return rc;
}

static int handle(reqctx *r)
{
    pfd_daemon *d = r->d;
    const uint8_t *req = r->req, *pdu;
    unsigned fc, pdu_len, addr, cnt;
    pfd_inst *in;
    uint8_t patched[MODBUS_TCP_MAX_ADU_LENGTH]; /* FC23's answer, see there */
    unsigned i;
    int rc;

    /* libmodbus frames by function code and ignores the MBAP length and
     * protocol id; a mismatch means the byte stream cannot be trusted. */
    if (r->len < MBAP_LEN + 1 || be16(req + 2) != 0 ||
        be16(req + 4) != (unsigned)(r->len - 6))
        return -1;
    in = d->by_unit[req[6]];
    fc = req[7];
    pdu = req + MBAP_LEN;
    pdu_len = (unsigned)(r->len - MBAP_LEN);
    if (in == NULL)
        return reply_exc(r, MODBUS_EXCEPTION_GATEWAY_TARGET);

    switch (fc) {
    case MODBUS_FC_READ_HOLDING_REGISTERS:
    case MODBUS_FC_READ_INPUT_REGISTERS: {
        int space = fc == MODBUS_FC_READ_HOLDING_REGISTERS ? PFD_HOLD : PFD_INPUT;
        unsigned size = space == PFD_HOLD ? PFD_HOLD_SIZE : PFD_INPUT_SIZE;
        if (pdu_len != 5)
            return -1;
        addr = be16(pdu + 1);
        cnt = be16(pdu + 3);
        if (cnt < 1 || cnt > MODBUS_MAX_READ_REGISTERS)
            return reply_exc(r, MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE);
        if (addr + cnt > size)
            return reply_exc(r, MODBUS_EXCEPTION_ILLEGAL_DATA_ADDRESS);
        fill(r, in, space);
        break;
    }
    case MODBUS_FC_WRITE_SINGLE_REGISTER:
        if (pdu_len != 5)
            return -1;
        if (d->set.read_only)
            return reply_exc(r, MODBUS_EXCEPTION_ILLEGAL_FUNCTION);
        rc = write_regs(r, in, be16(pdu + 1), 1, pdu + 3);
        if (rc != 0)
            return rc < 0 ? -1 : 0;
        break;
    case MODBUS_FC_WRITE_MULTIPLE_REGISTERS:
        if (pdu_len < 6)
            return -1;
        if (d->set.read_only)
            return reply_exc(r, MODBUS_EXCEPTION_ILLEGAL_FUNCTION);
        addr = be16(pdu + 1);
        cnt = be16(pdu + 3);
        if (cnt < 1 || cnt > MODBUS_MAX_WRITE_REGISTERS || pdu[5] != cnt * 2 ||
            pdu_len != 6 + cnt * 2)
            return reply_exc(r, MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE);
        rc = write_regs(r, in, addr, cnt, pdu + 6);
        if (rc != 0)
            return rc < 0 ? -1 : 0;
        break;
    case MODBUS_FC_WRITE_AND_READ_REGISTERS: {
        unsigned waddr, wcnt;
        if (pdu_len < 10)
            return -1;
        if (d->set.read_only)
            return reply_exc(r, MODBUS_EXCEPTION_ILLEGAL_FUNCTION);
        addr = be16(pdu + 1);
        cnt = be16(pdu + 3);
        waddr = be16(pdu + 5);
        wcnt = be16(pdu + 7);
        if (cnt < 1 || cnt > MODBUS_MAX_WR_READ_REGISTERS || wcnt < 1 ||
            wcnt > MODBUS_MAX_WR_WRITE_REGISTERS || pdu[9] != wcnt * 2 ||
            pdu_len != 10 + wcnt * 2)
            return reply_exc(r, MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE);
        if (addr + cnt > PFD_HOLD_SIZE)
            return reply_exc(r, MODBUS_EXCEPTION_ILLEGAL_DATA_ADDRESS);
        rc = write_regs(r, in, waddr, wcnt, pdu + 10);
        if (rc != 0)
            return rc < 0 ? -1 : 0;
        /* Read after the write, as the function code specifies. But
         * libmodbus 3.1.6 copies the written values into the mapping
         * before it reads, so registers the two ranges share would echo
         * the raw write (tick, commit or command instead of 0, e_i16
         * before rounding). Answer from a copy of the request whose write
         * payload is what the registers now read. */
        fill(r, in, PFD_HOLD);
        memcpy(patched, req, (size_t)r->len);
        for (i = 0; i < wcnt; i++) {
            uint16_t v = r->map->tab_registers[waddr + i];
            patched[MBAP_LEN + 10 + 2 * i] = (uint8_t)(v >> 8);
            patched[MBAP_LEN + 11 + 2 * i] = (uint8_t)(v & 0xFFu);
        }
        req = patched;
        break;
    }
    default:
        return reply_exc(r, MODBUS_EXCEPTION_ILLEGAL_FUNCTION);
    }
    /* Validated above, so modbus_reply() only frames the answer: reads
     * come from the scratch mapping just filled, writes are echoed. */
    return modbus_reply(r->ctx, req, r->len, r->map) < 0 ? -1 : 0;
}

/* ---- client thread ----------------------------------------------------- */

/* libmodbus 3.1.6 reads no data at all for function codes it does not know
 * (it frames by function code, not by the MBAP length). Read the rest of
 * such a PDU as the MBAP header announces it, so that the request can be
 * answered with exception 01 and the stream stays in step.
 * @return the full ADU length, or -1. */
static int read_rest(int fd, uint8_t *req, int have, int timeout_ms)
{
    unsigned mlen = be16(req + 4);
    int want;

    if (have != MBAP_LEN + 1 || mlen <= 2 || mlen > MODBUS_TCP_MAX_ADU_LENGTH - 6)
        return have;
    want = 6 + (int)mlen;
    while (have < want) {
        struct pollfd pfd;
        ssize_t n;
        pfd.fd = fd;
        pfd.events = POLLIN;
        pfd.revents = 0;
        if (poll(&pfd, 1, timeout_ms) <= 0)
            return -1;
        n = recv(fd, req + have, (size_t)(want - have), 0);
        if (n <= 0)
            return -1;
        have += (int)n;
    }
    return have;
}

static void *client_main(void *arg)
{
    pfd_client *c = (pfd_client *)arg;
    pfd_daemon *d = c->d;
    uint8_t req[MODBUS_TCP_MAX_ADU_LENGTH];
    modbus_t *ctx = modbus_new_tcp("127.0.0.1", 502);
    modbus_mapping_t *map = modbus_mapping_new_start_address(
        0, 0, 0, 0, 0, PFD_HOLD_SIZE, 0, PFD_INPUT_SIZE);
    const char *why = "closed";
    uint32_t bt_s = (uint32_t)(d->set.byte_timeout_ms / 1000);
    uint32_t bt_us = (uint32_t)(d->set.byte_timeout_ms % 1000) * 1000u;
    long idle_ms = 0;

    if (ctx == NULL || map == NULL) {
        why = "out-of-memory";
        goto out;
    }
    modbus_set_socket(ctx, c->fd);
    /* libmodbus 3.1.6 waits this long for each further byte of a frame;
     * a client that stalls mid-frame is dropped after it. */
    modbus_set_byte_timeout(ctx, bt_s, bt_us);
    modbus_set_indication_timeout(ctx, bt_s, bt_us);
    modbus_set_response_timeout(ctx, bt_s, bt_us);

    while (!pfd_stopping(d)) {
        struct pollfd pfd;
        reqctx r;
        int rc;

        pfd.fd = c->fd;
        pfd.events = POLLIN;
        pfd.revents = 0;
        rc = poll(&pfd, 1, 200);
        if (rc < 0 && errno != EINTR) {
            why = "poll-error";
            break;
        }
        if (rc <= 0) {
            idle_ms += 200;
            if (d->set.idle_timeout_s > 0 && idle_ms >= 1000L * d->set.idle_timeout_s) {
                why = "idle-timeout";
                break;
            }
            continue;
        }
        idle_ms = 0;
        rc = modbus_receive(ctx, req);
        if (rc < 0) {
            why = errno == ECONNRESET ? "peer-closed"
                  : errno == ETIMEDOUT ? "byte-timeout"
                                       : "bad-frame";
            break;
        }
        if (rc == 0)
            continue;
        rc = read_rest(c->fd, req, rc, d->set.byte_timeout_ms);
        if (rc < 0) {
            why = "byte-timeout";
            break;
        }
        r.d = d;
        r.ctx = ctx;
        r.map = map;
        r.req = req;
        r.len = rc;
        if (handle(&r) != 0) {
            why = pfd_stopping(d) ? "shutdown" : "bad-frame-or-send-error";
            break;
        }
    }
    if (pfd_stopping(d))
        why = "shutdown";
out:
    pfd_log(PFD_LOG_DEBUG, "client-closed", "peer=%s reason=%s", c->peer, why);
    if (map != NULL)
        modbus_mapping_free(map);
    if (ctx != NULL)
        modbus_free(ctx); /* does not close the socket */
    /* reap() closes the fd after the join, so pfd_server_stop() can
     * shutdown() any fd of a slot in use without racing a reuse. */
    __atomic_store_n(&c->done, 1, __ATOMIC_RELEASE);
    return NULL;
}

/* ---- accept thread ----------------------------------------------------- */

/* Under clients_mx. */
static void reap(pfd_daemon *d, int all)
{
    int i;
    for (i = 0; i < d->set.max_clients; i++) {
        pfd_client *c = &d->server.clients[i];
        if (c->in_use && (all || __atomic_load_n(&c->done, __ATOMIC_ACQUIRE))) {
            pthread_join(c->th, NULL);
            close(c->fd);
            c->in_use = 0;
        }
    }
}

static void refuse(int fd, const char *peer, const char *why)
{
    pfd_log(PFD_LOG_WARN, "client-refused", "peer=%s reason=%s", peer, why);
    close(fd);
}

static void *accept_main(void *arg)
{
    pfd_daemon *d = (pfd_daemon *)arg;

    while (!pfd_stopping(d)) {
        struct pollfd pfd;
        struct sockaddr_in sa;
        socklen_t sl = sizeof sa;
        char peer[48], ip[INET_ADDRSTRLEN];
        pthread_attr_t attr;
        int fd, i, one = 1;
        pfd_client *c = NULL;
        struct timeval tv;

        pthread_mutex_lock(&d->server.clients_mx);
        reap(d, 0);
        pthread_mutex_unlock(&d->server.clients_mx);

        pfd.fd = d->server.listen_fd;
        pfd.events = POLLIN;
        pfd.revents = 0;
        if (poll(&pfd, 1, 200) <= 0)
            continue;
        fd = accept(d->server.listen_fd, (struct sockaddr *)&sa, &sl);
        if (fd < 0)
            continue;
        if (sa.sin_family != AF_INET || inet_ntop(AF_INET, &sa.sin_addr, ip, sizeof ip) == NULL)
            strcpy(ip, "?");
        snprintf(peer, sizeof peer, "%s:%u", ip, (unsigned)ntohs(sa.sin_port));
        if (fd >= FD_SETSIZE) {
            refuse(fd, peer, "fd-above-FD_SETSIZE");
            continue;
        }
        if (sa.sin_family != AF_INET || !pfd_allow_match(&d->server.allow, ntohl(sa.sin_addr.s_addr))) {
            refuse(fd, peer, "not-in-allow-list");
            continue;
        }
        pthread_mutex_lock(&d->server.clients_mx);
        reap(d, 0);
        for (i = 0; i < d->set.max_clients && c == NULL; i++)
            if (!d->server.clients[i].in_use)
                c = &d->server.clients[i];
        if (c == NULL) {
            pthread_mutex_unlock(&d->server.clients_mx);
            refuse(fd, peer, "max-clients");
            continue;
        }
        setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
        /* A client that never reads its answers fails a send after 1 s
         * instead of holding its thread forever. */
        tv.tv_sec = 1;
        tv.tv_usec = 0;
        setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof tv);
        memset(c, 0, sizeof *c);
        c->d = d;
        c->fd = fd;
        strcpy(c->peer, peer);
        pthread_attr_init(&attr);
        pthread_attr_setstacksize(&attr, CLIENT_STACK);
        if (pthread_create(&c->th, &attr, client_main, c) != 0) {
            pthread_attr_destroy(&attr);
            pthread_mutex_unlock(&d->server.clients_mx);
            refuse(fd, peer, "thread-create-failed");
            continue;
        }
        pthread_attr_destroy(&attr);
        c->in_use = 1;
        pthread_mutex_unlock(&d->server.clients_mx);
        pfd_log(PFD_LOG_DEBUG, "client-connected", "peer=%s", peer);
    }
    return NULL;
}

static void close_listener(pfd_daemon *d)
{
    if (d->server.listen_fd >= 0) {
        close(d->server.listen_fd);
        d->server.listen_fd = -1;
    }
}

int pfd_server_start(pfd_daemon *d)
{
    struct sockaddr_in sa;
    socklen_t sl = sizeof sa;
    char err[200];
    int one = 1, fd;

    if (pfd_allow_parse(d->set.allow, &d->server.allow, err, sizeof err) != 0) {
        pfd_fatal("allow: %s", err);
        return -1;
    }
    memset(&sa, 0, sizeof sa);
    sa.sin_family = AF_INET;
    sa.sin_port = htons((uint16_t)d->set.listen.port);
    if (inet_pton(AF_INET, d->set.listen.addr, &sa.sin_addr) != 1) {
        pfd_fatal("--listen: '%s' is not an IPv4 address", d->set.listen.addr);
        return -1;
    }
    fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) {
        pfd_fatal("socket: %s", strerror(errno));
        return -1;
    }
    d->server.listen_fd = fd;
    setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    if (bind(fd, (struct sockaddr *)&sa, sizeof sa) != 0 || listen(fd, 32) != 0) {
        pfd_fatal("cannot listen on %s:%d: %s", d->set.listen.addr,
                  d->set.listen.port, strerror(errno));
        close_listener(d);
        return -1;
    }
    getsockname(fd, (struct sockaddr *)&sa, &sl);
    d->server.clients = calloc((size_t)d->set.max_clients, sizeof *d->server.clients);
    if (d->server.clients == NULL) {
        pfd_fatal("out of memory");
        close_listener(d);
        return -1;
    }
    if (pthread_create(&d->server.accept_th, NULL, accept_main, d) != 0) {
        pfd_fatal("cannot start the accept thread");
        free(d->server.clients);
        d->server.clients = NULL;
        close_listener(d);
        return -1;
    }
    d->server.accept_running = 1;
    pfd_log(PFD_LOG_INFO, "listening",
            "addr=%s port=%u max_clients=%d allow=\"%s\" read_only=%d",
            d->set.listen.addr, (unsigned)ntohs(sa.sin_port), d->set.max_clients,
            d->set.allow[0] ? d->set.allow : PFD_ALLOW_DEFAULT, d->set.read_only);
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
    close_listener(d);
    if (d->server.clients == NULL)
        return;
    pthread_mutex_lock(&d->server.clients_mx);
    for (i = 0; i < d->set.max_clients; i++)
        if (d->server.clients[i].in_use)
            shutdown(d->server.clients[i].fd, SHUT_RDWR);
    reap(d, 1);
    pthread_mutex_unlock(&d->server.clients_mx);
    free(d->server.clients);
    d->server.clients = NULL;
}
