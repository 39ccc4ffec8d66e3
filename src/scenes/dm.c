/* dm.c — the discontinuity mesher as real radiosity front-ends build it: the receiver
 * split by the scene's event segments, each face fanned from one of its corners. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scenes/build.h"
#include "scenes/dm_graph.h"

static const double PI = 3.14159265358979323846;

/* Mesh point p turned by the angle whose cosine and sine are (c, s) about o. */
static void turn(const double p[2], const double o[2], double c, double s, double out[2]) {
    double x = p[0] - o[0], y = p[1] - o[1];
    out[0] = o[0] + c * x - s * y;
    out[1] = o[1] + s * x + c * y;
}

static void centre_of(const tc_scene *s, double o[2]) {
    o[0] = 0.5 * (s->domain[0] + s->domain[2]);
    o[1] = 0.5 * (s->domain[1] + s->domain[3]);
}

/* Clips a to b against the convex counter-clockwise polygon poly[4] (Cyrus-Beck);
 * returns 0 when nothing of it is left. Ends already inside stay bit for bit. */
static int clip(double a[2], double b[2], const double (*poly)[2]) {
    double t0 = 0, t1 = 1, d[2] = {b[0] - a[0], b[1] - a[1]};
    for (int k = 0; k < 4; k++) {
        const double *p = poly[k], *q = poly[(k + 1) % 4];
        double n[2] = {-(q[1] - p[1]), q[0] - p[0]}; /* inward normal */
        double num = n[0] * (a[0] - p[0]) + n[1] * (a[1] - p[1]), den = n[0] * d[0] + n[1] * d[1];
        if (den == 0) {
            if (num < 0) return 0;
            continue;
        }
        double t = -num / den;
        if (den > 0) t0 = fmax(t0, t);
        else t1 = fmin(t1, t);
    }
    if (!((t1 - t0) * hypot(d[0], d[1]) > TC__DM_TOL)) return 0;
    double a2[2] = {a[0] + t0 * d[0], a[1] + t0 * d[1]};
    if (t1 < 1) b[0] = a[0] + t1 * d[0], b[1] = a[1] + t1 * d[1];
    if (t0 > 0) a[0] = a2[0], a[1] = a2[1];
    return 1;
}

/* The receiver's sides and the scene's events, in the scene's frame: the
 * receiver is the scene's domain turned by -rotation about its centre, and the
 * events are those of its bounding box clipped to it (an event the domain cuts
 * short may reach into a turned receiver). Returns the count. */
static int segments(const tc_scene *s, double rotation, tc__dm_seg *out) {
    const double *d = s->domain, corner[4][2] = {{d[0], d[1]}, {d[2], d[1]}, {d[2], d[3]}, {d[0], d[3]}};
    double o[2], c = cos(rotation * PI / 180), sn = -sin(rotation * PI / 180), poly[4][2];
    double box[4] = {INFINITY, INFINITY, -INFINITY, -INFINITY};
    centre_of(s, o);
    for (int k = 0; k < 4; k++) {
        if (rotation != 0) turn(corner[k], o, c, sn, poly[k]);
        else poly[k][0] = corner[k][0], poly[k][1] = corner[k][1];
        for (int a = 0; a < 2; a++) box[a] = fmin(box[a], poly[k][a]), box[a + 2] = fmax(box[a + 2], poly[k][a]);
    }
    tc_scene local = *s;
    if (rotation != 0) tc_scene_init_domain(&local, s->id, box);
    int n = 0;
    for (int k = 0; k < 4; k++) {
        tc__dm_seg side = {{poly[k][0], poly[k][1]}, {poly[(k + 1) % 4][0], poly[(k + 1) % 4][1]}, TC_C1, 1};
        out[n++] = side;
    }
    for (int i = 0; i < local.nevents; i++) {
        const tc_scene_event *e = &local.events[i];
        tc__dm_seg g = {{0, 0}, {0, 0}, (int8_t)e->kind, 0};
        g.a[e->axis] = g.b[e->axis] = e->at;
        g.a[1 - e->axis] = e->lo, g.b[1 - e->axis] = e->hi;
        if (clip(g.a, g.b, (const double(*)[2])poly)) out[n++] = g;
    }
    return n;
}

/* ---- faces --------------------------------------------------------------------------- */

/* Half-edge h runs along edge h/2, from its a to its b when h is even. */
static int32_t origin(const tc__dm_graph *g, int32_t h) { return h & 1 ? g->e[h / 2].b : g->e[h / 2].a; }
static int32_t target(const tc__dm_graph *g, int32_t h) { return h & 1 ? g->e[h / 2].a : g->e[h / 2].b; }

/* The half-edges leaving each vertex, counter-clockwise by angle (CSR), and
 * each half-edge's place in that list. */
typedef struct {
    int32_t *start, *out, *pos;
} star;

static void star_free(star *S) { free(S->start), free(S->out), free(S->pos); }

typedef struct {
    int32_t h, origin;
    double angle;
} hkey;

static int by_origin_angle(const void *pa, const void *pb) {
    const hkey *a = pa, *b = pb;
    if (a->origin != b->origin) return a->origin < b->origin ? -1 : 1;
    return (a->angle > b->angle) - (a->angle < b->angle);
}

static int star_build(const tc__dm_graph *g, star *S) {
    int32_t nh = 2 * g->ne;
    hkey *key = malloc((size_t)nh * sizeof *key);
    S->start = calloc((size_t)g->nv + 1, sizeof *S->start);
    S->out = malloc((size_t)nh * sizeof *S->out);
    S->pos = malloc((size_t)nh * sizeof *S->pos);
    if (!key || !S->start || !S->out || !S->pos) {
        free(key);
        return TC_ENOMEM;
    }
    for (int32_t h = 0; h < nh; h++) {
        const double *p = g->xy + 2 * origin(g, h), *q = g->xy + 2 * target(g, h);
        key[h] = (hkey){h, origin(g, h), atan2(q[1] - p[1], q[0] - p[0])};
        S->start[origin(g, h) + 1]++;
    }
    for (int32_t v = 0; v < g->nv; v++) S->start[v + 1] += S->start[v];
    qsort(key, (size_t)nh, sizeof *key, by_origin_angle);
    for (int32_t i = 0; i < nh; i++) S->out[i] = key[i].h, S->pos[key[i].h] = i;
    free(key);
    return TC_OK;
}

/* The next half-edge of h's face (the face on h's left): at h's target, the
 * edge just clockwise of the way back. */
static int32_t next_of(const tc__dm_graph *g, const star *S, int32_t h) {
    int32_t v = target(g, h), i = S->pos[h ^ 1], lo = S->start[v], deg = S->start[v + 1] - lo;
    return S->out[lo + (i - lo + deg - 1) % deg];
}

/* ---- fans ------------------------------------------------------------------------------ */

typedef struct {
    const tc__dm_graph *g;
    const uint8_t *on_event; /* [nv]: 1 on a discontinuity (a shadow boundary) */
    tc__mbuild *b;
    int32_t *w;              /* the face's vertices, counter-clockwise */
    int32_t m;
    int32_t *corner;         /* positions in w where the boundary turns */
    int32_t nc;
} face;

static int turns(const face *f, int32_t i) {
    const double *p = f->g->xy + 2 * f->w[(i + f->m - 1) % f->m], *v = f->g->xy + 2 * f->w[i];
    const double *q = f->g->xy + 2 * f->w[(i + 1) % f->m];
    double u[2] = {v[0] - p[0], v[1] - p[1]}, d[2] = {q[0] - v[0], q[1] - v[1]};
    return fabs(u[0] * d[1] - u[1] * d[0]) > 1e-9 * hypot(u[0], u[1]) * hypot(d[0], d[1]);
}

static int32_t at(const face *f, int32_t apex, int32_t i) { return f->w[(apex + i) % f->m]; }

/* With the apex at corner c, the positions (relative to it) of the next corner
 * k and of the previous corner l. A fan from the apex covers the face with
 * (apex, w_i, w_i+1) for k <= i < l; the first and last of these have a side
 * of the apex for an edge, so T-vertices on that side (k >= 2, l <= m-2) are
 * fanned from the triangle's third vertex instead. Both in one triangle
 * (l == k + 1) cannot be: that apex is refused. */
static void apex_sides(const face *f, int c, int32_t *k, int32_t *l) {
    int32_t apex = f->corner[c];
    *k = (f->corner[(c + 1) % f->nc] - apex + f->m) % f->m;
    *l = (f->corner[(c + f->nc - 1) % f->nc] - apex + f->m) % f->m;
}

static int apex_ok(const face *f, int c) {
    int32_t k, l;
    apex_sides(f, c, &k, &l);
    return !(k >= 2 && l <= f->m - 2 && l == k + 1);
}

/* The apex: a corner on a shadow boundary if one will do (real meshers fan
 * from the vertices their segments end at), the first such in the face's order. */
static int choose_apex(const face *f) {
    int fallback = -1;
    for (int c = 0; c < f->nc; c++) {
        if (!apex_ok(f, c)) continue;
        if (f->on_event[f->w[f->corner[c]]]) return c;
        if (fallback < 0) fallback = c;
    }
    return fallback;
}

static int fan(face *f) {
    int c = f->nc >= 3 ? choose_apex(f) : -1;
    if (c < 0) return TC_EINVAL; /* cannot happen: a convex face has a usable corner */
    int32_t apex = f->corner[c], k, l, m = f->m;
    apex_sides(f, c, &k, &l);
    for (int32_t i = k; i < l; i++) {
        if (i == k && k >= 2) {
            for (int32_t j = 0; j < k; j++) tc__mb_triangle(f->b, at(f, apex, k + 1), at(f, apex, j), at(f, apex, j + 1));
        } else if (i == l - 1 && l <= m - 2) {
            for (int32_t j = l; j < m; j++) tc__mb_triangle(f->b, at(f, apex, l - 1), at(f, apex, j), at(f, apex, j + 1));
        } else {
            tc__mb_triangle(f->b, at(f, apex, 0), at(f, apex, i), at(f, apex, i + 1));
        }
    }
    return TC_OK;
}

static double cycle_area(const tc__dm_graph *g, const int32_t *w, int32_t m) {
    double a = 0;
    for (int32_t i = 0; i < m; i++) {
        const double *p = g->xy + 2 * w[i], *q = g->xy + 2 * w[(i + 1) % m];
        a += p[0] * q[1] - p[1] * q[0];
    }
    return a / 2;
}

/* Traces every face; fans the bounded ones (counter-clockwise). Exactly one
 * cycle is clockwise, the receiver's outside, when the graph is connected. */
static int fan_faces(const tc__dm_graph *g, const uint8_t *on_event, tc__mbuild *b) {
    star S = {0};
    int32_t nh = 2 * g->ne, outside = 0;
    face f = {g, on_event, b, malloc((size_t)nh * sizeof *f.w), 0, malloc((size_t)nh * sizeof *f.corner), 0};
    uint8_t *seen = calloc((size_t)nh, 1);
    int rc = f.w && f.corner && seen ? star_build(g, &S) : TC_ENOMEM;
    for (int32_t h0 = 0; rc == TC_OK && h0 < nh; h0++) {
        if (seen[h0]) continue;
        f.m = 0;
        for (int32_t h = h0; !seen[h]; h = next_of(g, &S, h)) seen[h] = 1, f.w[f.m++] = origin(g, h);
        if (cycle_area(g, f.w, f.m) <= 0) {
            outside++;
            continue;
        }
        f.nc = 0;
        for (int32_t i = 0; i < f.m; i++)
            if (turns(&f, i)) f.corner[f.nc++] = i;
        rc = fan(&f);
    }
    if (rc == TC_OK && outside != 1) rc = TC_EINVAL; /* not connected: cannot happen after unreflex */
    star_free(&S);
    free(f.w), free(f.corner), free(seen);
    return rc;
}

/* ---- output ----------------------------------------------------------------------------- */

typedef struct {
    int32_t lo, hi; /* the edge's ends in the segment's direction */
    double t;       /* where its midpoint is along the segment */
    int8_t flag;
} piece;

static int by_t(const void *pa, const void *pb) {
    double a = ((const piece *)pa)->t, b = ((const piece *)pb)->t;
    return (a > b) - (a < b);
}

/* The flagged edges of segment s, in order along it. */
static int32_t segment_pieces(const tc__dm_graph *g, const tc__dm_seg *seg, int s, piece *out) {
    double d[2] = {seg->b[0] - seg->a[0], seg->b[1] - seg->a[1]};
    int32_t n = 0;
    for (int32_t i = 0; i < g->ne; i++) {
        const tc__dm_edge *e = &g->e[i];
        if (e->seg != s || e->flag == TC_C1) continue;
        const double *p = g->xy + 2 * e->a, *q = g->xy + 2 * e->b;
        double tp = d[0] * p[0] + d[1] * p[1], tq = d[0] * q[0] + d[1] * q[1];
        out[n++] = (piece){tp < tq ? e->a : e->b, tp < tq ? e->b : e->a, tp + tq, e->flag};
    }
    qsort(out, (size_t)n, sizeof *out, by_t);
    return n;
}

/* Segment s's flagged edges as polylines: each maximal chain of one flag one
 * polyline (an overlap with a stronger segment may have taken some edges). */
static void segment_lines(const tc__dm_graph *g, const tc__dm_seg *segs, int s, piece *pc, int32_t *run,
                          tc__mbuild *b) {
    int32_t n = segment_pieces(g, &segs[s], s, pc), len = 0;
    int8_t flag = TC_C1;
    for (int32_t i = 0; i < n; i++) {
        if (len && (run[len - 1] != pc[i].lo || pc[i].flag != flag)) {
            tc__mb_line(b, flag == TC_CM1, run, len);
            len = 0;
        }
        if (!len) run[len++] = pc[i].lo, flag = pc[i].flag;
        run[len++] = pc[i].hi;
    }
    if (len) tc__mb_line(b, flag == TC_CM1, run, len);
}

static int emit_lines(const tc__dm_graph *g, const tc__dm_seg *segs, int nseg, tc__mbuild *b) {
    piece *pc = malloc(((size_t)g->ne + 1) * sizeof *pc);
    int32_t *run = malloc(((size_t)g->ne + 2) * sizeof *run);
    for (int s = 0; pc && run && s < nseg; s++) segment_lines(g, segs, s, pc, run, b);
    int rc = pc && run ? TC_OK : TC_ENOMEM;
    free(pc), free(run);
    return rc;
}

/* Puts the vertices on the receiver's sides back on them exactly: turning
 * moves them off by rounding. Side k of the receiver (segments 0..3) is
 * y = y0, x = x1, y = y1, x = x0 in the mesh's frame. */
static void snap_to_sides(const tc_scene *sc, const tc__dm_graph *g, double *xy) {
    const double *d = sc->domain;
    const int axis[4] = {1, 0, 1, 0};
    const double at[4] = {d[1], d[2], d[3], d[0]};
    for (int32_t i = 0; i < g->ne; i++) {
        const tc__dm_edge *e = &g->e[i];
        if (!e->side || e->seg < 0 || e->seg > 3) continue;
        xy[2 * e->a + axis[e->seg]] = xy[2 * e->b + axis[e->seg]] = at[e->seg];
    }
}

/* The vertices in the mesh's frame (the scene turned back by +rotation), and the
 * frame that takes them to the scene's for sampling. */
static int emit_vertices(const tc_scene *sc, const tc__dm_graph *g, double rotation, tc__mbuild *b) {
    double o[2], c = cos(rotation * PI / 180), s = sin(rotation * PI / 180);
    double *xy = malloc(2 * ((size_t)g->nv + 1) * sizeof *xy);
    if (!xy) return TC_ENOMEM;
    centre_of(sc, o);
    for (int32_t v = 0; v < g->nv; v++) {
        xy[2 * v] = g->xy[2 * v], xy[2 * v + 1] = g->xy[2 * v + 1];
        if (rotation != 0) turn(g->xy + 2 * v, o, c, s, xy + 2 * v);
    }
    if (rotation != 0) snap_to_sides(sc, g, xy);
    for (int32_t v = 0; v < g->nv; v++) tc__mb_vertex(b, xy[2 * v], xy[2 * v + 1]);
    free(xy);
    if (rotation == 0) return TC_OK;
    const double frame[6] = {o[0], o[1], c, s, -s, c};
    b->framed = 1;
    memcpy(b->frame, frame, sizeof frame);
    return TC_OK;
}

static uint8_t *event_vertices(const tc__dm_graph *g) {
    uint8_t *on = calloc((size_t)g->nv + 1, 1);
    for (int32_t i = 0; on && i < g->ne; i++)
        if (g->e[i].flag != TC_C1) on[g->e[i].a] = on[g->e[i].b] = 1;
    return on;
}

/* Arrangement, local prolongations from reflex corners, subdivision to 1/N,
 * faces fanned; vertex values are left to the sampling stage. */
int tc__scene_dm(const tc_scene *s, const tc_scene_mesh_opts *o, tc__mbuild *b) {
    tc__dm_seg segs[4 + TC_SCENE_MAX_EVENTS];
    int nseg = segments(s, o->rotation, segs);
    tc__dm_graph g = {0};
    int rc = tc__dm_arrange(&g, segs, nseg);
    if (rc == TC_OK) rc = tc__dm_unreflex(&g);
    double extent = fmax(s->domain[2] - s->domain[0], s->domain[3] - s->domain[1]);
    if (rc == TC_OK) rc = tc__dm_subdivide(&g, extent / o->density);
    if (rc == TC_OK && 2 * (int64_t)g.ne > TC__SCENE_MAX_TRIS) rc = TC_ELIMIT;
    uint8_t *on_event = rc == TC_OK ? event_vertices(&g) : NULL;
    if (rc == TC_OK && !on_event) rc = TC_ENOMEM;
    if (rc == TC_OK) rc = emit_vertices(s, &g, o->rotation, b);
    if (rc == TC_OK) rc = fan_faces(&g, on_event, b);
    if (rc == TC_OK) rc = emit_lines(&g, segs, nseg, b);
    free(on_event);
    tc__dm_graph_free(&g);
    return rc == TC_OK && b->oom ? TC_ENOMEM : rc;
}
