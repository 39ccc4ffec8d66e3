/* ct_range.c — range-restricted Clough-Tocher: the wedge planes limited (range.c),
 * then each edge's cross-boundary ordinates, keeping C1 wherever the bound allows.
 *
 * Every ordinate of a triangle is one of: a corner value (inside its bound by
 * definition), an edge ordinate z + g.(p - v)/3 (kept inside by the plane
 * limiter), cuu (the mean of a corner value and its two edge ordinates), a
 * cross-boundary ordinate cab, or ccu / ccc (means of the above). So once the
 * planes and the three cab are inside, the whole net is, and the cubic is.
 *
 * C1 across an interior edge ab between T (centroid c) and T' (centroid c')
 * ties their cross-boundary ordinates: with (la, lb, lc) the barycentrics of
 * c' in the subtriangle (a, b, c), c'ab = la aab + lb abb + lc cab, lc < 0. With
 * mu = -lc: mu cab + c'ab = (1 + mu) X, where X = aab + tx (abb - aab) is the
 * middle leg of the edge's control polygon extended to where the segment cc'
 * crosses the edge's line (parameter tx). When that crossing lies on the edge
 * (tx in [0, 1]: the two triangles form a convex quad, or nearly), X lies
 * between aab and abb, inside both bounds, and cab = c'ab = X is a C1 choice
 * inside both: the edge is always feasible, and the rule's choice is moved
 * along the C1 line only as far as the bounds ask. When the crossing lies far
 * outside the edge (a "dart": both triangles reach far along the edge's line
 * on one side), X extrapolates the middle leg, and C1 may force an overshoot:
 * then the planes at the edge's ends are scaled down while that helps, and
 * where it cannot (proved impossible: no admissible ordinates satisfy the tie),
 * C1 is given up on that edge with the smallest mismatch, and said so. */
#include <math.h>
#include <string.h>

#include "core/alloc.h"
#include "core/ct.h"
#include "core/geom.h"
#include "core/minmax.h"
#include "core/parallel.h"
#include "core/range.h"

/* The directions of a corner's two edge ordinates: (p - v) / 3. */
static int ct_dirs(const void *ctx, int32_t c, double d[TC_PLANE_DIRS_MAX][2]) {
    const struct tc_mesh *m = ctx;
    int32_t t = c / 3, k = c % 3;
    const double *v = tc__vxy(m, m->tri[c]);
    for (int j = 1; j <= 2; j++) {
        const double *p = tc__vxy(m, m->tri[3 * t + (k + j) % 3]);
        d[j - 1][0] = (p[0] - v[0]) / 3;
        d[j - 1][1] = (p[1] - v[1]) / 3;
    }
    return 2;
}

/* ---- the C1 tie across an edge ---- */

typedef struct {
    int32_t t, t2;  /* the two triangles; edge k of t is edge k2 of t2 */
    int k, k2;
    int32_t ca, cb; /* t's corners at the edge's ends a and b */
    double la, lb, mu;
} tie;

/* The barycentrics of t2's centroid in the subtriangle (a, b, c) of t. */
static void tie_geometry(const struct tc_mesh *m, int32_t t, int k, tie *e) {
    int32_t ea = 3 * t + k;
    e->t = t, e->k = k, e->t2 = m->nbr[ea], e->k2 = m->nbr_k[ea];
    e->ca = ea, e->cb = 3 * t + (k + 1) % 3;
    const double *a = tc__vxy(m, m->tri[e->ca]);
    double ab[2], aw[2], aw2[2], c[2], c2[2];
    tc__sub(ab, tc__vxy(m, m->tri[e->cb]), a);
    tc__sub(aw, tc__vxy(m, m->tri[3 * t + (k + 2) % 3]), a);
    tc__sub(aw2, tc__vxy(m, m->tri[3 * e->t2 + (e->k2 + 2) % 3]), a);
    for (int i = 0; i < 2; i++) c[i] = (ab[i] + aw[i]) / 3, c2[i] = (ab[i] + aw2[i]) / 3;
    double det = tc__cross(ab, c);
    double lc = tc__cross(ab, c2) / det;
    e->lb = tc__cross(c2, c) / det;
    e->la = 1 - e->lb - lc;
    e->mu = -lc;
}

/* The tie's right-hand side (1 + mu) X from t's edge ordinates. */
static double tie_rhs(const tie *e, const double *o) {
    return e->la * o[tc__ct_iij[e->ca % 3][e->cb % 3]] + e->lb * o[tc__ct_iij[e->cb % 3][e->ca % 3]];
}

/* The rounding a tie carries: its right-hand side sums edge ordinates with
 * weights la, lb (large for a dart), so it is exact only to that many tols. */
static double tie_slack(const tie *e, double tol) { return tol * (2 + fabs(e->la) + fabs(e->lb) + e->mu); }

/* What the edge limiter works with. */
typedef struct {
    const tc__ct_input *ci;
    const tc__bounds *b;
    tc__range_stats *stats;
} limiter;

static int is_tied(const tc__ct_input *ci, int32_t e) {
    return ci->m->nbr[e] >= 0 && tc__eff_flag(ci->m, ci->ws->honor_flags, e) == TC_C1;
}

/* ---- darts: scale the planes at an edge's ends while that makes C1 feasible ---- */

/* Edge ordinates of t's edge k in channel ch from the corner planes: aab, abb. */
static void edge_ordinates(const tc__ct_input *ci, const double *planes, const tie *e, int ch, double *aab,
                           double *abb) {
    const struct tc_mesh *m = ci->m;
    int nc = m->nc;
    const double *a = tc__vxy(m, m->tri[e->ca]), *b = tc__vxy(m, m->tri[e->cb]);
    const double *ga = planes + tc__ix(e->ca, nc, ch) * 2, *gb = planes + tc__ix(e->cb, nc, ch) * 2;
    double ab[2];
    tc__sub(ab, b, a);
    *aab = ci->cz[tc__ix(e->ca, nc, ch)] + tc__dot(ga, ab) / 3;
    *abb = ci->cz[tc__ix(e->cb, nc, ch)] - tc__dot(gb, ab) / 3;
}

/* The largest lambda in [0, 1] such that scaling both end planes by lambda
 * makes the tie feasible; -1 if none does (not even flat planes). */
static double dart_lambda(const tie *e, double za, double zb, double aab, double abb, double flo, double fhi,
                          double tol) {
    double r1 = e->la * aab + e->lb * abb, r0 = e->la * za + e->lb * zb; /* rhs at lambda 1 and 0 */
    if (r1 >= flo - tol && r1 <= fhi + tol) return 1;
    if (!(r0 >= flo - tol && r0 <= fhi + tol)) return -1;
    double target = r1 > fhi ? fhi : flo; /* r(lambda) = r0 + lambda (r1 - r0) reaches it */
    double lambda = (target - r0) / (r1 - r0);
    return tc__fmin(tc__fmax(lambda, 0), 1);
}

/* Tied edge (t, k) in channel ch: the lambda that makes it feasible, as dart_lambda. */
static double edge_lambda(const limiter *lim, const double *planes, const tie *e, int ch) {
    const tc__ct_input *ci = lim->ci;
    int nc = ci->m->nc;
    size_t i1 = tc__ix(e->t, nc, ch), i2 = tc__ix(e->t2, nc, ch);
    double flo = lim->b->lo[i2] + e->mu * lim->b->lo[i1], fhi = lim->b->hi[i2] + e->mu * lim->b->hi[i1];
    double aab, abb, za = ci->cz[tc__ix(e->ca, nc, ch)], zb = ci->cz[tc__ix(e->cb, nc, ch)];
    edge_ordinates(ci, planes, e, ch, &aab, &abb);
    return dart_lambda(e, za, zb, aab, abb, flo, fhi, tie_slack(e, lim->b->tol[ch]));
}

/* The edges a round visits: tied, seen from the lower triangle. */
static int dart_edge(const struct tc_mesh *m, const tc__ct_input *ci, int32_t t, int k) {
    return is_tied(ci, 3 * t + k) && m->nbr[3 * t + k] > t;
}

/* The first of triangles [lo, hi) with an edge that needs scaling, the planes
 * as they are before the round. */
typedef struct {
    const limiter *lim;
    const double *planes;
    int32_t first[TC_PARALLEL_MAX]; /* the part's first triangle with an edge in need, or INT32_MAX */
} dart_pass;

static void dart_part(void *ctx, int32_t lo, int32_t hi, int part) {
    dart_pass *dp = ctx;
    const struct tc_mesh *m = dp->lim->ci->m;
    dp->first[part] = INT32_MAX;
    for (int32_t t = lo; t < hi; t++)
        for (int k = 0; k < 3; k++) {
            if (!dart_edge(m, dp->lim->ci, t, k)) continue;
            tie e;
            tie_geometry(m, t, k, &e);
            for (int ch = 0; ch < m->nc; ch++) {
                double lambda = edge_lambda(dp->lim, dp->planes, &e, ch);
                if (!(lambda >= 0 && lambda < 1)) continue;
                dp->first[part] = t;
                return;
            }
        }
}

/* One round over the tied edges: for each infeasible one, scales the planes
 * at both ends (and their C0 groups). Returns how many planes it scaled. In
 * order, each edge seeing the scalings before it: the lambdas are found on
 * threads first, and the ordered pass starts at the first edge that needs a
 * scaling (before it nothing changes), so the round is the serial one. Darts
 * are rare: on most meshes the round ends after the threaded pass. */
static int dart_round(const limiter *lim, double *planes) {
    const tc__ct_input *ci = lim->ci;
    const struct tc_mesh *m = ci->m;
    int nc = m->nc, scaled = 0;
    dart_pass dp = {lim, planes, {0}};
    tc__parallel_for(ci->threads, m->nt, 2048, dart_part, &dp);
    int32_t first = INT32_MAX;
    for (int p = 0; p < tc__parallel_parts(ci->threads, m->nt, 2048); p++)
        if (dp.first[p] < first) first = dp.first[p];
    for (int32_t t = first; t < m->nt; t++)
        for (int k = 0; k < 3; k++) {
            if (!dart_edge(m, ci, t, k)) continue;
            tie e;
            tie_geometry(m, t, k, &e);
            for (int ch = 0; ch < nc; ch++) {
                double lambda = edge_lambda(lim, planes, &e, ch);
                if (lambda < 0 || lambda >= 1) continue;
                tc__range_scale_group(ci->ws, nc, ci->ws->of_corner[e.ca], ch, lambda, planes);
                tc__range_scale_group(ci->ws, nc, ci->ws->of_corner[e.cb], ch, lambda, planes);
                scaled += 2;
            }
        }
    return scaled;
}

/* ---- the cross-boundary ordinates ---- */

/* Counts a move of size `move` (absolute) in tally t if it is material. */
static void note(const limiter *lim, tc__range_tally *t, int ch, double move, int32_t tri, int k) {
    double span = lim->b->span[ch];
    if (move > TC_RANGE_MATERIAL * span) tc__range_note(t, move / span, tri, k);
}

/* An edge that ties nothing (boundary, C-1, C0): cab is t's alone. */
static int clamp_free(const limiter *lim, int32_t t, int k, double *coef) {
    int nc = lim->ci->m->nc, moved = 0;
    for (int ch = 0; ch < nc; ch++) {
        size_t i = tc__ix(t, nc, ch);
        double *cab = coef + i * TC_CT_ORDINATES + tc__ct_cij[k];
        if (tc__outside(*cab, lim->b->lo[i], lim->b->hi[i], lim->b->tol[ch]) == 0) continue;
        double v = tc__fmin(tc__fmax(*cab, lim->b->lo[i]), lim->b->hi[i]);
        note(lim, &lim->stats->edges, ch, fabs(v - *cab), t, k);
        *cab = v, moved = 1;
    }
    return moved;
}

/* Both cross-boundary ordinates of a tied edge in one channel. The tie
 * mu x1 + x2 = rhs is written kappa p + q = g with kappa = min(mu, 1/mu), so
 * q follows from p without growth of rounding. */
static int clamp_tied_channel(const limiter *lim, const tie *e, int ch, double *o, double *o2) {
    int nc = lim->ci->m->nc;
    size_t i1 = tc__ix(e->t, nc, ch), i2 = tc__ix(e->t2, nc, ch);
    double *x1 = o + tc__ct_cij[e->k], *x2 = o2 + tc__ct_cij[e->k2], tol = lim->b->tol[ch];
    double rhs = tie_rhs(e, o), slack = tie_slack(e, tol);
    /* Inside and tied (to rounding): nothing to do. The literal Project near
     * its singularity ties the pair only to its own amplified rounding: that
     * pair is re-tied below, so the limited reconstruction is C1 to rounding. */
    int inside = tc__outside(*x1, lim->b->lo[i1], lim->b->hi[i1], tol) == 0 &&
                 tc__outside(*x2, lim->b->lo[i2], lim->b->hi[i2], tol) == 0;
    if (inside && fabs(e->mu * *x1 + *x2 - rhs) <= slack) return 0;
    int swap = e->mu > 1;
    double kappa = swap ? 1 / e->mu : e->mu, g = swap ? rhs / e->mu : rhs;
    double *p = swap ? x2 : x1, *q = swap ? x1 : x2;
    size_t ip = swap ? i2 : i1, iq = swap ? i1 : i2;
    double plo = lim->b->lo[ip], phi = lim->b->hi[ip], qlo = lim->b->lo[iq], qhi = lim->b->hi[iq];
    double p0 = *p, q0 = *q, pn, qn;
    /* q = g - kappa p falls as p rises: some p in [plo, phi] puts q in [qlo, qhi] iff */
    int high = g - kappa * phi > qhi + slack, low = g - kappa * plo < qlo - slack;
    if (!high && !low) { /* C1 inside both bounds: move p no further than needed */
        double jlo = tc__fmax(plo, (g - qhi) / kappa), jhi = tc__fmin(phi, (g - qlo) / kappa);
        if (jlo > jhi) jlo = jhi = tc__fmin(tc__fmax(0.5 * (jlo + jhi), plo), phi); /* rounding */
        pn = tc__fmin(tc__fmax(p0, jlo), jhi);
        qn = g - kappa * pn; /* exactly C1; outside q's bound by rounding (slack) at most */
    } else { /* no C1 choice inside: the nearest pair, C1 given up here */
        pn = high ? phi : plo;
        qn = high ? qhi : qlo;
        note(lim, &lim->stats->kinks, ch, fabs(qn - (g - kappa * pn)), e->t, e->k);
    }
    if (!inside) note(lim, &lim->stats->edges, ch, tc__fmax(fabs(pn - p0), fabs(qn - q0)), e->t, e->k);
    *p = pn, *q = qn;
    return 1;
}

/* Limits the cross-boundary ordinates of the edges of triangles [lo, hi) (a
 * tied edge from its lower triangle). An edge moves only its own two
 * ordinates (cab of each side) and reads only edge ordinates, so triangles
 * may be done on different threads; the notes go to lim's own stats. */
static void limit_edges(const limiter *lim, double *coef, int32_t lo, int32_t hi) {
    const struct tc_mesh *m = lim->ci->m;
    int nc = m->nc;
    size_t per = (size_t)nc * TC_CT_ORDINATES;
    for (int32_t t = lo; t < hi; t++)
        for (int k = 0; k < 3; k++) {
            int32_t ea = 3 * t + k;
            if (!is_tied(lim->ci, ea)) {
                clamp_free(lim, t, k, coef);
                continue;
            }
            if (m->nbr[ea] < t) continue;
            tie e;
            tie_geometry(m, t, k, &e);
            for (int ch = 0; ch < nc; ch++) {
                double *o = coef + (size_t)t * per + (size_t)ch * TC_CT_ORDINATES;
                double *o2 = coef + (size_t)e.t2 * per + (size_t)ch * TC_CT_ORDINATES;
                clamp_tied_channel(lim, &e, ch, o, o2);
            }
        }
}

/* The parts of limit_edges, each with its own stats (merged in order), then
 * the closing ordinates of every triangle made again: those of a triangle
 * whose cab did not move come out as they were, bit for bit. */
typedef struct {
    const limiter *lim;
    double *coef;
    tc__range_stats stats[TC_PARALLEL_MAX];
} edges_pass;

static void edges_part(void *ctx, int32_t lo, int32_t hi, int part) {
    edges_pass *ep = ctx;
    limiter lim = *ep->lim;
    tc__range_stats_init(&ep->stats[part]);
    lim.stats = &ep->stats[part];
    limit_edges(&lim, ep->coef, lo, hi);
}

static void close_part(void *ctx, int32_t lo, int32_t hi, int part) {
    const edges_pass *ep = ctx;
    int nc = ep->lim->ci->m->nc;
    (void)part;
    for (int32_t t = lo; t < hi; t++)
        for (int ch = 0; ch < nc; ch++) tc__ct_close(ep->coef + tc__ix(t, nc, ch) * TC_CT_ORDINATES);
}

static void limit_all_edges(const limiter *lim, double *coef) {
    const struct tc_mesh *m = lim->ci->m;
    int threads = lim->ci->threads;
    edges_pass ep;
    ep.lim = lim, ep.coef = coef;
    tc__parallel_for(threads, m->nt, 2048, edges_part, &ep);
    for (int p = 0; p < tc__parallel_parts(threads, m->nt, 2048); p++) {
        tc__range_tally_merge(&lim->stats->edges, &ep.stats[p].edges);
        tc__range_tally_merge(&lim->stats->kinks, &ep.stats[p].kinks);
    }
    tc__parallel_for(threads, m->nt, 2048, close_part, &ep);
}

/* ---- the pipeline ---- */

enum { DART_ROUNDS = 4 };

int tc__ct_ordinates_ranged(const tc__ct_input *ci, tc_range mode, double *planes, double *coef, tc_diags *dg) {
    const struct tc_mesh *m = ci->m;
    tc__bounds b;
    tc__range_stats stats;
    tc__range_stats_init(&stats);
    int rc = tc__bounds_build(m, ci->ws, ci->cz, planes, ci->tangents, mode, 0, &b);
    if (rc == TC_OK) rc = tc__range_planes(m, ci->ws, ci->cz, &b, ct_dirs, m, planes, &stats);
    limiter lim = {ci, &b, &stats};
    for (int round = 0; rc == TC_OK && round < DART_ROUNDS; round++) {
        int n = dart_round(&lim, planes);
        stats.flattened += n;
        if (!n) break;
    }
    if (rc == TC_OK) rc = tc__ct_ordinates(ci, coef, dg);
    if (rc == TC_OK) {
        limit_all_edges(&lim, coef);
        tc__range_warn(m, &stats, mode, dg);
    }
    tc__bounds_free(&b);
    return rc;
}
