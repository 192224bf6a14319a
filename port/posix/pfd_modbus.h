/* SPDX-License-Identifier: MIT */
/*
 * One Modbus request, from its ADU to its answer: validation against the
 * register table, authorisation (the client's access, the lock), the
 * writes, and the answer. Plain TCP and Modbus/TCP Security clients come
 * through here alike; the server (pfd_server.c) only frames and carries
 * the bytes. Framing is by the MBAP header (length field), as the
 * Modbus/TCP specification has it.
 */
#ifndef PFD_MODBUS_H
#define PFD_MODBUS_H

#include <stdint.h>

#include "pfd_access.h"
#include "pfd_stage.h"
#include "pfd_state.h"

#define PFD_MBAP_LEN 7   /**< transaction, protocol, length, unit */
#define PFD_ADU_MAX 260  /**< Modbus/TCP's largest ADU */

/** One connection's side of the conversation. */
typedef struct pfd_session {
    pfd_who who;
    pfd_stage *stage[256]; /**< by unit id; NULL: nothing staged */
} pfd_session;

/** The length of the whole ADU an MBAP header announces, or -1 if the
 *  stream cannot be trusted: a protocol id other than 0, a length below 2
 *  (unit and function code) or an ADU over PFD_ADU_MAX bytes. */
int pfd_mbap_length(const uint8_t *hdr);

/** Answer the request @p req (@p len bytes, as pfd_mbap_length() gave)
 *  into @p rsp (PFD_ADU_MAX bytes). @return the answer's length, or -1 to
 *  drop the connection (a PDU whose length contradicts its function code,
 *  or the daemon is stopping). */
int pfd_request(pfd_daemon *d, pfd_session *s, const uint8_t *req, int len, uint8_t *rsp);

/** The connection is gone: its locks are released and its staged writes
 *  dropped. */
void pfd_session_end(pfd_daemon *d, pfd_session *s);

#endif
