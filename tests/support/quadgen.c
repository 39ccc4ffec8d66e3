/* quadgen.c — test quad meshes built without the core (see quadgen.h), and a
 * walk over the quad edges of a built mesh for continuity checks. */
#include "quadgen.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void *xcalloc(size_t n, size_t sz) {
    void *p = calloc(n ? n : 1, sz);
    if (!p) abort();
    return p;
}

/* Grid line k of n: even, or uneven but monotone (widths 0.6 .. 1.4 of even). */
static double line_at(int k, int n, int uneven, const double *w) {
    if (!uneven) return (double)k / n;
    double s = 0, all = 0;
    for (int i = 0; i < n; i++) all += w[i], s += i < k ? w[i] : 0;
    return k == n ? 1.0 : s / all;
}

void qmesh_grid(qmesh *m, int nx, int ny, const qgrid_opts *o, trng *r) {
    memset(m, 0, sizeof *m);
    m->nx = nx, m->ny = ny, m->nv = (nx + 1) * (ny + 1), m->nq = nx * ny;
    m->xy = xcalloc(2 * (size_t)m->nv, sizeof *m->xy);
    m->quad = xcalloc(4 * (size_t)m->nq, sizeof *m->quad);
    double *wx = xcalloc((size_t)nx, sizeof *wx), *wy = xcalloc((size_t)ny, sizeof *wy);
    for (int i = 0; i < nx; i++) wx[i] = 0.6 + 0.8 * trng_uniform(r);
    for (int j = 0; j < ny; j++) wy[j] = 0.6 + 0.8 * trng_uniform(r);
    int affine = o->A[0] != 0 || o->A[1] != 0 || o->A[2] != 0 || o->A[3] != 0;
    for (int j = 0; j <= ny; j++)
        for (int i = 0; i <= nx; i++) {
            double x = line_at(i, nx, o->uneven, wx), y = line_at(j, ny, o->uneven, wy);
            if (i > 0 && i < nx && j > 0 && j < ny) {
                x += o->jitter / nx * (2 * trng_uniform(r) - 1);
                y += o->jitter / ny * (2 * trng_uniform(r) - 1);
            }
            double *p = m->xy + 2 * (size_t)(j * (nx + 1) + i);
            p[0] = affine ? o->A[0] * x + o->A[1] * y + o->off[0] : x;
            p[1] = affine ? o->A[2] * x + o->A[3] * y + o->off[1] : y;
        }
    for (int j = 0; j < ny; j++)
        for (int i = 0; i < nx; i++) {
            int32_t c[4] = {j * (nx + 1) + i, j * (nx + 1) + i + 1, (j + 1) * (nx + 1) + i + 1, (j + 1) * (nx + 1) + i};
            int start = trng_int(r, 4), dir = trng_int(r, 2) ? 1 : 3;
            int32_t *q = m->quad + 4 * (size_t)(j * nx + i);
            for (int k = 0; k < 4; k++) q[k] = c[(start + dir * k) % 4];
        }
    free(wx), free(wy);
}

void qmesh_sample(qmesh *m, int nc, qfunc f, const void *ctx) {
    m->nc = nc;
    free(m->values), free(m->grads), free(m->hess);
    m->values = xcalloc((size_t)m->nv * (size_t)nc, sizeof *m->values);
    m->grads = xcalloc((size_t)m->nv * (size_t)nc * 2, sizeof *m->grads);
    m->hess = xcalloc((size_t)m->nv * (size_t)nc * 3, sizeof *m->hess);
    for (int32_t v = 0; v < m->nv; v++)
        for (int ch = 0; ch < nc; ch++) {
            size_t i = (size_t)v * (size_t)nc + (size_t)ch;
            f(ctx, m->xy[2 * v], m->xy[2 * v + 1], ch, &m->values[i], m->grads + 2 * i, m->hess + 3 * i);
        }
}

void qmesh_free(qmesh *m) {
    free(m->xy), free(m->quad), free(m->values), free(m->grads), free(m->hess);
    memset(m, 0, sizeof *m);
}

void qmesh_desc(const qmesh *m, int with_grads, int with_hess, tc_mesh_desc *d) {
    memset(d, 0, sizeof *d);
    d->nverts = m->nv, d->xy = m->xy;
    d->nquads = m->nq, d->quads = m->quad;
    d->nchan = m->nc, d->values = m->values;
    if (with_grads) d->gradients = m->grads;
    if (with_hess) d->hessians = m->hess;
}

void qmesh_shared_edges(const tc_mesh *m, qedge_fn f, void *ctx) {
    const double *xy = tc_mesh_xy(m);
    const int32_t *tri = tc_mesh_triangles(m);
    for (int32_t t = 0; t < tc_mesh_triangle_count(m); t++)
        for (int k = 0; k < 3; k++) {
            if (k == (t % 2 == 0 ? 2 : 0)) continue; /* the diagonal: inside the quad */
            int nk;
            int32_t t2 = tc_mesh_neighbor(m, t, k, &nk);
            if (t2 < t) continue; /* boundary, or seen from t2 */
            f(ctx, t, t2, xy + 2 * tri[3 * t + k], xy + 2 * tri[3 * t + (k + 1) % 3]);
        }
}
