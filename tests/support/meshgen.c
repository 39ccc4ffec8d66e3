/* meshgen.c — test meshes built without the core: grids, Lawson-flipped
 * Delaunay-like meshes, polylines along edges, and sampled data with jumps. */
#include "meshgen.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"

void trng_seed(trng *r, uint64_t seed) { r->s = seed * 0x9E3779B97F4A7C15ULL + 0x632BE59BD9B4E019ULL; }

static uint64_t next(trng *r) { /* splitmix64 */
    uint64_t z = (r->s += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
}
double trng_uniform(trng *r) { return (double)(next(r) >> 11) * 0x1.0p-53; }
int trng_int(trng *r, int n) { return (int)(trng_uniform(r) * n); }

static void *xcalloc(size_t n, size_t sz) {
    void *p = calloc(n ? n : 1, sz);
    if (!p) abort();
    return p;
}

int32_t tmesh_gv(int nx, int i, int j) { return (int32_t)j * (nx + 1) + i; }

/* ---- adjacency (sorting edge records) ---- */

typedef struct { int32_t a, b, t, k; } erec;

static int erec_cmp(const void *x, const void *y) {
    const erec *p = x, *q = y;
    if (p->a != q->a) return p->a < q->a ? -1 : 1;
    if (p->b != q->b) return p->b < q->b ? -1 : 1;
    return p->t - q->t;
}

static void rebuild_adjacency(tmesh *m) {
    erec *e = xcalloc(3 * (size_t)m->nt, sizeof *e);
    for (int32_t t = 0; t < m->nt; t++)
        for (int k = 0; k < 3; k++) {
            int32_t a = m->tri[3 * t + k], b = m->tri[3 * t + (k + 1) % 3];
            e[3 * t + k] = (erec){a < b ? a : b, a < b ? b : a, t, k};
            m->enbr[3 * t + k] = -1;
        }
    qsort(e, 3 * (size_t)m->nt, sizeof *e, erec_cmp);
    for (size_t i = 0; i + 1 < 3 * (size_t)m->nt; i++)
        if (e[i].a == e[i + 1].a && e[i].b == e[i + 1].b) {
            m->enbr[3 * e[i].t + e[i].k] = e[i + 1].t;
            m->enbr[3 * e[i + 1].t + e[i + 1].k] = e[i].t;
        }
    for (size_t c = 0; c < 3 * (size_t)m->nt; c++)
        if (m->enbr[c] < 0) m->eflag[c] = -1;
        else if (m->eflag[c] < 0) m->eflag[c] = 1;
    free(e);
}

static void put_tri(tmesh *m, int32_t t, int32_t a, int32_t b, int32_t c, trng *r) {
    int flip = r ? trng_int(r, 2) : 0; /* random orientation */
    m->tri[3 * t] = a;
    m->tri[3 * t + 1] = flip ? c : b;
    m->tri[3 * t + 2] = flip ? b : c;
}

void tmesh_grid(tmesh *m, int nx, int ny, double jitter, int diag, trng *r) {
    memset(m, 0, sizeof *m);
    m->nv = (nx + 1) * (ny + 1);
    m->nt = 2 * nx * ny;
    m->xy = xcalloc(2 * (size_t)m->nv, sizeof *m->xy);
    m->tri = xcalloc(3 * (size_t)m->nt, sizeof *m->tri);
    m->eflag = xcalloc(3 * (size_t)m->nt, sizeof *m->eflag);
    m->enbr = xcalloc(3 * (size_t)m->nt, sizeof *m->enbr);
    for (int j = 0; j <= ny; j++)
        for (int i = 0; i <= nx; i++) {
            double *p = m->xy + 2 * tmesh_gv(nx, i, j);
            p[0] = (double)i / nx;
            p[1] = (double)j / ny;
            int interior = i > 0 && i < nx && j > 0 && j < ny;
            /* Rows and columns that are multiples of 4 stay straight lines. */
            if (interior && jitter > 0 && i % 4) p[0] += jitter * (2 * trng_uniform(r) - 1) / nx;
            if (interior && jitter > 0 && j % 4) p[1] += jitter * (2 * trng_uniform(r) - 1) / ny;
        }
    for (int j = 0; j < ny; j++)
        for (int i = 0; i < nx; i++) {
            int32_t a = tmesh_gv(nx, i, j), b = tmesh_gv(nx, i + 1, j), c = tmesh_gv(nx, i + 1, j + 1),
                    d = tmesh_gv(nx, i, j + 1), t = 2 * (j * nx + i);
            int dg = diag >= 0 ? diag : trng_int(r, 2);
            if (dg == 0) put_tri(m, t, a, b, c, r), put_tri(m, t + 1, a, c, d, r);
            else put_tri(m, t, a, b, d, r), put_tri(m, t + 1, b, c, d, r);
        }
    memset(m->eflag, -1, 3 * (size_t)m->nt); /* unset: adjacency makes interior edges C1 */
    rebuild_adjacency(m);
}

static double orient(const double *a, const double *b, const double *c) {
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/* d strictly inside the circumcircle of counter-clockwise (a, b, c). */
static int incircle(const double *a, const double *b, const double *c, const double *d) {
    double ax = a[0] - d[0], ay = a[1] - d[1], bx = b[0] - d[0], by = b[1] - d[1], cx = c[0] - d[0], cy = c[1] - d[1];
    double det = (ax * ax + ay * ay) * (bx * cy - cx * by) - (bx * bx + by * by) * (ax * cy - cx * ay) +
                 (cx * cx + cy * cy) * (ax * by - bx * ay);
    return det > 1e-12;
}

/* Axis-parallel edges on the straight rows/columns are kept (constrained). */
static int protected_edge(const tmesh *m, int32_t a, int32_t b) {
    const double *p = m->xy + 2 * a, *q = m->xy + 2 * b;
    return p[0] == q[0] || p[1] == q[1];
}

static int try_flip(tmesh *m, int32_t t, int k, uint8_t *touched) {
    int32_t t2 = m->enbr[3 * t + k];
    if (t2 < 0 || touched[t] || touched[t2]) return 0;
    int32_t a = m->tri[3 * t + k], b = m->tri[3 * t + (k + 1) % 3], c = m->tri[3 * t + (k + 2) % 3], d = -1;
    for (int j = 0; j < 3; j++)
        if (m->tri[3 * t2 + j] != a && m->tri[3 * t2 + j] != b) d = m->tri[3 * t2 + j];
    if (protected_edge(m, a, b)) return 0;
    const double *pa = m->xy + 2 * a, *pb = m->xy + 2 * b, *pc = m->xy + 2 * c, *pd = m->xy + 2 * d;
    int ccw = orient(pa, pb, pc) > 0;
    if (!incircle(ccw ? pa : pb, ccw ? pb : pa, pc, pd)) return 0;
    /* The flipped pair (c, d, a) and (d, c, b) must both be proper triangles. */
    if (orient(pc, pd, pa) * orient(pc, pd, pb) >= 0) return 0;
    if (fabs(orient(pc, pd, pa)) < 1e-9 || fabs(orient(pc, pd, pb)) < 1e-9) return 0;
    m->tri[3 * t] = c, m->tri[3 * t + 1] = d, m->tri[3 * t + 2] = a;
    m->tri[3 * t2] = d, m->tri[3 * t2 + 1] = c, m->tri[3 * t2 + 2] = b;
    touched[t] = touched[t2] = 1;
    return 1;
}

void tmesh_delaunay_flips(tmesh *m) {
    uint8_t *touched = xcalloc((size_t)m->nt, 1);
    for (int pass = 0; pass < 200; pass++) {
        int flips = 0;
        memset(touched, 0, (size_t)m->nt);
        for (int32_t t = 0; t < m->nt; t++)
            for (int k = 0; k < 3; k++) flips += try_flip(m, t, k, touched);
        for (size_t c = 0; c < 3 * (size_t)m->nt; c++) m->eflag[c] = -1;
        rebuild_adjacency(m);
        if (!flips) break;
    }
    free(touched);
}

void tmesh_free(tmesh *m) {
    free(m->xy), free(m->tri), free(m->values), free(m->grads);
    free(m->cv_tri), free(m->cv), free(m->cg_tri), free(m->cg);
    free(m->mid_edge), free(m->mid_tri), free(m->mid_val);
    for (int i = 0; i < 2; i++) free(m->line_start[i]), free(m->line_verts[i]);
    free(m->eflag), free(m->enbr);
    memset(m, 0, sizeof *m);
}

/* ---- polylines ---- */

static int find_edge(const tmesh *m, int32_t a, int32_t b) {
    for (int32_t t = 0; t < m->nt; t++)
        for (int k = 0; k < 3; k++) {
            int32_t p = m->tri[3 * t + k], q = m->tri[3 * t + (k + 1) % 3];
            if ((p == a && q == b) || (p == b && q == a)) return 3 * t + k;
        }
    return -1;
}

int tmesh_add_line(tmesh *m, int kind, const int32_t *verts, int n) {
    int s = kind == TC_C0 ? 0 : 1;
    for (int i = 0; i + 1 < n; i++)
        if (find_edge(m, verts[i], verts[i + 1]) < 0) return -1;
    if (m->nline[s] + 2 > m->line_cap[s]) {
        m->line_cap[s] = 2 * m->line_cap[s] + 8;
        m->line_start[s] = realloc(m->line_start[s], (size_t)m->line_cap[s] * sizeof(int32_t));
        if (m->nline[s] == 0) m->line_start[s][0] = 0;
    }
    int32_t used = m->line_start[s][m->nline[s]];
    if (used + n > m->vert_cap[s]) {
        m->vert_cap[s] = 2 * (used + n) + 16;
        m->line_verts[s] = realloc(m->line_verts[s], (size_t)m->vert_cap[s] * sizeof(int32_t));
    }
    memcpy(m->line_verts[s] + used, verts, (size_t)n * sizeof *verts);
    m->line_start[s][++m->nline[s]] = used + n;
    for (int i = 0; i + 1 < n; i++) {
        int c = find_edge(m, verts[i], verts[i + 1]);
        if (m->enbr[c] < 0) continue;
        int32_t t2 = m->enbr[c];
        m->eflag[c] = (int8_t)kind;
        for (int k = 0; k < 3; k++)
            if (m->enbr[3 * t2 + k] == c / 3 &&
                (m->tri[3 * t2 + k] == verts[i] || m->tri[3 * t2 + k] == verts[i + 1]) &&
                (m->tri[3 * t2 + (k + 1) % 3] == verts[i] || m->tri[3 * t2 + (k + 1) % 3] == verts[i + 1]))
                m->eflag[3 * t2 + k] = (int8_t)kind;
    }
    return 0;
}

void tmesh_random_line(tmesh *m, int kind, int len, trng *r) {
    int32_t path[64], n = 0;
    if (len > 63) len = 63;
    path[n++] = trng_int(r, m->nv);
    while (n <= len) {
        int32_t cand[32], nc = 0, v = path[n - 1];
        for (int32_t t = 0; t < m->nt && nc < 32; t++)
            for (int k = 0; k < 3; k++) {
                int32_t a = m->tri[3 * t + k], b = m->tri[3 * t + (k + 1) % 3];
                if (a != v || m->eflag[3 * t + k] != 1) continue; /* interior, unflagged */
                int seen = 0;
                for (int i = 0; i < n; i++) seen |= path[i] == b;
                if (!seen && nc < 32) cand[nc++] = b;
            }
        if (!nc) break;
        path[n++] = cand[trng_int(r, nc)];
    }
    if (n >= 2) tmesh_add_line(m, kind, path, n);
}

/* ---- data ---- */

/* Sector of each corner around its vertex, split only by C-1 edges (and the
 * boundary): union-find of corners across non-C-1 interior edges. */
static int32_t find(int32_t *up, int32_t x) {
    while (up[x] != x) x = up[x] = up[up[x]];
    return x;
}

static void sectors(const tmesh *m, int32_t *sector) {
    int32_t nc3 = 3 * m->nt, *up = xcalloc((size_t)nc3, sizeof *up);
    for (int32_t c = 0; c < nc3; c++) up[c] = c;
    for (int32_t c = 0; c < nc3; c++) {
        int32_t t = c / 3, k = c % 3, t2 = m->enbr[c];
        if (t2 < 0 || m->eflag[c] == TC_CM1) continue;
        for (int e = 0; e < 2; e++) { /* both ends of edge k */
            int32_t v = m->tri[3 * t + (k + e) % 3];
            for (int j = 0; j < 3; j++)
                if (m->tri[3 * t2 + j] == v) up[find(up, 3 * t + (k + e) % 3)] = find(up, 3 * t2 + j);
        }
    }
    /* Number each vertex's sectors 0, 1, ... in order of the lowest corner. */
    int32_t *rootv = xcalloc((size_t)nc3, sizeof *rootv), *count = xcalloc((size_t)m->nv, sizeof *count);
    for (int32_t c = 0; c < nc3; c++) rootv[c] = -1;
    for (int32_t c = 0; c < nc3; c++) {
        int32_t root = find(up, c);
        if (rootv[root] < 0) rootv[root] = count[m->tri[c]]++;
        sector[c] = rootv[root];
    }
    free(up), free(rootv), free(count);
}

static void sample_midpoints(tmesh *m, tfunc f, const void *ctx, const int32_t *sector, double jump) {
    int nc = m->nc;
    m->mid_edge = xcalloc(6 * (size_t)m->nt, sizeof *m->mid_edge);
    m->mid_tri = xcalloc(3 * (size_t)m->nt, sizeof *m->mid_tri);
    m->mid_val = xcalloc(3 * (size_t)m->nt * (size_t)nc, sizeof *m->mid_val);
    for (int32_t c = 0; c < 3 * m->nt; c++) {
        int32_t t = c / 3, k = c % 3, t2 = m->enbr[c];
        int split = t2 >= 0 && m->eflag[c] == TC_CM1;
        if (t2 >= 0 && t2 < t && !split) continue; /* one sample per shared edge */
        int32_t a = m->tri[c], b = m->tri[3 * t + (k + 1) % 3], i = m->nmid++;
        const double *pa = m->xy + 2 * a, *pb = m->xy + 2 * b;
        m->mid_edge[2 * i] = a, m->mid_edge[2 * i + 1] = b;
        m->mid_tri[i] = split ? t : -1;
        for (int ch = 0; ch < nc; ch++) {
            double g[2], off = 0.5 * jump * (sector[c] + sector[3 * t + (k + 1) % 3]) * (1 + 0.1 * ch);
            f(ctx, 0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1]), ch, &m->mid_val[(size_t)i * (size_t)nc + (size_t)ch], g);
            m->mid_val[(size_t)i * (size_t)nc + (size_t)ch] += off;
        }
    }
}

void tmesh_sample(tmesh *m, int nc, tfunc f, const void *ctx, int with_grads, int with_mid, double jump) {
    m->nc = nc;
    m->values = xcalloc((size_t)m->nv * (size_t)nc, sizeof *m->values);
    if (with_grads) m->grads = xcalloc((size_t)m->nv * (size_t)nc * 2, sizeof *m->grads);
    for (int32_t v = 0; v < m->nv; v++)
        for (int ch = 0; ch < nc; ch++) {
            double g[2];
            f(ctx, m->xy[2 * v], m->xy[2 * v + 1], ch, &m->values[(size_t)v * (size_t)nc + (size_t)ch], g);
            if (with_grads) memcpy(m->grads + ((size_t)v * (size_t)nc + (size_t)ch) * 2, g, sizeof g);
        }
    int32_t *sector = xcalloc(3 * (size_t)m->nt, sizeof *sector);
    sectors(m, sector);
    m->cv_tri = xcalloc((size_t)m->nt, sizeof *m->cv_tri);
    m->cv = xcalloc(3 * (size_t)m->nt * (size_t)nc, sizeof *m->cv);
    for (int32_t t = 0; t < m->nt && jump != 0; t++) {
        if (!sector[3 * t] && !sector[3 * t + 1] && !sector[3 * t + 2]) continue;
        int32_t i = m->ncv++;
        m->cv_tri[i] = t;
        for (int k = 0; k < 3; k++)
            for (int ch = 0; ch < nc; ch++)
                m->cv[((size_t)i * 3 + (size_t)k) * (size_t)nc + (size_t)ch] =
                    m->values[(size_t)m->tri[3 * t + k] * (size_t)nc + (size_t)ch] + jump * sector[3 * t + k] * (1 + 0.1 * ch);
    }
    if (with_mid) sample_midpoints(m, f, ctx, sector, jump);
    free(sector);
}

void tmesh_desc(const tmesh *m, tc_mesh_desc *d) {
    memset(d, 0, sizeof *d);
    d->nverts = m->nv, d->xy = m->xy;
    d->ntris = m->nt, d->tris = m->tri;
    d->nchan = m->nc, d->values = m->values;
    d->ncorner_values = m->ncv, d->corner_values_tri = m->cv_tri, d->corner_values = m->cv;
    d->gradients = m->grads;
    d->ncorner_gradients = m->ncg, d->corner_gradients_tri = m->cg_tri, d->corner_gradients = m->cg;
    d->nmidpoints = m->nmid, d->midpoint_edge = m->mid_edge, d->midpoint_tri = m->mid_tri;
    d->midpoint_values = m->mid_val;
    d->c0 = (tc_polylines){m->nline[0], m->line_start[0], m->line_verts[0]};
    d->cm1 = (tc_polylines){m->nline[1], m->line_start[1], m->line_verts[1]};
}

tc_mesh *tmesh_build(const tmesh *m) {
    tc_mesh_desc d;
    tc_diags dg;
    tc_mesh *out = NULL;
    tmesh_desc(m, &d);
    tc_diags_init(&dg);
    if (tc_mesh_new(&d, &out, &dg) != TC_OK)
        tc_test_fail(__FILE__, __LINE__, "tc_mesh_new failed: %s: %s", dg.count ? dg.items[0].path : "",
                     dg.count ? dg.items[0].message : "(no message)");
    tc_diags_free(&dg);
    return out;
}
