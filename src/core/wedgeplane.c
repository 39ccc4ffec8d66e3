/* wedgeplane.c — one tangent plane per wedge: the paper's WedgeNormal (Figure 6),
 * in gradient form, corrected (default) or literal. Figure 6 as printed has two
 * defects, both at 180-degree wedges: C0 breaks at a vertex whose only two
 * delimiters are collinear, one C0 and one C-1 or boundary (the wedge's two side
 * heights come from different normals), and a kink along a straight C0 line
 * through a vertex with no other delimiter is flattened (both wedges end up with
 * the same averaged normal). `corrected` fixes both with one rule (corrected()
 * below; docs/design-notes.md, "Wedges"). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/fhypot.h"
#include "core/geom.h"
#include "core/minmax.h"
#include "core/parallel.h"
#include "core/plane.h"
#include "core/tangent.h"

/* Below this |sin| of the angle between its sides, a wedge counts as nearly
 * straight (within about 14.5 degrees of 180, or of 0/360): the plane through
 * its two side ordinates would grow like 1/sin, so it is blended, in
 * proportion to 1 - sin/NEAR_STRAIGHT, towards a rule that stays bounded. */
#define NEAR_STRAIGHT 0.25

/* A straight C0 line may keep a kink at a vertex; a line bent by any angle may
 * not (with both side slopes exact, two edges fix the plane: the paper's
 * theorem). Between sin = TC_COLLINEAR_TOL (straight) and TC_STRAIGHT_BAND the
 * kink is let go gradually (log-spaced in the angle), at the price of a C0
 * mismatch of at most sin * (the kink) on the far side: <= 1e-9 relative. At
 * the band's end both wedges reach the same plane — with average "area", the
 * one the vertex gets as a C1 vertex just outside the band. */

typedef struct {
    const tc__wedge_set *ws;
    const double *avg;  /* [nw][nc][2] step 1: each wedge's average plane */
    const double *vplane; /* [nw][nc][2] the mean plane of the wedge's vertex (all its wedges) */
    const double *area; /* [nw] total area of each wedge's faces (by_area) */
    int nc;
    int by_area;        /* average "area" (else unit normals) */
    int corrected;      /* wedges "corrected": nearly straight wedges are blended */
} plane_rules;

static const double *avg_of(const plane_rules *pr, int32_t w, int ch) {
    return pr->avg + (2 * tc__ix(w, pr->nc, ch));
}

/* average "area": the area-weighted mean of the faces' gradients. It is linear in
 * the data (scaling every value scales the plane, as it must the whole
 * reconstruction: test_stab_invariance.c), and a sliver — a face of near-zero area
 * whose plane, from three nearly collinear samples, can be wildly steep —
 * cannot tilt it (the stiff scene of the report). */
static void area_mean(const struct tc_mesh *m, const tc__wedge_set *ws, const tc__wedge *w, const double *inputs,
                      int nc, double *out, double *total) {
    size_t stride = 2 * (size_t)nc;
    double sum[2 * TC_MAX_CHANNELS] = {0}, wsum = 0;
    for (int32_t i = 0; i < w->count; i++) {
        int32_t c = ws->corners[w->first + i];
        double a = tc__face_area(m, c / 3);
        for (size_t k = 0; k < stride; k++) sum[k] += a * inputs[(size_t)c * stride + k];
        wsum += a;
    }
    for (size_t k = 0; k < stride; k++) out[k] = sum[k] / wsum;
    *total = wsum;
}

/* Step 1, AverageNormalForWedge. average "normals" (always with wedges
 * "literal"): the paper's normalized sum of the faces' unit normals. Identical inputs (a given per-vertex plane) are
 * returned exactly in both modes. */
static void wedge_average(const struct tc_mesh *m, const tc__wedge_set *ws, const tc__wedge *w, const double *inputs,
                          int by_area, double *out, double *total) {
    int nc = m->nc;
    size_t stride = 2 * (size_t)nc;
    const double *g0 = inputs + (size_t)ws->corners[w->first] * stride;
    int same = 1;
    if (by_area) area_mean(m, ws, w, inputs, nc, out, total);
    else *total = 0;
    for (int32_t i = 1; i < w->count && same; i++)
        same = !memcmp(g0, inputs + (size_t)ws->corners[w->first + i] * stride, stride * sizeof *g0);
    if (same) {
        memcpy(out, g0, stride * sizeof *out);
        return;
    }
    if (by_area) return;
    for (int ch = 0; ch < nc; ch++) {
        double S[3] = {0, 0, 0};
        for (int32_t i = 0; i < w->count; i++)
            tc__normal_acc(S, inputs + (size_t)ws->corners[w->first + i] * stride + 2 * ch);
        tc__normal_to_grad(S, out + 2 * ch);
    }
}

/* Step 3's switch: the plane whose slope along C0 side s the wedge and its
 * neighbour across s both use. Depends only on the pair, never on which of
 * the two asks, so the ordinates along the shared edge agree (C0). */
static void coupling(const plane_rules *pr, int32_t wi, int s, int ch, double g[2]) {
    const tc__wedge *w = &pr->ws->w[wi];
    int32_t o = w->across[s];
    int cw = w->collinear, co = pr->ws->w[o].collinear;
    const double *a = avg_of(pr, wi, ch), *b = avg_of(pr, o, ch);
    if (cw == co && pr->by_area) {
        /* The two wedges' planes weighted by their areas: linear in the data,
         * and the same bits whichever wedge asks (sums commute). */
        double wa = pr->area[wi], wb = pr->area[o];
        g[0] = (wa * a[0] + wb * b[0]) / (wa + wb);
        g[1] = (wa * a[1] + wb * b[1]) / (wa + wb);
    } else if (cw == co) {
        tc__avg2(a, b, g);
    } else {
        const double *src = cw ? a : b; /* the 180-degree wedge's own plane wins */
        g[0] = src[0];
        g[1] = src[1];
    }
}

/* |sin| of the angle between a wedge's two sides (0 when they share a line). */
static double side_sin(const tc__wedge *w) {
    const double *a = w->dir[0], *b = w->dir[1];
    return fabs(tc__cross(a, b)) / (tc__hypot(a[0], a[1]) * tc__hypot(b[0], b[1]));
}

/* How far a wedge is pulled towards a bounded rule: 0 for a well-shaped wedge,
 * rising linearly to 1 as it becomes straight. 0 for wedges the exact rules
 * already handle (flagged collinear, sides on one ray, no two distinct sides). */
static double straightness(const tc__wedge *w) {
    if (w->side_edge[0] < 0 || w->collinear || w->side_edge[0] == w->side_edge[1]) return 0;
    double k = 1 - side_sin(w) / NEAR_STRAIGHT;
    return k > 0 ? k : 0;
}

/* A wedge whose two sides are both C0: its side slopes are shared with its
 * neighbours, so a nearly straight one cannot fix its plane alone. */
static double straightness_c0c0(const tc__wedge *w) {
    return w->across[0] >= 0 && w->across[1] >= 0 ? straightness(w) : 0;
}

/* A wedge of (nearly) 180 degrees between the two rays of a straight C0 line
 * whose other sides belong to two different wedges (more C0 edges, or a C-1
 * edge, on the line's other side). Its one plane has one slope along the
 * line, so both neighbours must take that slope for their sides on the line:
 * coupling each side with its own neighbour would give two (C0 broken). */
static int on_line(const plane_rules *pr, int32_t wi) {
    const tc__wedge *w = &pr->ws->w[wi];
    return w->across[0] >= 0 && w->across[1] >= 0 && w->across[0] != w->across[1] &&
           (w->collinear || side_sin(w) < TC_STRAIGHT_BAND);
}

/* The plane all the wedges touching line wedge L take their slope along the
 * line from: the mean of L's and its two neighbours' planes (area-weighted,
 * or the paper's unit normals), pulled towards the vertex's mean plane by the
 * straightest of the three. The same whichever of them asks. */
static void line_plane(const plane_rules *pr, int32_t L, int ch, double g[2]) {
    const tc__wedge *w = &pr->ws->w[L];
    int32_t three[3] = {L, w->across[0], w->across[1]};
    double S[3] = {0, 0, 0}, wsum = 0, k = 0;
    g[0] = g[1] = 0;
    for (int i = 0; i < 3; i++) {
        const double *a = avg_of(pr, three[i], ch);
        if (pr->by_area) {
            double wa = pr->area[three[i]];
            g[0] += wa * a[0], g[1] += wa * a[1], wsum += wa;
        } else {
            tc__normal_acc(S, a);
        }
        if (pr->corrected) k = tc__fmax(k, straightness_c0c0(&pr->ws->w[three[i]]));
    }
    if (pr->by_area) g[0] /= wsum, g[1] /= wsum;
    else tc__normal_to_grad(S, g);
    const double *v = pr->vplane + 2 * tc__ix(L, pr->nc, ch);
    g[0] += k * (v[0] - g[0]);
    g[1] += k * (v[1] - g[1]);
}

/* The plane each side of the wedge takes its edge slope from: the coupling
 * plane, pulled towards the vertex's mean plane by the straighter of the two
 * wedges at the edge when that one has two C0 sides. Both wedges compute the
 * same weight and the same planes, so they agree on the edge (C0), and a
 * nearly straight wedge gets side slopes that nearly fit one plane. Sides on
 * a straight line with different wedges beyond take the line's plane. */
static void side_plane(const plane_rules *pr, int32_t wi, int s, int ch, double g[2]) {
    int32_t o = pr->ws->w[wi].across[s];
    if (o >= 0 && (on_line(pr, wi) || on_line(pr, o))) {
        line_plane(pr, on_line(pr, wi) ? wi : o, ch, g);
    } else if (o >= 0) {
        coupling(pr, wi, s, ch, g);
        double k = pr->corrected ? tc__fmax(straightness_c0c0(&pr->ws->w[wi]), straightness_c0c0(&pr->ws->w[o])) : 0;
        if (k > 0) {
            const double *v = pr->vplane + 2 * tc__ix(wi, pr->nc, ch);
            g[0] += k * (v[0] - g[0]);
            g[1] += k * (v[1] - g[1]);
        }
    } else {
        g[0] = avg_of(pr, wi, ch)[0];
        g[1] = avg_of(pr, wi, ch)[1];
    }
}

/* The two sides lie along one ray (the same edge, or coincident edges of a
 * crack made by duplicated vertices): they constrain one direction only. */
static int sides_parallel(const tc__wedge *w) {
    const double *a = w->dir[0], *b = w->dir[1];
    return w->side_edge[0] == w->side_edge[1] ||
           (fabs(tc__cross(a, b)) <= TC_COLLINEAR_TOL * tc__hypot(a[0], a[1]) * tc__hypot(b[0], b[1]) && tc__dot(a, b) > 0);
}

/* Corrected step 4. A 180-degree wedge (or one whose sides share a ray) takes
 * its slope along the line from one plane and keeps its own cross slope — both
 * defects of the literal version are about this case. Otherwise the plane
 * through the two side ordinates, as in the paper. */
static void corrected(const plane_rules *pr, int32_t wi, int ch, double out[2]) {
    const tc__wedge *w = &pr->ws->w[wi];
    const double *own = avg_of(pr, wi, ch);
    double ga[2], gb[2];
    if (w->collinear || sides_parallel(w)) {
        int s = w->across[TC_SIDE_A] >= 0 ? TC_SIDE_A : TC_SIDE_B;
        side_plane(pr, wi, s, ch, ga);
        tc__match_along(own, ga, w->dir[s], out);
        return;
    }
    side_plane(pr, wi, TC_SIDE_A, ch, ga);
    side_plane(pr, wi, TC_SIDE_B, ch, gb);
    tc__solve2(w->dir[0], w->dir[1], tc__dot(ga, w->dir[0]), tc__dot(gb, w->dir[1]), out);
    double sn = side_sin(w);
    if (w->across[0] >= 0 && w->across[1] >= 0 && sn < TC_STRAIGHT_BAND) {
        /* Nearly straight C0 line: fade from the straight line's rule (the
         * coupled slope along it, the wedge's own cross slope) to the plane above. */
        double t = sn > TC_COLLINEAR_TOL ? log(sn / TC_COLLINEAR_TOL) / log(TC_STRAIGHT_BAND / TC_COLLINEAR_TOL) : 0;
        double gc[2], kink[2];
        if (on_line(pr, wi)) side_plane(pr, wi, TC_SIDE_A, ch, gc);
        else coupling(pr, wi, TC_SIDE_A, ch, gc);
        tc__match_along(own, gc, w->dir[TC_SIDE_A], kink);
        out[0] = t * out[0] + (1 - t) * kink[0];
        out[1] = t * out[1] + (1 - t) * kink[1];
        return;
    }
    /* One C0 side and one free (C-1 or boundary) side, nearly straight: blend
     * with the plane that matches the C0 slope and keeps its own cross slope.
     * Both planes meet the C0 constraint exactly, so their blend does too, and
     * the solve's 1/sin growth is cancelled by the weight 1 - k ~ sin. */
    double k = straightness(w);
    int c0 = w->across[TC_SIDE_A] >= 0 ? TC_SIDE_A : w->across[TC_SIDE_B] >= 0 ? TC_SIDE_B : -1;
    if (k > 0 && c0 >= 0 && w->across[1 - c0] < 0) {
        double m[2];
        tc__match_along(own, c0 == TC_SIDE_A ? ga : gb, w->dir[c0], m);
        out[0] += k * (m[0] - out[0]);
        out[1] += k * (m[1] - out[1]);
    }
}

/* Literal step 4 for a 180-degree wedge: Project(N, <w_next - w_prev,
 * 3(s_next - s_prev)>) with N the plane of the last side visited (next), in 3D
 * normal form. As the projection goes vertical (1 + a s -> 0) its slope grows
 * without bound: *amp is that slope over the larger side slope, and the result
 * is refused (-1) above PROJECT_LIMIT, reported above PROJECT_WARN (as in ct.c).
 * Past vertical (P_z < 0) the normal points down but is a plane's, gradient
 * -P_xy / P_z, like any other: only P_z = 0 is singular. */
#define PROJECT_WARN 10.0
#define PROJECT_LIMIT 1e3
static int literal_collinear(const tc__wedge *w, const double gp[2], const double gn[2], double out[2], double *amp) {
    double D[3] = {w->dir[1][0] - w->dir[0][0], w->dir[1][1] - w->dir[0][1],
                   tc__dot(gn, w->dir[1]) - tc__dot(gp, w->dir[0])};
    double N[3] = {-gn[0], -gn[1], 1};
    double k = (N[0] * D[0] + N[1] * D[1] + N[2] * D[2]) / (D[0] * D[0] + D[1] * D[1] + D[2] * D[2]);
    double P[3] = {N[0] - k * D[0], N[1] - k * D[1], N[2] - k * D[2]};
    *amp = INFINITY;
    if (!(P[2] != 0)) return -1; /* vertical: no plane */
    tc__normal_to_grad(P, out);
    double inputs = tc__fmax(tc__hypot(gp[0], gp[1]), tc__hypot(gn[0], gn[1])), g = tc__hypot(out[0], out[1]);
    *amp = inputs > 0 ? g / inputs : g > 0 ? INFINITY : 1;
    return *amp <= PROJECT_LIMIT ? 0 : -1;
}

static int literal(const plane_rules *pr, int32_t wi, int ch, double out[2], double *amp) {
    const tc__wedge *w = &pr->ws->w[wi];
    double gp[2], gn[2];
    side_plane(pr, wi, TC_SIDE_A, ch, gp);
    side_plane(pr, wi, TC_SIDE_B, ch, gn);
    *amp = 1;
    if (w->collinear) return literal_collinear(w, gp, gn, out, amp);
    if (sides_parallel(w)) { /* the paper's cross product vanishes here */
        corrected(pr, wi, ch, out);
        return 0;
    }
    tc__solve2(w->dir[0], w->dir[1], tc__dot(gp, w->dir[0]), tc__dot(gn, w->dir[1]), out);
    return 0;
}

/* The literal Projects that amplified the gradient past PROJECT_WARN: how
 * many, the first vertices (in vertex order) and the worst. */
#define AMP_LIST 3
typedef struct {
    int count, nfirst;
    int32_t first[AMP_LIST], worst_v;
    double worst;
} amp_report;

static void note_amp(amp_report *a, double amp, int32_t v) {
    if (!(amp > PROJECT_WARN)) return;
    if (a->count++ == 0 || amp > a->worst) a->worst = amp, a->worst_v = v;
    if (a->nfirst < AMP_LIST && (a->nfirst == 0 || a->first[a->nfirst - 1] != v)) a->first[a->nfirst++] = v;
}

/* One warning at the worst vertex, listing the first ones too. */
static void warn_amp(const amp_report *a, tc_diags *dg) {
    if (!a->count) return;
    char path[48], at[AMP_LIST * 16 + 16] = "";
    snprintf(path, sizeof path, "vertices[%d]", (int)a->worst_v);
    if (a->count == 1) {
        tc_diags_add(dg, TC_SEV_WARNING, path,
                     "the wedge plane (literal Project) at vertex %d amplifies the gradient %.3gx, more than %.0fx "
                     "(1 + a*s near 0): wedges \"corrected\" does not", (int)a->worst_v, a->worst, PROJECT_WARN);
        return;
    }
    size_t len = 0;
    for (int i = 0; i < a->nfirst; i++)
        len += (size_t)snprintf(at + len, sizeof at - len, "%s%d", i ? ", " : "", (int)a->first[i]);
    if (a->count > a->nfirst) snprintf(at + len, sizeof at - len, " and others");
    tc_diags_add(dg, TC_SEV_WARNING, path,
                 "%d wedge planes (literal Project) amplify the gradient more than %.0fx, at vertices %s; the worst, "
                 "vertex %d, %.3gx (1 + a*s near 0): wedges \"corrected\" does not",
                 a->count, PROJECT_WARN, at, (int)a->worst_v, a->worst);
}

/* For every wedge, the area-weighted mean of the average planes of all the
 * wedges at its vertex (wedges of one vertex are contiguous in ws->w): the
 * groups that start in [lo, hi), the last one read to its end. */
static void vertex_planes(const struct tc_mesh *m, const tc__wedge_set *ws, const double *avg, double *vplane,
                          int32_t lo, int32_t hi) {
    size_t stride = 2 * (size_t)m->nc;
    int32_t w0 = lo;
    while (w0 > 0 && w0 < hi && ws->w[w0].v == ws->w[w0 - 1].v) w0++; /* its group started before lo */
    for (int32_t w1; w0 < hi; w0 = w1) {
        double sum[2 * TC_MAX_CHANNELS] = {0}, wsum = 0;
        for (w1 = w0; w1 < ws->nw && ws->w[w1].v == ws->w[w0].v; w1++) {
            double a = 0;
            for (int32_t i = 0; i < ws->w[w1].count; i++) a += tc__face_area(m, ws->corners[ws->w[w1].first + i] / 3);
            for (size_t k = 0; k < stride; k++) sum[k] += a * avg[(size_t)w1 * stride + k];
            wsum += a;
        }
        for (int32_t w = w0; w < w1; w++)
            for (size_t k = 0; k < stride; k++) vplane[(size_t)w * stride + k] = sum[k] / wsum;
    }
}

/* The planes of the wedges with a C0 side, from the averages and vertex
 * planes (read only), in parts: each writes its own wedges' planes and keeps
 * its own amplification report, merged in part order (the serial report); a
 * part stops at its first singular Project, and then the whole loop runs
 * again in order to report it as the serial one does. */
typedef struct {
    const struct tc_mesh *m;
    const tc__wedge_set *ws;
    plane_rules pr;
    double *vplane; /* pr.vplane, written by vertex_planes_part first */
    double *out;
    amp_report amps[TC_PARALLEL_MAX];
    int bad[TC_PARALLEL_MAX];
} coupled_pass;

static int coupled_planes(const coupled_pass *cp, int32_t lo, int32_t hi, amp_report *amps, tc_diags *dg) {
    const tc__wedge_set *ws = cp->ws;
    int nc = cp->pr.nc;
    size_t stride = 2 * (size_t)nc;
    for (int32_t w = lo; w < hi; w++) {
        const tc__wedge *wd = &ws->w[w];
        if (wd->across[0] < 0 && wd->across[1] < 0) continue;
        for (int ch = 0; ch < nc; ch++) {
            double *g = cp->out + (size_t)w * stride + 2 * ch, amp = 1;
            if (cp->pr.corrected) {
                corrected(&cp->pr, w, ch, g);
                continue;
            }
            int bad = literal(&cp->pr, w, ch, g, &amp) < 0;
            note_amp(amps, amp, wd->v);
            if (bad) {
                char path[48];
                snprintf(path, sizeof path, "vertices[%d]", (int)wd->v);
                return tc_diags_add(dg, TC_SEV_ERROR, path,
                                    "wedges \"literal\": Figure 6's Project is singular at vertex %d (1 + a*s near 0; "
                                    "it would amplify the gradient %.3gx, limit %.0fx); use wedges \"corrected\"",
                                    (int)wd->v, amp, PROJECT_LIMIT);
            }
        }
    }
    return TC_OK;
}

static void coupled_part(void *ctx, int32_t lo, int32_t hi, int part) {
    coupled_pass *cp = ctx;
    memset(&cp->amps[part], 0, sizeof cp->amps[part]);
    cp->bad[part] = coupled_planes(cp, lo, hi, &cp->amps[part], NULL) != TC_OK;
}

static void vertex_planes_part(void *ctx, int32_t lo, int32_t hi, int part) {
    const coupled_pass *cp = ctx;
    (void)part;
    vertex_planes(cp->m, cp->ws, cp->pr.avg, cp->vplane, lo, hi);
}

/* The averages of wedges [lo, hi) (each writes its own entries). */
typedef struct {
    const struct tc_mesh *m;
    const tc__wedge_set *ws;
    const double *inputs;
    int by_area;
    double *out, *area;
} average_pass;

static void average_part(void *ctx, int32_t lo, int32_t hi, int part) {
    const average_pass *ap = ctx;
    size_t stride = 2 * (size_t)ap->m->nc;
    (void)part;
    for (int32_t w = lo; w < hi; w++)
        wedge_average(ap->m, ap->ws, &ap->ws->w[w], ap->inputs, ap->by_area, ap->out + (size_t)w * stride, &ap->area[w]);
}

int tc__wedge_planes(const struct tc_mesh *m, const tc__wedge_set *ws, const double *inputs, tc_wedges mode,
                     tc_average average, double *out, tc_diags *dg) {
    /* Figure 6 as printed averages unit normals, whatever was asked. */
    int by_area = mode == TC_WEDGES_CORRECTED && average == TC_AVERAGE_AREA;
    int nc = m->nc;
    size_t stride = 2 * (size_t)nc;
    double *area = malloc(((size_t)ws->nw + 1) * sizeof *area);
    if (!area) return TC_ENOMEM;
    average_pass ap = {m, ws, inputs, by_area, out, area};
    tc__parallel_for(ws->threads, ws->nw, 4096, average_part, &ap);
    double *avg = ws->ncoupled ? tc__malloc((size_t)ws->nw * stride, sizeof *avg) : NULL;
    if (ws->ncoupled == 0 || !avg) { /* no C0 sides: the averages are final */
        tc__free(area);
        return ws->ncoupled == 0 ? TC_OK : TC_ENOMEM;
    }
    tc__parallel_copy(ws->threads, avg, out, (size_t)ws->nw * stride * sizeof *avg);
    double *vplane = tc__malloc((size_t)ws->nw * stride, sizeof *vplane);
    if (!vplane) {
        tc__free(avg), tc__free(area);
        return TC_ENOMEM;
    }
    coupled_pass cp = {m, ws, {ws, avg, vplane, area, nc, by_area, mode == TC_WEDGES_CORRECTED}, vplane, out, {{0}}, {0}};
    tc__parallel_for(ws->threads, ws->nw, 4096, vertex_planes_part, &cp);
    tc__parallel_for(ws->threads, ws->nw, 4096, coupled_part, &cp);
    int rc = TC_OK, bad = 0;
    amp_report amps;
    memset(&amps, 0, sizeof amps);
    for (int p = 0; p < tc__parallel_parts(ws->threads, ws->nw, 4096); p++) {
        const amp_report *a = &cp.amps[p];
        bad |= cp.bad[p];
        if (a->count && (amps.count == 0 || a->worst > amps.worst)) amps.worst = a->worst, amps.worst_v = a->worst_v;
        amps.count += a->count;
        for (int i = 0; i < a->nfirst; i++)
            if (amps.nfirst < AMP_LIST && (amps.nfirst == 0 || amps.first[amps.nfirst - 1] != a->first[i]))
                amps.first[amps.nfirst++] = a->first[i];
    }
    if (bad) { /* again in order, for the finding */
        memset(&amps, 0, sizeof amps);
        rc = coupled_planes(&cp, 0, ws->nw, &amps, dg);
    }
    if (rc == TC_OK) warn_amp(&amps, dg);
    tc__free(avg);
    tc__free(vplane);
    tc__free(area);
    return rc;
}
