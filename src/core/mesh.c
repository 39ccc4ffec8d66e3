/* mesh.c — tc_mesh: a validated copy of a front-end's mesh description.
 * Builds in phases (geometry, topology, flags, samples); each phase collects
 * every error it finds, and a phase runs only if the ones before it passed. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/alloc.h"
#include "core/assert.h"
#include "core/fhypot.h"
#include "core/geom.h"
#include "core/mesh_build.h"
#include "core/parallel.h"
#include "core/range.h"

void tc_mesh_free(tc_mesh *m) {
    if (!m) return;
    tc__free(m->xy);
    tc__free(m->tri);
    tc__free(m->given);
    tc__free(m->kept);
    tc__free(m->quad);
    tc__free(m->orient);
    tc__free(m->cz);
    tc__free(m->given_grad);
    tc__free(m->given_grad_has);
    tc__free(m->mid);
    tc__free(m->mid_has);
    tc__free(m->hess);
    tc__free(m->hess_has);
    tc__free(m->nbr);
    tc__free(m->nbr_k);
    tc__free(m->flag);
    tc__free(m->vstart);
    tc__free(m->vcorner);
    tc__free(m->dstart);
    tc__free(m->dtri);
    tc__free(m);
}

void tc_mesh_desc_init(tc_mesh_desc *d) {
    memset(d, 0, sizeof *d);
    d->value_tolerance = TC_VALUE_TOLERANCE_DEFAULT;
}

static int check_sizes(const tc_mesh_desc *d, tc_diags *dg) {
    int rc = TC_OK;
    if (!(d->value_tolerance >= 0 && d->value_tolerance <= 1))
        rc = tc_diags_add(dg, TC_SEV_ERROR, "value_tolerance", "value_tolerance %g must be 0 to 1", d->value_tolerance);
    if (d->nverts < 1 || !d->xy)
        rc = tc_diags_add(dg, TC_SEV_ERROR, "vertices", "the mesh has no vertices");
    int tris = d->ntris > 0 && d->tris, quads = d->nquads > 0 && d->quads;
    if (tris && quads)
        rc = tc_diags_add(dg, TC_SEV_ERROR, "quads", "give either triangles or quads, not both");
    else if (!tris && !quads)
        rc = tc_diags_add(dg, TC_SEV_ERROR, "triangles", "the mesh has no triangles (nor quads)");
    if (d->nchan < 1 || d->nchan > TC_MAX_CHANNELS)
        rc = tc_diags_add(dg, TC_SEV_ERROR, "values", "%d channels; 1 to %d are supported",
                          (int)d->nchan, TC_MAX_CHANNELS);
    else if (!d->values)
        rc = tc_diags_add(dg, TC_SEV_ERROR, "values", "the mesh has no values");
    return rc;
}

typedef struct {
    const double *x;
    size_t n;
    int bad[TC_PARALLEL_MAX];
} finite_pass;

enum { FINITE_BLOCK = 4096 }; /* numbers per index of the loop */

static void finite_part(void *ctx, int32_t lo, int32_t hi, int part) {
    finite_pass *fp = ctx;
    size_t from = (size_t)lo * FINITE_BLOCK, to = (size_t)hi * FINITE_BLOCK;
    int bad = 0;
    if (to > fp->n) to = fp->n;
    for (size_t i = from; i < to; i++) bad |= !isfinite(fp->x[i]);
    fp->bad[part] = bad;
}

int tc__all_finite_on(int threads, const double *x, size_t n) {
    size_t blocks = (n + FINITE_BLOCK - 1) / FINITE_BLOCK;
    if (blocks <= 1 || blocks > INT32_MAX || threads <= 1) { /* beyond INT32_MAX blocks: beyond any mesh */
        for (size_t i = 0; i < n; i++)
            if (!isfinite(x[i])) return 0;
        return 1;
    }
    finite_pass fp = {x, n, {0}};
    tc__parallel_for(threads, (int32_t)blocks, 16, finite_part, &fp);
    for (int p = 0; p < tc__parallel_parts(threads, (int32_t)blocks, 16); p++)
        if (fp.bad[p]) return 0;
    return 1;
}

static int check_finite_xy(const tc_mesh_desc *d, tc_diags *dg) {
    int rc = TC_OK;
    if (tc__all_finite_on(d->threads, d->xy, 2 * (size_t)d->nverts)) return TC_OK;
    for (int32_t i = 0; i < d->nverts; i++)
        for (int j = 0; j < 2; j++)
            if (!isfinite(d->xy[2 * (size_t)i + (size_t)j])) {
                char path[48];
                snprintf(path, sizeof path, "vertices[%d][%d]", (int)i, j);
                rc = tc_diags_add(dg, TC_SEV_ERROR, path, "number is not finite");
            }
    return rc;
}

/* Index range, distinct corners and non-zero area. The area test is relative
 * to the two edges from corner 0, so slivers of any aspect ratio pass as long
 * as the sign of their area is above the rounding of its computation. A
 * degenerate triangle is an error, or with `drop` only marked (*degenerate). */
static int check_triangle(const tc_mesh_desc *d, int32_t t, int drop, int *degenerate, tc_diags *dg) {
    const int32_t *v = d->tris + 3 * (size_t)t;
    char path[48];
    *degenerate = 0;
    for (int k = 0; k < 3; k++)
        if (v[k] < 0 || v[k] >= d->nverts) {
            snprintf(path, sizeof path, "triangles[%d][%d]", (int)t, k);
            return tc_diags_add(dg, TC_SEV_ERROR, path, "vertex index %d out of range (%d vertices)",
                                (int)v[k], (int)d->nverts);
        }
    const double *p0 = d->xy + 2 * (size_t)v[0], *p1 = d->xy + 2 * (size_t)v[1], *p2 = d->xy + 2 * (size_t)v[2];
    int repeated = v[0] == v[1] || v[1] == v[2] || v[0] == v[2];
    if (!repeated && tc__nonzero_area(p0, p1, p2)) return TC_OK; /* the path is formatted only on failure */
    *degenerate = 1;
    if (drop) return TC_OK;
    snprintf(path, sizeof path, "triangles[%d]", (int)t);
    if (repeated)
        return tc_diags_add(dg, TC_SEV_ERROR, path, "degenerate triangle: a vertex appears twice in [%d, %d, %d]",
                            (int)v[0], (int)v[1], (int)v[2]);
    return tc_diags_add(dg, TC_SEV_ERROR, path, "zero-area triangle: vertices %d, %d, %d are collinear or coincide",
                        (int)v[0], (int)v[1], (int)v[2]);
}

/* One warning for the dropped triangles: the first few given indices and the count. */
static void warn_dropped(const struct tc_mesh *m, tc_diags *dg) {
    enum { SHOW = 8 };
    char path[48], list[160];
    size_t n = 0;
    int32_t shown = 0, first = -1;
    for (int32_t i = 0; i < m->ngiven && shown < SHOW; i++) {
        if (m->kept[i] >= 0) continue;
        if (first < 0) first = i;
        int w = snprintf(list + n, sizeof list - n, "%s%d", shown ? ", " : "", (int)i);
        if (w > 0 && (size_t)w < sizeof list - n) n += (size_t)w;
        shown++;
    }
    snprintf(path, sizeof path, "triangles[%d]", (int)first);
    int32_t ndropped = m->ngiven - m->nt;
    tc_diags_add(dg, TC_SEV_WARNING, path,
                 "%d degenerate triangles (zero area or a vertex repeated) dropped (degenerate \"drop\"): %s%s; "
                 "the others keep their index", (int)ndropped, list, ndropped > shown ? ", ..." : "");
}

/* The dropped triangles at each vertex (m->dstart, m->dtri), so that asking
 * which dropped triangle has an edge costs the vertex's dropped triangles,
 * not a scan of all (a polyline of many segments that are no edges would
 * make that quadratic). A triangle repeating a vertex is listed twice there. */
static int index_dropped(struct tc_mesh *m, const tc_mesh_desc *d) {
    m->dstart = tc__calloc((size_t)m->nv + 1, sizeof *m->dstart);
    m->dtri = tc__malloc(3 * (size_t)(m->ngiven - m->nt), sizeof *m->dtri);
    if (!m->dstart || !m->dtri) return TC_ENOMEM;
    for (int32_t i = 0; i < m->ngiven; i++)
        for (int k = 0; m->kept[i] < 0 && k < 3; k++) m->dstart[d->tris[3 * (size_t)i + (size_t)k] + 1]++;
    for (int32_t v = 0; v < m->nv; v++) m->dstart[v + 1] += m->dstart[v];
    int32_t *fill = tc__malloc((size_t)m->nv, sizeof *fill);
    if (!fill) return TC_ENOMEM;
    memcpy(fill, m->dstart, (size_t)m->nv * sizeof *fill);
    for (int32_t i = 0; i < m->ngiven; i++)
        for (int k = 0; m->kept[i] < 0 && k < 3; k++) m->dtri[fill[d->tris[3 * (size_t)i + (size_t)k]]++] = i;
    tc__free(fill);
    return TC_OK;
}

/* The triangles kept (all, or those not degenerate with `drop`), and the
 * given <-> kept index maps when some were dropped. */
static int keep_triangles(struct tc_mesh *m, const tc_mesh_desc *d, const uint8_t *bad, int32_t nbad, tc_diags *dg) {
    m->ngiven = d->ntris;
    m->nt = d->ntris - nbad;
    if (m->nt == 0)
        return tc_diags_add(dg, TC_SEV_ERROR, "triangles", "every triangle is degenerate (%d dropped)", (int)nbad);
    m->tri = tc__malloc((size_t)m->nt * 3, sizeof *m->tri);
    if (!m->tri) return TC_ENOMEM;
    if (nbad == 0) {
        tc__parallel_copy(m->threads, m->tri, d->tris, (size_t)m->nt * 3 * sizeof *m->tri);
        return TC_OK;
    }
    m->given = tc__malloc((size_t)m->nt, sizeof *m->given);
    m->kept = tc__malloc((size_t)m->ngiven, sizeof *m->kept);
    if (!m->given || !m->kept) return TC_ENOMEM;
    for (int32_t i = 0, t = 0; i < m->ngiven; i++) {
        m->kept[i] = bad[i] ? -1 : t;
        if (bad[i]) continue;
        m->given[t] = i;
        memcpy(m->tri + 3 * (size_t)t++, d->tris + 3 * (size_t)i, 3 * sizeof *m->tri);
    }
    warn_dropped(m, dg);
    return index_dropped(m, d);
}

/* The triangles checked in parts (no findings: made again in order if any failed). */
typedef struct {
    const tc_mesh_desc *d;
    int drop;
    uint8_t *bad;
    int32_t nbad[TC_PARALLEL_MAX];
    int failed[TC_PARALLEL_MAX];
} tri_pass;

static void triangles_part(void *ctx, int32_t lo, int32_t hi, int part) {
    tri_pass *tp = ctx;
    tp->nbad[part] = 0, tp->failed[part] = 0;
    for (int32_t t = lo; t < hi; t++) {
        int degenerate;
        if (check_triangle(tp->d, t, tp->drop, &degenerate, NULL) != TC_OK) tp->failed[part] = 1;
        if (tp->drop && degenerate) tp->bad[t] = 1, tp->nbad[part]++;
    }
}

/* The triangles as given (less the degenerate ones, with degenerate "drop"),
 * or the quads checked and split (quads.c). */
static int copy_elements(struct tc_mesh *m, const tc_mesh_desc *d, tc_diags *dg) {
    if (m->nq) {
        m->ngiven = m->nt;
        return tc__quads_split(m, d, dg);
    }
    int rc = TC_OK, drop = d->degenerate == TC_DEGENERATE_DROP;
    int32_t nbad = 0;
    uint8_t *bad = drop ? tc__calloc((size_t)d->ntris, sizeof *bad) : NULL;
    if (drop && !bad) return TC_ENOMEM;
    tri_pass tp = {d, drop, bad, {0}, {0}};
    tc__parallel_for(d->threads, d->ntris, 4096, triangles_part, &tp);
    int parts = tc__parallel_parts(d->threads, d->ntris, 4096);
    for (int p = 0; p < parts; p++) {
        nbad += tp.nbad[p];
        if (tp.failed[p]) rc = TC_EINVAL;
    }
    if (rc != TC_OK) /* again in order, for the findings */
        for (int32_t t = 0; t < d->ntris; t++) {
            int degenerate;
            check_triangle(d, t, drop, &degenerate, dg);
        }
    if (rc == TC_OK) rc = keep_triangles(m, d, bad, nbad, dg);
    tc__free(bad);
    return rc;
}

int32_t tc__dropped_with_edge(const struct tc_mesh *m, const tc_mesh_desc *d, int32_t a, int32_t b) {
    if (!m->dstart) return -1;
    for (int32_t j = m->dstart[a]; j < m->dstart[a + 1]; j++) {
        int32_t i = m->dtri[j];
        const int32_t *v = d->tris + 3 * (size_t)i;
        if (v[0] == b || v[1] == b || v[2] == b) return i; /* the first: the lowest given index */
    }
    return -1;
}

static void orient_part(void *ctx, int32_t lo, int32_t hi, int part) {
    struct tc_mesh *m = ctx;
    (void)part;
    for (int32_t t = lo; t < hi; t++) {
        const int32_t *v = m->tri + 3 * (size_t)t;
        double e1[2], e2[2];
        tc__sub(e1, tc__vxy(m, v[1]), tc__vxy(m, v[0]));
        tc__sub(e2, tc__vxy(m, v[2]), tc__vxy(m, v[0]));
        m->orient[t] = tc__cross(e1, e2) > 0 ? 1 : -1;
    }
}

static int copy_geometry(struct tc_mesh *m, const tc_mesh_desc *d, tc_diags *dg) {
    int rc = copy_elements(m, d, dg);
    if (rc != TC_OK) return rc;
    m->xy = tc__malloc((size_t)m->nv * 2, sizeof *m->xy);
    m->orient = tc__malloc((size_t)m->nt, sizeof *m->orient);
    if (!m->xy || !m->orient) return TC_ENOMEM;
    tc__parallel_copy(m->threads, m->xy, d->xy, (size_t)m->nv * 2 * sizeof *m->xy);
    tc__parallel_for(m->threads, m->nt, 4096, orient_part, m);
    return TC_OK;
}

/* Above this aspect ratio (longest edge over shortest altitude) a triangle is
 * reported: it stays valid and continuous, but its pieces can overshoot, and a
 * gradient read across it carries rounding of about eps * aspect relative
 * (docs/stability.md: the ordinates vary by |g| L along it, by |g| h across). */
#define ASPECT_WARN 1e4

/* The slivers of triangles [lo, hi): how many, and the first worst. */
typedef struct {
    const struct tc_mesh *m;
    int32_t n[TC_PARALLEL_MAX], worst[TC_PARALLEL_MAX];
    double worst_ar[TC_PARALLEL_MAX];
} sliver_pass;

static void slivers_part(void *ctx, int32_t lo, int32_t hi, int part) {
    sliver_pass *sp = ctx;
    int32_t n = 0, worst = -1;
    double worst_ar = 0;
    for (int32_t t = lo; t < hi; t++) {
        double ar = tc__face_aspect(sp->m, t);
        if (ar <= ASPECT_WARN) continue;
        if (isnan(ar)) ar = INFINITY; /* coordinates near the double range: the area overflows */
        n++;
        if (worst < 0 || ar > worst_ar) worst_ar = ar, worst = t;
    }
    sp->n[part] = n, sp->worst[part] = worst, sp->worst_ar[part] = worst_ar;
}

/* One warning for all the slivers, naming the worst (the first of the largest). */
static void warn_slivers(const struct tc_mesh *m, tc_diags *dg) {
    int32_t n = 0, worst = -1;
    double worst_ar = 0;
    sliver_pass sp;
    sp.m = m;
    tc__parallel_for(m->threads, m->nt, 4096, slivers_part, &sp);
    for (int p = 0; p < tc__parallel_parts(m->threads, m->nt, 4096); p++) {
        n += sp.n[p];
        if (sp.worst[p] >= 0 && (worst < 0 || sp.worst_ar[p] > worst_ar)) worst_ar = sp.worst_ar[p], worst = sp.worst[p];
    }
    if (!n) return;
    char path[48], size[64];
    tc__elem_path(m, worst, path, sizeof path);
    if (isinf(worst_ar)) snprintf(size, sizeof size, "beyond the double range");
    else snprintf(size, sizeof size, "%.3g", worst_ar);
    tc_diags_add(dg, TC_SEV_WARNING, path,
                 "%d triangles have an aspect ratio above %.0e (longest edge / shortest altitude); the worst, %s, "
                 "%s: the reconstruction stays continuous but may overshoot there, and gradients across it lose "
                 "about log10(aspect) digits to rounding",
                 (int)n, ASPECT_WARN, path, size);
}

/* A vertex no triangle uses is harmless (it is never evaluated) but is
 * usually a front-end bug, so it is reported as a warning. */
static void warn_unused(const struct tc_mesh *m, tc_diags *dg) {
    for (int32_t v = 0; v < m->nv; v++)
        if (m->vstart[v] == m->vstart[v + 1]) {
            char path[48];
            snprintf(path, sizeof path, "vertices[%d]", (int)v);
            tc_diags_add(dg, TC_SEV_WARNING, path, "vertex %d is used by no %s", (int)v, m->nq ? "quad" : "triangle");
        }
}

static int build(struct tc_mesh *m, const tc_mesh_desc *d, tc_diags *dg) {
    int rc = check_sizes(d, dg);
    if (rc != TC_OK) return rc;
    if (d->ntris > INT32_MAX / 3 - 1 || d->nquads > INT32_MAX / 6 - 1 || d->nverts > INT32_MAX - 1)
        return TC_ELIMIT;
    m->nv = d->nverts;
    m->nq = d->ntris > 0 ? 0 : d->nquads;
    m->nt = m->nq ? 2 * m->nq : d->ntris;
    m->nc = d->nchan;
    m->threads = d->threads;
    if (d->degenerate != TC_DEGENERATE_REFUSE && d->degenerate != TC_DEGENERATE_DROP)
        return tc_diags_add(dg, TC_SEV_ERROR, "degenerate", "unknown degenerate mode %d", (int)d->degenerate);
    if ((rc = check_finite_xy(d, dg)) != TC_OK) return rc;
    if ((rc = copy_geometry(m, d, dg)) != TC_OK) return rc;
    if ((rc = tc__topology_build(m, dg)) != TC_OK) return rc;
    if ((rc = tc__flags_apply(m, d, dg)) != TC_OK) return rc;
    if ((rc = tc__samples_build(m, d, dg)) != TC_OK) return rc;
    tc__channel_range(m, m->cz, m->threads, m->cz_lo, m->cz_hi, m->cz_big); /* m->cz: not the cache yet */
    m->cz_range_kept = 1;
    warn_unused(m, dg);
    warn_slivers(m, dg);
    TC_ASSERT_CHECK(tc__mesh_check, m); /* mesh.h's invariants, once every phase has run */
    return TC_OK;
}

int tc_mesh_new(const tc_mesh_desc *desc, tc_mesh **out, tc_diags *diags) {
    TC_ASSERT(desc && out);
    *out = NULL;
    struct tc_mesh *m = calloc(1, sizeof *m);
    if (!m) return TC_ENOMEM;
    int rc = build(m, desc, diags);
    tc__free(m->dstart), tc__free(m->dtri); /* only the checks use them */
    m->dstart = m->dtri = NULL;
    if (rc != TC_OK) {
        tc_mesh_free(m);
        return rc;
    }
    *out = m;
    return TC_OK;
}

int32_t tc_mesh_vertex_count(const tc_mesh *m) { return m->nv; }
int32_t tc_mesh_triangle_count(const tc_mesh *m) { return m->nt; }
int32_t tc_mesh_given_triangle_count(const tc_mesh *m) { return m->ngiven; }
int32_t tc_mesh_triangle_of_given(const tc_mesh *m, int32_t i) { return i >= 0 && i < m->ngiven ? tc__kept(m, i) : -1; }
int32_t tc_mesh_given_triangle(const tc_mesh *m, int32_t t) { return tc__given(m, t); }
int tc_mesh_channel_count(const tc_mesh *m) { return m->nc; }
const double *tc_mesh_xy(const tc_mesh *m) { return m->xy; }
const int32_t *tc_mesh_triangles(const tc_mesh *m) { return m->tri; }
int32_t tc_mesh_quad_count(const tc_mesh *m) { return m->nq; }
const int32_t *tc_mesh_quads(const tc_mesh *m) { return m->quad; }

const double *tc_mesh_corner_value(const tc_mesh *m, int32_t t, int k) {
    return m->cz + (3 * (size_t)t + (size_t)k) * (size_t)m->nc;
}

tc_continuity tc_mesh_edge_flag(const tc_mesh *m, int32_t t, int k) {
    return (tc_continuity)m->flag[3 * (size_t)t + (size_t)k];
}

int32_t tc_mesh_neighbor(const tc_mesh *m, int32_t t, int k, int *nk) {
    size_t c = 3 * (size_t)t + (size_t)k;
    if (nk) *nk = m->nbr[c] >= 0 ? m->nbr_k[c] : -1;
    return m->nbr[c];
}
