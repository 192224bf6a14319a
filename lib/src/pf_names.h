/* SPDX-License-Identifier: MIT */
/* A constant table of names indexed by an enum: the name of a value, and
 * the value of a name (n, one past the last, when there is none). */
#ifndef PF_NAMES_H
#define PF_NAMES_H

#include <stddef.h>
#include <string.h>

static inline const char *pf_name_of(const char *const *names, int n, int i)
{
    return (unsigned)i < (unsigned)n ? names[i] : "?";
}

static inline int pf_name_find(const char *const *names, int n, const char *name)
{
    int i;
    for (i = 0; name != NULL && i < n; i++)
        if (strcmp(name, names[i]) == 0)
            return i;
    return n;
}

#endif
