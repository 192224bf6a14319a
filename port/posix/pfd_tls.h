/* SPDX-License-Identifier: MIT */
/*
 * Modbus/TCP Security (Modbus Organization, MB-TCP-Security v36, 2021):
 * TLS 1.2 or later with mutual authentication by X.509v3 certificates.
 * The client's role is the value of the certificate extension with OID
 * 1.3.6.1.4.1.50316.802.1, an ASN.1 UTF8String (requirements );
 * the roles this daemon knows, and the access each grants, are the
 * `tls_roles` setting (pfd_access.h). A client without a certificate that
 * chains to `tls_ca`, with an expired one, or with no known role, is
 * refused during the handshake. OpenSSL (Debian's libssl) does the TLS.
 */
#ifndef PFD_TLS_H
#define PFD_TLS_H

#include <stddef.h>

#include "pfd_access.h"
#include "pfd_settings.h"

struct ssl_st; /* OpenSSL's SSL */
typedef struct pfd_tls pfd_tls;

/** The role extension's OID (MB-TCP-Security, R-21). */
#define PFD_TLS_ROLE_OID "1.3.6.1.4.1.50316.802.1"

/** Server context from the tls_* settings: certificate, key, CA, roles,
 *  which pfd_settings_check() has found given and readable.
 *  @return the context, or NULL with a message in @p err. */
pfd_tls *pfd_tls_new(const pfd_settings *set, char *err, size_t n);

void pfd_tls_free(pfd_tls *t);

/** A session for an accepted socket, or NULL (out of memory). */
struct ssl_st *pfd_tls_session(pfd_tls *t, int fd);

/** After the handshake: the client's role (into @p role) and its access.
 *  @return the access, or -1 (cannot happen after a verified handshake,
 *  which checked the role). */
int pfd_tls_peer(pfd_tls *t, struct ssl_st *ssl, char *role, size_t n);

/** A TLS record's header: content type, version, length (RFC 8446 5.1,
 *  RFC 5246 6.2.1). */
#define PFD_TLS_HDR 5
/** The longest record body TLS allows: 2^14 bytes of plaintext and 2048
 *  of expansion (RFC 5246 6.2.3; TLS 1.3 allows 256). */
#define PFD_TLS_BODY_MAX (16384 + 2048)
/** The content type application_data; in TLS 1.3 every record after the
 *  handshake carries it outside (alerts and key updates too). */
#define PFD_TLS_APP_DATA 0x17

/** The whole length (header included) of the record whose header is
 *  @p h (PFD_TLS_HDR bytes), or -1 if TLS allows no such record. */
int pfd_tls_record_length(const unsigned char *h);

#endif
