/* SPDX-License-Identifier: MIT */
/*
 * Modbus TCP server: an accept thread (allow-list, client limit, fds below
 * FD_SETSIZE because libmodbus select()s on them) and one thread per
 * client with its own libmodbus context. A slow, partial or hostile client
 * blocks only its own thread, for at most the byte timeout; the loop never
 * waits for any of them.
 */
#ifndef PFD_MODBUS_H
#define PFD_MODBUS_H

#include "pfd_state.h"

/** Bind and listen, then start accepting. Logs msg=listening with the
 *  bound port (useful with port 0). @return 0, or -1 after a fatal message. */
int pfd_server_start(pfd_daemon *d);

/** Stop accepting, disconnect every client, join their threads. */
void pfd_server_stop(pfd_daemon *d);

#endif
