/* SPDX-License-Identifier: MIT */
/*
 * One client connection's byte stream, plain TCP or TLS, on a non-blocking
 * socket: every wait is a poll() with a deadline, so that no read or write
 * can hold a client thread longer than the timeouts allow, and a
 * shutdown() of the socket (eviction, stop) wakes it at once.
 */
#ifndef PFD_CONN_H
#define PFD_CONN_H

#include <stddef.h>
#include <stdint.h>

struct ssl_st; /* OpenSSL's SSL */

typedef struct pfd_conn {
    int fd;
    struct ssl_st *ssl; /**< NULL: plain TCP */
} pfd_conn;

/** Return values of the calls below besides 0 and a count. */
#define PFD_CONN_CLOSED (-1)  /**< the peer closed, or the socket failed */
#define PFD_CONN_TIMEOUT (-2) /**< a deadline or the byte gap passed */

/** CLOCK_MONOTONIC in ns. */
int64_t pfd_now_ns(void);

/** Wait until data can be read, at most @p ms. @return 1 readable (or
 *  closed: the read says which), 0 not yet, PFD_CONN_CLOSED. */
int pfd_conn_wait(pfd_conn *c, int ms);

/** The same, and never past @p deadline_ns (0: none; one look, with no
 *  wait, if it has passed). */
int pfd_conn_wait_until(pfd_conn *c, int ms, int64_t deadline_ns);

/** Read exactly @p n bytes: each further byte within @p gap_ms, the last
 *  by @p deadline_ns (0: none). @return 0, PFD_CONN_CLOSED or
 *  PFD_CONN_TIMEOUT. */
int pfd_conn_read(pfd_conn *c, void *buf, size_t n, int gap_ms, int64_t deadline_ns);

/** Write all @p n bytes within @p ms. @return 0, PFD_CONN_CLOSED or
 *  PFD_CONN_TIMEOUT. */
int pfd_conn_write(pfd_conn *c, const void *buf, size_t n, int ms);

/** The TLS handshake (c->ssl set) by @p deadline_ns. @return 0,
 *  PFD_CONN_CLOSED (refused: @p why says why) or PFD_CONN_TIMEOUT. */
int pfd_conn_handshake(pfd_conn *c, int64_t deadline_ns, char *why, size_t n);

/** Free the TLS session (after a close_notify, when it can be sent
 *  without waiting); the fd stays open. */
void pfd_conn_end_tls(pfd_conn *c);

#endif
