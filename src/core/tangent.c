/* tangent.c — where each corner's tangent plane comes from before wedges are
 * reconciled: given (gradient or normal), the paper's midpoint parabolas, or a
 * least-squares fit to samples inside the corner's wedge (never across a delimiter). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/fhypot.h"
#include "core/geom.h"
#include "core/internal.h"
#include "core/lsq.h"
#include "core/plane.h"
#include "core/tangent.h"

/* Paper §3.3: the parabola through z_v, the midpoint sample and z_p along edge
 * v -> p has slope 4 m - 3 z_v - z_p per edge length at v; the two edges of a
 * face at v give that face's plane. */
static void from_midpoints(const struct tc_mesh *m, const double *cz, int32_t c, double *g) {
    int32_t t = c / 3, k = c % 3, nc = m->nc;
    size_t cp = 3 * (size_t)t + (size_t)(k + 1) % 3, cq = 3 * (size_t)t + (size_t)(k + 2) % 3;
    const double *mvp = m->mid + (size_t)c * nc, *mqv = m->mid + cq * nc;
    double dp[2], dq[2];
    tc__sub(dp, tc__vxy(m, m->tri[cp]), tc__vxy(m, m->tri[c]));
    tc__sub(dq, tc__vxy(m, m->tri[cq]), tc__vxy(m, m->tri[c]));
    for (int ch = 0; ch < nc; ch++) {
        double zv = cz[(size_t)c * nc + ch];
        double sp = 4 * mvp[ch] - 3 * zv - cz[cp * nc + ch];
        double sq = 4 * mqv[ch] - 3 * zv - cz[cq * nc + ch];
        tc__solve2(dp, dq, sp, sq, g + 2 * ch);
    }
}

/* ---- least squares within a wedge ---- */

typedef struct {
    int n;
    int64_t key[TC_LSQ_MAXROWS]; /* vertex id, or -1 - edge id for a midpoint */
    double d[TC_LSQ_MAXROWS][2]; /* position relative to the wedge's vertex */
    const double *z[TC_LSQ_MAXROWS];
} samples;

static void add_sample(samples *s, int64_t key, const double d[2], const double *z) {
    for (int i = 0; i < s->n; i++)
        if (s->key[i] == key) return;
    if (s->n == TC_LSQ_MAXROWS) return;
    s->key[s->n] = key;
    s->d[s->n][0] = d[0];
    s->d[s->n][1] = d[1];
    s->z[s->n++] = z;
}

static void add_vertex(const struct tc_mesh *m, const double *cz, samples *s, int32_t v, int32_t c) {
    double d[2];
    tc__sub(d, tc__vxy(m, m->tri[c]), tc__vxy(m, v));
    add_sample(s, m->tri[c], d, cz + (size_t)c * m->nc);
}

static void add_midpoint(const struct tc_mesh *m, samples *s, int32_t v, int32_t e) {
    if (!m->mid_has || !m->mid_has[e]) return;
    int32_t t = e / 3, k = e % 3, other = m->nbr[e] >= 0 ? 3 * m->nbr[e] + m->nbr_k[e] : e;
    const double *a = tc__vxy(m, m->tri[e]), *b = tc__vxy(m, m->tri[3 * t + (k + 1) % 3]), *p = tc__vxy(m, v);
    double d[2] = {0.5 * ((a[0] - p[0]) + (b[0] - p[0])), 0.5 * ((a[1] - p[1]) + (b[1] - p[1]))};
    add_sample(s, -1 - (int64_t)(e < other ? e : other), d, m->mid + (size_t)e * m->nc);
}

/* The 1-ring of the wedge (vertices and midpoint samples of its faces); if
 * that is too few for a quadratic, the faces across the wedge's outer C1 edges. */
static void gather(const struct tc_mesh *m, const tc_wedge_set *ws, const tc_wedge *w, const double *cz,
                   samples *s) {
    for (int32_t i = 0; i < w->count; i++) {
        int32_t c = ws->corners[w->first + i], t = c / 3, k = c % 3;
        add_vertex(m, cz, s, w->v, 3 * t + (k + 1) % 3);
        add_vertex(m, cz, s, w->v, 3 * t + (k + 2) % 3);
        for (int j = 0; j < 3; j++) add_midpoint(m, s, w->v, 3 * t + j);
    }
    if (s->n >= 6) return;
    for (int32_t i = 0; i < w->count; i++) {
        int32_t c = ws->corners[w->first + i], t = c / 3, k = c % 3, e = 3 * t + (k + 1) % 3;
        if (m->nbr[e] < 0 || tc__eff_flag(m, ws->honor_flags, e) != TC_C1) continue;
        int32_t t2 = m->nbr[e], k2 = m->nbr_k[e];
        add_vertex(m, cz, s, w->v, 3 * t2 + (k2 + 2) % 3);
    }
}

/* Weighted fit of z - z_v = g.d (+ 1/2 d'Hd when there are enough samples),
 * in coordinates scaled by the farthest sample and rows weighted by 1/|d| so
 * near samples count more; exact for quadratics when the quadratic fit runs. */
static void fit(const samples *s, const double *zv, int nc, double *g) {
    double h = 0;
    for (int i = 0; i < s->n; i++) h = fmax(h, tc__hypot(s->d[i][0], s->d[i][1]));
    for (int cols = s->n >= 6 ? 5 : 2; cols >= 2; cols -= 3) {
        double A[TC_LSQ_MAXROWS][TC_LSQ_MAXCOLS], B[TC_LSQ_MAXROWS][TC_LSQ_MAXRHS], X[TC_LSQ_MAXCOLS][TC_LSQ_MAXRHS];
        for (int i = 0; i < s->n; i++) {
            double x = s->d[i][0] / h, y = s->d[i][1] / h, w = 1.0 / tc__hypot(x, y);
            double row[5] = {x, y, 0.5 * x * x, x * y, 0.5 * y * y};
            for (int j = 0; j < cols; j++) A[i][j] = row[j] * w;
            for (int ch = 0; ch < nc; ch++) B[i][ch] = (s->z[i][ch] - zv[ch]) * w;
        }
        if (tc__lsq_solve(A, s->n, cols, B, nc, 1e-9, X) == 0) {
            for (int ch = 0; ch < nc; ch++) {
                g[2 * ch] = X[0][ch] / h;
                g[2 * ch + 1] = X[1][ch] / h;
            }
            return;
        }
    }
    memset(g, 0, 2 * (size_t)nc * sizeof *g); /* unreachable: a face's two edges are independent */
}

static void estimate(const struct tc_mesh *m, const tc_wedge_set *ws, const tc_wedge *w, const double *cz,
                     double *g) {
    samples s;
    s.n = 0;
    gather(m, ws, w, cz, &s);
    fit(&s, cz + (size_t)ws->corners[w->first] * m->nc, m->nc, g);
}

/* ---- per corner ---- */

enum { SRC_GIVEN, SRC_MIDPOINTS, SRC_ESTIMATE };

static int has_midpoints(const struct tc_mesh *m, int32_t c) {
    int32_t t = c / 3, k = c % 3;
    return m->mid_has && m->mid_has[c] && m->mid_has[3 * t + (k + 2) % 3];
}

static int source_of(const struct tc_mesh *m, int32_t c, tc_tangents mode, tc_diags *dg) {
    int given = m->cg_has && m->cg_has[c];
    if (mode == TC_TANGENTS_ESTIMATE) return SRC_ESTIMATE;
    if (given && mode != TC_TANGENTS_MIDPOINTS) return SRC_GIVEN;
    if (mode != TC_TANGENTS_GIVEN && has_midpoints(m, c)) return SRC_MIDPOINTS;
    if (mode == TC_TANGENTS_AUTO) return SRC_ESTIMATE;
    char path[48];
    int32_t t = c / 3, k = c % 3;
    if (mode == TC_TANGENTS_GIVEN) {
        /* Corners a and c of a quad are in both its halves: report from the first. */
        if (m->nq && t % 2 == 1 && k < 2) return -1;
        tc__elem_path(m, t, path, sizeof path);
        tc_diags_add(dg, TC_SEV_ERROR, path, "corner %d (vertex %d) has no gradient or normal (tangents: \"given\")",
                     tc__elem_corner(m, t, k), (int)m->tri[c]);
    } else if (!(m->mid_has && m->mid_has[c]) && (m->nbr[c] < 0 || t < m->nbr[c])) {
        /* Report edge k of t (the edge leaving corner c) once per mesh edge;
         * a missing edge (k+2) is reported from the corner it leaves. */
        char diag[48] = "";
        if (tc__is_diagonal(m, c)) snprintf(diag, sizeof diag, " (the diagonal of quads[%d])", (int)(t / 2));
        tc_diags_add(dg, TC_SEV_ERROR, "midpoints", "edge [%d, %d]%s has no midpoint sample (tangents: \"midpoints\")",
                     (int)m->tri[c], (int)m->tri[3 * t + (k + 1) % 3], diag);
    }
    return -1;
}

/* ---- bounding estimated planes ---- */

/* An estimated plane may move an edge ordinate (z_v + g.e/3) at most this many
 * times the spread of the data in its wedge away from z_v. Exact planes of
 * smooth data stay far inside it (|g.e| is about the change of z along e); a
 * plane from three nearly collinear samples on a sliver does not. */
#define PLANE_BOUND 4.0

typedef struct {
    int32_t clamped, worst_vertex;
    double worst_factor; /* the largest slope reduction applied */
} clamp_stats;

/* Scales the estimated plane g of corner c down, channel by channel, so that no
 * edge of its wedge's faces sees |g.e| > PLANE_BOUND * (spread of the values
 * of the wedge's corners). Returns the factor applied (1: untouched). */
static double bound_plane(const struct tc_mesh *m, const tc_wedge_set *ws, const tc_wedge *w, const double *cz,
                          double *g) {
    int nc = m->nc;
    double worst = 1;
    for (int ch = 0; ch < nc; ch++) {
        double lo = INFINITY, hi = -INFINITY, rise = 0, *gc = g + 2 * ch;
        for (int32_t i = 0; i < w->count; i++) {
            int32_t c = ws->corners[w->first + i], t = c / 3;
            for (int k = 0; k < 3; k++) {
                double z = cz[(3 * (size_t)t + (size_t)k) * nc + ch], e[2];
                lo = fmin(lo, z), hi = fmax(hi, z);
                tc__sub(e, tc__vxy(m, m->tri[3 * (size_t)t + k]), tc__vxy(m, w->v));
                rise = fmax(rise, fabs(tc__dot(gc, e)));
            }
        }
        double limit = PLANE_BOUND * (hi - lo);
        if (rise > limit) { /* limit may be 0: flat data, flat plane */
            double f = limit > 0 ? limit / rise : 0;
            gc[0] *= f, gc[1] *= f;
            worst = fmin(worst, f);
        }
    }
    return worst;
}

static void note_clamp(clamp_stats *cs, double f, int32_t v) {
    if (f >= 1) return;
    cs->clamped++;
    if (cs->clamped == 1 || f < cs->worst_factor) cs->worst_factor = f, cs->worst_vertex = v;
}

/* One warning for all the planes bounded, naming the worst. */
static void warn_clamps(const clamp_stats *cs, tc_diags *dg) {
    if (!cs->clamped) return;
    char path[48];
    snprintf(path, sizeof path, "vertices[%d]", (int)cs->worst_vertex);
    tc_diags_add(dg, TC_SEV_WARNING, path,
                 "%d estimated tangent planes were too steep for their data and were scaled down; the most, at "
                 "vertex %d, to %.3g of its slope (ill-conditioned samples, e.g. slivers)",
                 (int)cs->clamped, (int)cs->worst_vertex, cs->worst_factor);
}

int tc__corner_inputs(const struct tc_mesh *m, const tc_wedge_set *ws, const double *cz, tc_tangents mode,
                      double *in, tc_diags *dg) {
    size_t stride = 2 * (size_t)m->nc;
    int st = TC_OK;
    clamp_stats cs = {0, -1, 1};
    for (int32_t w = 0; w < ws->nw; w++) {
        const tc_wedge *wd = &ws->w[w];
        double est[2 * TC_MAX_CHANNELS];
        int estimated = 0;
        for (int32_t i = 0; i < wd->count; i++) {
            int32_t c = ws->corners[wd->first + i];
            double *g = in + (size_t)c * stride;
            switch (source_of(m, c, mode, dg)) {
            case SRC_GIVEN: memcpy(g, m->cg + (size_t)c * stride, stride * sizeof *g); break;
            case SRC_MIDPOINTS:
                from_midpoints(m, cz, c, g);
                note_clamp(&cs, bound_plane(m, ws, wd, cz, g), wd->v);
                break;
            case SRC_ESTIMATE: /* one fit per wedge, shared by its corners */
                if (!estimated++) {
                    estimate(m, ws, wd, cz, est);
                    note_clamp(&cs, bound_plane(m, ws, wd, cz, est), wd->v);
                }
                memcpy(g, est, stride * sizeof *g);
                break;
            default: st = TC_EINVAL;
            }
        }
    }
    if (st == TC_OK) warn_clamps(&cs, dg);
    return st;
}
