/* wedge.c — classifies vertices (C1 / C0 / C-1, paper §2) and partitions the
 * faces around each vertex into wedges by walking its fan between delimiters. */
#include <string.h>

#include "core/alloc.h"
#include "core/assert.h"
#include "core/geom.h"
#include "core/mesh.h"
#include "core/parallel.h"
#include "core/wedge.h"

void tc__wedges_free(tc__wedge_set *ws) {
    if (!ws) return;
    tc__free(ws->w);
    tc__free(ws->corners);
    tc__free(ws->of_corner);
    tc__free(ws->vclass);
    memset(ws, 0, sizeof *ws);
}

/* The endpoint other than v of edge id e. */
static int32_t far_end(const struct tc_mesh *m, int32_t e, int32_t v) {
    int32_t t = e / 3, k = e % 3;
    int32_t a = m->tri[3 * t + k], b = m->tri[3 * t + (k + 1) % 3];
    return a == v ? b : a;
}

static void edge_dir(const struct tc_mesh *m, int32_t e, int32_t v, double d[2]) {
    tc__sub(d, tc__vxy(m, far_end(m, e, v)), tc__vxy(m, v));
}

/* Paper §2: C-1 if any incident edge is C-1 (the boundary included); else C0
 * with three or more C0 edges, or exactly two that are collinear (to within
 * TC_STRAIGHT_BAND: see there); else C1. */
static int8_t classify(const struct tc_mesh *m, int honor, int32_t v) {
    int ncm1 = 0, nc0 = 0;
    double d[2][2] = {{0}};
    for (int32_t i = m->vstart[v]; i < m->vstart[v + 1]; i++) {
        int32_t c = m->vcorner[i], t = c / 3, k = c % 3;
        int32_t edges[2] = {c, 3 * t + (k + 2) % 3}; /* the two edges of t at v */
        for (int j = 0; j < 2; j++) {
            int32_t e = edges[j];
            if (m->nbr[e] >= 0 && m->nbr[e] < t) continue; /* count each edge once */
            int f = tc__eff_flag(m, honor, e);
            if (f == TC_CM1) ncm1++;
            else if (f == TC_C0 && nc0++ < 2) edge_dir(m, e, v, d[nc0 - 1]);
        }
    }
    if (ncm1) return TC_CM1;
    if (nc0 >= 3 || (nc0 == 2 && tc__antiparallel_within(d[0], d[1], TC_STRAIGHT_BAND))) return TC_C0;
    return TC_C1;
}

static int is_delimiter(const struct tc_mesh *m, const tc__wedge_set *ws, int32_t v, int32_t e) {
    return ws->vclass[v] != TC_C1 && tc__eff_flag(m, ws->honor_flags, e) != TC_C1;
}

/* Crosses edge id e (of the triangle holding corner c) to the neighbour's
 * corner at v; *exit receives the neighbour's other edge at v. */
static int32_t step(const struct tc_mesh *m, int32_t v, int32_t e, int32_t *exit) {
    int32_t t2 = m->nbr[e], k2 = m->nbr_k[e];
    int32_t kv = tc__corner_of(m, t2, v);
    *exit = 3 * t2 + (k2 == kv ? (kv + 2) % 3 : kv);
    return 3 * t2 + kv;
}

/* Walks from corner c0 leaving through edge `exit` until a delimiter (whose id
 * goes to *end) or back to c0 (returns -1). Appends the corners passed. */
static int32_t walk(const struct tc_mesh *m, const tc__wedge_set *ws, int32_t v, int32_t c0, int32_t exit,
                    int32_t *seq, int32_t *n, int32_t limit, int32_t *end) {
    while (!is_delimiter(m, ws, v, exit)) {
        int32_t c = step(m, v, exit, &exit);
        if (c == c0 || *n >= limit) return -1;
        seq[(*n)++] = c;
    }
    *end = exit;
    return 0;
}

static void set_side(const struct tc_mesh *m, const tc__wedge_set *ws, tc__wedge *w, int s, int32_t e) {
    w->side_edge[s] = e;
    w->side_kind[s] = (int8_t)(tc__eff_flag(m, ws->honor_flags, e) == TC_C0 ? TC_C0 : TC_CM1);
    w->across[s] = -1;
    edge_dir(m, e, w->v, w->dir[s]);
}

/* Builds the wedge of vertex v that contains corner c0. `buf` has room for
 * twice the vertex degree. Corners go to ws->corners[*fill ..]. */
static void build_wedge(const struct tc_mesh *m, tc__wedge_set *ws, int32_t v, int32_t c0, int32_t *buf,
                        int32_t deg, int32_t *fill) {
    tc__wedge *w = &ws->w[ws->nw];
    int32_t t0 = c0 / 3, k0 = c0 % 3, nf = 0, nb = 0, end_f = -1, end_b = -1;
    int32_t *fwd = buf, *bwd = buf + deg;
    memset(w, 0, sizeof *w);
    w->v = v;
    w->side_edge[0] = w->side_edge[1] = w->across[0] = w->across[1] = -1;
    int cycle = walk(m, ws, v, c0, c0, fwd, &nf, deg, &end_f) < 0;
    if (!cycle) walk(m, ws, v, c0, 3 * t0 + (k0 + 2) % 3, bwd, &nb, deg, &end_b);
    /* Leaving a counter-clockwise face through its edge k (from v to the next
     * corner) turns clockwise, so that walk ends at side A. */
    int ccw = m->orient[t0] > 0;
    int32_t *first_part = ccw ? fwd : bwd, nfirst = ccw ? nf : nb;
    int32_t *last_part = ccw ? bwd : fwd, nlast = ccw ? nb : nf;
    w->first = *fill;
    for (int32_t i = nfirst - 1; i >= 0; i--) ws->corners[(*fill)++] = first_part[i];
    ws->corners[(*fill)++] = c0;
    for (int32_t i = 0; i < nlast; i++) ws->corners[(*fill)++] = last_part[i];
    w->count = *fill - w->first;
    for (int32_t i = w->first; i < *fill; i++) ws->of_corner[ws->corners[i]] = ws->nw;
    if (!cycle) {
        set_side(m, ws, w, TC_SIDE_A, ccw ? end_f : end_b);
        set_side(m, ws, w, TC_SIDE_B, ccw ? end_b : end_f);
        w->collinear = w->side_edge[0] != w->side_edge[1] && tc__antiparallel(w->dir[0], w->dir[1]);
    }
    ws->nw++;
}

/* Links each C0 side to the wedge across it. */
/* Wedges [lo, hi): the wedge across each C0 side; returns how many have one. */
static int32_t link_across(const struct tc_mesh *m, tc__wedge_set *ws, int32_t lo, int32_t hi) {
    int32_t ncoupled = 0;
    for (int32_t i = lo; i < hi; i++) {
        tc__wedge *w = &ws->w[i];
        for (int s = 0; s < 2; s++) {
            if (w->side_kind[s] != TC_C0 || w->side_edge[s] < 0) continue;
            int32_t e = w->side_edge[s], t2 = m->nbr[e];
            int32_t other = ws->of_corner[3 * t2 + tc__corner_of(m, t2, w->v)];
            if (other == i) {
                w->side_kind[s] = TC_CM1; /* cannot happen on a valid mesh; be safe */
                continue;
            }
            w->across[s] = other;
        }
        if (w->across[0] >= 0 || w->across[1] >= 0) ncoupled++;
    }
    return ncoupled;
}

/* The parallel build: part p makes the wedges of vertices [lo, hi) into its slice of one
 * slab (vertices and a quarter more, plus 16: a vertex has one wedge, or one per delimiting
 * edge at it, far fewer than its corners), or, where they outgrow the slice, into an array
 * of its own; numbered from 0, its corners at their serial place (fill = vstart[v] at
 * vertex v). Then the parts' wedges are copied together in order into the set's array,
 * exactly nw long, and renumbered, so the set is the serial one whatever the parts. (Sized
 * by corners, 3nt wedges, the array was 28 MB at 131k triangles for ~5 MB of wedges; one
 * array per part, each fresh, made the daemon fault its pages in on every request.) */
typedef struct {
    const struct tc_mesh *m;
    tc__wedge_set *ws;
    int32_t deg;
    tc__wedge *slab;
    tc__wedge *part_w[TC_PARALLEL_MAX]; /* part p's wedges: its slice of the slab, or its own */
    int own[TC_PARALLEL_MAX];           /* part_w[p] is an array of its own (freed once copied) */
    int32_t lo[TC_PARALLEL_MAX], nw[TC_PARALLEL_MAX], base[TC_PARALLEL_MAX], ncoupled[TC_PARALLEL_MAX];
    int nomem[TC_PARALLEL_MAX];
} wedge_pass;

/* Where the slice of the part starting at vertex lo begins in the slab: slices grow with
 * their vertices' count, so part p's ends where part p + 1's begins. */
static size_t slice_at(int32_t lo, int part) {
    return (size_t)lo + (size_t)lo / 4 + 16 * (size_t)part;
}

/* Room for one more wedge in *w (*cap of them): when full, an array of its own twice as
 * long (the slice it leaves stays the slab's). 0 when out of memory. */
static int wedge_room(tc__wedge **w, int32_t nw, int32_t *cap, int *own) {
    if (nw < *cap) return 1;
    int32_t more = *cap > INT32_MAX / 2 ? INT32_MAX : 2 * *cap;
    tc__wedge *bigger = more > *cap ? tc__malloc((size_t)more, sizeof *bigger) : NULL;
    if (!bigger) return 0;
    memcpy(bigger, *w, (size_t)nw * sizeof *bigger);
    if (*own) tc__free(*w);
    *w = bigger, *cap = more, *own = 1;
    return 1;
}

static void wedges_part(void *ctx, int32_t lo, int32_t hi, int part) {
    wedge_pass *wp = ctx;
    const struct tc_mesh *m = wp->m;
    tc__wedge_set local = *wp->ws;
    int32_t fill = m->vstart[lo], cap = (int32_t)(slice_at(hi, part + 1) - slice_at(lo, part));
    int own = 0;
    local.w = wp->slab + slice_at(lo, part);
    local.nw = 0;
    wp->lo[part] = lo;
    int32_t *buf = tc__malloc(2 * (size_t)wp->deg, sizeof *buf);
    int ok = buf != NULL;
    for (int32_t v = lo; v < hi && ok; v++) {
        local.vclass[v] = classify(m, local.honor_flags, v);
        for (int32_t i = m->vstart[v]; i < m->vstart[v + 1] && ok; i++)
            if (local.of_corner[m->vcorner[i]] < 0 && (ok = wedge_room(&local.w, local.nw, &cap, &own)))
                build_wedge(m, &local, v, m->vcorner[i], buf, wp->deg, &fill);
    }
    tc__free(buf);
    wp->nomem[part] = !ok;
    wp->part_w[part] = local.w;
    wp->own[part] = own;
    wp->nw[part] = local.nw;
}

static void renumber_part(void *ctx, int32_t lo, int32_t hi, int part) {
    wedge_pass *wp = ctx;
    const struct tc_mesh *m = wp->m;
    int32_t shift = wp->base[part];
    TC_ASSERT(wp->lo[part] == lo);
    if (wp->part_w[part] != wp->ws->w) /* else one part, its slice the set's array already */
        memcpy(wp->ws->w + shift, wp->part_w[part], (size_t)wp->nw[part] * sizeof *wp->ws->w);
    if (wp->own[part]) tc__free(wp->part_w[part]), wp->own[part] = 0;
    for (int32_t i = m->vstart[lo]; i < m->vstart[hi]; i++) wp->ws->of_corner[m->vcorner[i]] += shift;
}

static void no_wedge_part(void *ctx, int32_t lo, int32_t hi, int part) {
    tc__wedge_set *ws = ctx;
    (void)part;
    for (int32_t c = lo; c < hi; c++) ws->of_corner[c] = -1;
}

static void across_part(void *ctx, int32_t lo, int32_t hi, int part) {
    wedge_pass *wp = ctx;
    wp->ncoupled[part] = link_across(wp->m, wp->ws, lo, hi);
}

int tc__wedges_build_on(const struct tc_mesh *m, int honor_flags, int threads, tc__wedge_set *ws) {
    TC_ASSERT(m && ws);
    TC_ASSERT(honor_flags == TC_HONOR_NONE || honor_flags == TC_HONOR_ALL || honor_flags == TC_HONOR_CM1);
    size_t nc = 3 * (size_t)m->nt;
    int32_t deg = m->max_valence;
    memset(ws, 0, sizeof *ws);
    ws->honor_flags = honor_flags;
    ws->threads = threads;
    ws->corners = tc__malloc(nc, sizeof *ws->corners);
    ws->of_corner = tc__malloc(nc, sizeof *ws->of_corner);
    ws->vclass = tc__malloc((size_t)m->nv, sizeof *ws->vclass);
    if (!ws->corners || !ws->of_corner || !ws->vclass) {
        tc__wedges_free(ws);
        return TC_ENOMEM;
    }
    tc__parallel_for(threads, (int32_t)nc, 16384, no_wedge_part, ws);
    wedge_pass wp = {.m = m, .ws = ws, .deg = deg};
    int parts = tc__parallel_parts(threads, m->nv, 4096), nomem = 0;
    if (!(wp.slab = tc__malloc(slice_at(m->nv, parts), sizeof *wp.slab))) {
        tc__wedges_free(ws);
        return TC_ENOMEM;
    }
    tc__parallel_for(threads, m->nv, 4096, wedges_part, &wp);
    for (int p = 0; p < parts; p++) {
        nomem |= wp.nomem[p];
        wp.base[p] = ws->nw;
        ws->nw += wp.nw[p];
    }
    if (parts == 1 && !wp.own[0]) ws->w = wp.slab, wp.slab = NULL; /* its wedges in place */
    else if (!nomem && !(ws->w = tc__malloc((size_t)ws->nw, sizeof *ws->w))) nomem = 1;
    if (nomem) {
        for (int p = 0; p < parts; p++)
            if (wp.own[p]) tc__free(wp.part_w[p]);
        tc__free(wp.slab);
        tc__wedges_free(ws);
        return TC_ENOMEM;
    }
    tc__parallel_for(threads, m->nv, 4096, renumber_part, &wp); /* the same parts: the split depends on n only */
    tc__free(wp.slab);
    tc__parallel_for(threads, ws->nw, 4096, across_part, &wp);
    for (int p = 0; p < tc__parallel_parts(threads, ws->nw, 4096); p++) ws->ncoupled += wp.ncoupled[p];
    TC_ASSERT_CHECK(tc__wedges_check, m, ws);
    return TC_OK;
}

int32_t tc__first_wedge_at(const tc__wedge_set *ws, int32_t v) {
    int32_t lo = 0, hi = ws->nw;
    while (lo < hi) {
        int32_t mid = lo + (hi - lo) / 2;
        if (ws->w[mid].v < v) lo = mid + 1;
        else hi = mid;
    }
    return lo;
}

int tc__wedges_build(const struct tc_mesh *m, int honor_flags, tc__wedge_set *ws) {
    return tc__wedges_build_on(m, honor_flags, 1, ws);
}
