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

/** TLS, once the handshake is done: from now on the session decrypts only
 *  the records given to it (pfd_conn_give()) and never reads the socket
 *  itself, so that it never holds part of a record: the client thread
 *  takes a record from the socket only once all of it has come, and what
 *  waits in the socket then starts at a record (pfd_server.c, unread()).
 *  @return 0 or PFD_CONN_CLOSED (out of memory). */
int pfd_conn_records_only(pfd_conn *c);

/** Give the session one whole record of @p n bytes. @return 0 or
 *  PFD_CONN_CLOSED (out of memory). */
int pfd_conn_give(pfd_conn *c, const void *rec, size_t n);

/** A record that does not decrypt, or is not allowed here. */
#define PFD_CONN_BAD (-3)

/** A write the session needed while reading (e.g. its answer to a key
 *  update) could not be made. */
#define PFD_CONN_SEND (-4)

/** Up to @p n decrypted bytes of the records given. @return a count, 0
 *  when nothing more has been given, PFD_CONN_CLOSED (the peer's
 *  close_notify), PFD_CONN_BAD or PFD_CONN_SEND. */
long pfd_conn_take(pfd_conn *c, void *buf, size_t n);

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
