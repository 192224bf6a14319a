/* SPDX-License-Identifier: MIT */
#include "pfd_allow.h"

#include <arpa/inet.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int pfd_allow_parse(const char *list, pfd_allow *a, char *err, size_t errlen)
{
    const char *p = list;

    a->n = 0;
    for (;;) {
        char item[64], *slash;
        size_t len;
        const char *end;
        struct in_addr ia;
        long bits = 32;

        while (*p == ' ' || *p == '\t')
            p++;
        end = strchr(p, ',');
        len = end ? (size_t)(end - p) : strlen(p);
        while (len > 0 && (p[len - 1] == ' ' || p[len - 1] == '\t'))
            len--;
        if (len == 0 && end == NULL && a->n == 0 && *list == '\0')
            break;
        if (len == 0 || len >= sizeof item) {
            snprintf(err, errlen, "allow: empty or overlong network in '%s'", list);
            return -1;
        }
        memcpy(item, p, len);
        item[len] = '\0';
        slash = strchr(item, '/');
        if (slash != NULL) {
            char *e;
            *slash = '\0';
            bits = strtol(slash + 1, &e, 10);
            if (*e != '\0' || e == slash + 1 || bits < 0 || bits > 32) {
                snprintf(err, errlen, "allow: bad prefix length in '%s/%s'",
                         item, slash + 1);
                return -1;
            }
        }
        if (inet_pton(AF_INET, item, &ia) != 1) {
            snprintf(err, errlen, "allow: '%s' is not an IPv4 address", item);
            return -1;
        }
        if (a->n >= PFD_ALLOW_MAX) {
            snprintf(err, errlen, "allow: more than %d networks", PFD_ALLOW_MAX);
            return -1;
        }
        a->mask[a->n] = bits == 0 ? 0u : 0xFFFFFFFFu << (32 - bits);
        a->net[a->n] = ntohl(ia.s_addr) & a->mask[a->n];
        a->n++;
        if (end == NULL)
            break;
        p = end + 1;
    }
    if (a->n == 0) {
        a->net[0] = 0x7F000000u;
        a->mask[0] = 0xFF000000u;
        a->n = 1;
    }
    return 0;
}

int pfd_allow_match(const pfd_allow *a, uint32_t addr)
{
    int i;
    for (i = 0; i < a->n; i++)
        if ((addr & a->mask[i]) == a->net[i])
            return 1;
    return 0;
}
