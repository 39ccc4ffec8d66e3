/* routes.h — the route table: which path (exact, or a pattern with {name}
 * segments) answers which method with which handler. Handlers turn a complete
 * request into a tc_reply. */
#ifndef TC_SERVER_ROUTES_H
#define TC_SERVER_ROUTES_H

#include <stddef.h>

#include "io/api.h"
#include "server/reply.h"

struct tc_meshes;

/* The {name} segments of a pattern route, in order; longer ones do not match. */
enum { TC_ROUTE_MAX_PARAMS = 4, TC_ROUTE_PARAM_MAX = 64 };
typedef struct {
    int n;
    char seg[TC_ROUTE_MAX_PARAMS][TC_ROUTE_PARAM_MAX + 1];
} tc_path_params;

/* The decoded query arguments of a GET, in order. */
enum { TC_QUERY_MAX = 16 };
typedef struct {
    int n, overflow; /* overflow: more than TC_QUERY_MAX were given */
    char *key[TC_QUERY_MAX], *value[TC_QUERY_MAX]; /* value "" for a key without '=' */
} tc_query;

void tc_query_free(tc_query *q);

typedef struct {
    const char *body; /* NUL-terminated, valid UTF-8 (empty for GET) */
    size_t len;
    const char *accept; /* Accept header or NULL */
    tc_api_limits lim;
    const tc_path_params *params;
    const tc_query *query;
    const char *if_none_match; /* If-None-Match header or NULL */
    struct tc_meshes *meshes;  /* the mesh store and cache */
} tc_route_input;

typedef void (*tc_route_fn)(const tc_route_input *in, tc_reply *out);

typedef struct {
    const char *path;  /* "/v1/render", or "/v1/meshes/{id}/tiles/{z}/{x}/{y}" ({name}: one segment) */
    const char *allow; /* the Allow header of a 405 */
    tc_route_fn get, post, del; /* NULL: that method is not allowed; HEAD runs get */
    int compute;       /* its GET and DELETE run on the worker pool too (they may build) */
} tc_route;

/* The route for a path, or NULL; *index (if not NULL) gets its slot in the
 * table (metrics label it by path), -1 if none; params (if not NULL) the
 * segments a pattern matched. */
const tc_route *tc_route_find(const char *path, int *index, tc_path_params *params);
/* The handler of method on r, NULL if r does not answer it (405). */
tc_route_fn tc_route_handler(const tc_route *r, const char *method);
int tc_route_allows(const tc_route *r, const char *method);
/* POST reads a JSON body; the other methods ignore any body. */
int tc_route_takes_body(const tc_route *r, const char *method);
/* Runs on the worker pool (POST, and the GET/DELETE of compute routes), not on an I/O thread. */
int tc_route_on_pool(const tc_route *r, const char *method);

int tc_route_count(void);
const char *tc_route_path(int i); /* of slot i, NULL if out of range */

#endif
