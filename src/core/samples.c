/* samples.c — the data a front-end measured, spread onto triangle corners:
 * corner values (vertex values with sparse overrides), given tangent planes
 * (gradients or normals, per vertex or per corner) and edge-midpoint samples;
 * then those that must agree across C0/C1 edges are made to (agree.c). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/alloc.h"
#include "core/mesh_build.h"
#include "core/parallel.h"

/* Per-corner entries name elements: triangles (3 corners), or on a quad mesh
 * quads (4 corners, each landing on one or two split-triangle corners). */
static int elem_corners(const struct tc_mesh *m) { return m->nq ? 4 : 3; }
static int32_t elem_count(const struct tc_mesh *m) { return m->nq ? m->nq : m->ngiven; }

/* The corner ids (3t+k) where corner k of element e lands; returns 1 or 2.
 * e is a quad, or a triangle of the mesh (not a given index: see kept_elem). */
static int landing(const struct tc_mesh *m, int32_t e, int k, int32_t out[2]) {
    if (m->nq) return tc__quad_corners(e, k, out);
    out[0] = 3 * e + k;
    return 1;
}

/* "corner_values[3].triangle: triangle index 9 out of range (4 triangles)", or
 * the same with quads. */
static int check_elem(const struct tc_mesh *m, const char *field, int32_t i, int32_t e, tc_diags *dg) {
    if (e >= 0 && e < elem_count(m)) return TC_OK;
    char path[64];
    const char *w = tc__elem_word(m);
    snprintf(path, sizeof path, "%s[%d].%s", field, (int)i, w);
    return tc_diags_add(dg, TC_SEV_ERROR, path, "%s index %d out of range (%d %ss)", w, (int)e, (int)elem_count(m), w);
}

/* Entry i of `field` names element *e (in range): a triangle's given index
 * becomes the mesh's. Returns 0 if that triangle was dropped as degenerate,
 * after a warning that the entry is ignored. */
static int kept_elem(const struct tc_mesh *m, const char *field, int32_t i, int32_t *e, tc_diags *dg) {
    if (m->nq || tc__kept(m, *e) >= 0) {
        if (!m->nq) *e = tc__kept(m, *e);
        return 1;
    }
    char path[64];
    snprintf(path, sizeof path, "%s[%d].triangle", field, (int)i);
    tc_diags_add(dg, TC_SEV_WARNING, path, "triangle %d was dropped as degenerate: this entry is ignored", (int)*e);
    return 0;
}

/* Scratch shared by the steps: which corner_values entry set each corner and
 * which midpoints entry each edge side (for the paths of agreement errors). */
typedef struct {
    int32_t *cv_src;  /* [3nt] or NULL */
    int32_t *mid_src; /* [3nt] or NULL */
} scratch;

static int all_finite(const double *x, size_t n) {
    for (size_t i = 0; i < n; i++)
        if (!isfinite(x[i])) return 0;
    return 1;
}

/* The per-element checks below format the element's path only on failure:
 * snprintf for every vertex of a large mesh cost more than the checks. */
static int check_finite(const double *x, size_t n, const char *path, tc_diags *dg) {
    for (size_t i = 0; i < n; i++)
        if (!isfinite(x[i])) return tc_diags_add(dg, TC_SEV_ERROR, path, "number is not finite");
    return TC_OK;
}

/* Entry i of corner_values (already checked) onto the corners of element e. */
static void put_corner_values(struct tc_mesh *m, const tc_mesh_desc *d, scratch *s, int32_t i, int32_t e,
                              const double *z) {
    int nc = m->nc;
    for (int k = 0; k < elem_corners(m); k++) {
        int32_t cs[2];
        for (int n = landing(m, e, k, cs), j = 0; j < n; j++) {
            size_t c = (size_t)cs[j];
            s->cv_src[c] = i;
            memcpy(m->cz + c * (size_t)nc, z + (size_t)k * (size_t)nc, (size_t)nc * sizeof *m->cz);
            if (memcmp(z + (size_t)k * (size_t)nc, d->values + (size_t)m->tri[c] * (size_t)nc, (size_t)nc * sizeof *z))
                m->ncorner_overrides++;
        }
    }
}

/* The per-corner copies, in parts (each writes its own corners). */
typedef struct {
    struct tc_mesh *m;
    const tc_mesh_desc *d;
    int failed[TC_PARALLEL_MAX];
} copy_pass;

static void values_part(void *ctx, int32_t lo, int32_t hi, int part) {
    const copy_pass *cp = ctx;
    size_t nc = (size_t)cp->m->nc;
    (void)part;
    for (int32_t c = lo; c < hi; c++) {
        const double *src = cp->d->values + (size_t)cp->m->tri[c] * nc;
        double *dst = cp->m->cz + (size_t)c * nc;
        for (size_t ch = 0; ch < nc; ch++) dst[ch] = src[ch];
    }
}

static int corner_values(struct tc_mesh *m, const tc_mesh_desc *d, scratch *s, tc_diags *dg) {
    int nc = m->nc, rc = TC_OK, nk = elem_corners(m);
    char path[64];
    int finite = tc__all_finite_on(m->threads, d->values, (size_t)m->nv * (size_t)nc); /* else the findings: */
    for (int32_t v = 0; !finite && v < m->nv; v++) {
        if (all_finite(d->values + (size_t)v * (size_t)nc, (size_t)nc)) continue;
        snprintf(path, sizeof path, "values[%d]", (int)v);
        if (check_finite(d->values + (size_t)v * (size_t)nc, (size_t)nc, path, dg) != TC_OK) rc = TC_EINVAL;
    }
    if (rc != TC_OK) return rc;
    m->cz = tc__malloc(3 * (size_t)m->nt * (size_t)nc, sizeof *m->cz);
    if (!m->cz) return TC_ENOMEM;
    copy_pass cp = {m, d, {0}};
    tc__parallel_for(m->threads, 3 * m->nt, 8192, values_part, &cp);
    if (d->ncorner_values == 0) return TC_OK;
    s->cv_src = tc__malloc(3 * (size_t)m->nt, sizeof *s->cv_src);
    if (!s->cv_src) return TC_ENOMEM;
    for (size_t c = 0; c < 3 * (size_t)m->nt; c++) s->cv_src[c] = -1;
    for (int32_t i = 0; i < d->ncorner_values; i++) {
        int32_t e = d->corner_values_tri[i], c0[2];
        const double *z = d->corner_values + (size_t)i * (size_t)nk * (size_t)nc;
        if (check_elem(m, "corner_values", i, e, dg) != TC_OK) {
            rc = TC_EINVAL;
            continue;
        }
        if (!kept_elem(m, "corner_values", i, &e, dg)) continue;
        landing(m, e, 0, c0); /* every element's corner 0 lands on its own first triangle */
        if (s->cv_src[c0[0]] >= 0) {
            snprintf(path, sizeof path, "corner_values[%d].%s", (int)i, tc__elem_word(m));
            rc = tc_diags_add(dg, TC_SEV_ERROR, path, "%s %d already has corner values (corner_values[%d])",
                              tc__elem_word(m), (int)e, (int)s->cv_src[c0[0]]);
            continue;
        }
        snprintf(path, sizeof path, "corner_values[%d].values", (int)i);
        if (check_finite(z, (size_t)nk * (size_t)nc, path, dg) != TC_OK) {
            rc = TC_EINVAL;
            continue;
        }
        put_corner_values(m, d, s, i, e, z);
    }
    return rc;
}

static int alloc_gradients(struct tc_mesh *m) {
    if (m->given_grad) return TC_OK;
    size_t n = 3 * (size_t)m->nt * (size_t)m->nc * 2; /* zeroed on the threads: the pages fault in there */
    m->given_grad = tc__malloc(n, sizeof *m->given_grad);
    m->given_grad_has = tc__malloc(3 * (size_t)m->nt, sizeof *m->given_grad_has);
    if (!m->given_grad || !m->given_grad_has) return TC_ENOMEM;
    tc__parallel_zero(m->threads, m->given_grad, n * sizeof *m->given_grad);
    tc__parallel_zero(m->threads, m->given_grad_has, 3 * (size_t)m->nt * sizeof *m->given_grad_has);
    return TC_OK;
}

/* Converts a vertex's normals (one per channel) to gradients, g = -(nx, ny)/nz. */
static int normal_to_gradient(const double *n, int nc, int32_t v, double *g, tc_diags *dg) {
    char path[48];
    for (int ch = 0; ch < nc; ch++) {
        const double *nn = n + 3 * ch;
        if (nc > 1) snprintf(path, sizeof path, "normals[%d][%d]", (int)v, ch);
        else snprintf(path, sizeof path, "normals[%d]", (int)v);
        if (!(nn[2] > 0)) {
            return tc_diags_add(dg, TC_SEV_ERROR, path, "N.z = %g must be > 0 (a height field's normal points up)",
                                nn[2]);
        }
        g[2 * ch] = -nn[0] / nn[2];
        g[2 * ch + 1] = -nn[1] / nn[2];
        if (!isfinite(g[2 * ch]) || !isfinite(g[2 * ch + 1]))
            return tc_diags_add(dg, TC_SEV_ERROR, path, "normal is too close to horizontal (N.z = %g)", nn[2]);
    }
    return TC_OK;
}

/* Per-vertex gradients or normals of vertices [lo, hi), copied onto every
 * corner of the vertex (dg may be NULL: vertex_gradients). */
static int vertex_gradients_of(struct tc_mesh *m, const tc_mesh_desc *d, int32_t lo, int32_t hi, tc_diags *dg) {
    int nc = m->nc, rc = TC_OK;
    size_t stride = 2 * (size_t)nc;
    double g[2 * TC_MAX_CHANNELS];
    char path[48] = "";
    for (int32_t v = lo; v < hi; v++) {
        if (d->gradients) {
            if (d->gradients_mask && !d->gradients_mask[v]) continue;
            if (!all_finite(d->gradients + (size_t)v * stride, stride))
                snprintf(path, sizeof path, "gradients[%d]", (int)v);
            if (check_finite(d->gradients + (size_t)v * stride, stride, path, dg) != TC_OK) {
                rc = TC_EINVAL;
                continue;
            }
            memcpy(g, d->gradients + (size_t)v * stride, stride * sizeof *g);
        } else {
            if (d->normals_mask && !d->normals_mask[v]) continue;
            if (!all_finite(d->normals + (size_t)v * 3 * (size_t)nc, 3 * (size_t)nc))
                snprintf(path, sizeof path, "normals[%d]", (int)v);
            if (check_finite(d->normals + (size_t)v * 3 * (size_t)nc, 3 * (size_t)nc, path, dg) != TC_OK ||
                normal_to_gradient(d->normals + (size_t)v * 3 * (size_t)nc, nc, v, g, dg) != TC_OK) {
                rc = TC_EINVAL;
                continue;
            }
        }
        for (int32_t i = m->vstart[v]; i < m->vstart[v + 1]; i++) {
            int32_t c = m->vcorner[i];
            double *to = m->given_grad + (size_t)c * stride;
            for (size_t j = 0; j < stride; j++) to[j] = g[j];
            m->given_grad_has[c] = 1;
        }
    }
    return rc;
}

static void gradients_part(void *ctx, int32_t lo, int32_t hi, int part) {
    copy_pass *cp = ctx;
    cp->failed[part] = vertex_gradients_of(cp->m, cp->d, lo, hi, NULL) != TC_OK;
}

/* On threads; if a vertex failed, all again in order for the findings. */
static int vertex_gradients(struct tc_mesh *m, const tc_mesh_desc *d, tc_diags *dg) {
    copy_pass cp = {m, d, {0}};
    tc__parallel_for(m->threads, m->nv, 4096, gradients_part, &cp);
    for (int p = 0; p < tc__parallel_parts(m->threads, m->nv, 4096); p++)
        if (cp.failed[p]) return vertex_gradients_of(m, d, 0, m->nv, dg);
    return TC_OK;
}

/* Corner k of corner_gradients entry i onto the corners of element e. */
static int put_corner_gradient(struct tc_mesh *m, const tc_mesh_desc *d, int32_t i, int32_t e, int k, tc_diags *dg) {
    int nk = elem_corners(m);
    size_t stride = 2 * (size_t)m->nc;
    if (d->corner_gradients_mask && !d->corner_gradients_mask[tc__ix(i, nk, k)]) return TC_OK;
    const double *g = d->corner_gradients + tc__ix(i, nk, k) * stride;
    char path[64];
    snprintf(path, sizeof path, "corner_gradients[%d].gradients[%d]", (int)i, k);
    if (check_finite(g, stride, path, dg) != TC_OK) return TC_EINVAL;
    int32_t cs[2];
    for (int n = landing(m, e, k, cs), j = 0; j < n; j++) {
        memcpy(m->given_grad + (size_t)cs[j] * stride, g, stride * sizeof *g);
        m->given_grad_has[cs[j]] = 1;
    }
    return TC_OK;
}

static int corner_gradients(struct tc_mesh *m, const tc_mesh_desc *d, tc_diags *dg) {
    int rc = TC_OK;
    int32_t ne = elem_count(m);
    char path[64];
    int32_t *seen = d->ncorner_gradients ? tc__malloc((size_t)ne, sizeof *seen) : NULL;
    if (d->ncorner_gradients && !seen) return TC_ENOMEM;
    for (int32_t e = 0; seen && e < ne; e++) seen[e] = -1;
    for (int32_t i = 0; i < d->ncorner_gradients; i++) {
        int32_t e = d->corner_gradients_tri[i];
        if (check_elem(m, "corner_gradients", i, e, dg) != TC_OK) {
            rc = TC_EINVAL;
            continue;
        }
        if (seen[e] >= 0) {
            snprintf(path, sizeof path, "corner_gradients[%d].%s", (int)i, tc__elem_word(m));
            rc = tc_diags_add(dg, TC_SEV_ERROR, path, "%s %d already has corner gradients (corner_gradients[%d])",
                              tc__elem_word(m), (int)e, (int)seen[e]);
            continue;
        }
        seen[e] = i;
        if (!kept_elem(m, "corner_gradients", i, &e, dg)) continue;
        for (int k = 0; k < elem_corners(m); k++)
            if (put_corner_gradient(m, d, i, e, k, dg) != TC_OK) rc = TC_EINVAL;
    }
    tc__free(seen);
    return rc;
}

static int gradients(struct tc_mesh *m, const tc_mesh_desc *d, tc_diags *dg) {
    if (d->gradients && d->normals)
        return tc_diags_add(dg, TC_SEV_ERROR, "normals", "give either gradients or normals, not both");
    if (!d->gradients && !d->normals && d->ncorner_gradients == 0) return TC_OK;
    int rc = alloc_gradients(m);
    if (rc != TC_OK) return rc;
    if (d->gradients || d->normals) rc = vertex_gradients(m, d, dg);
    if (corner_gradients(m, d, dg) != TC_OK) rc = TC_EINVAL;
    return rc;
}

/* Stores midpoint sample i on edge side c (corner id of the edge). */
static int put_midpoint(struct tc_mesh *m, int32_t *src, size_t c, int32_t i, const double *z, const char *path,
                        tc_diags *dg) {
    if (src[c] >= 0)
        return tc_diags_add(dg, TC_SEV_ERROR, path, "this edge side already has a sample (midpoints[%d])", (int)src[c]);
    src[c] = i;
    m->mid_has[c] = 1;
    memcpy(m->mid + c * (size_t)m->nc, z, (size_t)m->nc * sizeof *z);
    return TC_OK;
}

/* The edge side (3t+k) of triangle t joining a and b, or -1. */
static int32_t side_in(const struct tc_mesh *m, int32_t t, int32_t a, int32_t b) {
    int ka = tc__corner_of(m, t, a), kb = tc__corner_of(m, t, b);
    if (ka < 0 || kb < 0) return -1;
    return 3 * t + (kb == (ka + 1) % 3 ? ka : kb);
}

/* A sample that names its side (element e): the edge side in each of e's
 * triangles that has the edge — one, or both halves of a quad for a sample on
 * its own diagonal (both sides of which are that quad). */
static int put_named(struct tc_mesh *m, int32_t *src, int32_t e, int32_t a, int32_t b, int32_t i, const double *z,
                     tc_diags *dg) {
    char path[64];
    int rc = TC_OK, found = 0;
    int32_t k = e, halves = e >= elem_count(m) ? 0 : m->nq ? 2 : 1; /* past the end: none */
    if (halves && !kept_elem(m, "midpoints", i, &k, dg)) return TC_OK;
    snprintf(path, sizeof path, "midpoints[%d]", (int)i);
    int32_t first = m->nq ? 2 * k : k;
    for (int32_t t = first; t < first + halves; t++) {
        int32_t c = side_in(m, t, a, b);
        if (c < 0) continue;
        found = 1;
        if (put_midpoint(m, src, (size_t)c, i, z, path, dg) != TC_OK) rc = TC_EINVAL;
    }
    if (found) return rc;
    snprintf(path, sizeof path, "midpoints[%d].%s", (int)i, tc__elem_word(m));
    return tc_diags_add(dg, TC_SEV_ERROR, path, "%s %d does not have edge [%d, %d]", tc__elem_word(m), (int)e, (int)a,
                        (int)b);
}

/* Sample i is on an edge only dropped triangles had: ignored, with a warning. */
static int dropped_edge(const struct tc_mesh *m, const tc_mesh_desc *d, int32_t i, int32_t a, int32_t b,
                        tc_diags *dg) {
    int32_t t = a == b ? -1 : tc__dropped_with_edge(m, d, a, b);
    if (t < 0) return 0;
    char path[64];
    snprintf(path, sizeof path, "midpoints[%d].edge", (int)i);
    tc_diags_add(dg, TC_SEV_WARNING, path,
                 "[%d, %d] is an edge only of triangles dropped as degenerate (triangles[%d]): sample ignored", (int)a,
                 (int)b, (int)t);
    return 1;
}

static int midpoint(struct tc_mesh *m, const tc_mesh_desc *d, int32_t i, int32_t *src, tc_diags *dg) {
    int32_t a = d->midpoint_edge[2 * (size_t)i], b = d->midpoint_edge[2 * (size_t)i + 1];
    int32_t t = d->midpoint_tri ? d->midpoint_tri[i] : -1;
    const double *z = d->midpoint_values + (size_t)i * (size_t)m->nc;
    char path[64];
    snprintf(path, sizeof path, "midpoints[%d].edge", (int)i);
    if (a < 0 || a >= m->nv || b < 0 || b >= m->nv)
        return tc_diags_add(dg, TC_SEV_ERROR, path, "vertex index out of range in [%d, %d] (%d vertices)", (int)a,
                            (int)b, (int)m->nv);
    int32_t c = a == b ? -1 : tc__find_edge(m, a, b);
    if (c < 0 && dropped_edge(m, d, i, a, b, dg)) return TC_OK;
    if (c < 0) return tc_diags_add(dg, TC_SEV_ERROR, path, "[%d, %d] is not an edge of the mesh", (int)a, (int)b);
    snprintf(path, sizeof path, "midpoints[%d].value", (int)i);
    if (check_finite(z, (size_t)m->nc, path, dg) != TC_OK) return TC_EINVAL;
    snprintf(path, sizeof path, "midpoints[%d]", (int)i);
    if (t < -1 && check_elem(m, "midpoints", i, t, dg) != TC_OK) return TC_EINVAL; /* past the end: no such edge */
    if (t >= 0) return put_named(m, src, t, a, b, i, z, dg);
    int rc = put_midpoint(m, src, (size_t)c, i, z, path, dg);
    if (rc == TC_OK && m->nbr[c] >= 0)
        rc = put_midpoint(m, src, 3 * (size_t)m->nbr[c] + (size_t)m->nbr_k[c], i, z, path, dg);
    return rc;
}

static int midpoints(struct tc_mesh *m, const tc_mesh_desc *d, scratch *s, tc_diags *dg) {
    if (d->nmidpoints == 0) return TC_OK;
    size_t nc = 3 * (size_t)m->nt;
    m->mid = tc__malloc(nc * (size_t)m->nc, sizeof *m->mid);
    m->mid_has = tc__malloc(nc, sizeof *m->mid_has);
    int32_t *src = s->mid_src = tc__malloc(nc, sizeof *src);
    if (!m->mid || !m->mid_has || !src) return TC_ENOMEM;
    tc__parallel_zero(m->threads, m->mid, nc * (size_t)m->nc * sizeof *m->mid);
    tc__parallel_zero(m->threads, m->mid_has, nc * sizeof *m->mid_has);
    int rc = TC_OK;
    for (size_t c = 0; c < nc; c++) src[c] = -1;
    for (int32_t i = 0; i < d->nmidpoints; i++)
        if (midpoint(m, d, i, src, dg) != TC_OK) rc = TC_EINVAL;
    return rc;
}

/* Per-vertex second derivatives (fxx, fxy, fyy) per channel, for the Hermite
 * twists; null entries leave a vertex without. */
static int hessians(struct tc_mesh *m, const tc_mesh_desc *d, tc_diags *dg) {
    if (!d->hessians) return TC_OK;
    size_t stride = 3 * (size_t)m->nc;
    m->hess = tc__calloc((size_t)m->nv * stride, sizeof *m->hess);
    m->hess_has = tc__calloc((size_t)m->nv, sizeof *m->hess_has);
    if (!m->hess || !m->hess_has) return TC_ENOMEM;
    int rc = TC_OK;
    for (int32_t v = 0; v < m->nv; v++) {
        if (d->hessians_mask && !d->hessians_mask[v]) continue;
        char path[48];
        snprintf(path, sizeof path, "hessians[%d]", (int)v);
        const double *h = d->hessians + (size_t)v * stride;
        if (check_finite(h, stride, path, dg) != TC_OK) {
            rc = TC_EINVAL;
            continue;
        }
        memcpy(m->hess + (size_t)v * stride, h, stride * sizeof *h);
        m->hess_has[v] = 1;
    }
    return rc;
}

int tc__samples_build(struct tc_mesh *m, const tc_mesh_desc *d, tc_diags *dg) {
    scratch s = {0};
    int rc = corner_values(m, d, &s, dg);
    if (rc == TC_OK) rc = gradients(m, d, dg);
    if (rc == TC_OK) rc = hessians(m, d, dg);
    if (rc == TC_OK) rc = midpoints(m, d, &s, dg);
    if (rc == TC_OK) rc = tc__values_agree(m, d->value_tolerance, s.cv_src, s.mid_src, dg);
    tc__free(s.cv_src);
    tc__free(s.mid_src);
    return rc;
}
