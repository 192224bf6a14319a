/* SPDX-License-Identifier: MIT */
#include "pfd_access.h"

#include <stdio.h>
#include <string.h>

#include "pfd_parse.h"
#include "pfd_regmap.h"

const char *pfd_access_name(int access)
{
    static const char *const names[PFD_ACCESS_COUNT] = {"none", "read", "operate",
                                                        "engineer"};
    return access >= 0 && access < PFD_ACCESS_COUNT ? names[access] : "?";
}

int pfd_access_to_write(const struct pfd_reg *r)
{
    return (r->flags & PFD_F_OPERATE) ? PFD_ACCESS_OPERATE : PFD_ACCESS_ENGINEER;
}

static int name_char(char c)
{
    return c > ' ' && c < 127 && c != ',' && c != ':';
}

int pfd_roles_parse(const char *text, pfd_roles *out, char *err, size_t n)
{
    const char *p = text;

    memset(out, 0, sizeof *out);
    while (*p != '\0') {
        char name[PFD_ROLE_NAME_MAX], level[16];
        size_t len = 0, k = 0;
        int a, i;

        p += strspn(p, " ");
        while (len < sizeof name - 1 && name_char(p[len]))
            len++;
        if (len == 0 || name_char(p[len]) || p[len] != ':') {
            snprintf(err, n, "'%s' is not NAME:ACCESS[,NAME:ACCESS...]", text);
            return -1;
        }
        memcpy(name, p, len);
        name[len] = '\0';
        p += len + 1;
        while (k < sizeof level - 1 && p[k] >= 'a' && p[k] <= 'z')
            k++;
        memcpy(level, p, k);
        level[k] = '\0';
        a = pfd_parse_name(level, pfd_access_name, PFD_ACCESS_COUNT);
        if (a < 0) {
            snprintf(err, n, "'%s': role %s: '%s' is not none, read, operate or engineer",
                     text, name, level);
            return -1;
        }
        p += k;
        p += strspn(p, " ");
        if (*p == ',' && p[1 + strspn(p + 1, " ")] != '\0')
            p++;
        else if (*p != '\0') {
            snprintf(err, n, "'%s' is not NAME:ACCESS[,NAME:ACCESS...]", text);
            return -1;
        }
        for (i = 0; i < out->n; i++)
            if (!strcmp(out->name[i], name)) {
                snprintf(err, n, "'%s': role %s given twice", text, name);
                return -1;
            }
        if (out->n >= PFD_ROLES_MAX) {
            snprintf(err, n, "'%s': more than %d roles", text, PFD_ROLES_MAX);
            return -1;
        }
        strcpy(out->name[out->n], name);
        out->access[out->n] = a;
        out->n++;
    }
    return 0;
}

int pfd_roles_lookup(const pfd_roles *roles, const char *name)
{
    int i;
    for (i = 0; i < roles->n; i++)
        if (!strcmp(roles->name[i], name))
            return roles->access[i];
    return -1;
}
