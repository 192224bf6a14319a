/* SPDX-License-Identifier: MIT */
/*
 * Who may do what. A client has one access level: plain Modbus TCP clients
 * the level of `plain_access`, Modbus/TCP Security clients the level their
 * certificate's role maps to (`tls_roles`). Each register of the table
 * says which level a write of it needs (pfd_access_to_write), so the map
 * "function code x register range -> allowed" is the register table
 * itself, and docs/register-map.md prints it.
 */
#ifndef PFD_ACCESS_H
#define PFD_ACCESS_H

#include <stddef.h>
#include <stdint.h>

struct pfd_reg;

/** Access levels, each including the ones before it. */
enum pfd_access_level {
    PFD_ACCESS_NONE = 0,  /**< nothing (plain: no plain listener at all) */
    PFD_ACCESS_READ,      /**< FC03 and FC04 on every register */
    PFD_ACCESS_OPERATE,   /**< and writes of the process inputs, mode,
                               manual output and tick */
    PFD_ACCESS_ENGINEER,  /**< and every other write: parameters, commit,
                               commands, watchdog, fail-safe, param_lock */
    PFD_ACCESS_COUNT
};

/** "none", "read", "operate", "engineer". */
const char *pfd_access_name(int access);

/** The level a write of @p r needs: OPERATE or ENGINEER. */
int pfd_access_to_write(const struct pfd_reg *r);

/** Who sent a request: the connection, for logs, locks and staging. */
typedef struct pfd_who {
    uint64_t id;          /**< connection serial number, never 0 */
    const char *peer;     /**< "A.B.C.D:PORT" */
    const char *role;     /**< certificate role, or "plain" */
    int access;           /**< enum pfd_access_level */
} pfd_who;

#define PFD_ROLES_MAX 16
#define PFD_ROLE_NAME_MAX 64

/** Certificate roles and the access each grants. */
typedef struct pfd_roles {
    int n;
    char name[PFD_ROLES_MAX][PFD_ROLE_NAME_MAX];
    int access[PFD_ROLES_MAX];
} pfd_roles;

/** "viewer:read, operator:operate, ...". A role name is 1..63 printable
 *  ASCII characters other than ',', ':' and spaces; each name once; an
 *  access of none is allowed (the role is known and may do nothing).
 *  @return 0, or -1 with a message in @p err. */
int pfd_roles_parse(const char *text, pfd_roles *out, char *err, size_t n);

/** The access of role @p name, or -1 if @p roles does not name it. */
int pfd_roles_lookup(const pfd_roles *roles, const char *name);

#endif
