/* meshes.h — the stored-mesh resources (/v1/meshes...): the mesh store (ids ->
 * canonical bytes) and the cache of built reconstructions, and their handlers. */
#ifndef TC_SERVER_MESHES_H
#define TC_SERVER_MESHES_H

#include <stddef.h>

#include "io/strbuf.h"
#include "server/routes.h"

typedef struct tc_meshes tc_meshes;

/* store: "memory" (the only backend of this build); cache_bytes: the built
 * reconstructions' LRU bound; tile_bytes: the encoded tiles' (0: no tile cache).
 * NULL with a reason in err on failure. */
tc_meshes *tc_meshes_new(const char *store, long long cache_bytes, long long tile_bytes, char *err,
                         size_t errlen);
void tc_meshes_free(tc_meshes *m);

/* The cache and store figures in Prometheus text: tocher_cache_hits_total,
 * _misses_total, _evictions_total, tocher_cache_bytes, tocher_meshes_stored. */
void tc_meshes_write_metrics(tc_meshes *m, tc_strbuf *out);

/* POST /v1/meshes */
void tc_meshes_post(const tc_route_input *in, tc_reply *out);
/* GET and DELETE /v1/meshes/{id} */
void tc_meshes_get(const tc_route_input *in, tc_reply *out);
void tc_meshes_delete(const tc_route_input *in, tc_reply *out);
/* GET /v1/meshes/{id}/ordinates, POST .../evaluate, POST .../render */
void tc_meshes_ordinates(const tc_route_input *in, tc_reply *out);
void tc_meshes_evaluate(const tc_route_input *in, tc_reply *out);
void tc_meshes_render(const tc_route_input *in, tc_reply *out);
/* GET /v1/meshes/{id}/tiles/{z}/{x}/{y}.{format} */
void tc_meshes_tile(const tc_route_input *in, tc_reply *out);

#endif
