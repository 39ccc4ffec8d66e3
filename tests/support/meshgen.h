/* meshgen.h — test meshes: jittered grids, Delaunay-like meshes, discontinuity
 * polylines and sampled data, built independently of the core under test. */
#ifndef TC_TEST_MESHGEN_H
#define TC_TEST_MESHGEN_H

#include <stdint.h>

#include "tocher.h"

typedef struct { uint64_t s; } trng;
void trng_seed(trng *r, uint64_t seed);
double trng_uniform(trng *r);            /* [0, 1) */
int trng_int(trng *r, int n);            /* 0 .. n-1 */

/* A function to sample: value and gradient of channel ch at (x, y). */
typedef void (*tfunc)(const void *ctx, double x, double y, int ch, double *val, double grad[2]);

typedef struct {
    int32_t nv, nt, nc;
    double *xy;          /* [nv][2] */
    int32_t *tri;        /* [nt][3] */
    double *values;      /* [nv][nc] */
    double *grads;       /* [nv][nc][2] or NULL */
    int32_t ncv;         /* corner value overrides */
    int32_t *cv_tri;
    double *cv;          /* [ncv][3][nc] */
    int32_t ncg;         /* corner gradients */
    int32_t *cg_tri;
    double *cg;          /* [ncg][3][nc][2] */
    int32_t nmid;
    int32_t *mid_edge;   /* [nmid][2] */
    int32_t *mid_tri;    /* [nmid] */
    double *mid_val;     /* [nmid][nc] */
    int32_t nline[2];    /* polylines: [0] = c0, [1] = c-1 */
    int32_t *line_start[2];
    int32_t *line_verts[2];
    int32_t line_cap[2], vert_cap[2];
    int8_t *eflag;       /* [nt][3] flag of edge k as the generator set it (1, 0, -1) */
    int32_t *enbr;       /* [nt][3] neighbour across edge k or -1 */
} tmesh;

/* nx by ny cells over [0,1]^2, each split along a random diagonal (or always
 * the same one if diag >= 0), corners listed in random orientation; interior
 * vertices jittered by up to jitter*h in x and y, except rows in keep_row and
 * columns in keep_col (so straight lines through vertices stay straight). */
void tmesh_grid(tmesh *m, int nx, int ny, double jitter, int diag, trng *r);
/* Lawson-flips edges to the Delaunay criterion (an irregular mesh). */
void tmesh_delaunay_flips(tmesh *m);
void tmesh_free(tmesh *m);

/* Grid vertex index of (i, j), 0 <= i <= nx, 0 <= j <= ny (valid until flips only
 * change connectivity, never vertex numbering). */
int32_t tmesh_gv(int nx, int i, int j);

/* Adds a polyline of kind TC_C0 or TC_CM1 and flags its edges; returns 0, or
 * -1 if some segment is not an edge. */
int tmesh_add_line(tmesh *m, int kind, const int32_t *verts, int n);
/* A random walk of up to len edges from a random interior vertex that does
 * not revisit a vertex and avoids already flagged edges. */
void tmesh_random_line(tmesh *m, int kind, int len, trng *r);

/* Samples f at vertices (values; gradients if with_grads), at every edge
 * midpoint if with_mid, and splits corner values along C-1 edges: each corner
 * gets f + jump * (index of its C-1 sector around the vertex). */
void tmesh_sample(tmesh *m, int nc, tfunc f, const void *ctx, int with_grads, int with_mid, double jump);

/* A description of the mesh for tc_mesh_new (views into m). */
void tmesh_desc(const tmesh *m, tc_mesh_desc *d);

/* Builds the tc_mesh or fails the test. */
tc_mesh *tmesh_build(const tmesh *m);

#endif
