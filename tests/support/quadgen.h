/* quadgen.h — test quad meshes built without the core: grids (uneven, jittered, mapped affinely),
 * corners from random starts in random orientations, samples with exact gradients and hessians. */
#ifndef TC_TEST_QUADGEN_H
#define TC_TEST_QUADGEN_H

#include <stdint.h>

#include "meshgen.h"
#include "tocher.h"

/* A function to sample: value, gradient and hessian (fxx, fxy, fyy) of
 * channel ch at (x, y). */
typedef void (*qfunc)(const void *ctx, double x, double y, int ch, double *v, double g[2], double h[3]);

typedef struct {
    int32_t nv, nq, nc, nx, ny;
    double *xy;      /* [nv][2] */
    int32_t *quad;   /* [nq][4] */
    double *values;  /* [nv][nc] */
    double *grads;   /* [nv][nc][2] */
    double *hess;    /* [nv][nc][3] */
} qmesh;

typedef struct {
    double jitter;   /* interior vertices move by up to jitter * cell size in x and y */
    int uneven;      /* grid lines at uneven spacing (cells of different widths) */
    double A[4];     /* then x -> A x + off (row-major 2x2); identity when all 0 */
    double off[2];
} qgrid_opts;

/* nx x ny cells over [0,1]^2, vertex (i, j) at index j (nx + 1) + i; quad
 * j nx + i is cell (i, j) listed from a random corner in a random orientation. */
void qmesh_grid(qmesh *m, int nx, int ny, const qgrid_opts *o, trng *r);
void qmesh_sample(qmesh *m, int nc, qfunc f, const void *ctx);
void qmesh_free(qmesh *m);
/* A description of the mesh (views into m): quads, values, and gradients or
 * hessians if asked for. */
void qmesh_desc(const qmesh *m, int with_grads, int with_hess, tc_mesh_desc *d);

/* For each pair of quads sharing an edge, calls f with the two split
 * triangles (one per quad) and the edge's end points. */
typedef void (*qedge_fn)(void *ctx, int32_t ta, int32_t tb, const double p[2], const double q[2]);
void qmesh_shared_edges(const tc_mesh *m, qedge_fn f, void *ctx);

#endif
