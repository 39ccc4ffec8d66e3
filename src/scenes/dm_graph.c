/* dm_graph.c — the discontinuity mesher's planar graph: the arrangement of the
 * receiver's sides and the event segments, local prolongations, subdivision. */
#include "scenes/dm_graph.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tocher.h"

static const double PI = 3.14159265358979323846;

/* ---- storage ---------------------------------------------------------------------- */

static int grow(void **p, int32_t *cap, int32_t need, size_t size) {
    if (need <= *cap) return 0;
    int32_t c = *cap ? *cap : 64;
    while (c < need) c *= 2;
    void *q = realloc(*p, (size_t)c * size);
    if (!q) return -1;
    *p = q;
    *cap = c;
    return 0;
}

static int32_t add_vertex(tc__dm_graph *g, double x, double y) {
    if (g->oom || grow((void **)&g->xy, &g->cap_v, g->nv + 1, 2 * sizeof *g->xy)) {
        g->oom = 1;
        return -1;
    }
    g->xy[2 * g->nv] = x, g->xy[2 * g->nv + 1] = y;
    return g->nv++;
}

/* The vertex at (x, y) within TC__DM_TOL, added if there is none. Linear: the
 * arrangement has a few hundred vertices before subdivision. */
static int32_t vertex_at(tc__dm_graph *g, double x, double y) {
    for (int32_t v = 0; v < g->nv; v++)
        if (fabs(g->xy[2 * v] - x) <= TC__DM_TOL && fabs(g->xy[2 * v + 1] - y) <= TC__DM_TOL) return v;
    return add_vertex(g, x, y);
}

static void add_edge(tc__dm_graph *g, tc__dm_edge e) {
    if (g->oom || grow((void **)&g->e, &g->cap_e, g->ne + 1, sizeof *g->e)) {
        g->oom = 1;
        return;
    }
    g->e[g->ne++] = e;
}

void tc__dm_graph_free(tc__dm_graph *g) {
    free(g->xy), free(g->e);
    memset(g, 0, sizeof *g);
}

static double cross(const double u[2], const double v[2]) { return u[0] * v[1] - u[1] * v[0]; }

/* ---- the arrangement ------------------------------------------------------------------ */

/* A point on a segment: its parameter (0 at a, 1 at b) and exact coordinates. */
typedef struct {
    double t, x, y;
} onseg;

typedef struct {
    onseg *p;
    int32_t n, cap;
} onseg_list;

static void push_point(onseg_list *l, double t, double x, double y, int *oom) {
    if (*oom || grow((void **)&l->p, &l->cap, l->n + 1, sizeof *l->p)) {
        *oom = 1;
        return;
    }
    l->p[l->n++] = (onseg){t, x, y};
}

/* a + t d, keeping exact any coordinate that one of the two segments holds
 * constant (the events are axis-parallel: their crossings are then exact). */
static void point_on(const tc__dm_seg *s, const tc__dm_seg *o, double t, double out[2]) {
    for (int k = 0; k < 2; k++) {
        out[k] = s->a[k] + t * (s->b[k] - s->a[k]);
        if (o->a[k] == o->b[k]) out[k] = o->a[k];
        if (s->a[k] == s->b[k]) out[k] = s->a[k];
    }
}

/* Segment o's ends that lie on the line of s (collinear overlap) and within s. */
static void collinear_points(const tc__dm_seg *s, const tc__dm_seg *o, onseg_list *l, int *oom) {
    double d[2] = {s->b[0] - s->a[0], s->b[1] - s->a[1]}, L2 = d[0] * d[0] + d[1] * d[1], L = sqrt(L2);
    const double *ends[2] = {o->a, o->b};
    for (int k = 0; k < 2; k++) {
        double r[2] = {ends[k][0] - s->a[0], ends[k][1] - s->a[1]};
        if (fabs(cross(d, r)) > TC__DM_TOL * L) continue;
        double t = (r[0] * d[0] + r[1] * d[1]) / L2;
        if (t * L >= -TC__DM_TOL && (t - 1) * L <= TC__DM_TOL) push_point(l, t, ends[k][0], ends[k][1], oom);
    }
}

/* Where o meets s (a crossing, or an end of one on the other), as a point of s.
 * An end of either segment within TC__DM_TOL of the other is taken exactly. */
static void meet(const tc__dm_seg *s, const tc__dm_seg *o, onseg_list *l, int *oom) {
    double d1[2] = {s->b[0] - s->a[0], s->b[1] - s->a[1]}, d2[2] = {o->b[0] - o->a[0], o->b[1] - o->a[1]};
    double L1 = hypot(d1[0], d1[1]), L2 = hypot(d2[0], d2[1]), den = cross(d1, d2);
    if (fabs(den) <= 1e-12 * L1 * L2) {
        collinear_points(s, o, l, oom);
        return;
    }
    double w[2] = {o->a[0] - s->a[0], o->a[1] - s->a[1]};
    double t = cross(w, d2) / den, u = cross(w, d1) / den;
    if (t * L1 < -TC__DM_TOL || (t - 1) * L1 > TC__DM_TOL || u * L2 < -TC__DM_TOL || (u - 1) * L2 > TC__DM_TOL) return;
    double p[2];
    if (u * L2 <= TC__DM_TOL) p[0] = o->a[0], p[1] = o->a[1];
    else if ((1 - u) * L2 <= TC__DM_TOL) p[0] = o->b[0], p[1] = o->b[1];
    else if (t * L1 <= TC__DM_TOL) p[0] = s->a[0], p[1] = s->a[1];
    else if ((1 - t) * L1 <= TC__DM_TOL) p[0] = s->b[0], p[1] = s->b[1];
    else point_on(s, o, t, p);
    push_point(l, t, p[0], p[1], oom);
}

static int by_t(const void *pa, const void *pb) {
    double a = ((const onseg *)pa)->t, b = ((const onseg *)pb)->t;
    return a < b ? -1 : a > b;
}

/* Segment i split at the points the others put on it, as edges. */
static void split_segment(tc__dm_graph *g, const tc__dm_seg *segs, int n, int i, onseg_list *l) {
    const tc__dm_seg *s = &segs[i];
    l->n = 0;
    push_point(l, 0, s->a[0], s->a[1], &g->oom);
    push_point(l, 1, s->b[0], s->b[1], &g->oom);
    for (int j = 0; j < n; j++)
        if (j != i) meet(s, &segs[j], l, &g->oom);
    if (g->oom) return;
    qsort(l->p, (size_t)l->n, sizeof *l->p, by_t);
    int32_t prev = -1;
    for (int32_t k = 0; k < l->n && !g->oom; k++) {
        int32_t v = vertex_at(g, l->p[k].x, l->p[k].y);
        if (prev >= 0 && v != prev) add_edge(g, (tc__dm_edge){prev, v, i, s->flag, s->side});
        prev = v;
    }
}

static int flag_rank(int8_t f) { return f == TC_CM1 ? 2 : f == TC_C0 ? 1 : 0; }

static int by_ends(const void *pa, const void *pb) {
    const tc__dm_edge *a = pa, *b = pb;
    int32_t a0 = a->a < a->b ? a->a : a->b, a1 = a->a ^ a->b ^ a0;
    int32_t b0 = b->a < b->b ? b->a : b->b, b1 = b->a ^ b->b ^ b0;
    if (a0 != b0) return a0 < b0 ? -1 : 1;
    return (a1 > b1) - (a1 < b1);
}

/* One edge per pair of vertices: overlapping collinear segments gave the same
 * edge twice; the strongest flag (and its segment) wins, a side stays a side. */
static void merge_duplicates(tc__dm_graph *g) {
    if (g->ne < 2) return;
    qsort(g->e, (size_t)g->ne, sizeof *g->e, by_ends);
    int32_t n = 1;
    for (int32_t i = 1; i < g->ne; i++) {
        tc__dm_edge *last = &g->e[n - 1], *e = &g->e[i];
        if (by_ends(last, e) != 0) {
            g->e[n++] = *e;
            continue;
        }
        int8_t side = last->side | e->side;
        if (flag_rank(e->flag) > flag_rank(last->flag)) *last = *e;
        last->side = side;
    }
    g->ne = n;
}

int tc__dm_arrange(tc__dm_graph *g, const tc__dm_seg *segs, int n) {
    onseg_list l = {0};
    for (int i = 0; i < n && !g->oom; i++) split_segment(g, segs, n, i, &l);
    free(l.p);
    if (!g->oom) merge_duplicates(g);
    return g->oom ? TC_ENOMEM : TC_OK;
}

/* ---- local prolongations ------------------------------------------------------------ */

static int on_side(const tc__dm_graph *g, int32_t v) {
    for (int32_t i = 0; i < g->ne; i++)
        if (g->e[i].side && (g->e[i].a == v || g->e[i].b == v)) return 1;
    return 0;
}

static int by_double(const void *pa, const void *pb) {
    double a = *(const double *)pa, b = *(const double *)pb;
    return a < b ? -1 : a > b;
}

/* The directions of v's edges, sorted; returns how many (at most cap). */
static int star_angles(const tc__dm_graph *g, int32_t v, double *ang, int cap) {
    int n = 0;
    for (int32_t i = 0; i < g->ne && n < cap; i++) {
        const tc__dm_edge *e = &g->e[i];
        if (e->a != v && e->b != v) continue;
        int32_t w = e->a == v ? e->b : e->a;
        ang[n++] = atan2(g->xy[2 * w + 1] - g->xy[2 * v + 1], g->xy[2 * w] - g->xy[2 * v]);
    }
    qsort(ang, (size_t)n, sizeof *ang, by_double);
    return n;
}

/* The first thing a ray from o along unit d meets: *dist, and either the vertex
 * it hits (*vert) or the edge whose interior it crosses (*edge) at hit. */
typedef struct {
    double dist, hit[2];
    int32_t vert, edge;
} ray_hit;

static void consider(ray_hit *h, double s, int32_t vert, int32_t edge, const double p[2]) {
    if (s <= TC__DM_TOL || s >= h->dist) return;
    h->dist = s, h->vert = vert, h->edge = edge;
    h->hit[0] = p[0], h->hit[1] = p[1];
}

/* The ray against edge i = (p, q), not incident to its origin. */
static void ray_edge(const tc__dm_graph *g, const double o[2], const double d[2], int32_t i, ray_hit *h) {
    const tc__dm_edge *e = &g->e[i];
    const double *p = g->xy + 2 * e->a, *q = g->xy + 2 * e->b;
    double r[2] = {q[0] - p[0], q[1] - p[1]}, w[2] = {p[0] - o[0], p[1] - o[1]}, L = hypot(r[0], r[1]);
    double den = cross(d, r);
    if (fabs(den) <= 1e-12 * L) { /* parallel: only a collinear edge's ends can be hit */
        if (fabs(cross(d, w)) > TC__DM_TOL) return;
        double wq[2] = {q[0] - o[0], q[1] - o[1]};
        consider(h, w[0] * d[0] + w[1] * d[1], e->a, -1, p);
        consider(h, wq[0] * d[0] + wq[1] * d[1], e->b, -1, q);
        return;
    }
    double s = cross(w, r) / den, t = cross(w, d) / den;
    if (t * L < -TC__DM_TOL || (t - 1) * L > TC__DM_TOL) return;
    if (t * L <= TC__DM_TOL) return consider(h, s, e->a, -1, p);
    if ((1 - t) * L <= TC__DM_TOL) return consider(h, s, e->b, -1, q);
    double x[2] = {o[0] + s * d[0], o[1] + s * d[1]};
    for (int k = 0; k < 2; k++) { /* exact where the ray or the edge is axis-parallel */
        if (d[k] == 0) x[k] = o[k];
        if (r[k] == 0) x[k] = p[k];
    }
    consider(h, s, -1, i, x);
}

static ray_hit shoot(const tc__dm_graph *g, int32_t v, const double d[2]) {
    ray_hit h = {INFINITY, {0, 0}, -1, -1};
    for (int32_t i = 0; i < g->ne; i++)
        if (g->e[i].a != v && g->e[i].b != v) ray_edge(g, g->xy + 2 * v, d, i, &h);
    return h;
}

/* Joins v to what the ray hit: a vertex, or a new vertex splitting the edge. */
static void join(tc__dm_graph *g, int32_t v, const ray_hit *h) {
    int32_t w = h->vert;
    if (h->edge >= 0) {
        w = add_vertex(g, h->hit[0], h->hit[1]);
        if (w < 0) return;
        tc__dm_edge rest = g->e[h->edge];
        rest.a = w;
        g->e[h->edge].b = w;
        add_edge(g, rest);
    }
    add_edge(g, (tc__dm_edge){v, w, -1, TC_C1, 0});
}

/* The unit direction at angle a, exact on the axes (the events' directions). */
static void unit(double a, double d[2]) {
    d[0] = cos(a), d[1] = sin(a);
    for (int k = 0; k < 2; k++)
        if (fabs(d[k]) < 1e-15) d[k] = 0, d[1 - k] = d[1 - k] > 0 ? 1 : -1;
}

/* If v has a gap wider than 180 degrees, prolongs the edge on one side of it
 * backwards (its reverse direction lies inside the gap): whichever reaches
 * something sooner. One prolongation per vertex suffices: it leaves a gap of
 * exactly 180 degrees and one narrower than the old one less 180. */
static void unreflex_vertex(tc__dm_graph *g, int32_t v) {
    double ang[64];
    int n = star_angles(g, v, ang, 64);
    for (int i = 0; i < n; i++) {
        double next = i + 1 < n ? ang[i + 1] : ang[0] + 2 * PI;
        if (next - ang[i] <= PI + 1e-9) continue;
        double d0[2], d1[2];
        unit(ang[i] + PI, d0);
        unit(next - PI, d1);
        ray_hit h0 = shoot(g, v, d0), h1 = shoot(g, v, d1);
        const ray_hit *h = h0.dist <= h1.dist ? &h0 : &h1;
        if (isfinite(h->dist)) join(g, v, h);
        return;
    }
}

int tc__dm_unreflex(tc__dm_graph *g) {
    int32_t nv = g->nv; /* the vertices rays create lie on an edge: never reflex */
    for (int32_t v = 0; v < nv && !g->oom; v++)
        if (!on_side(g, v)) unreflex_vertex(g, v);
    return g->oom ? TC_ENOMEM : TC_OK;
}

/* ---- subdivision ---------------------------------------------------------------------- */

int tc__dm_subdivide(tc__dm_graph *g, double max_len) {
    int32_t ne = g->ne;
    for (int32_t i = 0; i < ne && !g->oom; i++) {
        tc__dm_edge e = g->e[i];
        if (e.seg >= 0 && !e.side) continue; /* events stay whole: see the header */
        const double p[2] = {g->xy[2 * e.a], g->xy[2 * e.a + 1]}, q[2] = {g->xy[2 * e.b], g->xy[2 * e.b + 1]};
        int32_t parts = (int32_t)ceil(hypot(q[0] - p[0], q[1] - p[1]) / max_len - 1e-9), prev = e.a;
        for (int32_t k = 1; k < parts && !g->oom; k++) {
            double f = (double)k / parts, x = p[0] + f * (q[0] - p[0]), y = p[1] + f * (q[1] - p[1]);
            if (p[0] == q[0]) x = p[0]; /* an axis-parallel edge's new vertices stay on its line */
            if (p[1] == q[1]) y = p[1];
            int32_t w = add_vertex(g, x, y);
            tc__dm_edge piece = e;
            piece.a = prev, piece.b = w;
            if (k == 1) g->e[i] = piece;
            else add_edge(g, piece);
            prev = w;
        }
        if (parts > 1 && !g->oom) {
            e.a = prev;
            add_edge(g, e);
        }
    }
    return g->oom ? TC_ENOMEM : TC_OK;
}
