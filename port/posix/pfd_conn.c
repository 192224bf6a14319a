/* SPDX-License-Identifier: MIT */
#include "pfd_conn.h"

#include <errno.h>
#include <openssl/err.h>
#include <openssl/ssl.h>
#include <poll.h>
#include <stdio.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>

int64_t pfd_now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

/* Wait for @p events, at most @p ms and never past @p deadline_ns (0:
 * none). @return 1 ready, 0 timed out, PFD_CONN_CLOSED. A deadline
 * already past still gets one look (a zero timeout): the thread may have
 * slept past it while the bytes came in time. */
static int wait_fd(int fd, short events, int ms, int64_t deadline_ns)
{
    struct pollfd p;
    int rc;

    if (deadline_ns > 0) {
        int64_t left = (deadline_ns - pfd_now_ns() + 999999) / 1000000;
        if (left < ms)
            ms = left > 0 ? (int)left : 0;
    }
    p.fd = fd;
    p.events = events;
    p.revents = 0;
    do {
        rc = poll(&p, 1, ms);
    } while (rc < 0 && errno == EINTR);
    if (rc < 0)
        return PFD_CONN_CLOSED;
    /* HUP or an error: the next read or write reports it. */
    return rc > 0 ? 1 : 0;
}

int pfd_conn_wait(pfd_conn *c, int ms)
{
    return pfd_conn_wait_until(c, ms, 0);
}

int pfd_conn_wait_until(pfd_conn *c, int ms, int64_t deadline_ns)
{
    if (c->ssl != NULL && SSL_pending(c->ssl) > 0)
        return 1;
    return wait_fd(c->fd, POLLIN, ms, deadline_ns);
}

/* One write attempt. @return bytes written (> 0), 0 to wait for *events,
 * or PFD_CONN_CLOSED. (Reads go through pfd_server.c's take_unit(): whole
 * frames on plain TCP, whole records given to the TLS session.) */
static long write_once(pfd_conn *c, const void *buf, size_t n, short *events)
{
    if (c->ssl == NULL) {
        ssize_t k = send(c->fd, buf, n, MSG_NOSIGNAL);
        if (k > 0)
            return (long)k;
        if (k < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) {
            *events = POLLOUT;
            return 0;
        }
        return PFD_CONN_CLOSED;
    } else {
        int k = SSL_write(c->ssl, buf, (int)n);
        if (k > 0)
            return k;
        switch (SSL_get_error(c->ssl, k)) {
        case SSL_ERROR_WANT_READ:
            *events = POLLIN;
            return 0;
        case SSL_ERROR_WANT_WRITE:
            *events = POLLOUT;
            return 0;
        default:
            ERR_clear_error();
            return PFD_CONN_CLOSED;
        }
    }
}

int pfd_conn_records_only(pfd_conn *c)
{
    BIO *b = BIO_new(BIO_s_mem());
    if (b == NULL)
        return PFD_CONN_CLOSED;
    /* empty: "try again" (SSL_ERROR_WANT_READ), not the end of the stream */
    BIO_set_mem_eof_return(b, -1);
    /* frees the socket BIO's read reference; the write side keeps it */
    SSL_set0_rbio(c->ssl, b);
    return 0;
}

int pfd_conn_give(pfd_conn *c, const void *rec, size_t n)
{
    return BIO_write(SSL_get_rbio(c->ssl), rec, (int)n) == (int)n ? 0 : PFD_CONN_CLOSED;
}

long pfd_conn_take(pfd_conn *c, void *buf, size_t n)
{
    int k = SSL_read(c->ssl, buf, (int)n);
    if (k > 0)
        return k;
    k = SSL_get_error(c->ssl, k);
    ERR_clear_error();
    if (k == SSL_ERROR_WANT_READ)
        return 0;
    /* the read side is a memory BIO (pfd_conn_records_only()): a
     * system call or a write that would block is the socket's write side */
    if (k == SSL_ERROR_WANT_WRITE || k == SSL_ERROR_SYSCALL)
        return PFD_CONN_SEND;
    return k == SSL_ERROR_ZERO_RETURN ? PFD_CONN_CLOSED : PFD_CONN_BAD;
}

int pfd_conn_write(pfd_conn *c, const void *buf, size_t n, int ms)
{
    const unsigned char *p = (const unsigned char *)buf;
    const int64_t deadline_ns = pfd_now_ns() + (int64_t)ms * 1000000;
    while (n > 0) {
        short ev = 0;
        /* OpenSSL retries a write with the same buffer and length. */
        long k = write_once(c, p, n, &ev);
        int w;
        if (k < 0)
            return PFD_CONN_CLOSED;
        if (k > 0) {
            p += k;
            n -= (size_t)k;
            continue;
        }
        w = wait_fd(c->fd, ev, ms, deadline_ns);
        if (w < 0)
            return PFD_CONN_CLOSED;
        if (w == 0)
            return PFD_CONN_TIMEOUT;
    }
    return 0;
}

int pfd_conn_handshake(pfd_conn *c, int64_t deadline_ns, char *why, size_t n)
{
    for (;;) {
        int k = SSL_accept(c->ssl), w;
        short ev;
        if (k == 1)
            return 0;
        switch (SSL_get_error(c->ssl, k)) {
        case SSL_ERROR_WANT_READ:
            ev = POLLIN;
            break;
        case SSL_ERROR_WANT_WRITE:
            ev = POLLOUT;
            break;
        default: {
            unsigned long e = ERR_peek_last_error();
            long v = SSL_get_verify_result(c->ssl);
            const char *app = (const char *)SSL_get_app_data(c->ssl);
            if (v == X509_V_ERR_APPLICATION_VERIFICATION && app != NULL)
                snprintf(why, n, "%s", app); /* pfd_tls.c's verify callback */
            else if (v != X509_V_OK)
                snprintf(why, n, "%s", X509_verify_cert_error_string(v));
            else if (e != 0)
                snprintf(why, n, "%s", ERR_reason_error_string(e) ? ERR_reason_error_string(e)
                                                                  : "handshake failed");
            else
                snprintf(why, n, "handshake failed");
            ERR_clear_error();
            return PFD_CONN_CLOSED;
        }
        }
        w = wait_fd(c->fd, ev, 1000, deadline_ns);
        if (w < 0) {
            snprintf(why, n, "socket error");
            return PFD_CONN_CLOSED;
        }
        if (w == 0) {
            snprintf(why, n, "handshake timeout");
            return PFD_CONN_TIMEOUT;
        }
    }
}

void pfd_conn_end_tls(pfd_conn *c)
{
    if (c->ssl == NULL)
        return;
    /* Best effort: the socket is non-blocking, so this never waits. */
    if (SSL_is_init_finished(c->ssl))
        (void)SSL_shutdown(c->ssl);
    ERR_clear_error();
    SSL_free(c->ssl);
    c->ssl = NULL;
}
