/* sampling.c — what a front-end measures on its mesh: vertex values, each side's
 * limit where a vertex is on a C-1 line, edge-midpoint samples, corner gradients. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scenes/build.h"

static const double PI = 3.14159265358979323846;

/* Step of the one-sided differences, relative to the edge's length. */
#define GRAD_STEP 1e-4
/* Most C-1 or boundary edges at one vertex that get their own sector (a grid
 * vertex has at most 4; beyond this the extra edges are ignored). */
#define MAX_DELIMITERS 16

/* An undirected mesh edge: v[0] < v[1]; t[1] = -1 on the boundary. */
typedef struct {
    int32_t v[2], t[2];
    int8_t flag;
} edge;

typedef struct {
    const tc_scene *s;
    const tc__mbuild *b;
    edge *e;
    int32_t ne;
    int32_t *tri_edge;         /* [3nt]: the edge from corner k to corner k+1 */
    int32_t *vstart, *vcorner; /* vertex -> corners (3t + k), CSR */
    double *cz;                /* [3nt] corner values */
    int quads;                 /* per-corner data goes to quads: cell q = triangles 2q, 2q+1 */
    int digits;                /* values rounded to this many significant digits (0: exact) */
    tc_scene_mesh *m;
} ctx;

/* The elements per-corner data names: triangles, or quads (pairs of them). */
static int32_t elem_count(const ctx *c) { return c->quads ? c->b->nt / 2 : c->b->nt; }

/* The corner ids (3t + k) of element e's corners, in its order; returns how
 * many (3, or 4: quad e's halves are 2e = (a, b, c) and 2e+1 = (a, c, d)). */
static int elem_corners(const ctx *c, int32_t e, int32_t id[4]) {
    if (!c->quads) {
        for (int k = 0; k < 3; k++) id[k] = 3 * e + k;
        return 3;
    }
    id[0] = 6 * e, id[1] = 6 * e + 1, id[2] = 6 * e + 2, id[3] = 6 * e + 5;
    return 4;
}

/* ---- topology ---------------------------------------------------------------------- */

static uint64_t edge_key(int32_t a, int32_t b) {
    return a < b ? (uint64_t)a << 32 | (uint32_t)b : (uint64_t)b << 32 | (uint32_t)a;
}

/* Edges of the triangles, found through a hash of their end points. */
static int build_edges(ctx *c) {
    const tc__mbuild *b = c->b;
    size_t cap = 16;
    while (cap < 6 * (size_t)b->nt) cap *= 2;
    uint64_t *keys = malloc(cap * sizeof *keys);
    int32_t *ids = malloc(cap * sizeof *ids);
    c->e = malloc(3 * (size_t)b->nt * sizeof *c->e);
    c->tri_edge = malloc(3 * (size_t)b->nt * sizeof *c->tri_edge);
    int rc = keys && ids && c->e && c->tri_edge ? TC_OK : TC_ENOMEM;
    if (rc == TC_OK) memset(keys, 0xff, cap * sizeof *keys);
    for (int32_t t = 0; rc == TC_OK && t < b->nt; t++)
        for (int k = 0; k < 3; k++) {
            int32_t p = b->tri[3 * t + k], q = b->tri[3 * t + (k + 1) % 3];
            uint64_t key = edge_key(p, q);
            size_t i = (size_t)((key * 0x9E3779B97F4A7C15ull) >> 20) & (cap - 1);
            while (keys[i] != UINT64_MAX && keys[i] != key) i = (i + 1) & (cap - 1);
            if (keys[i] == UINT64_MAX) {
                keys[i] = key, ids[i] = c->ne;
                c->e[c->ne++] = (edge){{p < q ? p : q, p < q ? q : p}, {t, -1}, TC_C1};
            } else {
                c->e[ids[i]].t[1] = t;
            }
            c->tri_edge[3 * t + k] = ids[i];
        }
    free(keys), free(ids);
    return rc;
}

/* The edge joining a and b, through the corners of a (-1 if none). */
static int32_t find_edge(const ctx *c, int32_t a, int32_t b) {
    for (int32_t i = c->vstart[a]; i < c->vstart[a + 1]; i++) {
        int32_t corner = c->vcorner[i], t = corner / 3, k = corner % 3;
        int32_t e0 = c->tri_edge[corner], e1 = c->tri_edge[3 * t + (k + 2) % 3];
        if (c->e[e0].v[0] == b || c->e[e0].v[1] == b) return e0;
        if (c->e[e1].v[0] == b || c->e[e1].v[1] == b) return e1;
    }
    return -1;
}

static int build_corners(ctx *c) {
    const tc__mbuild *b = c->b;
    c->vstart = calloc((size_t)b->nv + 1, sizeof *c->vstart);
    c->vcorner = malloc(3 * (size_t)b->nt * sizeof *c->vcorner + 1);
    if (!c->vstart || !c->vcorner) return TC_ENOMEM;
    for (int32_t i = 0; i < 3 * b->nt; i++) c->vstart[b->tri[i] + 1]++;
    for (int32_t v = 0; v < b->nv; v++) c->vstart[v + 1] += c->vstart[v];
    int32_t *fill = malloc(((size_t)b->nv + 1) * sizeof *fill);
    if (!fill) return TC_ENOMEM;
    memcpy(fill, c->vstart, ((size_t)b->nv + 1) * sizeof *fill);
    for (int32_t i = 0; i < 3 * b->nt; i++) c->vcorner[fill[b->tri[i]]++] = i;
    free(fill);
    return TC_OK;
}

/* Flags from the polylines (a jump outranks a kink) and their counts. */
static void apply_flags(ctx *c) {
    for (int kind = 0; kind < 2; kind++)
        for (int32_t l = 0; l < c->b->nline[kind]; l++)
            for (int32_t i = c->b->line_start[kind][l]; i + 1 < c->b->line_start[kind][l + 1]; i++) {
                int32_t e = find_edge(c, c->b->line_verts[kind][i], c->b->line_verts[kind][i + 1]);
                if (e >= 0 && (kind == 1 || c->e[e].flag == TC_C1)) c->e[e].flag = kind ? TC_CM1 : TC_C0;
            }
    for (int32_t e = 0; e < c->ne; e++) {
        c->m->flagged_c0 += c->e[e].flag == TC_C0;
        c->m->flagged_cm1 += c->e[e].flag == TC_CM1;
    }
}

static const double *vxy(const ctx *c, int32_t v) { return c->b->xy + 2 * (size_t)v; }

/* ---- the scene seen from the mesh ------------------------------------------------- */

/* Mesh vector d in the scene's frame (the linear part of b->frame). */
static void scene_vector(const ctx *c, const double d[2], double q[2]) {
    const double *f = c->b->frame;
    q[0] = f[2] * d[0] + f[3] * d[1];
    q[1] = f[4] * d[0] + f[5] * d[1];
}

/* B at mesh point p, and its limit from direction d: every scene evaluation goes
 * through these two, so a rotated mesh samples the scene in the scene's frame. */
static double B_at(const ctx *c, const double p[2]) {
    if (!c->b->framed) return tc_scene_value(c->s, p[0], p[1]);
    const double *f = c->b->frame;
    double d[2] = {p[0] - f[0], p[1] - f[1]}, q[2];
    scene_vector(c, d, q);
    return tc_scene_value(c->s, f[0] + q[0], f[1] + q[1]);
}

static double B_from(const ctx *c, const double p[2], double dx, double dy) {
    if (!c->b->framed) return tc_scene_value_from(c->s, p[0], p[1], dx, dy);
    const double *f = c->b->frame;
    double d[2] = {p[0] - f[0], p[1] - f[1]}, q[2], dir[2] = {dx, dy}, u[2];
    scene_vector(c, d, q);
    scene_vector(c, dir, u);
    return tc_scene_value_from(c->s, f[0] + q[0], f[1] + q[1], u[0], u[1]);
}

/* v as a front-end prints it: rounded to c->digits significant digits
 * (correctly rounded by printf, read back exactly by strtod). */
static double printed(const ctx *c, double v) {
    if (!c->digits || !isfinite(v)) return v;
    char buf[40];
    snprintf(buf, sizeof buf, "%.*e", c->digits - 1, v);
    return strtod(buf, NULL);
}

static void centroid(const ctx *c, int32_t t, double g[2]) {
    const int32_t *v = c->b->tri + 3 * (size_t)t;
    for (int d = 0; d < 2; d++) g[d] = (vxy(c, v[0])[d] + vxy(c, v[1])[d] + vxy(c, v[2])[d]) / 3;
}

/* B at p from the side of triangle t (toward its centroid). */
static double value_in(const ctx *c, int32_t t, const double p[2]) {
    double g[2];
    centroid(c, t, g);
    return B_from(c, p, g[0] - p[0], g[1] - p[1]);
}

/* ---- values ----------------------------------------------------------------------- */

static int vertex_values(ctx *c) {
    const tc__mbuild *b = c->b;
    c->m->values_ = malloc(((size_t)b->nv + 1) * sizeof *c->m->values_);
    if (!c->m->values_) return TC_ENOMEM;
    if (b->values) {
        memcpy(c->m->values_, b->values, (size_t)b->nv * sizeof *b->values);
        c->m->samples += b->value_evals;
    } else {
        for (int32_t v = 0; v < b->nv; v++) c->m->values_[v] = B_at(c, vxy(c, v));
        c->m->samples += b->nv;
    }
    for (int32_t v = 0; v < b->nv; v++) c->m->values_[v] = printed(c, c->m->values_[v]);
    return TC_OK;
}

static int is_delimiter(const edge *e) { return e->flag == TC_CM1 || e->t[1] < 0; }

static int by_angle(const void *pa, const void *pb) {
    double a = *(const double *)pa, b = *(const double *)pb;
    return a < b ? -1 : a > b;
}

/* Directions of the C-1 and boundary edges at v, sorted (atan2 range); returns
 * their count, 0 when v is on no C-1 edge (then it needs no sectors). */
static int delimiters(const ctx *c, int32_t v, double *ang) {
    int32_t seen[MAX_DELIMITERS];
    int n = 0, jumps = 0;
    for (int32_t i = c->vstart[v]; i < c->vstart[v + 1]; i++) {
        int32_t corner = c->vcorner[i], t = corner / 3, k = corner % 3;
        int32_t es[2] = {c->tri_edge[corner], c->tri_edge[3 * t + (k + 2) % 3]};
        for (int j = 0; j < 2; j++) {
            const edge *e = &c->e[es[j]];
            int dup = 0;
            for (int q = 0; q < n; q++) dup |= seen[q] == es[j];
            if (dup || !is_delimiter(e) || n == MAX_DELIMITERS) continue;
            const double *p = vxy(c, v), *o = vxy(c, e->v[0] == v ? e->v[1] : e->v[0]);
            seen[n] = es[j];
            ang[n++] = atan2(o[1] - p[1], o[0] - p[0]);
            jumps += e->flag == TC_CM1;
        }
    }
    qsort(ang, (size_t)n, sizeof *ang, by_angle);
    return jumps ? n : 0;
}

/* Corner values at a vertex on a C-1 line: the edges that are C-1 or on the
 * boundary cut the disc around it into sectors; every corner in a sector gets
 * the limit along the sector's bisector. One value per sector keeps the values
 * equal across the sector's C0/C1 edges, as tc_mesh_new requires — also at the
 * box's footprint corners, where the true limit varies with the direction. */
static void sector_values(ctx *c, int32_t v) {
    double ang[MAX_DELIMITERS], val[MAX_DELIMITERS];
    int n = delimiters(c, v, ang), done[MAX_DELIMITERS] = {0};
    const double *p = vxy(c, v);
    for (int32_t i = c->vstart[v]; n && i < c->vstart[v + 1]; i++) {
        int32_t corner = c->vcorner[i];
        double g[2];
        centroid(c, corner / 3, g);
        double a = atan2(g[1] - p[1], g[0] - p[0]);
        int s = n - 1;
        for (int j = 0; j < n; j++)
            if (ang[j] <= a) s = j;
        if (!done[s]) {
            double gap = (s + 1 < n ? ang[s + 1] : ang[0] + 2 * PI) - ang[s], bis = ang[s] + gap / 2;
            val[s] = printed(c, B_from(c, p, cos(bis), sin(bis)));
            done[s] = 1;
            c->m->samples++;
        }
        c->cz[corner] = val[s];
    }
}

/* Element e has a corner whose value differs from its vertex value. */
static int elem_differs(const ctx *c, int32_t e) {
    int32_t id[4];
    int differs = 0;
    for (int k = 0, n = elem_corners(c, e, id); k < n; k++) differs |= c->cz[id[k]] != c->m->values_[c->b->tri[id[k]]];
    return differs;
}

/* Corner values (vertex values, then the sectors), and the corner_values
 * entries of the elements where some corner differs from its vertex value.
 * Both halves of a quad meet its shared corners a and c inside the quad's
 * angle there, hence in one sector: they got the same value. */
static int corner_values(ctx *c) {
    const tc__mbuild *b = c->b;
    tc_scene_mesh *m = c->m;
    c->cz = malloc(3 * (size_t)b->nt * sizeof *c->cz);
    if (!c->cz) return TC_ENOMEM;
    for (int32_t i = 0; i < 3 * b->nt; i++) c->cz[i] = m->values_[b->tri[i]];
    for (int32_t v = 0; v < b->nv; v++) sector_values(c, v);
    int32_t n = 0, nk = c->quads ? 4 : 3, id[4];
    for (int32_t e = 0; e < elem_count(c); e++) n += elem_differs(c, e);
    m->corner_values_tri_ = malloc(((size_t)n + 1) * sizeof *m->corner_values_tri_);
    m->corner_values_ = malloc((size_t)nk * ((size_t)n + 1) * sizeof *m->corner_values_);
    if (!m->corner_values_tri_ || !m->corner_values_) return TC_ENOMEM;
    n = 0;
    for (int32_t e = 0; e < elem_count(c); e++) {
        if (!elem_differs(c, e)) continue;
        m->corner_values_tri_[n] = e;
        elem_corners(c, e, id);
        for (int k = 0; k < nk; k++) m->corner_values_[(size_t)nk * (size_t)n + (size_t)k] = c->cz[id[k]];
        n++;
    }
    m->desc.ncorner_values = n;
    return TC_OK;
}

/* One sample at every edge midpoint; two on an interior C-1 edge, one per side. */
static int midpoints(ctx *c) {
    tc_scene_mesh *m = c->m;
    int32_t n = 0;
    for (int32_t e = 0; e < c->ne; e++) n += c->e[e].flag == TC_CM1 && c->e[e].t[1] >= 0 ? 2 : 1;
    m->midpoint_edge_ = malloc(2 * ((size_t)n + 1) * sizeof *m->midpoint_edge_);
    m->midpoint_tri_ = malloc(((size_t)n + 1) * sizeof *m->midpoint_tri_);
    m->midpoint_values_ = malloc(((size_t)n + 1) * sizeof *m->midpoint_values_);
    if (!m->midpoint_edge_ || !m->midpoint_tri_ || !m->midpoint_values_) return TC_ENOMEM;
    n = 0;
    for (int32_t i = 0; i < c->ne; i++) {
        const edge *e = &c->e[i];
        const double *a = vxy(c, e->v[0]), *b = vxy(c, e->v[1]);
        double mid[2] = {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])};
        int sides = e->flag == TC_CM1 && e->t[1] >= 0 ? 2 : 1;
        for (int k = 0; k < sides; k++, n++) {
            m->midpoint_edge_[2 * n] = e->v[0], m->midpoint_edge_[2 * n + 1] = e->v[1];
            m->midpoint_tri_[n] = sides == 2 ? (c->quads ? e->t[k] / 2 : e->t[k]) : -1;
            m->midpoint_values_[n] = printed(c, sides == 2 ? value_in(c, e->t[k], mid) : B_at(c, mid));
        }
    }
    m->desc.nmidpoints = n;
    m->samples += n;
    return TC_OK;
}

/* ---- gradients --------------------------------------------------------------------- */

/* The derivative at corner p along the unit direction u into triangle t, from
 * samples at p + j h u, j = 1..4 (h = GRAD_STEP * len): the cubic through them
 * differentiated at p, (-26 f1 + 57 f2 - 42 f3 + 11 f4) / (6h). That is the
 * one-sided second-order difference carried one order further (what one
 * Richardson step would give): truncation error 25/12 h^3 |B''''|, rounding
 * about 23 eps |B| / h. The corner value itself is not used: at the box's
 * footprint corners it is a compromise between directions, while the samples
 * along the edge are each taken from t's side of any C-1 line (the edge may be one). */
static double edge_derivative(const ctx *c, int32_t t, const double p[2], const double u[2], double len) {
    double h = GRAD_STEP * len, f[4];
    for (int j = 0; j < 4; j++) {
        double q[2] = {p[0] + (j + 1) * h * u[0], p[1] + (j + 1) * h * u[1]};
        f[j] = value_in(c, t, q);
    }
    return (-26 * f[0] + 57 * f[1] - 42 * f[2] + 11 * f[3]) / (6 * h);
}

/* The gradient at corner p from the derivatives along its edges to q[0] and
 * q[1], each taken from the side of the triangle t[j] holding that edge (a
 * 2x2 solve; the edges are independent). */
static void corner_gradient(const ctx *c, const double *p, const double *const q[2], const int32_t t[2], double g[2]) {
    double u[2][2], d[2];
    for (int j = 0; j < 2; j++) {
        double len = hypot(q[j][0] - p[0], q[j][1] - p[1]);
        u[j][0] = (q[j][0] - p[0]) / len, u[j][1] = (q[j][1] - p[1]) / len;
        d[j] = edge_derivative(c, t[j], p, u[j], len);
    }
    double det = u[0][0] * u[1][1] - u[0][1] * u[1][0];
    g[0] = (d[0] * u[1][1] - d[1] * u[0][1]) / det;
    g[1] = (u[0][0] * d[1] - u[1][0] * d[0]) / det;
}

/* Corner k of element e: along the element's own two edges there (a quad's,
 * not its diagonal), from the half that holds each edge. */
static void elem_corner_gradient(const ctx *c, int32_t e, int k, double g[2]) {
    int32_t id[4], n = elem_corners(c, e, id), v[4];
    for (int j = 0; j < n; j++) v[j] = c->b->tri[id[j]];
    const double *q[2] = {vxy(c, v[(k + 1) % n]), vxy(c, v[(k + n - 1) % n])};
    /* quad edges k -> k+1: ab and bc lie in half 2e, cd and da in 2e+1 */
    int32_t t[2] = {c->quads ? 2 * e + (k >= 2) : e, c->quads ? 2 * e + (k == 0 || k == 3) : e};
    corner_gradient(c, vxy(c, v[k]), q, t, g);
}

static int gradients(ctx *c) {
    tc_scene_mesh *m = c->m;
    int32_t ne = elem_count(c), nk = c->quads ? 4 : 3;
    m->corner_gradients_tri_ = malloc(((size_t)ne + 1) * sizeof *m->corner_gradients_tri_);
    m->corner_gradients_ = malloc(2 * (size_t)nk * ((size_t)ne + 1) * sizeof *m->corner_gradients_);
    if (!m->corner_gradients_tri_ || !m->corner_gradients_) return TC_ENOMEM;
    for (int32_t e = 0; e < ne; e++) {
        m->corner_gradients_tri_[e] = e;
        for (int k = 0; k < nk; k++) elem_corner_gradient(c, e, k, m->corner_gradients_ + 2 * ((size_t)nk * (size_t)e + (size_t)k));
    }
    m->desc.ncorner_gradients = ne;
    m->gradient_samples += 8 * (int64_t)nk * ne; /* 4 per edge, 2 edges per corner */
    return TC_OK;
}

/* ---- assembly ---------------------------------------------------------------------- */

/* Pairs of triangles into quads: (a, b, c) and (a, c, d) are quad (a, b, c, d). */
static int to_quads(ctx *c) {
    tc_scene_mesh *m = c->m;
    int32_t nq = c->b->nt / 2;
    m->quads_ = malloc(4 * ((size_t)nq + 1) * sizeof *m->quads_);
    if (!m->quads_) return TC_ENOMEM;
    for (int32_t q = 0; q < nq; q++) {
        const int32_t *t = c->b->tri + 6 * (size_t)q;
        int32_t *v = m->quads_ + 4 * (size_t)q;
        v[0] = t[0], v[1] = t[1], v[2] = t[2], v[3] = t[5];
    }
    return TC_OK;
}

/* Moves the geometry and polylines out of b and points desc at everything. */
static void assemble(ctx *c, tc__mbuild *b) {
    tc_scene_mesh *m = c->m;
    tc_mesh_desc *d = &m->desc;
    m->xy_ = b->xy, m->tris_ = b->tri;
    b->xy = NULL, b->tri = NULL;
    d->nverts = b->nv, d->xy = m->xy_;
    d->ntris = b->nt, d->tris = m->tris_;
    if (c->quads) d->ntris = 0, d->tris = NULL, d->nquads = b->nt / 2, d->quads = m->quads_;
    d->nchan = 1, d->values = m->values_;
    d->corner_values_tri = m->corner_values_tri_, d->corner_values = m->corner_values_;
    d->corner_gradients_tri = m->corner_gradients_tri_, d->corner_gradients = m->corner_gradients_;
    d->midpoint_edge = m->midpoint_edge_, d->midpoint_tri = m->midpoint_tri_;
    d->midpoint_values = m->midpoint_values_;
    tc_polylines *lines[2] = {&d->c0, &d->cm1};
    for (int k = 0; k < 2; k++) {
        m->line_start_[k] = b->line_start[k], m->line_verts_[k] = b->line_verts[k];
        b->line_start[k] = NULL, b->line_verts[k] = NULL;
        lines[k]->count = b->nline[k];
        lines[k]->start = m->line_start_[k];
        lines[k]->verts = m->line_verts_[k];
    }
    for (int32_t t = 0; t < b->nt; t++) {
        const int32_t *v = m->tris_ + 3 * (size_t)t;
        const double *p = m->xy_ + 2 * (size_t)v[0], *q = m->xy_ + 2 * (size_t)v[1], *r = m->xy_ + 2 * (size_t)v[2];
        double a = tc_scene_triangle_aspect(p, q, r), angle = tc_scene_triangle_largest_angle(p, q, r);
        if (a > m->worst_aspect) m->worst_aspect = a, m->worst_aspect_angle = angle;
        m->largest_angle = fmax(m->largest_angle, angle);
    }
}

int tc__scene_sample(const tc_scene *s, const tc_scene_mesh_opts *o, tc__mbuild *b, tc_scene_mesh *m) {
    ctx c = {0};
    c.s = s, c.b = b, c.m = m, c.quads = o->quads, c.digits = o->digits;
    /* Without C0 flags the C0 events stay mesh lines but are not sent: they are C1. */
    if (o->no_c0) b->nline[0] = 0, b->nlv[0] = 0;
    int rc = b->nt > 0 ? build_edges(&c) : TC_EINVAL;
    if (rc == TC_OK) rc = build_corners(&c);
    if (rc == TC_OK) apply_flags(&c);
    if (rc == TC_OK) rc = vertex_values(&c);
    if (rc == TC_OK) rc = corner_values(&c);
    if (rc == TC_OK && o->midpoints) rc = midpoints(&c);
    if (rc == TC_OK && o->gradients) rc = gradients(&c);
    if (rc == TC_OK && c.quads) rc = to_quads(&c);
    if (rc == TC_OK) assemble(&c, b);
    free(c.e), free(c.tri_edge), free(c.vstart), free(c.vcorner), free(c.cz);
    return rc;
}
