/* agree.c — values that must agree across C0/C1 edges (corner values at a vertex):
 * checked within value_tolerance, then made equal; per-side midpoints within it too. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/alloc.h"
#include "core/mesh_build.h"
#include "core/minmax.h"
#include "core/parallel.h"

/* A tolerance below this is rounding of the front-end's own arithmetic (and
 * what a zero-filled description gets: the strict check of old). */
#define TOL_FLOOR 1e-12

typedef struct {
    struct tc_mesh *m;
    const int32_t *cv_src;  /* [3nt] corner_values entry of each corner, or -1; or NULL */
    const int32_t *mid_src; /* [3nt] midpoints entry of each edge side, or -1; or NULL */
    double tol;             /* relative to scale[] */
    double scale[TC_MAX_CHANNELS];
    int32_t nvert, nedge;   /* vertices and edges whose values were averaged */
    double worst_v, worst_e;/* the largest relative difference averaged at each */
    int32_t at_v, at_e;     /* where: a vertex, a midpoints entry */
} agree;

/* The channel's scale: the largest |value| of it over the mesh's corner
 * values and midpoint samples; found in parts (a maximum: the same for any
 * split). */
typedef struct {
    const struct tc_mesh *m;
    double scale[TC_PARALLEL_MAX][TC_MAX_CHANNELS];
} scale_pass;

static void scales_part(void *ctx, int32_t lo, int32_t hi, int part) {
    scale_pass *sp = ctx;
    const struct tc_mesh *m = sp->m;
    double *scale = sp->scale[part];
    for (int ch = 0; ch < m->nc; ch++) scale[ch] = 0;
    for (size_t c = (size_t)lo; c < (size_t)hi; c++)
        for (int ch = 0; ch < m->nc; ch++) {
            scale[ch] = tc__fmax(scale[ch], fabs(m->cz[c * (size_t)m->nc + (size_t)ch]));
            if (m->mid_has && m->mid_has[c]) scale[ch] = tc__fmax(scale[ch], fabs(m->mid[c * (size_t)m->nc + (size_t)ch]));
        }
}

static int channel_scales(agree *a) {
    const struct tc_mesh *m = a->m;
    scale_pass *sp = malloc(sizeof *sp); /* 8 KiB: off the stack */
    if (!sp) return TC_ENOMEM;
    sp->m = m;
    tc__parallel_for(m->threads, 3 * m->nt, 16384, scales_part, sp);
    for (int ch = 0; ch < m->nc; ch++) a->scale[ch] = 0;
    for (int p = 0; p < tc__parallel_parts(m->threads, 3 * m->nt, 16384); p++)
        for (int ch = 0; ch < m->nc; ch++) a->scale[ch] = tc__fmax(a->scale[ch], sp->scale[p][ch]);
    tc__free(sp);
    return TC_OK;
}

static double relative(const agree *a, int ch, double diff) { return a->scale[ch] > 0 ? diff / a->scale[ch] : 0; }

/* Corner values at both ends of the C0/C1 edge side c agree within the
 * tolerance; the error names the edge, the vertex and both values. */
static int check_edge(const agree *a, size_t c, tc_diags *dg) {
    const struct tc_mesh *m = a->m;
    int32_t t = (int32_t)(c / 3), k = (int32_t)(c % 3), t2 = m->nbr[c];
    for (int e = 0; e < 2; e++) {
        size_t ca = 3 * (size_t)t + (size_t)(k + e) % 3;
        int32_t v = m->tri[ca];
        size_t cb = 3 * (size_t)t2 + (size_t)tc__corner_of(m, t2, v);
        for (int ch = 0; ch < m->nc; ch++) {
            double za = m->cz[ca * (size_t)m->nc + (size_t)ch], zb = m->cz[cb * (size_t)m->nc + (size_t)ch];
            if (fabs(za - zb) <= a->tol * a->scale[ch]) continue;
            char path[48];
            const char *w = tc__elem_word(m);
            int32_t src = a->cv_src ? (a->cv_src[cb] >= 0 ? a->cv_src[cb] : a->cv_src[ca]) : -1;
            if (src >= 0) snprintf(path, sizeof path, "corner_values[%d]", (int)src);
            else tc__elem_path(m, t2, path, sizeof path);
            return tc_diags_add(dg, TC_SEV_ERROR, path,
                                "values disagree across %s edge [%d, %d] at vertex %d: %.17g (%s %d) vs %.17g "
                                "(%s %d), %.2g of the channel's scale (value_tolerance %g); flag the edge c-1 or "
                                "give equal values",
                                m->flag[c] == TC_C0 ? "the C0" : "the C1", (int)m->tri[c],
                                (int)m->tri[3 * (size_t)t + (size_t)(k + 1) % 3], (int)v, za, w,
                                (int)tc__elem_index(m, t), zb, w, (int)tc__elem_index(m, t2),
                                relative(a, ch, fabs(za - zb)), a->tol);
        }
    }
    return TC_OK;
}

/* Edge side c is interior and not C-1: its two sides must agree. Each edge
 * is visited once, from its lower-numbered triangle. */
static int joins(const struct tc_mesh *m, size_t c) {
    return m->nbr[c] > (int32_t)(c / 3) && m->flag[c] != TC_CM1;
}

static int check_edges(const agree *a, tc_diags *dg) {
    int rc = TC_OK;
    for (size_t c = 0; c < 3 * (size_t)a->m->nt; c++)
        if (joins(a->m, c) && check_edge(a, c, dg) != TC_OK) rc = TC_EINVAL;
    return rc;
}

/* ---- corners joined through C0/C1 edges: union-find over corner ids ---- */

static int32_t root(int32_t *up, int32_t c) {
    while (up[c] != c) c = up[c] = up[up[c]];
    return c;
}

static void unite(int32_t *up, int32_t a, int32_t b) {
    a = root(up, a), b = root(up, b);
    if (a != b) up[a > b ? a : b] = a < b ? a : b; /* the lowest corner is the root */
}

/* up[c]: the corners of one vertex joined across C0/C1 edges share a root. */
static void group_corners(const struct tc_mesh *m, int32_t *up) {
    for (int32_t c = 0; c < 3 * m->nt; c++) up[c] = c;
    for (size_t c = 0; c < 3 * (size_t)m->nt; c++) {
        if (!joins(m, c)) continue;
        int32_t t = (int32_t)(c / 3), k = (int32_t)(c % 3), t2 = m->nbr[c];
        for (int e = 0; e < 2; e++) {
            int32_t ca = 3 * t + (k + e) % 3;
            unite(up, ca, 3 * t2 + tc__corner_of(m, t2, m->tri[ca]));
        }
    }
}

/* Replaces each group's values, channel by channel, by their mean where they
 * differ (lo + mean offset: no overflow near the double range; equal values
 * stay bit for bit). up[c] is c's root, the lowest corner of its group, so a
 * group is first met at its root; lo/hi/sum ([3nt][nc]) and n are kept there.
 * seen[nv] counts each vertex once. */
static void average_groups(agree *a, const int32_t *up, double *lo, double *hi, double *sum, int32_t *n,
                           uint8_t *seen) {
    struct tc_mesh *m = a->m;
    size_t nc = (size_t)m->nc, ncorner = 3 * (size_t)m->nt;
    for (size_t c = 0; c < ncorner; c++) {
        size_t r = (size_t)up[c];
        if (r == c) n[r] = 0;
        for (size_t ch = 0; ch < nc; ch++) {
            double z = m->cz[c * nc + ch];
            if (r == c) lo[r * nc + ch] = hi[r * nc + ch] = z, sum[r * nc + ch] = 0;
            lo[r * nc + ch] = tc__fmin(lo[r * nc + ch], z), hi[r * nc + ch] = tc__fmax(hi[r * nc + ch], z);
        }
        n[r]++;
    }
    for (size_t c = 0; c < ncorner; c++) { /* sums of offsets from the group's lowest value */
        size_t r = (size_t)up[c];
        for (size_t ch = 0; ch < nc; ch++) sum[r * nc + ch] += m->cz[c * nc + ch] - lo[r * nc + ch];
    }
    for (size_t c = 0; c < ncorner; c++) {
        size_t r = (size_t)up[c];
        int differ = 0;
        for (size_t ch = 0; ch < nc; ch++) {
            double spread = hi[r * nc + ch] - lo[r * nc + ch];
            if (spread == 0) continue;
            differ = 1;
            m->cz[c * nc + ch] = lo[r * nc + ch] + sum[r * nc + ch] / n[r];
            if (c == r && relative(a, (int)ch, spread) > a->worst_v)
                a->worst_v = relative(a, (int)ch, spread), a->at_v = m->tri[c];
        }
        if (differ && !seen[m->tri[c]]) seen[m->tri[c]] = 1, a->nvert++;
    }
}

static int average_corners(agree *a) {
    struct tc_mesh *m = a->m;
    size_t n = 3 * (size_t)m->nt;
    int32_t *up = tc__malloc(n, sizeof *up), *cnt = tc__malloc(n, sizeof *cnt);
    double *lo = tc__malloc(n * (size_t)m->nc, sizeof *lo), *hi = tc__malloc(n * (size_t)m->nc, sizeof *hi);
    double *sum = tc__malloc(n * (size_t)m->nc, sizeof *sum);
    uint8_t *seen = tc__calloc((size_t)m->nv, sizeof *seen);
    int rc = up && cnt && lo && hi && sum && seen ? TC_OK : TC_ENOMEM;
    if (rc == TC_OK) {
        group_corners(m, up);
        for (size_t c = 0; c < n; c++) up[c] = root(up, (int32_t)c); /* flat: up[c] is the root */
        average_groups(a, up, lo, hi, sum, cnt, seen);
    }
    tc__free(up), tc__free(cnt), tc__free(lo), tc__free(hi), tc__free(sum), tc__free(seen);
    return rc;
}

/* ---- midpoint samples given for both sides of a C0/C1 edge ---- */

/* The validator lets the two sides' samples of one edge differ (a jump in
 * the samples is the front-end's to make), so only differences within the
 * tolerance — printing noise — are averaged away; larger ones stay as given. */
static void midpoints_agree(agree *a) {
    struct tc_mesh *m = a->m;
    int nc = m->nc;
    for (size_t c = 0; m->mid_has && c < 3 * (size_t)m->nt; c++) {
        size_t c2 = 3 * (size_t)m->nbr[c] + (size_t)m->nbr_k[c];
        if (!joins(m, c) || !m->mid_has[c] || !m->mid_has[c2]) continue;
        double *za = m->mid + c * (size_t)nc, *zb = m->mid + c2 * (size_t)nc, worst = 0;
        for (int ch = 0; ch < nc; ch++) worst = tc__fmax(worst, relative(a, ch, fabs(za[ch] - zb[ch])));
        if (worst == 0 || worst > a->tol) continue;
        for (int ch = 0; ch < nc; ch++) za[ch] = zb[ch] = za[ch] + (zb[ch] - za[ch]) / 2;
        a->nedge++;
        if (worst > a->worst_e) a->worst_e = worst, a->at_e = a->mid_src ? a->mid_src[c2] : -1;
    }
}

static void warn_averaged(const agree *a, tc_diags *dg) {
    char path[48];
    if (a->nvert) {
        snprintf(path, sizeof path, "vertices[%d]", (int)a->at_v);
        tc_diags_add(dg, TC_SEV_WARNING, path,
                     "corner values that must agree across C0/C1 edges differed at %d vertices, by up to %.2g of the "
                     "channel's scale (at vertex %d; value_tolerance %g): each replaced by their mean",
                     (int)a->nvert, a->worst_v, (int)a->at_v, a->tol);
    }
    if (a->nedge) {
        snprintf(path, sizeof path, "midpoints[%d]", (int)a->at_e);
        tc_diags_add(dg, TC_SEV_WARNING, path,
                     "midpoint samples given for both sides of %d C0/C1 edges differed, by up to %.2g of the "
                     "channel's scale (value_tolerance %g): each pair replaced by its mean",
                     (int)a->nedge, a->worst_e, a->tol);
    }
}

int tc__values_agree(struct tc_mesh *m, double tolerance, const int32_t *cv_src, const int32_t *mid_src,
                     tc_diags *dg) {
    agree a = {m, cv_src, mid_src, tc__fmax(tolerance, TOL_FLOOR), {0}, 0, 0, 0, 0, -1, -1};
    int rc = channel_scales(&a);
    if (rc != TC_OK) return rc;
    if (m->ncorner_overrides) { /* else every corner holds its vertex's value */
        rc = check_edges(&a, dg);
        if (rc == TC_OK) rc = average_corners(&a);
    }
    if (rc == TC_OK) midpoints_agree(&a);
    if (rc == TC_OK) warn_averaged(&a, dg);
    return rc;
}
