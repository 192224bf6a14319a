/* SPDX-License-Identifier: MIT */
/*
 * Triple buffer: one producer, one consumer, neither ever waits. The
 * producer fills its back buffer and swaps it with the middle one; the
 * consumer swaps its front buffer with the middle one when that holds
 * something newer. Each side only ever touches a buffer the other cannot
 * reach, so the real-time thread never blocks on, or spins behind, a
 * Modbus thread that was preempted half-way through a copy (which a
 * seqlock or a mutex would allow).
 *
 * Uses the GCC/Clang __atomic builtins (C99 has no atomics).
 */
#ifndef PFD_TBUF_H
#define PFD_TBUF_H

#include <stddef.h>
#include <string.h>

#define PFD_TBUF_FRESH 4u

typedef struct pfd_tbuf {
    unsigned char *buf[3];
    size_t size;
    unsigned mid;   /* index of the middle buffer | PFD_TBUF_FRESH; atomic */
    unsigned back;  /* producer's */
    unsigned front; /* consumer's */
} pfd_tbuf;

/** Three buffers of @p size bytes, all set to @p initial. */
static inline void pfd_tbuf_init(pfd_tbuf *t, void *b0, void *b1, void *b2,
                                 size_t size, const void *initial)
{
    t->buf[0] = (unsigned char *)b0;
    t->buf[1] = (unsigned char *)b1;
    t->buf[2] = (unsigned char *)b2;
    t->size = size;
    memcpy(b0, initial, size);
    memcpy(b1, initial, size);
    memcpy(b2, initial, size);
    t->back = 0;
    t->mid = 1;
    t->front = 2;
}

/** Producer: the buffer to fill (holds what was written two publishes ago). */
static inline void *pfd_tbuf_back(pfd_tbuf *t) { return t->buf[t->back]; }

/** Producer: make the back buffer the newest. */
static inline void pfd_tbuf_publish(pfd_tbuf *t)
{
    unsigned old = __atomic_exchange_n(&t->mid, t->back | PFD_TBUF_FRESH,
                                       __ATOMIC_ACQ_REL);
    t->back = old & 3u;
}

/** Consumer: the newest published buffer (stable until the next call). */
static inline const void *pfd_tbuf_latest(pfd_tbuf *t)
{
    if (__atomic_load_n(&t->mid, __ATOMIC_ACQUIRE) & PFD_TBUF_FRESH) {
        unsigned old = __atomic_exchange_n(&t->mid, t->front, __ATOMIC_ACQ_REL);
        t->front = old & 3u;
    }
    return t->buf[t->front];
}

#endif
