/* server.h — the listening daemon: binds the configured address, starts the
 * libmicrohttpd thread pool, stops accepting on shutdown, stops. */
#ifndef TC_SERVER_SERVER_H
#define TC_SERVER_SERVER_H

#include <stddef.h>

#include "server/config.h"

typedef struct tc_server tc_server;

/* Starts serving. NULL on failure, with the reason in err. */
tc_server *tc_server_start(const tc_srv_config *cfg, char *err, size_t errlen);

/* "127.0.0.1:8080", "[::1]:8080": the bound address with the actual port. */
const char *tc_server_address(const tc_server *s);

/* Stops accepting connections; connections already in the listen queue are
 * taken (their request gets 503 with Retry-After), requests on open
 * connections still run, and new ones on them get 503 with Connection: close. */
void tc_server_quiesce(tc_server *s);

/* Connections open now (idle keep-alive ones included). */
unsigned tc_server_connections(const tc_server *s);

/* Waits for the requests computing now; those still waiting for a worker
 * get 503 with Retry-After. New ones are refused alike. */
void tc_server_cancel_waiting(tc_server *s);

/* Stops the threads (waiting for handlers still running) and frees s. */
void tc_server_stop(tc_server *s);

#endif
