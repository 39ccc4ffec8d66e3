/* topology.c — who touches whom: vertex -> corner lists, edge adjacency, and
 * the continuity flags the front-end's polylines put on edges. Rejects meshes
 * that are not 2-manifold with consistent sides (repeats, 3-way edges, folds). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/geom.h"
#include "core/mesh_build.h"
#include "core/parallel.h"

/* Corners of each vertex, in increasing corner (so triangle) order: a counting
 * sort. On one part, count, prefix, place. On P parts, with no atomic update
 * and nothing sorted after (an atomic add per corner, twice, cost more than the
 * whole sort on one thread): the vertices are split into P ranges; each corner
 * part sends its corners, in order, to the bucket of its vertex's range (a
 * P x P table of counts gives every (corner part, range) its place), and each
 * range then counts, prefixes and places its bucket alone. A bucket holds its
 * corners in increasing order (corner parts in order, each in order), so each
 * vertex's list comes out sorted: the lists are the same for any thread count. */
typedef struct {
    struct tc_mesh *m;
    int parts;
    int32_t *bucket;                /* [3nt] corners grouped by vertex range */
    int32_t *slot;                  /* [nv] count of a vertex, then its next place */
    int32_t vlo[TC_PARALLEL_MAX + 1]; /* vertex range q: [vlo[q], vlo[q + 1]) */
    int32_t blo[TC_PARALLEL_MAX + 1]; /* its bucket: bucket[blo[q] .. blo[q + 1]) */
    int32_t (*at)[TC_PARALLEL_MAX];   /* [part][q]: count, then next place in bucket q */
    int32_t maxval[TC_PARALLEL_MAX];  /* the largest valence in range q */
} corner_pass;

/* The range of vertex v: the last q with vlo[q] <= v. */
static int range_of(const corner_pass *cp, int32_t v) {
    int q = (int)((int64_t)v * cp->parts / cp->m->nv); /* vlo[q] <= v; at most one range short */
    while (q + 1 < cp->parts && cp->vlo[q + 1] <= v) q++;
    return q;
}

static void bucket_count_part(void *ctx, int32_t lo, int32_t hi, int part) {
    corner_pass *cp = ctx;
    int32_t *n = cp->at[part];
    for (int q = 0; q < cp->parts; q++) n[q] = 0;
    for (int32_t c = lo; c < hi; c++) n[range_of(cp, cp->m->tri[c])]++;
}

static void bucket_fill_part(void *ctx, int32_t lo, int32_t hi, int part) {
    corner_pass *cp = ctx;
    int32_t *next = cp->at[part];
    for (int32_t c = lo; c < hi; c++) cp->bucket[next[range_of(cp, cp->m->tri[c])]++] = c;
}

/* Counting sort of corners[0 .. n) (increasing) by vertex, for the vertices
 * [vlo, vhi), whose lists start at `first`: sets vstart[vlo .. vhi) and places
 * the corners; returns the largest valence among them. slot[vlo .. vhi) is
 * this call's alone. */
static int32_t place_corners(struct tc_mesh *m, int32_t *slot, const int32_t *corners, int32_t n, int32_t vlo,
                             int32_t vhi, int32_t first) {
    int32_t maxval = 0;
    for (int32_t v = vlo; v < vhi; v++) slot[v] = 0;
    for (int32_t i = 0; i < n; i++) slot[m->tri[corners ? corners[i] : i]]++;
    for (int32_t v = vlo; v < vhi; v++) { /* the counts become the first places */
        int32_t k = slot[v];
        m->vstart[v] = slot[v] = first;
        first += k;
        if (k > maxval) maxval = k;
    }
    for (int32_t i = 0; i < n; i++) {
        int32_t c = corners ? corners[i] : i;
        m->vcorner[slot[m->tri[c]]++] = c;
    }
    return maxval;
}

static void range_place_part(void *ctx, int32_t lo, int32_t hi, int part) {
    corner_pass *cp = ctx;
    (void)part;
    for (int q = lo; q < hi; q++)
        cp->maxval[q] = place_corners(cp->m, cp->slot, cp->bucket + cp->blo[q], cp->blo[q + 1] - cp->blo[q],
                                      cp->vlo[q], cp->vlo[q + 1], cp->blo[q]);
}

/* The places of the P x P table: bucket q holds range q's corners from part 0,
 * then part 1, ... */
static void bucket_places(corner_pass *cp) {
    int32_t run = 0;
    for (int q = 0; q < cp->parts; q++) {
        cp->blo[q] = run;
        for (int p = 0; p < cp->parts; p++) {
            int32_t n = cp->at[p][q];
            cp->at[p][q] = run;
            run += n;
        }
    }
    cp->blo[cp->parts] = run;
}

static int build_vertex_corners(struct tc_mesh *m) {
    int32_t nc = 3 * m->nt; /* below INT32_MAX: mesh.c's limits */
    corner_pass cp = {.m = m, .parts = tc__parallel_parts(m->threads, nc, 16384)};
    m->vstart = tc__malloc((size_t)m->nv + 1, sizeof *m->vstart);
    m->vcorner = tc__malloc((size_t)nc, sizeof *m->vcorner);
    cp.slot = tc__malloc((size_t)m->nv, sizeof *cp.slot);
    if (cp.parts > 1) {
        cp.bucket = tc__malloc((size_t)nc, sizeof *cp.bucket);
        cp.at = tc__malloc((size_t)cp.parts, sizeof *cp.at);
    }
    int rc = TC_ENOMEM;
    if (!m->vstart || !m->vcorner || !cp.slot || (cp.parts > 1 && (!cp.bucket || !cp.at))) goto done;
    m->vstart[m->nv] = nc;
    if (cp.parts == 1) {
        m->max_valence = place_corners(m, cp.slot, NULL, nc, 0, m->nv, 0);
    } else {
        for (int q = 0; q <= cp.parts; q++) cp.vlo[q] = (int32_t)((int64_t)m->nv * q / cp.parts);
        tc__parallel_for(m->threads, nc, 16384, bucket_count_part, &cp); /* cp.parts parts, as counted */
        bucket_places(&cp);
        tc__parallel_for(m->threads, nc, 16384, bucket_fill_part, &cp); /* the same parts again */
        tc__parallel_for(m->threads, cp.parts, 1, range_place_part, &cp); /* one range per part */
        m->max_valence = 0;
        for (int q = 0; q < cp.parts; q++)
            if (cp.maxval[q] > m->max_valence) m->max_valence = cp.maxval[q];
    }
    rc = TC_OK;
done:
    tc__free(cp.slot), tc__free(cp.bucket), tc__free(cp.at);
    return rc;
}

/* Index (0..2) of the edge of triangle t that joins a and b, or -1. */
static int edge_index(const struct tc_mesh *m, int32_t t, int32_t a, int32_t b) {
    const int32_t *v = m->tri + 3 * (size_t)t;
    for (int j = 0; j < 3; j++) {
        int32_t p = v[j], q = v[(j + 1) % 3];
        if ((p == a && q == b) || (p == b && q == a)) return j;
    }
    return -1;
}

/* The side of the line a -> b that triangle t's third vertex lies on (1 left, -1 right), t's
 * edge k joining a and b in either direction: t's orientation (m->orient), reversed where t
 * runs the edge b -> a. Taken from m->orient, not from a cross product of its own, because
 * the fans and wedges walk the mesh by that orientation: two triangles linked across an edge
 * must lie on opposite sides of it as m->orient has them. A cross product of their own could
 * disagree with it for a third vertex within rounding of the edge's line (a subnormal
 * offset: the fuzzer found two folded triangles running their shared edge the same way,
 * both seen from that edge's start on opposite sides, linked, and the wedges inconsistent). */
static int side_of_third(const struct tc_mesh *m, int32_t t, int k, int32_t a) {
    int forward = m->tri[3 * (size_t)t + (size_t)k] == a;
    return forward ? m->orient[t] : -m->orient[t];
}

/* The other triangles on each edge side e = 3t+k, found per vertex in
 * O(its corners log its corners) rather than by a scan of the vertex's corners
 * per edge (quadratic in the valence): at vertex a, the edges of its corners
 * to each b > a are sorted by (b, e), so each edge's sides come together in
 * increasing triangle order, as the corner lists have them. Per side: the
 * first two others (-1: none) and how many there are. */
typedef struct {
    struct tc_mesh *m;
    int32_t *oth0, *oth1, *noth;
    int32_t max_pairs;      /* 2 x the largest valence */
    int32_t *scratch[TC_PARALLEL_MAX];
    int failed[TC_PARALLEL_MAX]; /* a part ran out of memory, or met a bad edge */
} edge_sides;

typedef struct {
    int32_t b, e;
} side_pair;

static int pair_cmp(const void *x, const void *y) {
    const side_pair *p = x, *q = y;
    if (p->b != q->b) return p->b < q->b ? -1 : 1;
    return (p->e > q->e) - (p->e < q->e);
}

static void sort_pairs(side_pair *sp, int32_t n) {
    if (n > 24) {
        qsort(sp, (size_t)n, sizeof *sp, pair_cmp);
        return;
    }
    for (int32_t i = 1; i < n; i++) { /* few: insertion sort */
        side_pair x = sp[i];
        int32_t j = i;
        for (; j > 0 && pair_cmp(&sp[j - 1], &x) > 0; j--) sp[j] = sp[j - 1];
        sp[j] = x;
    }
}

/* Sides E[0..n) of one edge, in increasing triangle order. */
static void note_group(const edge_sides *es, const side_pair *E, int32_t n) {
    for (int32_t i = 0; i < n; i++) {
        int32_t e = E[i].e;
        es->oth0[e] = n > 1 ? E[i == 0 ? 1 : 0].e : -1;
        es->oth1[e] = n > 2 ? E[i <= 1 ? 2 : 1].e : -1;
        es->noth[e] = n - 1;
    }
}

static void sides_part(void *ctx, int32_t lo, int32_t hi, int part) {
    edge_sides *es = ctx;
    const struct tc_mesh *m = es->m;
    side_pair *sp = (side_pair *)es->scratch[part];
    for (int32_t a = lo; a < hi; a++) {
        int32_t n = 0;
        for (int32_t i = m->vstart[a]; i < m->vstart[a + 1]; i++) {
            int32_t c = m->vcorner[i], t = c / 3, k = c % 3;
            int32_t next = m->tri[3 * (size_t)t + (size_t)(k + 1) % 3], prev = m->tri[3 * (size_t)t + (size_t)(k + 2) % 3];
            if (next > a) sp[n++] = (side_pair){next, 3 * t + k};
            if (prev > a) sp[n++] = (side_pair){prev, 3 * t + (k + 2) % 3};
        }
        sort_pairs(sp, n);
        for (int32_t i = 0, j; i < n; i = j) {
            for (j = i + 1; j < n && sp[j].b == sp[i].b; j++) continue;
            note_group(es, sp + i, j - i);
        }
    }
}

static int find_sides(struct tc_mesh *m, edge_sides *es) {
    size_t nc = 3 * (size_t)m->nt;
    es->m = m;
    es->max_pairs = 2 * m->max_valence;
    es->oth0 = tc__malloc(nc, sizeof *es->oth0);
    es->oth1 = tc__malloc(nc, sizeof *es->oth1);
    es->noth = tc__malloc(nc, sizeof *es->noth);
    if (!es->oth0 || !es->oth1 || !es->noth) return TC_ENOMEM;
    int parts = tc__parallel_parts(m->threads, m->nv, 4096);
    for (int p = 0; p < parts; p++) {
        es->scratch[p] = tc__malloc((size_t)es->max_pairs, sizeof(side_pair));
        if (!es->scratch[p]) return TC_ENOMEM;
    }
    tc__parallel_for(m->threads, m->nv, 4096, sides_part, es);
    return TC_OK;
}

static void sides_free(edge_sides *es) {
    tc__free(es->oth0), tc__free(es->oth1), tc__free(es->noth);
    for (int p = 0; p < TC_PARALLEL_MAX; p++) tc__free(es->scratch[p]);
}

/* Links edge k of t to the first other triangle on it (es). Reports repeats,
 * non-manifold edges (once, from the lowest triangle) and folds; dg may be
 * NULL (the parallel pass: the findings are made again, in order, if any). */
static int link_edge(struct tc_mesh *m, const edge_sides *es, int32_t t, int k, tc_diags *dg) {
    int32_t a = m->tri[3 * (size_t)t + (size_t)k], b = m->tri[3 * (size_t)t + (size_t)(k + 1) % 3];
    size_t e = 3 * (size_t)t + (size_t)k;
    int32_t nothers = es->noth[e];
    char path[48];
    if (nothers == 0) return TC_OK;
    int32_t others[2] = {es->oth0[e] / 3, es->oth1[e] >= 0 ? es->oth1[e] / 3 : -1};
    int32_t lowest = others[0] < t ? others[0] : t; /* the sides come in increasing triangle order */
    int32_t t2 = others[0];
    int k2 = es->oth0[e] % 3;
    int32_t w = m->tri[3 * (size_t)t + (size_t)(k + 2) % 3];
    char other[48];
    if (tc__corner_of(m, t2, w) >= 0) {
        if (t2 > t) return TC_OK;  /* reported from the later copy, */
        if (k != 0) return TC_EINVAL; /* once: all its edges see it */
        tc__elem_path(m, t, path, sizeof path);
        tc__elem_path(m, t2, other, sizeof other);
        if (m->nq) /* whole repeated quads were refused before: these share one half */
            return tc_diags_add(dg, TC_SEV_ERROR, path, "overlaps %s: both contain the triangle [%d, %d, %d]", other,
                                (int)a, (int)b, (int)w);
        return tc_diags_add(dg, TC_SEV_ERROR, path, "repeats %s (same three vertices)", other);
    }
    if (nothers > 1) {
        if (lowest != t) return TC_EINVAL;
        tc__elem_path(m, others[1], path, sizeof path);
        return tc_diags_add(dg, TC_SEV_ERROR, path,
                            "non-manifold edge [%d, %d]: shared by %d triangles (%s%d, %d, %d%s)", (int)a, (int)b,
                            (int)nothers + 1, m->nq ? "halves of quads " : "", (int)tc__elem_index(m, t),
                            (int)tc__elem_index(m, others[0]), (int)tc__elem_index(m, others[1]),
                            nothers > 2 ? ", ..." : "");
    }
    if (side_of_third(m, t, k, a) == side_of_third(m, t2, k2, a)) {
        if (t2 < t) return TC_EINVAL; /* both see it: reported once, from the lower triangle */
        tc__elem_path(m, t2, path, sizeof path);
        tc__elem_path(m, t, other, sizeof other);
        return tc_diags_add(dg, TC_SEV_ERROR, path,
                            "overlaps %s: both lie on the same side of their shared edge [%d, %d]", other, (int)a,
                            (int)b);
    }
    m->nbr[3 * (size_t)t + (size_t)k] = t2;
    m->nbr_k[3 * (size_t)t + (size_t)k] = (int8_t)k2;
    return TC_OK;
}

/* One step around vertex v: from corner *c, whose triangle was entered across
 * its edge v-*w, across its other edge at v; *c and *w become the next corner
 * and the vertex of the edge crossed. Triangles keep the orientation they were
 * given, so the walk goes by edges, not by turning direction. Returns 0 at the
 * mesh's boundary. */
static int fan_step(const struct tc_mesh *m, int32_t v, int32_t *c, int32_t *w) {
    int32_t t = *c / 3, k = *c % 3;
    int32_t p = m->tri[3 * (size_t)t + (size_t)(k + 1) % 3], q = m->tri[3 * (size_t)t + (size_t)(k + 2) % 3];
    int leave_k = *w != p; /* edge k joins v and p; edge k + 2 joins q and v */
    int32_t t2 = m->nbr[3 * (size_t)t + (size_t)(leave_k ? k : (k + 2) % 3)];
    if (t2 < 0) return 0;
    *c = 3 * t2 + tc__corner_of(m, t2, v);
    *w = leave_k ? p : q;
    return 1;
}

/* A vertex whose triangles around it close a full turn, and that has more
 * triangles than that turn: the others overlap it (the fan covers every
 * direction from v), which no edge test sees when they share only v. Each
 * walk starts at an unmarked corner and marks its fan both ways, so every
 * corner is visited once: O(corners). seen[] holds marks of v's corners only,
 * so vertices may be checked on different threads. */
static int check_fan(const struct tc_mesh *m, int32_t v, int32_t *seen, tc_diags *dg) {
    int32_t count = m->vstart[v + 1] - m->vstart[v];
    for (int32_t i = m->vstart[v]; i < m->vstart[v + 1]; i++) {
        int32_t c0 = m->vcorner[i], n = 1, c = c0, k0 = c0 % 3;
        int32_t p0 = m->tri[3 * (size_t)(c0 / 3) + (size_t)(k0 + 1) % 3], q0 = m->tri[3 * (size_t)(c0 / 3) + (size_t)(k0 + 2) % 3];
        if (seen[c0] == v + 1) continue;
        seen[c0] = v + 1;
        int32_t w = q0; /* as if entered across v-q0: leaves across v-p0 */
        while (fan_step(m, v, &c, &w) && seen[c] != v + 1) seen[c] = v + 1, n++;
        int closed = c == c0 && seen[c] == v + 1 && n > 1;
        if (!closed) { /* open: mark the rest of this fan, behind c0 */
            c = c0, w = p0;
            while (fan_step(m, v, &c, &w) && seen[c] != v + 1) seen[c] = v + 1;
            continue;
        }
        if (n == count) continue;
        /* Name a triangle outside this fan: mark the fan apart (-(v + 1)) and take one
         * corner of v that is not in it (an earlier walk may have marked the others). */
        c = c0, w = q0, seen[c0] = -(v + 1);
        while (fan_step(m, v, &c, &w) && seen[c] != -(v + 1)) seen[c] = -(v + 1);
        int32_t other = -1;
        for (int32_t j = m->vstart[v]; j < m->vstart[v + 1] && other < 0; j++)
            if (seen[m->vcorner[j]] != -(v + 1)) other = m->vcorner[j] / 3;
        char path[48];
        tc__elem_path(m, other, path, sizeof path);
        return tc_diags_add(dg, TC_SEV_ERROR, path,
                            "overlaps the triangles around vertex %d: %d of them close a full turn around it, so "
                            "any other triangle at that vertex lies on top of one of them",
                            (int)v, (int)n);
    }
    return TC_OK;
}

/* The parallel passes: each part notes the first index at which it failed
 * (INT32_MAX: none), and the first over all parts is made again with the
 * diagnostics, so the finding is the serial one. */
typedef struct {
    struct tc_mesh *m;
    const edge_sides *es;
    int32_t *seen;
    int32_t first_bad[TC_PARALLEL_MAX];
} topo_pass;

static void link_part(void *ctx, int32_t lo, int32_t hi, int part) {
    topo_pass *tp = ctx;
    tp->first_bad[part] = INT32_MAX;
    for (int32_t t = lo; t < hi; t++)
        for (int k = 0; k < 3; k++)
            if (link_edge(tp->m, tp->es, t, k, NULL) != TC_OK && tp->first_bad[part] == INT32_MAX)
                tp->first_bad[part] = t;
}

static void fans_part(void *ctx, int32_t lo, int32_t hi, int part) {
    topo_pass *tp = ctx;
    tp->first_bad[part] = INT32_MAX;
    for (int32_t v = lo; v < hi && tp->first_bad[part] == INT32_MAX; v++)
        if (check_fan(tp->m, v, tp->seen, NULL) != TC_OK) tp->first_bad[part] = v;
}

static int32_t first_bad(const topo_pass *tp, int parts) {
    int32_t first = INT32_MAX;
    for (int p = 0; p < parts; p++)
        if (tp->first_bad[p] < first) first = tp->first_bad[p];
    return first;
}

/* Every edge linked; on a bad one, all the findings again in triangle order
 * (each edge reports for itself, so every error is reported, as it was serially). */
static int link_edges(struct tc_mesh *m, const edge_sides *es, tc_diags *dg) {
    topo_pass tp = {m, es, NULL, {0}};
    tc__parallel_for(m->threads, m->nt, 2048, link_part, &tp);
    int32_t bad = first_bad(&tp, tc__parallel_parts(m->threads, m->nt, 2048));
    if (bad == INT32_MAX) return TC_OK;
    int rc = TC_OK;
    for (int32_t t = bad; t < m->nt; t++)
        for (int k = 0; k < 3; k++)
            if (link_edge(m, es, t, k, dg) != TC_OK) rc = TC_EINVAL;
    return rc;
}

/* The fans; the serial check stops at the first vertex found bad. */
static int check_fans(struct tc_mesh *m, tc_diags *dg) {
    int32_t *seen = tc__malloc(3 * (size_t)m->nt, sizeof *seen); /* zeroed on the threads (first touch) */
    if (!seen) return TC_ENOMEM;
    tc__parallel_zero(m->threads, seen, 3 * (size_t)m->nt * sizeof *seen);
    topo_pass tp = {m, NULL, seen, {0}};
    tc__parallel_for(m->threads, m->nv, 4096, fans_part, &tp);
    int32_t bad = first_bad(&tp, tc__parallel_parts(m->threads, m->nv, 4096));
    int rc = TC_OK;
    if (bad != INT32_MAX) { /* again with the findings, its corners unmarked */
        for (int32_t i = m->vstart[bad]; i < m->vstart[bad + 1]; i++) seen[m->vcorner[i]] = 0;
        rc = check_fan(m, bad, seen, dg);
        TC_ASSERT(rc != TC_OK);
    }
    tc__free(seen);
    return rc;
}

static void unlinked_part(void *ctx, int32_t lo, int32_t hi, int part) {
    struct tc_mesh *m = ctx;
    (void)part;
    for (int32_t c = lo; c < hi; c++) m->nbr[c] = -1, m->nbr_k[c] = 0;
}

static void flags_part(void *ctx, int32_t lo, int32_t hi, int part) {
    struct tc_mesh *m = ctx;
    (void)part;
    for (int32_t c = lo; c < hi; c++) m->flag[c] = m->nbr[c] >= 0 ? TC_C1 : TC_CM1;
}

int tc__topology_build(struct tc_mesh *m, tc_diags *dg) {
    size_t nc = 3 * (size_t)m->nt;
    int rc = build_vertex_corners(m);
    if (rc != TC_OK) return rc;
    m->nbr = tc__malloc(nc, sizeof *m->nbr);
    m->nbr_k = tc__malloc(nc, sizeof *m->nbr_k); /* nbr, nbr_k: set by unlinked_part */
    m->flag = tc__malloc(nc, sizeof *m->flag);
    if (!m->nbr || !m->nbr_k || !m->flag) return TC_ENOMEM;
    tc__parallel_for(m->threads, (int32_t)nc, 16384, unlinked_part, m);
    edge_sides es;
    memset(&es, 0, sizeof es);
    rc = find_sides(m, &es);
    if (rc == TC_OK) rc = link_edges(m, &es, dg);
    sides_free(&es);
    if (rc != TC_OK) return rc;
    if ((rc = check_fans(m, dg)) != TC_OK) return rc;
    tc__parallel_for(m->threads, (int32_t)nc, 16384, flags_part, m);
    return TC_OK;
}

int32_t tc__find_edge(const struct tc_mesh *m, int32_t a, int32_t b) {
    if (m->vstart[b + 1] - m->vstart[b] < m->vstart[a + 1] - m->vstart[a]) { /* both lists hold the edge's */
        int32_t s = a;                                                       /* triangles in increasing order */
        a = b, b = s;
    }
    for (int32_t i = m->vstart[a]; i < m->vstart[a + 1]; i++) {
        int32_t c = m->vcorner[i], t = c / 3;
        int k = edge_index(m, t, a, b);
        if (k >= 0) return 3 * t + k;
    }
    return -1;
}

/* ---- continuity flags from polylines ---- */

typedef struct {
    const tc_mesh_desc *d;
    const char *name;   /* "c0" or "c-1" */
    tc_continuity kind;
    int32_t *src;       /* [3nt] polyline that flagged each edge side, or -1 */
    tc_continuity *src_kind;
} flag_ctx;

/* c: the edge side from p to q (tc__find_edge), or -1. */
static int flag_segment(struct tc_mesh *m, flag_ctx *fc, int32_t line, int32_t j, int32_t p, int32_t q, int32_t c,
                        tc_diags *dg) {
    char path[64]; /* formatted only for a finding: a clean segment costs an edge look-up */
#define SEGMENT_PATH() snprintf(path, sizeof path, "discontinuities.%s[%d][%d]", fc->name, (int)line, (int)j)
    if (p == q && SEGMENT_PATH() > 0)
        return tc_diags_add(dg, TC_SEV_ERROR, path, "segment [%d, %d] repeats a vertex", (int)p, (int)q);
    int32_t dropped = c < 0 ? tc__dropped_with_edge(m, fc->d, p, q) : -1;
    if (c < 0 || tc__is_diagonal(m, c) || (fc->src[c] >= 0 && fc->src_kind[c] != fc->kind)) SEGMENT_PATH();
#undef SEGMENT_PATH
    if (dropped >= 0) /* nothing left to flag: the edge went with the triangle */
        return tc_diags_add(dg, TC_SEV_WARNING, path,
                            "segment [%d, %d] is an edge only of triangles dropped as degenerate (triangles[%d]): "
                            "ignored", (int)p, (int)q, (int)dropped);
    if (c < 0)
        return tc_diags_add(dg, TC_SEV_ERROR, path, "segment [%d, %d] is not an edge of the mesh", (int)p,
                            (int)q);
    if (tc__is_diagonal(m, c)) /* inside one quad: flagging it would cut the quad's patch */
        return tc_diags_add(dg, TC_SEV_ERROR, path,
                            "segment [%d, %d] is the diagonal of quads[%d], not an edge of the mesh", (int)p, (int)q,
                            (int)(c / 6));
    if (fc->src[c] >= 0 && fc->src_kind[c] != fc->kind)
        return tc_diags_add(dg, TC_SEV_ERROR, path, "edge [%d, %d] is flagged both c0 and c-1 (also in %s[%d])",
                            (int)p, (int)q, fc->src_kind[c] == TC_C0 ? "discontinuities.c0" : "discontinuities.c-1",
                            (int)fc->src[c]);
    fc->src[c] = line;
    fc->src_kind[c] = fc->kind;
    if (m->nbr[c] < 0) return TC_OK; /* a boundary edge is already as cut as it can be */
    int32_t other = 3 * m->nbr[c] + m->nbr_k[c];
    if (fc->src[other] < 0) m->nflagged++;
    m->flag[c] = m->flag[other] = (int8_t)fc->kind;
    fc->src[other] = line;
    fc->src_kind[other] = fc->kind;
    return TC_OK;
}

/* The edge look-ups of a set of polylines, on the threads (they read the
 * topology only, never the flags): edge[j] for the segment from verts[j - 1]
 * to verts[j], for every j in (first, n) (a pair that spans two polylines is
 * looked up for nothing), or -2 where a vertex is out of range or repeated
 * (the serial pass reports those). Only for polylines laid end to end
 * (start[] nondecreasing): then verts[first .. n) is what the pass reads. */
typedef struct {
    const struct tc_mesh *m;
    const int32_t *verts;
    int32_t first;
    int32_t *edge; /* [n], or NULL: looked up in the serial pass */
} edge_lookup;

static void lookup_part(void *ctx, int32_t lo, int32_t hi, int part) {
    const edge_lookup *el = ctx;
    int32_t nv = el->m->nv;
    (void)part;
    for (int32_t j = lo > el->first ? lo : el->first + 1; j < hi; j++) {
        int32_t p = el->verts[j - 1], q = el->verts[j];
        el->edge[j] = p < 0 || p >= nv || q < 0 || q >= nv || p == q ? -2 : tc__find_edge(el->m, p, q);
    }
}

static int flag_polylines(struct tc_mesh *m, const tc_polylines *pl, flag_ctx *fc, tc_diags *dg) {
    int rc = TC_OK;
    char path[64];
    int end_to_end = pl->count > 0 && pl->start[0] >= 0;
    for (int32_t i = 0; end_to_end && i < pl->count; i++) end_to_end = pl->start[i] <= pl->start[i + 1];
    int32_t n = end_to_end ? pl->start[pl->count] : 0;
    edge_lookup el = {m, pl->verts, end_to_end ? pl->start[0] : 0, n > 1 ? tc__malloc((size_t)n, sizeof *el.edge) : NULL};
    if (el.edge) tc__parallel_for(m->threads, n, 1024, lookup_part, &el); /* else looked up below */
    for (int32_t i = 0; i < pl->count; i++) {
        int32_t s = pl->start[i], e = pl->start[i + 1];
        snprintf(path, sizeof path, "discontinuities.%s[%d]", fc->name, (int)i);
        if (e - s < 2) {
            rc = tc_diags_add(dg, TC_SEV_ERROR, path, "a polyline needs at least 2 vertices");
            continue;
        }
        for (int32_t j = s; j < e; j++) {
            int32_t v = pl->verts[j];
            if (v < 0 || v >= m->nv) {
                snprintf(path, sizeof path, "discontinuities.%s[%d][%d]", fc->name, (int)i, (int)(j - s));
                rc = tc_diags_add(dg, TC_SEV_ERROR, path, "vertex index %d out of range (%d vertices)", (int)v,
                                  (int)m->nv);
                break;
            }
            if (j == s) continue;
            int32_t p = pl->verts[j - 1];
            int32_t c = el.edge && el.edge[j] != -2 ? el.edge[j] : p == v ? -1 : tc__find_edge(m, p, v);
            if (flag_segment(m, fc, i, j - 1 - s, p, v, c, dg) != TC_OK) rc = TC_EINVAL;
        }
    }
    tc__free(el.edge);
    return rc;
}

static void unflagged_part(void *ctx, int32_t lo, int32_t hi, int part) {
    int32_t *src = ctx;
    (void)part;
    for (int32_t c = lo; c < hi; c++) src[c] = -1;
}

int tc__flags_apply(struct tc_mesh *m, const tc_mesh_desc *d, tc_diags *dg) {
    if (d->c0.count == 0 && d->cm1.count == 0) return TC_OK;
    size_t nc = 3 * (size_t)m->nt;
    flag_ctx fc = {0};
    fc.d = d;
    fc.src = tc__malloc(nc, sizeof *fc.src);
    fc.src_kind = tc__malloc(nc, sizeof *fc.src_kind);
    int rc = TC_ENOMEM;
    if (fc.src && fc.src_kind) {
        tc__parallel_for(m->threads, (int32_t)nc, 16384, unflagged_part, fc.src);
        fc.name = "c0";
        fc.kind = TC_C0;
        rc = flag_polylines(m, &d->c0, &fc, dg);
        fc.name = "c-1";
        fc.kind = TC_CM1;
        if (flag_polylines(m, &d->cm1, &fc, dg) != TC_OK) rc = TC_EINVAL;
    }
    tc__free(fc.src);
    tc__free(fc.src_kind);
    return rc;
}
