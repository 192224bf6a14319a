/* SPDX-License-Identifier: MIT */
#include "pfd_tls.h"

#include <openssl/err.h>
#include <openssl/ssl.h>
#include <openssl/x509v3.h>
#include <stdlib.h>
#include <string.h>

struct pfd_tls {
    SSL_CTX *ctx;
    ASN1_OBJECT *role_oid;
    pfd_roles roles;
};

/* The role carried by @p cert: exactly one role extension holding one
 * DER UTF8String of printable ASCII (the names tls_roles can hold).
 * @return 0, or -1 with @p why. */
static int cert_role(const pfd_tls *t, X509 *cert, char *role, size_t n, const char **why)
{
    int idx = X509_get_ext_by_OBJ(cert, t->role_oid, -1);
    X509_EXTENSION *ext;
    const ASN1_OCTET_STRING *data;
    const unsigned char *p;
    ASN1_UTF8STRING *s;
    int ok = 0, i;

    *why = "no role extension in the client certificate";
    if (idx < 0)
        return -1;
    *why = "malformed role extension in the client certificate";
    if (X509_get_ext_by_OBJ(cert, t->role_oid, idx) >= 0)
        return -1;
    ext = X509_get_ext(cert, idx);
    data = X509_EXTENSION_get_data(ext);
    p = ASN1_STRING_get0_data(data);
    s = d2i_ASN1_UTF8STRING(NULL, &p, ASN1_STRING_length(data));
    if (s != NULL && p == ASN1_STRING_get0_data(data) + ASN1_STRING_length(data) &&
        ASN1_STRING_length(s) > 0 && (size_t)ASN1_STRING_length(s) < n) {
        *why = NULL;
        const unsigned char *v = ASN1_STRING_get0_data(s);
        ok = 1;
        for (i = 0; i < ASN1_STRING_length(s); i++)
            if (v[i] <= ' ' || v[i] >= 127)
                ok = 0;
        if (ok) {
            memcpy(role, v, (size_t)ASN1_STRING_length(s));
            role[ASN1_STRING_length(s)] = '\0';
        }
    }
    ASN1_UTF8STRING_free(s);
    if (!ok)
        *why = "malformed role extension in the client certificate";
    return ok ? 0 : -1;
}

/* OpenSSL's chain verification stands (CA, validity dates, signatures);
 * on top, the client's own certificate must carry a role we know. The
 * reason for a refusal is left as the session's app data, for the log
 * (pfd_conn_handshake). */
static int verify_cb(int ok, X509_STORE_CTX *x)
{
    SSL *ssl;
    const pfd_tls *t;
    char role[PFD_ROLE_NAME_MAX];
    const char *why;

    if (!ok || X509_STORE_CTX_get_error_depth(x) != 0)
        return ok;
    ssl = (SSL *)X509_STORE_CTX_get_ex_data(x, SSL_get_ex_data_X509_STORE_CTX_idx());
    t = (const pfd_tls *)SSL_CTX_get_app_data(SSL_get_SSL_CTX(ssl));
    if (cert_role(t, X509_STORE_CTX_get_current_cert(x), role, sizeof role, &why) == 0 &&
        pfd_roles_lookup(&t->roles, role) < 0)
        why = "the certificate's role is not in tls_roles";
    else if (why == NULL)
        return 1;
    SSL_set_app_data(ssl, (char *)why);
    X509_STORE_CTX_set_error(x, X509_V_ERR_APPLICATION_VERIFICATION);
    return 0;
}

static void ssl_error(char *err, size_t n, const char *what, const char *file)
{
    unsigned long e = ERR_get_error();
    snprintf(err, n, "%s %s: %s", what, file,
             e != 0 && ERR_reason_error_string(e) ? ERR_reason_error_string(e) : "failed");
    ERR_clear_error();
}

pfd_tls *pfd_tls_new(const pfd_settings *set, char *err, size_t n)
{
    pfd_tls *t;

    t = calloc(1, sizeof *t);
    if (t == NULL) {
        snprintf(err, n, "out of memory");
        return NULL;
    }
    if (pfd_roles_parse(set->tls_roles, &t->roles, err, n) != 0) {
        free(t);
        return NULL;
    }
    t->role_oid = OBJ_txt2obj(PFD_TLS_ROLE_OID, 1);
    t->ctx = SSL_CTX_new(TLS_server_method());
    if (t->role_oid == NULL || t->ctx == NULL) {
        snprintf(err, n, "TLS: out of memory");
        pfd_tls_free(t);
        return NULL;
    }
    SSL_CTX_set_app_data(t->ctx, t);
    /* MB-TCP-Security: TLS 1.2 or later; no renegotiation, no resumption
     * (each connection is authenticated from its own certificate). */
    SSL_CTX_set_min_proto_version(t->ctx, TLS1_2_VERSION);
    SSL_CTX_set_options(t->ctx, SSL_OP_NO_RENEGOTIATION | SSL_OP_NO_TICKET);
    SSL_CTX_set_session_cache_mode(t->ctx, SSL_SESS_CACHE_OFF);
    SSL_CTX_set_mode(t->ctx, SSL_MODE_ENABLE_PARTIAL_WRITE);
    SSL_CTX_set_verify(t->ctx, SSL_VERIFY_PEER | SSL_VERIFY_FAIL_IF_NO_PEER_CERT, verify_cb);
    if (SSL_CTX_use_certificate_chain_file(t->ctx, set->tls_cert) != 1) {
        ssl_error(err, n, "--tls-cert", set->tls_cert);
    } else if (SSL_CTX_use_PrivateKey_file(t->ctx, set->tls_key, SSL_FILETYPE_PEM) != 1 ||
               SSL_CTX_check_private_key(t->ctx) != 1) {
        ssl_error(err, n, "--tls-key", set->tls_key);
    } else if (SSL_CTX_load_verify_locations(t->ctx, set->tls_ca, NULL) != 1) {
        ssl_error(err, n, "--tls-ca", set->tls_ca);
    } else {
        return t;
    }
    pfd_tls_free(t);
    return NULL;
}

void pfd_tls_free(pfd_tls *t)
{
    if (t == NULL)
        return;
    SSL_CTX_free(t->ctx);
    ASN1_OBJECT_free(t->role_oid);
    free(t);
}

SSL *pfd_tls_session(pfd_tls *t, int fd)
{
    SSL *ssl = SSL_new(t->ctx);
    if (ssl != NULL && SSL_set_fd(ssl, fd) != 1) {
        SSL_free(ssl);
        ssl = NULL;
    }
    return ssl;
}

int pfd_tls_peer(pfd_tls *t, SSL *ssl, char *role, size_t n)
{
    X509 *cert = SSL_get1_peer_certificate(ssl);
    const char *why;
    int access = -1;
    if (cert != NULL && SSL_get_verify_result(ssl) == X509_V_OK &&
        cert_role(t, cert, role, n, &why) == 0)
        access = pfd_roles_lookup(&t->roles, role);
    X509_free(cert);
    return access;
}

int pfd_tls_record_length(const unsigned char *h)
{
    int len = h[3] << 8 | h[4];
    return len > PFD_TLS_BODY_MAX ? -1 : PFD_TLS_HDR + len;
}
