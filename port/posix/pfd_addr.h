/* SPDX-License-Identifier: MIT */
/*
 * IPv4 addresses as the command line and the config file write them: the
 * listening endpoint (ADDR:PORT) and the allow-list of client networks
 * (CIDR), which the accept thread checks.
 */
#ifndef PFD_ADDR_H
#define PFD_ADDR_H

#include <stddef.h>
#include <stdint.h>

/** An IPv4 address in dotted-quad text and a TCP port. */
typedef struct pfd_endpoint {
    char addr[16]; /* INET_ADDRSTRLEN */
    int port;      /* 0..65535; 0 lets the kernel pick */
} pfd_endpoint;

/** "A.B.C.D:PORT" into @p out. @return 0, or -1 with @p out untouched. */
int pfd_endpoint_parse(const char *text, pfd_endpoint *out);

#define PFD_ALLOW_MAX 32
/** What an empty list means: loopback only. */
#define PFD_ALLOW_DEFAULT "127.0.0.0/8"

typedef struct pfd_allow {
    int n;
    uint32_t net[PFD_ALLOW_MAX], mask[PFD_ALLOW_MAX]; /* host byte order */
} pfd_allow;

/** Parse "A.B.C.D[/N][,...]" (spaces allowed around commas). An empty
 *  list means PFD_ALLOW_DEFAULT. @return 0, or -1 with a message in @p err. */
int pfd_allow_parse(const char *list, pfd_allow *a, char *err, size_t errlen);

/** @return non-zero if @p addr (host byte order) is allowed. */
int pfd_allow_match(const pfd_allow *a, uint32_t addr);

#endif
