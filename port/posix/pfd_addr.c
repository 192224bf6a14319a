/* SPDX-License-Identifier: MIT */
#include "pfd_addr.h"

#include <arpa/inet.h>
#include <stdio.h>
#include <string.h>

#include "pfd_parse.h"

int pfd_endpoint_parse(const char *text, pfd_endpoint *out)
{
    const char *colon = strrchr(text, ':');
    struct in_addr ia;
    char addr[sizeof out->addr];
    long port;

    if (colon == NULL || colon == text || (size_t)(colon - text) >= sizeof addr)
        return -1;
    memcpy(addr, text, (size_t)(colon - text));
    addr[colon - text] = '\0';
    if (inet_pton(AF_INET, addr, &ia) != 1 ||
        pfd_parse_int(colon + 1, 0, 65535, &port) != 0)
        return -1;
    strcpy(out->addr, addr);
    out->port = (int)port;
    return 0;
}

int pfd_allow_parse(const char *list, pfd_allow *a, char *err, size_t errlen)
{
    const char *p;

    if (*list == '\0')
        list = PFD_ALLOW_DEFAULT;
    p = list;
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
        if (len == 0 || len >= sizeof item) {
            snprintf(err, errlen, "empty or overlong network in '%s'", list);
            return -1;
        }
        memcpy(item, p, len);
        item[len] = '\0';
        slash = strchr(item, '/');
        if (slash != NULL) {
            *slash = '\0';
            if (pfd_parse_int(slash + 1, 0, 32, &bits) != 0) {
                snprintf(err, errlen, "bad prefix length in '%s/%s'", item, slash + 1);
                return -1;
            }
        }
        if (inet_pton(AF_INET, item, &ia) != 1) {
            snprintf(err, errlen, "'%s' is not an IPv4 address", item);
            return -1;
        }
        if (a->n >= PFD_ALLOW_MAX) {
            snprintf(err, errlen, "more than %d networks", PFD_ALLOW_MAX);
            return -1;
        }
        a->mask[a->n] = bits == 0 ? 0u : 0xFFFFFFFFu << (32 - bits);
        a->net[a->n] = ntohl(ia.s_addr) & a->mask[a->n];
        a->n++;
        if (end == NULL)
            break;
        p = end + 1;
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
