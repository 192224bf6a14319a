/* SPDX-License-Identifier: MIT */
/*
 * The Modbus TCP server: a plain listener and, optionally, a Modbus/TCP
 * Security (TLS) listener; an accept thread that checks the allow-list and
 * gives out client slots (pfd_slots.h: per-address limit, eviction of the
 * longest-idle); and one thread per client that frames requests by their
 * MBAP header and hands each to pfd_request(). A slow, partial or hostile
 * client blocks only its own thread, for at most its timeouts; the loop
 * never waits for any of them.
 */
#ifndef PFD_SERVER_H
#define PFD_SERVER_H

#include "pfd_state.h"

/** Bind and listen, then start accepting. Logs msg=listening (and
 *  msg=listening-tls) with the bound port (useful with port 0). The caller
 *  (main's run()) has checked the settings (pfd_settings_check) and, with
 *  a TLS listener, built d->server.tls, which the server takes over: both
 *  before the loop starts, so that what cannot be used is a usage error.
 *  @return 0, or -1 after a fatal message. */
int pfd_server_start(pfd_daemon *d);

/** Stop accepting, disconnect every client, join their threads. */
void pfd_server_stop(pfd_daemon *d);

#endif
