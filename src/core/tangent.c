/* tangent.c — where each corner's tangent plane comes from before wedges are
 * reconciled: given (gradient or normal), the paper's midpoint parabolas, or a
 * least-squares fit to samples around the corner's wedge (tanfit.c, never across a delimiter). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/alloc.h"
#include "core/deadline.h"
#include "core/fhypot.h"
#include "core/geom.h"
#include "core/mesh.h"
#include "core/minmax.h"
#include "core/parallel.h"
#include "core/plane.h"
#include "core/range.h"
#include "core/tanfit.h"
#include "core/tangent.h"

/* Paper §3.3: the parabola through z_v, the midpoint sample and z_p along edge
 * v -> p has slope 4 m - 3 z_v - z_p per edge length at v; the two edges of a
 * face at v give that face's plane. */
static void from_midpoints(const struct tc_mesh *m, const double *cz, int32_t c, double *g) {
    int32_t t = c / 3, k = c % 3, nc = m->nc;
    size_t cp = 3 * (size_t)t + (size_t)(k + 1) % 3, cq = 3 * (size_t)t + (size_t)(k + 2) % 3;
    const double *mvp = m->mid + (size_t)c * (size_t)nc, *mqv = m->mid + cq * (size_t)nc;
    double dp[2], dq[2];
    tc__sub(dp, tc__vxy(m, m->tri[cp]), tc__vxy(m, m->tri[c]));
    tc__sub(dq, tc__vxy(m, m->tri[cq]), tc__vxy(m, m->tri[c]));
    for (int ch = 0; ch < nc; ch++) {
        double zv = cz[tc__ix(c, nc, ch)];
        double sp = 4 * mvp[ch] - 3 * zv - cz[cp * (size_t)nc + (size_t)ch];
        double sq = 4 * mqv[ch] - 3 * zv - cz[cq * (size_t)nc + (size_t)ch];
        tc__solve2(dp, dq, sp, sq, g + 2 * ch);
    }
}

/* ---- per corner ---- */

enum { SRC_GIVEN, SRC_MIDPOINTS, SRC_ESTIMATE };

static int has_midpoints(const struct tc_mesh *m, int32_t c) {
    int32_t t = c / 3, k = c % 3;
    return m->mid_has && m->mid_has[c] && m->mid_has[3 * t + (k + 2) % 3];
}

static int source_of(const struct tc_mesh *m, int32_t c, tc_tangents mode, tc_diags *dg) {
    int given = m->given_grad_has && m->given_grad_has[c];
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

/* ---- bounding planes ---- */

/* A plane from samples (estimated, or the midpoint parabolas) may move an edge
 * ordinate (z_v + g.e/3) at most this many times the spread of the data in its
 * wedge away from z_v. Exact planes of smooth data stay far inside it (|g.e| is
 * about the change of z along e); a plane from three nearly collinear samples
 * on a sliver does not. */
#define PLANE_BOUND 4.0

/* Data flat to within this fraction of its channel's scale (largest |value|)
 * carries no slope: one unit in the sixth significant digit of a value is at
 * most 1e-5 of it, the printing noise real front-ends send (issue 12), and far
 * below what a display shows (1/255 = 3.9e-3). Bounding such a wedge's plane,
 * to 0 when its values are equal, is what the data says, not news. */
#define FLAT_NOISE 1e-5

/* A bounded plane is reported when it moves some edge ordinate by more than
 * this fraction of its channel's range: a quarter of an 8-bit grey level at
 * full range, the least change a picture could show. */
#define CLAMP_MATERIAL 1e-3

/* How many bounded planes a warning lists by vertex. */
#define CLAMP_LIST 5

typedef struct {
    double scale[TC_MAX_CHANNELS]; /* largest |corner value| */
    double range[TC_MAX_CHANNELS]; /* largest - smallest corner value */
} chan_stats;

static void channel_stats(const struct tc_mesh *m, const tc__wedge_set *ws, const double *cz, chan_stats *cs) {
    double lo[TC_MAX_CHANNELS], hi[TC_MAX_CHANNELS];
    tc__channel_range(m, cz, ws->threads, lo, hi, cs->scale);
    for (int ch = 0; ch < m->nc; ch++) cs->range[ch] = m->nt ? hi[ch] - lo[ch] : 0;
}

/* What bounding did to one plane, over the channels where it mattered. */
typedef struct {
    double factor; /* the smallest slope factor applied (1: untouched) */
    double moved;  /* the largest edge-ordinate change over the channel's range */
} bound_effect;

/* Scales plane g of wedge w down, channel by channel, so that no edge of its
 * faces sees |g.e| > PLANE_BOUND * (spread of the wedge's corner values). A
 * channel counts in the effect only where its wedge is not flat to the noise
 * and the change is material (CLAMP_MATERIAL); else the effect stays {1, 0}. */
static bound_effect bound_plane(const struct tc_mesh *m, const tc__wedge_set *ws, const tc__wedge *w,
                                const double *cz, const chan_stats *cs, double *g) {
    int nc = m->nc;
    bound_effect fx = {1, 0};
    for (int ch = 0; ch < nc; ch++) {
        double lo = INFINITY, hi = -INFINITY, rise = 0, *gc = g + 2 * ch;
        for (int32_t i = 0; i < w->count; i++) {
            int32_t c = ws->corners[w->first + i], t = c / 3;
            for (int k = 0; k < 3; k++) {
                double z = cz[tc__ix(3 * t + k, nc, ch)], e[2];
                lo = tc__fmin(lo, z), hi = tc__fmax(hi, z);
                tc__sub(e, tc__vxy(m, m->tri[3 * (size_t)t + (size_t)k]), tc__vxy(m, w->v));
                rise = tc__fmax(rise, fabs(tc__dot(gc, e)));
            }
        }
        double limit = PLANE_BOUND * (hi - lo);
        if (!(rise > limit)) continue;
        double f = limit > 0 ? limit / rise : 0; /* limit 0: flat data, flat plane */
        gc[0] *= f, gc[1] *= f;
        double moved = (1 - f) * rise / 3; /* the most an edge ordinate z_v + g.e/3 moved */
        if (hi - lo <= FLAT_NOISE * cs->scale[ch] || !(moved > CLAMP_MATERIAL * cs->range[ch])) continue;
        fx.factor = tc__fmin(fx.factor, f);
        fx.moved = tc__fmax(fx.moved, moved / cs->range[ch]);
    }
    return fx;
}

/* The material bounds of one reconstruction: how many of each source, the
 * first few (by vertex) and the largest. */
typedef struct {
    int32_t v;
    bound_effect fx;
    int estimated; /* else from midpoint samples */
} clamp_entry;

typedef struct {
    int32_t count[2]; /* [0] from midpoint samples, [1] estimated */
    int nlist;
    clamp_entry list[CLAMP_LIST], worst;
} clamp_report;

static void note_clamp(clamp_report *cr, bound_effect fx, int32_t v, int estimated) {
    if (!(fx.moved > 0)) return;
    clamp_entry e = {v, fx, estimated};
    if (cr->count[0] + cr->count[1] == 0 || fx.moved > cr->worst.fx.moved) cr->worst = e;
    cr->count[estimated != 0]++;
    if (cr->nlist < CLAMP_LIST && (cr->nlist == 0 || cr->list[cr->nlist - 1].v != v)) cr->list[cr->nlist++] = e;
}

/* One warning per listed vertex (its path names it; what moved, why, what to
 * send instead), and one more when there were more than the list holds. */
static void warn_clamps(const clamp_report *cr, tc_diags *dg) {
    char path[48];
    for (int i = 0; i < cr->nlist; i++) {
        const clamp_entry *e = &cr->list[i];
        snprintf(path, sizeof path, "vertices[%d]", (int)e->v);
        if (e->estimated)
            tc_diags_add(dg, TC_SEV_WARNING, path,
                         "estimated tangent plane too steep for its wedge's data: scaled to %.3g of its slope, edge "
                         "ordinates moved %.3g of the channel's range (a sliver, or a kink no flag marks?): flag it, "
                         "or send gradients",
                         e->fx.factor, e->fx.moved);
        else
            tc_diags_add(dg, TC_SEV_WARNING, path,
                         "tangent plane from midpoint samples too steep for its wedge's data: scaled to %.3g of its "
                         "slope, edge ordinates moved %.3g of the channel's range (a sliver's sharp corner?): send "
                         "gradients",
                         e->fx.factor, e->fx.moved);
    }
    int32_t total = cr->count[0] + cr->count[1];
    if (total <= cr->nlist) return;
    snprintf(path, sizeof path, "vertices[%d]", (int)cr->worst.v);
    tc_diags_add(dg, TC_SEV_WARNING, path,
                 "%d tangent planes were scaled down in all (%d estimated, %d from midpoint samples); warnings name the "
                 "first %d; the largest change, %.3g of the channel's range, is at vertex %d",
                 (int)total, (int)cr->count[1], (int)cr->count[0], cr->nlist, cr->worst.fx.moved, (int)cr->worst.v);
}

/* The estimate of wedge w, with the fit's work space made on first use. */
static int estimate(const struct tc_mesh *m, const tc__wedge_set *ws, const tc__wedge *w, const double *cz,
                    tc__fit_space *fs, double *g) {
    if (!fs->tmark && tc__fit_space_init(m, fs) != TC_OK) return TC_ENOMEM;
    tc__fit_wedge(m, ws, w, cz, fs, g);
    return TC_OK;
}

/* One part of the vertices: the input planes of their wedges' corners, with
 * its own clamp report, fit space and status (dg NULL: the findings are made
 * again serially if any part failed). */
typedef struct {
    const struct tc_mesh *m;
    const tc__wedge_set *ws;
    const double *cz;
    tc_tangents mode;
    double *inputs;
    const chan_stats *cs;
    clamp_report cr[TC_PARALLEL_MAX];
    int rc[TC_PARALLEL_MAX];
} inputs_pass;

/* Wedges fitted between two looks at the deadline: a fit costs ~10 us (least squares over
 * the wedge's faces), the look one clock read. */
#define DEADLINE_EVERY 256

/* The input planes of wedges [w0, w1): TC_OK, TC_EINVAL (a corner's source), TC_ENOMEM, or
 * TC_ETIMEOUT past ws->deadline_ms (the planes then partly written). */
static int wedge_inputs(const inputs_pass *ip, int32_t w0, int32_t w1, clamp_report *cr, tc_diags *dg) {
    const struct tc_mesh *m = ip->m;
    const tc__wedge_set *ws = ip->ws;
    size_t stride = 2 * (size_t)m->nc;
    int rc = TC_OK;
    tc__fit_space fs = {0};
    for (int32_t w = w0; w < w1 && rc != TC_ENOMEM; w++) {
        if ((w - w0) % DEADLINE_EVERY == DEADLINE_EVERY - 1 && tc__past(ws->deadline_ms)) {
            rc = TC_ETIMEOUT;
            break;
        }
        const tc__wedge *wd = &ws->w[w];
        double est[2 * TC_MAX_CHANNELS];
        int estimated = 0;
        for (int32_t i = 0; i < wd->count; i++) {
            int32_t c = ws->corners[wd->first + i];
            double *g = ip->inputs + (size_t)c * stride;
            switch (source_of(m, c, ip->mode, dg)) {
            case SRC_GIVEN:
                for (size_t j = 0; j < stride; j++) g[j] = m->given_grad[(size_t)c * stride + j];
                break;
            case SRC_MIDPOINTS:
                from_midpoints(m, ip->cz, c, g);
                note_clamp(cr, bound_plane(m, ws, wd, ip->cz, ip->cs, g), wd->v, 0);
                break;
            case SRC_ESTIMATE: /* one fit per wedge, shared by its corners */
                if (!estimated++) {
                    if (estimate(m, ws, wd, ip->cz, &fs, est) != TC_OK) {
                        rc = TC_ENOMEM;
                        break;
                    }
                    note_clamp(cr, bound_plane(m, ws, wd, ip->cz, ip->cs, est), wd->v, 1);
                }
                for (size_t j = 0; j < stride; j++) g[j] = est[j];
                break;
            default: rc = TC_EINVAL;
            }
            if (rc == TC_ENOMEM) break;
        }
    }
    tc__fit_space_free(&fs);
    return rc;
}

static void inputs_part(void *ctx, int32_t lo, int32_t hi, int part) {
    inputs_pass *ip = ctx;
    memset(&ip->cr[part], 0, sizeof ip->cr[part]);
    ip->rc[part] = wedge_inputs(ip, tc__first_wedge_at(ip->ws, lo), tc__first_wedge_at(ip->ws, hi), &ip->cr[part], NULL);
}

/* Appends a later part's clamp report: as if its planes had been noted after
 * into's (the first listed, the first largest). */
static void merge_clamps(clamp_report *into, const clamp_report *part) {
    int32_t n = part->count[0] + part->count[1];
    if (n && (into->count[0] + into->count[1] == 0 || part->worst.fx.moved > into->worst.fx.moved))
        into->worst = part->worst;
    into->count[0] += part->count[0], into->count[1] += part->count[1];
    for (int i = 0; i < part->nlist; i++)
        if (into->nlist < CLAMP_LIST && (into->nlist == 0 || into->list[into->nlist - 1].v != part->list[i].v))
            into->list[into->nlist++] = part->list[i];
}

int tc__corner_inputs(const struct tc_mesh *m, const tc__wedge_set *ws, const double *cz, tc_tangents mode,
                      double *inputs, tc_diags *dg) {
    chan_stats cs;
    channel_stats(m, ws, cz, &cs);
    inputs_pass ip = {.m = m, .ws = ws, .cz = cz, .mode = mode, .inputs = inputs, .cs = &cs};
    tc__parallel_for(ws->threads, m->nv, 4096, inputs_part, &ip);
    clamp_report cr;
    memset(&cr, 0, sizeof cr);
    int rc = TC_OK;
    for (int p = 0; p < tc__parallel_parts(ws->threads, m->nv, 4096); p++) {
        if (ip.rc[p] == TC_ENOMEM || ip.rc[p] == TC_ETIMEOUT) return ip.rc[p];
        if (ip.rc[p] != TC_OK) rc = ip.rc[p];
        merge_clamps(&cr, &ip.cr[p]);
    }
    if (rc != TC_OK) { /* again in order, for the findings */
        memset(&cr, 0, sizeof cr);
        return wedge_inputs(&ip, 0, ws->nw, &cr, dg);
    }
    warn_clamps(&cr, dg);
    return TC_OK;
}
