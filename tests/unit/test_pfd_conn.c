/* SPDX-License-Identifier: MIT */
/*
 * pneufracd's connection rules that no client can show from outside the
 * process, because each needs the daemon's state held still at one point
 * (docs/pneufracd.md, "Tests that hold the connection still"): a flag
 * set between two loads, bytes that come between two system calls, a
 * thread between two requests of one record, an eviction during a wait.
 *
 * How: this file includes pfd_server.c, so that its own functions
 * (take_unit(), unread(), take_slot(), client_main()) run as the daemon
 * runs them, and the link replaces the system calls and the connection
 * layer below them with the __wrap_ functions here (ld's --wrap, see
 * tests/CMakeLists.txt). The system calls and the waits follow the test's
 * script on a fake descriptor (FAKE_FD to FAKE_FD + N_FAKE - 1) and pass
 * any other to the real call; the TLS session and the Modbus layer are
 * faked for every call (this binary has no real session); the clock is
 * faked while m.clock is set (the default). The daemon's code has no seam
 * for this: the rules are tested in the code that ships, and no table of
 * function pointers has to be kept in step with it.
 *
 * Built twice: test_pfd_conn, and test_pfd_conn_nordhup with POLLRDHUP
 * undefined, as on a platform without it (pfd_server.c's compile-time
 * switch in stream_stuck()).
 */
#define _GNU_SOURCE
#include <poll.h>
#ifdef PFD_TEST_NO_POLLRDHUP
#undef POLLRDHUP
#endif

#include "pfd_server.c"

#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>

#define NS_PER_S 1000000000LL
#define FAKE_FD 1000
#define N_FAKE 8
#define NEWCOMER 0x0a000009u /* 10.0.0.9 */

/* ---- the fakes --------------------------------------------------------- */

/* What waits in one fake socket. */
typedef struct fake_sock {
    uint8_t bytes[64];
    size_t n;              /* bytes come: a read and FIONREAD see them all */
    size_t peek_max;       /* a peek sees at most this many (0: all): the
                              rest came after it */
    int peeks;             /* looks (MSG_PEEK) */
    void (*in_peek)(void); /* runs during a peek */
} fake_sock;

static struct {
    fake_sock sock[N_FAKE];
    int clock;    /* 1: pfd_now_ns() is `now`, and a nap advances it */
    int64_t now;
    int naps;
    short revents;                  /* what a look (poll) on a fake fd reports */
    int (*wait)(int ms);            /* pfd_conn_wait*() on a fake fd */
    int waits, wait_ms[8];
    const uint8_t *plain;           /* TLS: what the record decrypts to */
    size_t n_plain, at_plain;
    int given;                      /* the record was given to the session */
    void (*on_length)(void);        /* runs in each pfd_mbap_length() */
    int requests, stop_after;       /* pfd_request() */
    int looks;
} m;

static pfd_daemon D;
static pfd_client slots[N_FAKE];
static char dummy_ssl;

static fake_sock *fake(int fd)
{
    return fd >= FAKE_FD && fd < FAKE_FD + N_FAKE ? &m.sock[fd - FAKE_FD] : NULL;
}

static void put(fake_sock *s, const uint8_t *b, size_t n)
{
    memcpy(s->bytes, b, n);
    s->n = n;
}

ssize_t __real_recv(int fd, void *buf, size_t n, int flags);
ssize_t __wrap_recv(int fd, void *buf, size_t n, int flags);
ssize_t __wrap_recv(int fd, void *buf, size_t n, int flags)
{
    fake_sock *s = fake(fd);
    size_t k;
    if (s == NULL)
        return __real_recv(fd, buf, n, flags);
    k = s->n;
    if (flags & MSG_PEEK) {
        s->peeks++;
        if (s->in_peek != NULL)
            s->in_peek();
        if (s->peek_max > 0 && k > s->peek_max)
            k = s->peek_max;
    }
    if (k > n)
        k = n;
    if (k == 0) {
        errno = EAGAIN;
        return -1;
    }
    memcpy(buf, s->bytes, k);
    if (!(flags & MSG_PEEK)) {
        memmove(s->bytes, s->bytes + k, s->n - k);
        s->n -= k;
    }
    return (ssize_t)k;
}

int __real_ioctl(int fd, unsigned long req, ...);
int __wrap_ioctl(int fd, unsigned long req, ...);
int __wrap_ioctl(int fd, unsigned long req, ...)
{
    va_list ap;
    void *arg;
    va_start(ap, req);
    arg = va_arg(ap, void *);
    va_end(ap);
    if (fake(fd) == NULL)
        return __real_ioctl(fd, req, arg);
    if (req != FIONREAD)
        return -1;
    *(int *)arg = (int)fake(fd)->n;
    return 0;
}

int __real_poll(struct pollfd *p, nfds_t n, int ms);
int __wrap_poll(struct pollfd *p, nfds_t n, int ms);
int __wrap_poll(struct pollfd *p, nfds_t n, int ms)
{
    if (n != 1 || fake(p->fd) == NULL)
        return __real_poll(p, n, ms);
    /* POLLHUP and POLLERR are reported whether asked or not */
    p->revents = (short)(m.revents & (p->events | POLLHUP | POLLERR));
    return p->revents != 0;
}

int __real_setsockopt(int fd, int level, int name, const void *v, socklen_t n);
int __wrap_setsockopt(int fd, int level, int name, const void *v, socklen_t n);
int __wrap_setsockopt(int fd, int level, int name, const void *v, socklen_t n)
{
    return fake(fd) != NULL ? 0 : __real_setsockopt(fd, level, name, v, n);
}

int __real_shutdown(int fd, int how);
int __wrap_shutdown(int fd, int how);
int __wrap_shutdown(int fd, int how)
{
    return fake(fd) != NULL ? 0 : __real_shutdown(fd, how);
}

int __real_nanosleep(const struct timespec *t, struct timespec *rem);
int __wrap_nanosleep(const struct timespec *t, struct timespec *rem);
int __wrap_nanosleep(const struct timespec *t, struct timespec *rem)
{
    if (!m.clock)
        return __real_nanosleep(t, rem);
    m.naps++;
    m.now += (int64_t)t->tv_sec * NS_PER_S + t->tv_nsec;
    return 0;
}

int64_t __real_pfd_now_ns(void);
int64_t __wrap_pfd_now_ns(void);
int64_t __wrap_pfd_now_ns(void)
{
    return m.clock ? m.now : __real_pfd_now_ns();
}

/* No test needs more than a few hundred waits or naps: a change that stops
 * the fake clock (a nap through a call not faked here) would otherwise
 * spin until ctest's timeout instead of failing. */
#define MAX_FAKE_WAITS 100000

/* A wait on a fake fd: the test's script, else readable if bytes wait. */
static int fake_wait(const pfd_conn *c, int ms)
{
    if (m.waits >= MAX_FAKE_WAITS)
        fail_msg("the thread waits without end (%d waits)", m.waits);
    if (m.waits < 8)
        m.wait_ms[m.waits] = ms;
    m.waits++;
    if (m.wait != NULL)
        return m.wait(ms);
    return fake(c->fd)->n > 0;
}

int __real_pfd_conn_wait(pfd_conn *c, int ms);
int __wrap_pfd_conn_wait(pfd_conn *c, int ms);
int __wrap_pfd_conn_wait(pfd_conn *c, int ms)
{
    return fake(c->fd) != NULL ? fake_wait(c, ms) : __real_pfd_conn_wait(c, ms);
}

int __real_pfd_conn_wait_until(pfd_conn *c, int ms, int64_t deadline_ns);
int __wrap_pfd_conn_wait_until(pfd_conn *c, int ms, int64_t deadline_ns);
int __wrap_pfd_conn_wait_until(pfd_conn *c, int ms, int64_t deadline_ns)
{
    if (fake(c->fd) == NULL)
        return __real_pfd_conn_wait_until(c, ms, deadline_ns);
    return fake_wait(c, ms);
}

/* The TLS session of a fake fd: the handshake succeeds, and a record
 * given decrypts to m.plain (the test's requests). */
struct ssl_st *__wrap_pfd_tls_session(pfd_tls *t, int fd);
struct ssl_st *__wrap_pfd_tls_session(pfd_tls *t, int fd)
{
    (void)t;
    (void)fd;
    return (struct ssl_st *)(void *)&dummy_ssl;
}

int __wrap_pfd_conn_handshake(pfd_conn *c, int64_t deadline_ns, char *why, size_t n);
int __wrap_pfd_conn_handshake(pfd_conn *c, int64_t deadline_ns, char *why, size_t n)
{
    (void)c;
    (void)deadline_ns;
    (void)why;
    (void)n;
    return 0;
}

int __wrap_pfd_tls_peer(pfd_tls *t, struct ssl_st *ssl, char *role, size_t n);
int __wrap_pfd_tls_peer(pfd_tls *t, struct ssl_st *ssl, char *role, size_t n)
{
    (void)t;
    (void)ssl;
    snprintf(role, n, "operator");
    return PFD_ACCESS_OPERATE;
}

int __wrap_pfd_conn_records_only(pfd_conn *c);
int __wrap_pfd_conn_records_only(pfd_conn *c)
{
    (void)c;
    return 0;
}

int __wrap_pfd_conn_give(pfd_conn *c, const void *rec, size_t n);
int __wrap_pfd_conn_give(pfd_conn *c, const void *rec, size_t n)
{
    (void)c;
    (void)rec;
    (void)n;
    m.given = 1;
    return 0;
}

long __wrap_pfd_conn_take(pfd_conn *c, void *buf, size_t n);
long __wrap_pfd_conn_take(pfd_conn *c, void *buf, size_t n)
{
    size_t k = m.given ? m.n_plain - m.at_plain : 0;
    (void)c;
    if (k > n)
        k = n;
    memcpy(buf, m.plain + m.at_plain, k);
    m.at_plain += k;
    return (long)k;
}

int __wrap_pfd_conn_write(pfd_conn *c, const void *buf, size_t n, int ms);
int __wrap_pfd_conn_write(pfd_conn *c, const void *buf, size_t n, int ms)
{
    (void)c;
    (void)buf;
    (void)n;
    (void)ms;
    return 0;
}

void __wrap_pfd_conn_end_tls(pfd_conn *c);
void __wrap_pfd_conn_end_tls(pfd_conn *c)
{
    c->ssl = NULL;
}

/* The Modbus side: an echo, and the daemon stops after m.stop_after. */
int __wrap_pfd_request(pfd_daemon *d, pfd_session *s, const uint8_t *req, int len, uint8_t *rsp);
int __wrap_pfd_request(pfd_daemon *d, pfd_session *s, const uint8_t *req, int len, uint8_t *rsp)
{
    (void)s;
    memcpy(rsp, req, (size_t)len);
    if (++m.requests == m.stop_after)
        pfd_request_stop(d);
    return len;
}

void __wrap_pfd_session_end(pfd_daemon *d, pfd_session *s);
void __wrap_pfd_session_end(pfd_daemon *d, pfd_session *s)
{
    (void)d;
    (void)s;
}

int __real_pfd_mbap_length(const uint8_t *hdr);
int __wrap_pfd_mbap_length(const uint8_t *hdr);
int __wrap_pfd_mbap_length(const uint8_t *hdr)
{
    if (m.on_length != NULL)
        m.on_length();
    return __real_pfd_mbap_length(hdr);
}

/* ---- fixtures ---------------------------------------------------------- */

/* Read holding registers 0-1 of unit 1, transaction @p tid: 12 bytes. */
static void fc03(uint8_t *f, uint8_t tid)
{
    const uint8_t b[12] = {0, 0, 0, 0, 0, 6, 1, 3, 0, 0, 0, 2};
    memcpy(f, b, sizeof b);
    f[1] = tid;
}

/* A TLS record of application data with a @p body-byte body (its content
 * is the fake session's business). */
static size_t app_record(uint8_t *r, size_t body)
{
    r[0] = PFD_TLS_APP_DATA;
    r[1] = 3;
    r[2] = 3;
    r[3] = (uint8_t)(body >> 8);
    r[4] = (uint8_t)body;
    memset(r + PFD_TLS_HDR, 0xa5, body);
    return PFD_TLS_HDR + body;
}

static int reset(void **state)
{
    (void)state;
    memset(&m, 0, sizeof m);
    memset(&D, 0, sizeof D);
    memset(slots, 0, sizeof slots);
    D.set.first_request_ms = 10000;
    D.set.byte_timeout_ms = 1000;
    D.set.idle_timeout_s = 0;
    D.set.max_clients = 4;
    D.set.max_per_addr = 8;
    D.set.plain_access = PFD_ACCESS_READ;
    pthread_mutex_init(&D.regs_mx, NULL);
    pthread_mutex_init(&D.server.clients_mx, NULL);
    D.server.clients = slots;
    D.server.n_slots = N_FAKE;
    m.now = 100 * NS_PER_S;
    m.clock = 1; /* the fake clock, unless a test needs the real one */
    memset(m.wait_ms, 0xff, sizeof m.wait_ms); /* -1: no such wait */
    return 0;
}

static int done(void **state)
{
    (void)state;
    pthread_mutex_destroy(&D.regs_mx);
    pthread_mutex_destroy(&D.server.clients_mx);
    return 0;
}

/* Slot @p i in use by a client on fake fd FAKE_FD + i, connected (or last
 * served) at @p since_ns. */
static pfd_client *client(int i, int tls, int64_t since_ns)
{
    pfd_client *c = &slots[i];
    c->d = &D;
    c->conn.fd = FAKE_FD + i;
    c->tls = tls;
    c->in_use = 1;
    c->addr = 0x0a000001u + (uint32_t)i;
    c->id = (uint64_t)i + 1;
    c->since_ns = since_ns;
    snprintf(c->peer, sizeof c->peer, "10.0.0.%d:5000", i + 1);
    return c;
}

/* ---- unread(): the handshake flag loaded before the look --------------- */

static pfd_client *finishing;

/* The client thread reads the client's Finished, the handshake's last
 * record, and says the handshake is done, while the look peeks. */
static void handshake_ends(void)
{
    __atomic_store_n(&finishing->tls_up, 1, SEQ);
}

static void look_loads_the_handshake_flag_first(void **state)
{
    uint8_t r[64];
    size_t n;
    int heard = 0, pending = 0;
    (void)state;
    finishing = client(0, 1, m.now);
    /* TLS 1.3 sends its Finished with the outer type of application data */
    n = app_record(r, 32);
    put(&m.sock[0], r, n);
    m.sock[0].in_peek = handshake_ends;
    unread(finishing, &heard, &pending);
    assert_int_equal(heard, 1);
    assert_int_equal(pending, 0); /* the handshake's record, no request */
    /* the same record once the handshake was done before the look */
    m.sock[0].in_peek = NULL;
    unread(finishing, &heard, &pending);
    assert_int_equal(pending, 1);
}

/* ---- unread(): the frame count loaded before the look ------------------ */

static pfd_client *serving;

/* The client's thread takes the waiting request during the look. */
static void thread_takes_the_frame(void)
{
    __atomic_add_fetch(&serving->frames, 1, SEQ);
}

static void look_loads_the_frame_count_first(void **state)
{
    uint8_t f[12];
    int heard = 0, pending = 0;
    (void)state;
    serving = client(0, 0, m.now);
    fc03(f, 1);
    put(&m.sock[0], f, sizeof f);
    m.sock[0].in_peek = thread_takes_the_frame;
    unread(serving, &heard, &pending);
    assert_int_equal(pending, 0); /* its thread is running, not late */
    /* the same request, the count not moving during the look */
    m.sock[0].in_peek = NULL;
    unread(serving, &heard, &pending);
    assert_int_equal(pending, 1);
}

/* ---- take_unit(): a header read only from the peek's own bytes --------- */

static uint8_t next_frame[17];

/* The rest of the next request comes during the wait. */
static int rest_comes(int ms)
{
    (void)ms;
    put(&m.sock[0], next_frame, sizeof next_frame);
    m.sock[0].peek_max = 0;
    return 1;
}

static void header_from_the_peeks_own_bytes(void **state)
{
    uint8_t buf[PFD_ADU_MAX];
    const char *why = "";
    pfd_client *c = client(0, 0, m.now);
    (void)state;
    /* the previous request's 12 bytes are still in the buffer */
    fc03(buf, 1);
    /* the next: write registers 0-1 (17 bytes), of which a peek sees 3
     * and FIONREAD, just after, 12 */
    {
        const uint8_t f[17] = {0, 2, 0, 0, 0, 11, 1, 16, 0, 0, 0, 2, 4, 0, 1, 0, 2};
        memcpy(next_frame, f, sizeof f);
    }
    put(&m.sock[0], next_frame, 12);
    m.sock[0].peek_max = 3;
    m.wait = rest_comes;
    assert_int_equal(take_unit(c, buf, &why), 17);
    assert_memory_equal(buf, next_frame, 17);
    assert_int_equal(m.sock[0].n, 0);
}

/* ---- take_unit(): the nap ends at an eviction or a stop ---------------- */

static pfd_client *napping;

/* An eviction's or a stop's shutdown() wakes the wait: readable, no new
 * byte; a look tells nothing (m.revents 0: neither POLLRDHUP, which this
 * platform may not have, nor POLLHUP). */
static int evicted_in_wait(int ms)
{
    (void)ms;
    __atomic_store_n(&napping->evicted, 1, SEQ);
    return 1;
}

static int stopped_in_wait(int ms)
{
    (void)ms;
    pfd_request_stop(&D);
    return 1;
}

/* Part of a frame waits; the wait ends as @p wake says. @return what
 * take_unit() returned, the reason in *why. */
static int part_of_a_frame(int (*wake)(int), const char **why)
{
    uint8_t f[12], buf[PFD_ADU_MAX];
    napping = client(0, 0, m.now);
    fc03(f, 1);
    put(&m.sock[0], f, 3);
    m.wait = wake;
    return take_unit(napping, buf, why);
}

static void nap_ends_at_an_eviction(void **state)
{
    const char *why = "";
    (void)state;
    assert_int_equal(part_of_a_frame(evicted_in_wait, &why), PFD_CONN_CLOSED);
    assert_int_equal(m.naps, 0); /* not one 10 ms nap, let alone the gap */
}

static void nap_ends_at_a_stop(void **state)
{
    const char *why = "";
    (void)state;
    assert_int_equal(part_of_a_frame(stopped_in_wait, &why), PFD_CONN_CLOSED);
    assert_int_equal(m.naps, 0);
}

/* Readable with no new byte, nothing evicted: a short nap, then again. */
static int readable(int ms)
{
    (void)ms;
    return 1;
}

/* Where POLLRDHUP is missing, POLLHUP (a reset, or both sides shut) still
 * ends the connection at once; without either the nap runs to the gap. */
static void nap_ends_at_pollhup(void **state)
{
    const char *why = "";
    (void)state;
    m.revents = POLLHUP;
    assert_int_equal(part_of_a_frame(readable, &why), PFD_CONN_CLOSED);
    assert_string_equal(why, "peer-closed");
    assert_int_equal(m.naps, 0);
}

/* Part of a frame waits and nothing more comes: the naps end after @p ms,
 * the connection with @p reason. */
static void naps_end_after(int64_t ms, const char *reason)
{
    const char *why = "";
    const int64_t start = m.now;
    assert_int_equal(part_of_a_frame(readable, &why), PFD_CONN_TIMEOUT);
    assert_string_equal(why, reason);
    assert_int_equal(m.now - start, ms * 1000000LL);
}

/* ... and its last nap is cut to the gap's end. */
static void nap_runs_to_the_gap(void **state)
{
    (void)state;
    D.set.byte_timeout_ms = 1005;
    naps_end_after(1005, "byte-timeout");
    assert_int_equal(m.naps, 101); /* 100 of 10 ms, one of 5 */
}

/* ... and to the deadline's end, when that comes first. */
static void nap_runs_to_the_deadline(void **state)
{
    (void)state;
    D.set.first_request_ms = 505;
    naps_end_after(505, "first-request-timeout");
}

/* ---- client_main(): busy while holding the next frame whole ------------ */

/* A newcomer from 10.0.0.9 asks the accept thread for a slot. */
static pfd_client *newcomer_arrives(const char **why)
{
    return take_slot(&D, NEWCOMER, "10.0.0.9:6000", why);
}

/* The accept thread, a newcomer in hand and the table full, looks at the
 * slot while its thread is between the two requests of one record. The
 * thread may have been descheduled for long: the served client is no
 * longer protected by its last request's time. */
static void accept_thread_looks(void)
{
    const char *why;
    if (m.requests != 1)
        return;
    m.looks++;
    m.now += 11 * NS_PER_S;
    pthread_mutex_lock(&D.server.clients_mx);
    (void)newcomer_arrives(&why);
    pthread_mutex_unlock(&D.server.clients_mx);
}

static void busy_while_holding_the_next_frame_whole(void **state)
{
    uint8_t r[64], two[24];
    size_t n;
    pfd_client *c;
    (void)state;
    D.set.max_clients = 1;
    D.server.n_slots = 2;
    c = client(0, 1, m.now);
    /* two requests sent back to back: one record (TLS 1.3 adds a type
     * byte and a 16-byte tag) */
    n = app_record(r, sizeof two + 17);
    put(&m.sock[0], r, n);
    fc03(two, 1);
    fc03(two + 12, 2);
    m.plain = two;
    m.n_plain = sizeof two;
    m.on_length = accept_thread_looks;
    m.stop_after = 2;
    (void)client_main(c);
    assert_int_equal(m.requests, 2);
    /* looked at before and after the thread said what it holds */
    assert_true(m.looks >= 2);
    assert_int_equal(c->evicted, 0);
}

/* ---- client_main(): a look once the deadline has passed ---------------- */

/* The thread's wait found nothing and it slept past the first-request
 * deadline; the request came in time. */
static int slept_past_the_deadline(int ms)
{
    (void)ms;
    if (m.waits == 1) {
        m.now += 11 * NS_PER_S;
        return 0;
    }
    return 1;
}

static void deadline_gets_one_more_look(void **state)
{
    uint8_t f[12];
    pfd_client *c = client(0, 0, m.now);
    (void)state;
    fc03(f, 1);
    put(&m.sock[0], f, sizeof f);
    m.wait = slept_past_the_deadline;
    m.stop_after = 1;
    (void)client_main(c);
    assert_int_equal(m.requests, 1);
    assert_int_equal(m.wait_ms[1], 0); /* a look, no wait */
}

/* ---- pfd_conn.c, wait_fd(): a deadline past still gets a look ---------- */

static void wait_past_the_deadline_looks(void **state)
{
    int sv[2];
    pfd_conn conn;
    char b = 'x';
    (void)state;
    m.clock = 0; /* pfd_conn.c reads its own clock: deadlines are real time */
    assert_int_equal(socketpair(AF_UNIX, SOCK_STREAM, 0, sv), 0);
    conn.fd = sv[0];
    conn.ssl = NULL;
    assert_int_equal(pfd_conn_wait_until(&conn, 1000, pfd_now_ns() - NS_PER_S), 0);
    assert_int_equal(write(sv[1], &b, 1), 1);
    assert_int_equal(pfd_conn_wait_until(&conn, 1000, pfd_now_ns() - NS_PER_S), 1);
    close(sv[0]);
    close(sv[1]);
}

/* ---- take_slot(): only the victim's socket is looked at ---------------- */

/* Four newcomers fill the table (max_clients 4), oldest first; the oldest
 * has a whole request waiting, the others nothing. */
static void four_newcomers(void)
{
    uint8_t f[12];
    int i;
    for (i = 0; i < 4; i++)
        client(i, 0, m.now - (10 - i) * NS_PER_S);
    fc03(f, 1);
    put(&m.sock[0], f, sizeof f);
}

static void only_the_victim_is_looked_at(void **state)
{
    const char *why;
    pfd_client *got;
    (void)state;
    four_newcomers();
    got = newcomer_arrives(&why);
    assert_ptr_equal(got, &slots[4]);
    /* the oldest, looked at, has a request: the next oldest goes */
    assert_int_equal(slots[0].evicted, 0);
    assert_int_equal(slots[1].evicted, 1);
    assert_int_equal(m.sock[0].peeks, 1);
    assert_int_equal(m.sock[1].peeks, 1);
    assert_int_equal(m.sock[2].peeks, 0);
    assert_int_equal(m.sock[3].peeks, 0);
}

static void no_look_while_there_is_room(void **state)
{
    const char *why;
    (void)state;
    four_newcomers();
    slots[3].in_use = 0;
    assert_ptr_equal(newcomer_arrives(&why), &slots[3]);
    assert_int_equal(m.sock[0].peeks + m.sock[1].peeks + m.sock[2].peeks, 0);
}

#define TEST(f) cmocka_unit_test_setup_teardown(f, reset, done)

int main(void)
{
    const struct CMUnitTest tests[] = {
        TEST(look_loads_the_handshake_flag_first),
        TEST(look_loads_the_frame_count_first),
        TEST(header_from_the_peeks_own_bytes),
        TEST(nap_ends_at_an_eviction),
        TEST(nap_ends_at_a_stop),
        TEST(nap_ends_at_pollhup),
        TEST(nap_runs_to_the_gap),
        TEST(nap_runs_to_the_deadline),
        TEST(busy_while_holding_the_next_frame_whole),
        TEST(deadline_gets_one_more_look),
        TEST(wait_past_the_deadline_looks),
        TEST(only_the_victim_is_looked_at),
        TEST(no_look_while_there_is_room),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
