/* SPDX-License-Identifier: MIT */
/* Allow-list of client networks (IPv4 CIDR), checked at accept. */
#ifndef PFD_ALLOW_H
#define PFD_ALLOW_H

#include <stddef.h>
#include <stdint.h>

#define PFD_ALLOW_MAX 32

typedef struct pfd_allow {
    int n;
    uint32_t net[PFD_ALLOW_MAX], mask[PFD_ALLOW_MAX]; /* host byte order */
} pfd_allow;

/** Parse "A.B.C.D[/N][,...]" (spaces allowed around commas). An empty
 *  list means 127.0.0.0/8. @return 0, or -1 with a message in @p err. */
int pfd_allow_parse(const char *list, pfd_allow *a, char *err, size_t errlen);

/** @return non-zero if @p addr (host byte order) is allowed. */
int pfd_allow_match(const pfd_allow *a, uint32_t addr);

#endif
