/* tangent.c — where each corner's tangent plane comes from before wedges are
 * reconciled: given (gradient or normal), the paper's midpoint parabolas, or a
 * least-squares fit to samples around the corner's wedge (tanfit.c, never across a delimiter). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/fhypot.h"
#include "core/geom.h"
#include "core/internal.h"
#include "core/plane.h"
#include "core/tanfit.h"
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

/* The estimate of wedge w (tanfit.c), with the fit's work space made on first use. */
static int estimate(const struct tc_mesh *m, const tc_wedge_set *ws, const tc_wedge *w, const double *cz,
                    tc_fit_space *fs, double *g) {
    if (!fs->tmark && tc__fit_space_init(m, fs) != TC_OK) return TC_ENOMEM;
    tc__fit_wedge(m, ws, w, cz, fs, g);
    return TC_OK;
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
    tc_fit_space fs = {0};
    for (int32_t w = 0; w < ws->nw && st != TC_ENOMEM; w++) {
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
                    if (estimate(m, ws, wd, cz, &fs, est) != TC_OK) {
                        st = TC_ENOMEM;
                        break;
                    }
                    note_clamp(&cs, bound_plane(m, ws, wd, cz, est), wd->v);
                }
                memcpy(g, est, stride * sizeof *g);
                break;
            default: st = TC_EINVAL;
            }
            if (st == TC_ENOMEM) break;
        }
    }
    tc__fit_space_free(&fs);
    if (st == TC_OK) warn_clamps(&cs, dg);
    return st;
}
