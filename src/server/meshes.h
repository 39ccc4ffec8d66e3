/* meshes.h — the stored-mesh resources (/v1/meshes...): the mesh store (ids ->
 * canonical bytes) and the cache of built reconstructions, and their handlers. */
#ifndef TC_SERVER_MESHES_H
#define TC_SERVER_MESHES_H

#include <stddef.h>

#include "io/strbuf.h"
#include "server/config.h"
#include "server/routes.h"

typedef struct tc_meshes tc_meshes;

/* The store of cfg->store ("memory", or redis://... with cfg->mesh_ttl and
 * timeouts within cfg->request_timeout), a cache of cfg->cache_memory bytes
 * and an encoded-tile cache of cfg->tile_cache_memory (0: none). A Redis not reachable yet is no failure (the store is down until it
 * is). NULL with a reason in err on failure. */
tc_meshes *tc_meshes_new(const tc_srv_config *cfg, char *err, size_t errlen);
void tc_meshes_free(tc_meshes *m);

/* The cache and store figures in Prometheus text: tocher_cache_hits_total,
 * _misses_total, _evictions_total, tocher_cache_bytes, tocher_meshes_stored
 * (memory store only), tocher_store_up, _errors_total, _reconnects_total. */
void tc_meshes_write_metrics(tc_meshes *m, tc_strbuf *out);
/* {"backend":"memory|redis","state":"up|down"}: the last known state, no I/O (/healthz). */
void tc_meshes_write_store(tc_meshes *m, tc_strbuf *out);
/* 1 if the store answers now (a PING for Redis, bounded by its timeouts and
 * backoff), else 0 (/readyz). */
int tc_meshes_ready(tc_meshes *m);

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
