/* meshing.c — the grid meshers (a priori discontinuity meshing, uniform) and the
 * entry points; the quadtree is in adaptive.c, the samples in sampling.c. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scenes/build.h"

static const char *const kind_names[] = {
    [TC_SCENE_MESH_DISC] = "disc", [TC_SCENE_MESH_UNIFORM] = "uniform", [TC_SCENE_MESH_ADAPTIVE] = "adaptive",
    [TC_SCENE_MESH_DM] = "dm"};
#define NKINDS ((int)(sizeof kind_names / sizeof kind_names[0]))

const char *tc_scene_mesh_kind_name(tc_scene_mesh_kind k) {
    return (int)k >= 0 && (int)k < NKINDS ? kind_names[k] : NULL;
}

int tc_scene_mesh_kind_parse(const char *s, tc_scene_mesh_kind *out) {
    for (int i = 0; s && i < NKINDS; i++)
        if (strcmp(kind_names[i], s) == 0) {
            *out = (tc_scene_mesh_kind)i;
            return 0;
        }
    return -1;
}

void tc_scene_mesh_opts_default(tc_scene_mesh_opts *o) {
    o->kind = TC_SCENE_MESH_DISC;
    o->density = 8;
    o->midpoints = 1;
    o->gradients = 0;
    o->threshold = 0.1;
    o->max_depth = 4;
    o->quads = 0;
    o->no_c0 = 0;
    o->digits = 0;
    o->rotation = 0;
}

double tc_scene_triangle_aspect(const double a[2], const double b[2], const double c[2]) {
    double l2 = 0;
    const double *p[3] = {a, b, c};
    for (int k = 0; k < 3; k++) {
        double dx = p[(k + 1) % 3][0] - p[k][0], dy = p[(k + 1) % 3][1] - p[k][1];
        l2 = fmax(l2, dx * dx + dy * dy);
    }
    double area2 = fabs((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
    return area2 > 0 ? l2 / area2 : INFINITY;
}

double tc_scene_triangle_largest_angle(const double a[2], const double b[2], const double c[2]) {
    const double *p[3] = {a, b, c};
    double worst = 0;
    for (int k = 0; k < 3; k++) {
        const double *o = p[k], *u = p[(k + 1) % 3], *v = p[(k + 2) % 3];
        double ux = u[0] - o[0], uy = u[1] - o[1], vx = v[0] - o[0], vy = v[1] - o[1];
        /* atan2 of |cross| and dot: accurate for angles near 0 and 180 degrees */
        worst = fmax(worst, atan2(fabs(ux * vy - uy * vx), ux * vx + uy * vy));
    }
    return worst * (180 / 3.14159265358979323846);
}

/* ---- the builder --------------------------------------------------------------- */

void tc__mb_init(tc__mbuild *b) { memset(b, 0, sizeof *b); }

void tc__mb_free(tc__mbuild *b) {
    free(b->xy), free(b->tri), free(b->values);
    for (int k = 0; k < 2; k++) free(b->line_start[k]), free(b->line_verts[k]);
    tc__mb_init(b);
}

/* Makes room for `need` elements of `size` bytes in *p (capacity *cap, doubling). */
static int reserve(void **p, int32_t *cap, int64_t need, size_t size) {
    if (need <= *cap) return 0;
    int64_t c = *cap ? *cap : 64;
    while (c < need) c *= 2;
    if (c > INT32_MAX) return -1;
    void *q = realloc(*p, (size_t)c * size);
    if (!q) return -1;
    *p = q;
    *cap = (int32_t)c;
    return 0;
}

int32_t tc__mb_vertex(tc__mbuild *b, double x, double y) {
    if (b->oom || reserve((void **)&b->xy, &b->cap_v, (int64_t)b->nv + 1, 2 * sizeof *b->xy)) {
        b->oom = 1;
        return -1;
    }
    b->xy[2 * (size_t)b->nv] = x;
    b->xy[2 * (size_t)b->nv + 1] = y;
    return b->nv++;
}

void tc__mb_triangle(tc__mbuild *b, int32_t p, int32_t q, int32_t r) {
    if (b->oom || reserve((void **)&b->tri, &b->cap_t, (int64_t)b->nt + 1, 3 * sizeof *b->tri)) {
        b->oom = 1;
        return;
    }
    int32_t *t = b->tri + 3 * (size_t)b->nt++;
    t[0] = p, t[1] = q, t[2] = r;
}

void tc__mb_line(tc__mbuild *b, int kind, const int32_t *verts, int32_t n) {
    if (b->oom || reserve((void **)&b->line_start[kind], &b->cap_line[kind], (int64_t)b->nline[kind] + 2,
                          sizeof(int32_t)) ||
        reserve((void **)&b->line_verts[kind], &b->cap_lv[kind], (int64_t)b->nlv[kind] + n, sizeof(int32_t))) {
        b->oom = 1;
        return;
    }
    memcpy(b->line_verts[kind] + b->nlv[kind], verts, (size_t)n * sizeof *verts);
    b->line_start[kind][b->nline[kind]] = b->nlv[kind];
    b->nlv[kind] += n;
    b->line_start[kind][++b->nline[kind]] = b->nlv[kind];
}

/* ---- grid lines ---------------------------------------------------------------- */

typedef struct {
    double *c;
    int32_t n, cap;
} coords;

static int coords_add(coords *k, double x) {
    if (reserve((void **)&k->c, &k->cap, (int64_t)k->n + 1, sizeof *k->c)) return -1;
    k->c[k->n++] = x;
    return 0;
}

static int by_value(const void *pa, const void *pb) {
    double a = *(const double *)pa, b = *(const double *)pb;
    return a < b ? -1 : a > b;
}

/* The lines of one axis: the domain's sides, the events on this axis and the
 * ends of the events on the other (so every event segment runs between grid
 * lines), each distinct double once; then every gap wider than 1/N of the
 * domain split evenly. Exact comparisons throughout: an event's coordinate is
 * the same double wherever it is used. */
static int axis_lines(const tc_scene *s, int axis, int use_events, int N, coords *out) {
    coords base = {0};
    int rc = coords_add(&base, s->domain[axis]) | coords_add(&base, s->domain[axis + 2]);
    for (int i = 0; use_events && i < s->nevents && rc == 0; i++) {
        const tc_scene_event *e = &s->events[i];
        rc = e->axis == axis ? coords_add(&base, e->at) : coords_add(&base, e->lo) | coords_add(&base, e->hi);
    }
    if (rc == 0) qsort(base.c, (size_t)base.n, sizeof *base.c, by_value);
    double len = s->domain[axis + 2] - s->domain[axis];
    for (int32_t i = 0; rc == 0 && i < base.n; i++) {
        if (i > 0 && base.c[i] == base.c[i - 1]) continue;
        if (i > 0) {
            double a = out->c[out->n - 1], gap = base.c[i] - a;
            int64_t parts = (int64_t)ceil(gap / len * N - 1e-9);
            for (int64_t k = 1; k < parts && rc == 0; k++) rc = coords_add(out, a + gap * ((double)k / (double)parts));
        }
        if (rc == 0) rc = coords_add(out, base.c[i]);
    }
    free(base.c);
    return rc ? TC_ENOMEM : TC_OK;
}

static int32_t line_index(const coords *k, double x) {
    const double *p = bsearch(&x, k->c, (size_t)k->n, sizeof *k->c, by_value);
    return p ? (int32_t)(p - k->c) : -1;
}

/* ---- the grid mesh ------------------------------------------------------------- */

typedef struct {
    coords xs, ys;
    int8_t *vflag; /* edge (i, j)-(i, j+1) at [i * ny + j] */
    int8_t *hflag; /* edge (i, j)-(i+1, j) at [j * nx + i] */
    int32_t nx, ny; /* cells */
} grid;

static int32_t gv(const grid *g, int32_t i, int32_t j) { return j * (g->nx + 1) + i; }

static void set_flag(int8_t *f, tc_continuity kind) {
    if (kind == TC_CM1 || *f == TC_C1) *f = (int8_t)kind; /* a jump outranks a kink */
}

/* Flags the grid edges lying on event e (whose ends are grid lines). */
static void flag_event(grid *g, const tc_scene_event *e) {
    const coords *along = e->axis == 0 ? &g->ys : &g->xs;
    int32_t line = line_index(e->axis == 0 ? &g->xs : &g->ys, e->at);
    for (int32_t j = 0; line >= 0 && j + 1 < along->n; j++) {
        if (along->c[j] < e->lo || along->c[j + 1] > e->hi) continue;
        set_flag(e->axis == 0 ? &g->vflag[line * g->ny + j] : &g->hflag[line * g->nx + j], e->kind);
    }
}

/* Polylines: along each grid line, each maximal run of edges with one flag. */
static void grid_polylines(const grid *g, tc__mbuild *b, int32_t *run) {
    for (int axis = 0; axis < 2; axis++) {
        int32_t nlines = axis == 0 ? g->nx + 1 : g->ny + 1, nseg = axis == 0 ? g->ny : g->nx;
        for (int32_t l = 0; l < nlines; l++) {
            int32_t n = 0;
            int8_t cur = TC_C1;
            for (int32_t j = 0; j <= nseg; j++) {
                int8_t f = j < nseg ? (axis == 0 ? g->vflag[l * g->ny + j] : g->hflag[l * g->nx + j]) : TC_C1;
                if (f != cur && n >= 2) tc__mb_line(b, cur == TC_CM1 ? 1 : 0, run, n);
                if (f != cur) n = 0;
                cur = f;
                if (f != TC_C1) {
                    if (n == 0) run[n++] = axis == 0 ? gv(g, l, j) : gv(g, j, l);
                    run[n++] = axis == 0 ? gv(g, l, j + 1) : gv(g, j + 1, l);
                }
            }
        }
    }
}

static void grid_geometry(const grid *g, tc__mbuild *b) {
    for (int32_t j = 0; j <= g->ny; j++)
        for (int32_t i = 0; i <= g->nx; i++) tc__mb_vertex(b, g->xs.c[i], g->ys.c[j]);
    for (int32_t j = 0; j < g->ny; j++)
        for (int32_t i = 0; i < g->nx; i++) {
            int32_t v00 = gv(g, i, j), v10 = gv(g, i + 1, j), v11 = gv(g, i + 1, j + 1), v01 = gv(g, i, j + 1);
            tc__mb_triangle(b, v00, v10, v11);
            tc__mb_triangle(b, v00, v11, v01);
        }
}

/* Disc: every event segment prolonged across the domain as a C1 grid line (no
 * T-vertices: the arrangement of axis-parallel lines is a grid), gaps wider
 * than 1/N split, each cell cut in two along its rising diagonal (triangles 2q
 * and 2q+1 of cell q, the split of quad (v00, v10, v11, v01)), and the grid
 * edges on event segments flagged with the event's kind. Uniform: the same
 * without events. */
static int grid_mesh(const tc_scene *s, const tc_scene_mesh_opts *o, tc__mbuild *b) {
    grid g = {0};
    int disc = o->kind == TC_SCENE_MESH_DISC;
    int rc = axis_lines(s, 0, disc, o->density, &g.xs);
    if (rc == TC_OK) rc = axis_lines(s, 1, disc, o->density, &g.ys);
    g.nx = g.xs.n - 1, g.ny = g.ys.n - 1;
    if (rc == TC_OK && 2 * (int64_t)g.nx * g.ny > TC__SCENE_MAX_TRIS) rc = TC_ELIMIT;
    if (rc == TC_OK) {
        g.vflag = malloc((size_t)(g.nx + 1) * (size_t)g.ny);
        g.hflag = malloc((size_t)(g.ny + 1) * (size_t)g.nx);
        int32_t *run = malloc((size_t)(g.nx > g.ny ? g.nx : g.ny) * sizeof *run + sizeof *run);
        if (g.vflag && g.hflag && run) {
            memset(g.vflag, TC_C1, (size_t)(g.nx + 1) * (size_t)g.ny);
            memset(g.hflag, TC_C1, (size_t)(g.ny + 1) * (size_t)g.nx);
            for (int i = 0; disc && i < s->nevents; i++) flag_event(&g, &s->events[i]);
            grid_geometry(&g, b);
            grid_polylines(&g, b, run);
        } else {
            rc = TC_ENOMEM;
        }
        free(run);
    }
    free(g.xs.c), free(g.ys.c), free(g.vflag), free(g.hflag);
    return rc == TC_OK && b->oom ? TC_ENOMEM : rc;
}

/* ---- entry points ---------------------------------------------------------------- */

const char *tc_scene_mesh_opts_check(const tc_scene_mesh_opts *o) {
    if ((int)o->kind < 0 || (int)o->kind >= NKINDS) return "unknown mesh kind";
    if (o->density < 1 || o->density > 1024) return "the density must be 1 to 1024";
    if (o->digits < 0 || o->digits > 17) return "the digits must be 0 (exact) or 1 to 17";
    if (!(fabs(o->rotation) <= 360)) return "the rotation must be a number of degrees from -360 to 360";
    if (o->rotation != 0 && o->kind != TC_SCENE_MESH_DM) return "only dm meshes can be rotated";
    if (o->kind == TC_SCENE_MESH_DM && o->quads) return "dm meshes are fans of triangles, not quads";
    if (o->kind != TC_SCENE_MESH_ADAPTIVE) return NULL;
    if (!(o->threshold >= 0)) return "the threshold must be a number >= 0";
    if (o->max_depth < 0 || o->max_depth > 12) return "the depth must be 0 to 12";
    if (o->quads) return "adaptive meshes have hanging vertices (T-junctions), so their cells cannot be given as quads";
    return NULL;
}

static int check_opts(const tc_scene_mesh_opts *o) { return tc_scene_mesh_opts_check(o) ? TC_EINVAL : TC_OK; }

int tc_scene_mesh_new(const tc_scene *s, const tc_scene_mesh_opts *o, tc_scene_mesh **out) {
    *out = NULL;
    int rc = check_opts(o);
    if (rc != TC_OK) return rc;
    tc_scene_mesh *m = calloc(1, sizeof *m);
    if (m) tc_mesh_desc_init(&m->desc); /* the defaults a front-end sends */
    if (!m) return TC_ENOMEM;
    tc__mbuild b;
    tc__mb_init(&b);
    rc = o->kind == TC_SCENE_MESH_ADAPTIVE ? tc__scene_adaptive(s, o, &b)
         : o->kind == TC_SCENE_MESH_DM    ? tc__scene_dm(s, o, &b)
                                          : grid_mesh(s, o, &b);
    if (rc == TC_OK) rc = tc__scene_sample(s, o, &b, m);
    tc__mb_free(&b);
    if (rc != TC_OK) {
        tc_scene_mesh_free(m);
        return rc;
    }
    *out = m;
    return TC_OK;
}

void tc_scene_mesh_free(tc_scene_mesh *m) {
    if (!m) return;
    free(m->xy_), free(m->values_), free(m->corner_values_), free(m->corner_gradients_), free(m->midpoint_values_);
    free(m->tris_), free(m->quads_), free(m->corner_values_tri_), free(m->corner_gradients_tri_), free(m->midpoint_edge_);
    free(m->midpoint_tri_);
    for (int k = 0; k < 2; k++) free(m->line_start_[k]), free(m->line_verts_[k]);
    free(m);
}
