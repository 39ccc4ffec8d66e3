/* conns.h — deadlines for slow clients: every open connection with the time by which
 * its request headers (or its body) must have arrived; a thread closes those late. */
#ifndef TC_SERVER_CONNS_H
#define TC_SERVER_CONNS_H

#include <microhttpd.h>

#include "server/config.h"

typedef struct tc_conns tc_conns;

/* Where a connection's current request is; each phase but WORK has a deadline. */
typedef enum {
    TC_CONN_BODY, /* headers complete: --body-timeout for the body */
    TC_CONN_WORK, /* body complete: the request deadline governs */
    TC_CONN_IDLE  /* answered: the idle timeout, then --header-timeout for the next headers */
} tc_conn_phase;

/* Starts the thread that closes late connections (none if both timeouts are 0). NULL if out of resources. */
tc_conns *tc_conns_start(const tc_srv_config *cfg);
/* Stops the thread; call after the daemon has stopped (no connection left). */
void tc_conns_stop(tc_conns *t);

/* MHD_OPTION_NOTIFY_CONNECTION, cls = the tc_conns: a connection opens (its headers
 * are due within --header-timeout) or closes. */
void tc_conns_notify(void *cls, struct MHD_Connection *c, void **socket_context,
                     enum MHD_ConnectionNotificationCode code);

/* The connection's request moved to phase p (a no-op for untracked connections). */
void tc_conns_phase(struct MHD_Connection *c, tc_conn_phase p);

#endif
