/* benchmesh.h — a bench mesh (bench/perf/meshes.py's JSON file) read and built as the tile
 * benchmarks use it: request, mesh, the request's reconstruction and a locator. */
#ifndef TC_BENCH_BENCHMESH_H
#define TC_BENCH_BENCHMESH_H

#include <stdio.h>
#include <stdlib.h>

#include "io/request.h"
#include "tocher.h"
#include "benchio.h"

typedef struct {
    char *json;
    tc_request *req;
    tc_mesh *m;
    tc_recon *r;
    tc_locator *L;
} bench_mesh;

static inline void bench_mesh_free(bench_mesh *b) {
    tc_locator_free(b->L), tc_recon_free(b->r), tc_mesh_free(b->m), tc_request_free(b->req);
    free(b->json);
}

/* 0, or -1 with a message on stderr (b freed). */
static inline int bench_mesh_load(const char *path, bench_mesh *b) {
    size_t len;
    *b = (bench_mesh){bench_slurp(path, &len), NULL, NULL, NULL, NULL};
    if (!b->json || tc_request_parse(b->json, len, TC_REQ_MESH, &b->req, NULL) != TC_REQ_OK ||
        tc_mesh_new(&b->req->desc, &b->m, NULL) != TC_OK || tc_recon_new(b->m, &b->req->opt, &b->r, NULL) != TC_OK ||
        tc_locator_new(b->m, &b->L) != TC_OK) {
        fprintf(stderr, "%s: cannot build\n", path);
        bench_mesh_free(b);
        return -1;
    }
    return 0;
}

#endif
