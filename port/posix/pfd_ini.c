/* SPDX-License-Identifier: MIT */
#include "pfd_ini.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

unsigned long pfd_crc32(unsigned long crc, const unsigned char *p, size_t n)
{
    unsigned long c = crc ^ 0xFFFFFFFFul;
    size_t i;
    int k;
    for (i = 0; i < n; i++) {
        c ^= p[i];
        for (k = 0; k < 8; k++)
            c = (c >> 1) ^ (0xEDB88320ul & (0ul - (c & 1ul)));
    }
    return c ^ 0xFFFFFFFFul;
}

int pfd_ini_error(pfd_ini *ini, const char *fmt, ...)
{
    char msg[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (ini->line > 0)
        snprintf(ini->err, ini->errlen, "config %s:%d: %s", ini->path, ini->line, msg);
    else
        snprintf(ini->err, ini->errlen, "config %s: %s", ini->path, msg);
    return -1;
}

static char *trim(char *s)
{
    char *e;
    while (*s == ' ' || *s == '\t')
        s++;
    e = s + strlen(s);
    while (e > s && (e[-1] == ' ' || e[-1] == '\t' || e[-1] == '\r'))
        *--e = '\0';
    return s;
}

/* `checksum = X`, given @p crc of every byte before its line. */
static int check_sum(pfd_ini *ini, const char *v, unsigned long crc, int need)
{
    char *e;
    unsigned long want;

    if (strlen(v) != 8 || (want = strtoul(v, &e, 16), *e != '\0'))
        return pfd_ini_error(ini, "checksum: '%s' is not 8 hex digits", v);
    if (need && want != crc)
        return pfd_ini_error(ini, "checksum mismatch (file %08lx, content %08lx): "
                             "the file is corrupt, or was edited without "
                             "`pneufracd --seal-config %s`", want, crc, ini->path);
    return 0;
}

/* One line that is not blank, a comment, or after the checksum.
 * @return 0, 1 for the checksum line, or -1. */
static int parse_line(pfd_ini *ini, char *line, unsigned long crc, int need,
                      const pfd_ini_sink *sink)
{
    char *eq, *k, *v;

    if (*line == '[') {
        char *close = strchr(line, ']');
        if (close == NULL || close[1] != '\0')
            return pfd_ini_error(ini, "malformed section header '%s'", line);
        *close = '\0';
        return sink->section(ini, sink->ctx, trim(line + 1));
    }
    eq = strchr(line, '=');
    if (eq == NULL)
        return pfd_ini_error(ini, "expected 'key = value', got '%s'", line);
    *eq = '\0';
    k = trim(line);
    v = trim(eq + 1);
    if (!strcmp(k, "checksum"))
        return check_sum(ini, v, crc, need) == 0 ? 1 : -1;
    if (*k == '\0' || *v == '\0')
        return pfd_ini_error(ini, "empty key or value");
    return sink->key(ini, sink->ctx, k, v);
}

int pfd_ini_parse(pfd_ini *ini, char *text, size_t len, int need_checksum,
                  const pfd_ini_sink *sink)
{
    unsigned long crc = 0; /* of every byte before the current line */
    int have_sum = 0;
    size_t bom = 0;
    char *p, *end;

    ini->line = 0;
    if (memchr(text, '\0', len) != NULL)
        return pfd_ini_error(ini, "contains NUL bytes: not a text file");
    /* A UTF-8 byte-order mark (Windows editors write one) is not part of
     * the first line's text; the checksum covers it like any byte. */
    if (len >= 3 && memcmp(text, "\xEF\xBB\xBF", 3) == 0) {
        bom = 3;
        crc = pfd_crc32(0, (const unsigned char *)text, bom);
    }
    for (p = text + bom; p < text + len; p = end + 1) {
        unsigned long crc_next;
        char *line;
        int rc;

        ini->line++;
        end = strchr(p, '\n');
        /* Every line the daemon writes ends in a newline: a file cut short
         * in the middle of a line is caught here. */
        if (end == NULL)
            return pfd_ini_error(ini, "the file is truncated: its last line has no newline "
                                 "(a hand edit without a final newline: add one)");
        crc_next = pfd_crc32(crc, (const unsigned char *)p, (size_t)(end - p) + 1);
        *end = '\0';
        line = trim(p);
        if (have_sum) {
            if (*line != '\0')
                return pfd_ini_error(ini, "text after the checksum line");
            continue;
        }
        if (*line == '\0' || *line == '#' || *line == ';') {
            crc = crc_next;
            continue;
        }
        rc = parse_line(ini, line, crc, need_checksum, sink);
        if (rc < 0)
            return -1;
        have_sum = rc == 1;
        crc = crc_next;
    }
    ini->line = 0;
    if (need_checksum && !have_sum)
        return pfd_ini_error(ini, "no checksum line: the file is incomplete, or was "
                             "written by hand (check it, then run `pneufracd "
                             "--seal-config %s`)", ini->path);
    return 0;
}

char *pfd_ini_seal(const char *body, size_t n, size_t *len)
{
    char *full = malloc(n + 32);
    if (full == NULL)
        return NULL;
    memcpy(full, body, n);
    *len = n + (size_t)sprintf(full + n, "checksum = %08lx\n",
                               pfd_crc32(0, (const unsigned char *)body, n));
    return full;
}
