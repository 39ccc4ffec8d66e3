/* routes.h — the route table: which path answers which method with which
 * handler. Handlers turn a complete request body into a tc_reply. */
#ifndef TC_SERVER_ROUTES_H
#define TC_SERVER_ROUTES_H

#include <stddef.h>

#include "io/api.h"
#include "server/reply.h"

typedef struct {
    const char *body; /* NUL-terminated, valid UTF-8 (empty for GET) */
    size_t len;
    const char *accept; /* Accept header or NULL */
    tc_api_limits lim;
} tc_route_input;

typedef void (*tc_route_fn)(const tc_route_input *in, tc_reply *out);

typedef struct {
    const char *path;
    const char *method; /* "GET" (HEAD too) or "POST" */
    const char *allow;  /* the Allow header of a 405 */
    tc_route_fn fn;
} tc_route;

/* The route for an exact path, or NULL; *index (if not NULL) gets its slot
 * in the table (metrics label it by path), -1 if none. */
const tc_route *tc_route_find(const char *path, int *index);
int tc_route_allows(const tc_route *r, const char *method);
/* POST routes read a JSON body; the others ignore any body. */
int tc_route_takes_body(const tc_route *r);

int tc_route_count(void);
const char *tc_route_path(int i); /* of slot i, NULL if out of range */

#endif
