/* SPDX-License-Identifier: MIT */
/*
 * The config file's text format, without its meaning (pfd_config.c gives
 * that): INI-like `[section]` headers and `key = value` lines, '#' and ';'
 * comments, every line ended by a newline, and a last line
 * `checksum = <crc32 hex>` over every byte before it. The checksum and the
 * final newline catch a truncated copy, a bad disk, or an edit that was
 * not re-sealed (`pneufracd --seal-config`). Format: docs/pneufracd.md.
 */
#ifndef PFD_INI_H
#define PFD_INI_H

#include <stddef.h>

/** Where a parse is, for its messages. */
typedef struct pfd_ini {
    const char *path;
    int line; /* 1-based; 0 for the file as a whole */
    char *err;
    size_t errlen;
} pfd_ini;

/** "config PATH:LINE: <message>" (no LINE when it is 0) into the error
 *  buffer. @return -1, so that a handler can `return pfd_ini_error(...)`. */
int pfd_ini_error(pfd_ini *ini, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/** What a parse hands on. Each returns 0, or -1 after pfd_ini_error(). */
typedef struct pfd_ini_sink {
    int (*section)(pfd_ini *ini, void *ctx, const char *name);
    int (*key)(pfd_ini *ini, void *ctx, const char *key, const char *value);
    void *ctx;
} pfd_ini_sink;

/** Parse the @p len bytes of @p text (text[len] must be '\0'; lines are
 *  cut in place). With @p need_checksum 0 the checksum line may be
 *  missing or stale (what --seal-config accepts). @return 0, or -1 with
 *  the message in ini->err. */
int pfd_ini_parse(pfd_ini *ini, char *text, size_t len, int need_checksum,
                  const pfd_ini_sink *sink);

/** @p body (@p n bytes, ending in a newline) followed by its checksum
 *  line, in a buffer from malloc(), or NULL if out of memory. */
char *pfd_ini_seal(const char *body, size_t n, size_t *len);

/** IEEE 802.3 CRC-32, continued from @p crc (0 to start), as zlib's crc32(). */
unsigned long pfd_crc32(unsigned long crc, const unsigned char *p, size_t n);

#endif
