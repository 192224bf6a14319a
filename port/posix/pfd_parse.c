/* SPDX-License-Identifier: MIT */
#include "pfd_parse.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int pfd_parse_number(const char *text, double *out)
{
    char *end;
    double x;

    /* strtod() alone would also take leading spaces, hex, inf and nan. */
    if (*text == '\0' || text[strspn(text, "0123456789+-.eE")] != '\0')
        return -1;
    errno = 0;
    x = strtod(text, &end);
    if (errno == ERANGE || end == text || *end != '\0' || !isfinite(x))
        return -1;
    *out = x;
    return 0;
}

int pfd_parse_int(const char *text, long lo, long hi, long *out)
{
    double x;
    if (pfd_parse_number(text, &x) != 0 || x != floor(x) || x < (double)lo ||
        x > (double)hi)
        return -1;
    *out = (long)x;
    return 0;
}

int pfd_parse_name(const char *text, const char *(*name)(int), int n)
{
    int v;
    for (v = 0; v < n; v++)
        if (!strcmp(text, name(v)))
            return v;
    return -1;
}

void pfd_parse_names(const char *(*name)(int), int n, char *buf, size_t len)
{
    size_t k = 0;
    int v;
    buf[0] = '\0';
    for (v = 0; v < n && k < len; v++)
        k += (size_t)snprintf(buf + k, len - k, "%s%s",
                              v == 0 ? "" : v == n - 1 ? " or " : ", ", name(v));
}
