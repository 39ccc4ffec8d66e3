/* http.h — the libmicrohttpd glue: the access handler that checks headers,
 * collects bodies under the limit, hands the route to the worker pool (the
 * connection suspended meanwhile) and sends the reply, and the completion
 * callback that logs and counts each request. */
#ifndef TC_SERVER_HTTP_H
#define TC_SERVER_HTTP_H

#include <stdatomic.h>
#include <stddef.h>
#include <sys/socket.h>
#include <sys/types.h>

#include <microhttpd.h>

#include "server/config.h"
#include "io/budget.h"
#include "server/pool.h"

/* Shared by all connections (the `cls` of both callbacks). */
typedef struct {
    const tc_srv_config *cfg;
    atomic_int draining; /* set on shutdown: new requests get 503 and Connection: close */
    tc_pool *pool;       /* runs the POST routes off the I/O threads */
    tc_budget memory;    /* what renders in flight hold (--max-memory); an answer's share is
                          * given back when libmicrohttpd frees it */
    struct tc_meshes *meshes; /* the stored meshes (server/meshes.h) */
} tc_http_state;

enum MHD_Result tc_http_access(void *cls, struct MHD_Connection *c, const char *url, const char *method,
                               const char *version, const char *upload_data, size_t *upload_data_size,
                               void **req_cls);

void tc_http_completed(void *cls, struct MHD_Connection *c, void **req_cls, enum MHD_RequestTerminationCode toe);

#endif
