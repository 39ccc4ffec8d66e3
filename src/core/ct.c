/* ct.c — the Clough-Tocher split: 19 Bézier ordinates per triangle from corner
 * values and wedge planes (paper Figure 5), the three cross-boundary rules, and
 * evaluation of the cubic subtriangle pieces. Geometry is local to corner 0. */
#include <math.h>
#include <stdio.h>

#include "core/alloc.h"
#include "core/assert.h"
#include "core/ct.h"
#include "core/fhypot.h"
#include "core/geom.h"
#include "core/mesh.h"
#include "core/minmax.h"
#include "core/parallel.h"
#include "core/plane.h"

const char *const tc__ct_labels[TC_CT_ORDINATES] = {
    "uuu", "vvv", "www", "uuv", "uuw", "uvv", "uww", "vvw", "vww", "cuu",
    "cvv", "cww", "ccu", "ccv", "ccw", "cuv", "cuw", "cvw", "ccc"};

/* Corners are 0 = u, 1 = v, 2 = w; edge k joins corners k and k+1. */
const int tc__ct_iij[3][3] = {{-1, CT_UUV, CT_UUW}, {CT_UVV, -1, CT_VVW}, {CT_UWW, CT_VWW, -1}};
const int tc__ct_cij[3] = {CT_CUV, CT_CVW, CT_CUW};
#define IIJ tc__ct_iij
#define CIJ tc__ct_cij
static const int CII[3] = {CT_CUU, CT_CVV, CT_CWW};
static const int CCI[3] = {CT_CCU, CT_CCV, CT_CCW};

typedef struct {
    double r[3][2]; /* corners relative to corner 0 */
    double tau[3];  /* per edge: d = (c - a) - tau (b - a) is the direction whose derivative is linear */
} geom;

static void local_geometry(const struct tc_mesh *m, int32_t t, geom *g) {
    const int32_t *v = m->tri + 3 * (size_t)t;
    g->r[0][0] = g->r[0][1] = 0;
    tc__sub(g->r[1], tc__vxy(m, v[1]), tc__vxy(m, v[0]));
    tc__sub(g->r[2], tc__vxy(m, v[2]), tc__vxy(m, v[0]));
}

/* tau for `normal`: the direction from the centroid perpendicular to the edge. */
static double tau_normal(const geom *g, int a, int b, int w) {
    double e[2], f[2];
    tc__sub(e, g->r[b], g->r[a]);
    tc__sub(f, g->r[w], g->r[a]);
    return (1.0 + tc__dot(f, e) / tc__dot(e, e)) / 3.0;
}

/* tau for `affine`: towards the neighbour's centroid, c' - c = (w' - w)/3,
 * where the edge is C1 and has a neighbour; else from the edge midpoint to the
 * own centroid (tau = 1/2). Both neighbours pick the same line: C1. */
static double tau_affine(const tc__ct_input *ci, int32_t t, int k, const geom *g) {
    const struct tc_mesh *m = ci->m;
    int32_t e = 3 * t + k, t2 = m->nbr[e];
    if (t2 < 0 || tc__eff_flag(m, ci->ws->honor_flags, e) != TC_C1) return 0.5;
    int a = k, b = (k + 1) % 3, w = (k + 2) % 3;
    double dw[2], ca[2], eb[2];
    tc__sub(dw, tc__vxy(m, m->tri[3 * (size_t)t2 + (size_t)(m->nbr_k[e] + 2) % 3]), tc__vxy(m, m->tri[3 * (size_t)t + (size_t)w]));
    tc__sub(eb, g->r[b], g->r[a]);
    ca[0] = (eb[0] + (g->r[w][0] - g->r[a][0])) / 3;
    ca[1] = (eb[1] + (g->r[w][1] - g->r[a][1])) / 3;
    return tc__cross(dw, ca) / tc__cross(dw, eb);
}

/* The linear-derivative rule: the derivative along (c - a) - tau (b - a) is
 * linear on edge ab, which fixes cab from the edge and vertex ordinates. */
/* The mean of `base` and two more ordinates, as base plus the mean offset:
 * exact when all three are equal (constant data is reproduced bit for bit). */
static double mean3(double base, double p, double q) { return base + ((p - base) + (q - base)) / 3; }

/* Worked relative to aaa: on a short edge of a steep function the ordinates
 * differ little from one another, and differences taken first keep the
 * cancellation below rounding of the local variation, not of |z|. */
static double cab_linear(const double *o, int a, int b, double tau) {
    double aaa = o[a], bbb = o[b] - aaa, aab = o[IIJ[a][b]] - aaa, abb = o[IIJ[b][a]] - aaa;
    double caa = o[CII[a]] - aaa, cbb = o[CII[b]] - aaa;
    return aaa + (0.5 * (caa + cbb) - (1 - tau) * (0.5 * abb - aab) - tau * (0.5 * (aab + bbb) - abb));
}

/* The paper's Project (wedges "literal") tilts the averaged plane about the
 * edge until it contains the control polygon's middle leg; as 1 + a*s -> 0 the
 * tilt goes vertical and the plane's slope grows without bound. Past vertical
 * (the projected normal points down, N_z < 0) it is a plane again, gradient
 * -N_xy / N_z: only N_z = 0 itself is singular, and the slope says how near. Above
 * PROJECT_WARN times the larger of the averaged slope and the leg's slope the
 * result is reported; above PROJECT_LIMIT it is refused (a gradient 1e3 times
 * the data's is no reconstruction of it). `corrected` has no such singularity. */
#define PROJECT_WARN 10.0
#define PROJECT_LIMIT 1e3

typedef struct {
    int32_t count, t; /* Projects amplified past PROJECT_WARN; the worst one's triangle and edge */
    int edge;
    double amp;
} project_stats;

/* The paper's rule: plane through the middle of aab-abb with the averaged
 * normal, projected to contain the control polygon's middle leg. *amp is the
 * projected slope over the larger input slope (literal only; else 1). */
static int cab_salesin(const tc__ct_input *ci, int32_t t, int k, int ch, const geom *g, const double *o, double *cab,
                       double *amp) {
    const struct tc_mesh *m = ci->m;
    int a = k, b = (k + 1) % 3, w = (k + 2) % 3, nc = m->nc;
    size_t ca = 3 * (size_t)t + (size_t)a, cb = 3 * (size_t)t + (size_t)b;
    int c1 = tc__eff_flag(m, ci->ws->honor_flags, 3 * t + k) == TC_C1;
    const double *src = c1 ? ci->planes : ci->inputs;
    double gn[2], e[2], gp[2];
    const double *ga = src + 2 * (ca * (size_t)nc + (size_t)ch), *gb = src + 2 * (cb * (size_t)nc + (size_t)ch);
    if (ci->by_area) { /* linear in the data, like the wedge planes */
        gn[0] = 0.5 * (ga[0] + gb[0]);
        gn[1] = 0.5 * (ga[1] + gb[1]);
    } else {
        tc__avg2(ga, gb, gn);
    }
    tc__sub(e, g->r[b], g->r[a]);
    double rise = 3 * (o[IIJ[b][a]] - o[IIJ[a][b]]); /* required g.e */
    *amp = 1;
    if (ci->wedges == TC_WEDGES_CORRECTED) {
        double s = (rise - tc__dot(gn, e)) / tc__dot(e, e);
        gp[0] = gn[0] + s * e[0];
        gp[1] = gn[1] + s * e[1];
    } else {
        double D[3] = {e[0], e[1], rise}, N[3] = {-gn[0], -gn[1], 1};
        double q = (N[0] * D[0] + N[1] * D[1] + N[2] * D[2]) / (D[0] * D[0] + D[1] * D[1] + D[2] * D[2]);
        double P[3] = {N[0] - q * D[0], N[1] - q * D[1], N[2] - q * D[2]};
        if (!(P[2] != 0)) { /* vertical: no plane (a downward normal is one, see above) */
            *amp = INFINITY;
            return -1;
        }
        tc__normal_to_grad(P, gp);
        double larger = tc__fmax(tc__hypot(gn[0], gn[1]), fabs(rise) / tc__hypot(e[0], e[1]));
        *amp = tc__hypot(gp[0], gp[1]) / larger;
        if (!(larger > 0)) *amp = tc__hypot(gp[0], gp[1]) > 0 ? INFINITY : 1;
        if (!(*amp <= PROJECT_LIMIT)) return -1;
    }
    double d[2] = {(2 * (g->r[w][0] - g->r[a][0]) - e[0]) / 18, (2 * (g->r[w][1] - g->r[a][1]) - e[1]) / 18};
    *cab = 0.5 * (o[IIJ[a][b]] + o[IIJ[b][a]]) + tc__dot(gp, d);
    return isfinite(*cab) ? 0 : -1;
}

static void note_project(project_stats *ps, double amp, int32_t t, int k) {
    if (!(amp > PROJECT_WARN)) return;
    if (ps->count++ == 0 || amp > ps->amp) ps->amp = amp, ps->t = t, ps->edge = k;
}

/* One warning for all the amplified Projects, naming the worst. */
static void warn_projects(const tc__ct_input *ci, const project_stats *ps, tc_diags *dg) {
    if (!ps->count) return;
    char path[48];
    tc__elem_path(ci->m, ps->t, path, sizeof path);
    tc_diags_add(dg, TC_SEV_WARNING, path,
                 "%d cross-boundary planes (salesin, literal Project) amplify the gradient more than %.0fx; the "
                 "worst, edge %d here, %.3gx (1 + a*s near 0); wedges \"corrected\" does not",
                 (int)ps->count, PROJECT_WARN, ps->edge, ps->amp);
}

static int triangle(const tc__ct_input *ci, int32_t t, const geom *g, double *coef, project_stats *ps,
                    tc_diags *dg) {
    const struct tc_mesh *m = ci->m;
    int nc = m->nc;
    for (int ch = 0; ch < nc; ch++) {
        double *o = coef + tc__ix(t, nc, ch) * TC_CT_ORDINATES;
        for (int i = 0; i < 3; i++) {
            size_t c = 3 * (size_t)t + (size_t)i;
            const double *gi = ci->planes + 2 * (c * (size_t)nc + (size_t)ch);
            o[i] = ci->cz[c * (size_t)nc + (size_t)ch];
            for (int j = 0; j < 3; j++)
                if (j != i)
                    o[IIJ[i][j]] = o[i] + (gi[0] * (g->r[j][0] - g->r[i][0]) + gi[1] * (g->r[j][1] - g->r[i][1])) / 3;
        }
        for (int i = 0; i < 3; i++) o[CII[i]] = mean3(o[i], o[IIJ[i][(i + 1) % 3]], o[IIJ[i][(i + 2) % 3]]);
        for (int k = 0; k < 3; k++) {
            if (ci->cross != TC_CROSS_SALESIN) {
                o[CIJ[k]] = cab_linear(o, k, (k + 1) % 3, g->tau[k]);
            } else {
                double amp;
                int rc = cab_salesin(ci, t, k, ch, g, o, &o[CIJ[k]], &amp);
                note_project(ps, amp, t, k);
                if (rc == 0) continue;
                char path[48];
                tc__elem_path(m, t, path, sizeof path);
                if (ci->wedges == TC_WEDGES_LITERAL && amp > PROJECT_LIMIT)
                    return tc_diags_add(dg, TC_SEV_ERROR, path,
                                        "cross_boundary \"salesin\" with wedges \"literal\": Project is singular on "
                                        "edge %d (it would amplify the gradient %.3gx, limit %.0fx); use wedges "
                                        "\"corrected\"", k, amp, PROJECT_LIMIT);
                return tc_diags_add(dg, TC_SEV_ERROR, path, "the cross-boundary ordinate of edge %d overflows", k);
            }
        }
        tc__ct_close(o);
    }
    return TC_OK;
}

void tc__ct_close(double *o) {
    for (int i = 0; i < 3; i++) o[CCI[i]] = mean3(o[CII[i]], o[CIJ[i]], o[CIJ[(i + 2) % 3]]);
    o[CT_CCC] = mean3(o[CT_CCU], o[CT_CCV], o[CT_CCW]);
}

/* One part of the triangles (tc__parallel_for): its own Project statistics
 * and the first triangle that failed (INT32_MAX: none); a part stops there. */
typedef struct {
    const tc__ct_input *ci;
    double *coef;
    project_stats ps[TC_PARALLEL_MAX];
    int32_t first_bad[TC_PARALLEL_MAX];
} ordinates_pass;

static void local_setup(const tc__ct_input *ci, int32_t t, geom *g) {
    local_geometry(ci->m, t, g);
    for (int k = 0; k < 3; k++)
        g->tau[k] = ci->cross == TC_CROSS_AFFINE ? tau_affine(ci, t, k, g) : tau_normal(g, k, (k + 1) % 3, (k + 2) % 3);
}

static void ordinates_part(void *ctx, int32_t lo, int32_t hi, int part) {
    ordinates_pass *op = ctx;
    op->ps[part] = (project_stats){0, -1, 0, 0};
    op->first_bad[part] = INT32_MAX;
    for (int32_t t = lo; t < hi; t++) {
        geom g;
        local_setup(op->ci, t, &g);
        if (triangle(op->ci, t, &g, op->coef, &op->ps[part], NULL) != TC_OK) {
            op->first_bad[part] = t;
            return;
        }
    }
}

int tc__ct_ordinates(const tc__ct_input *ci, double *coef, tc_diags *dg) {
    ordinates_pass op;
    op.ci = ci, op.coef = coef;
    int parts = tc__parallel_parts(ci->threads, ci->m->nt, 1024);
    tc__parallel_for(ci->threads, ci->m->nt, 1024, ordinates_part, &op);
    project_stats ps = {0, -1, 0, 0};
    for (int p = 0; p < parts; p++) {
        if (op.first_bad[p] != INT32_MAX) { /* the first failure, reported as the serial loop does */
            geom g;
            local_setup(ci, op.first_bad[p], &g);
            return triangle(ci, op.first_bad[p], &g, coef, &ps, dg);
        }
        const project_stats *q = &op.ps[p]; /* merged in triangle order: the first largest wins */
        if (q->count && (ps.count == 0 || q->amp > ps.amp)) ps.amp = q->amp, ps.t = q->t, ps.edge = q->edge;
        ps.count += q->count;
    }
    warn_projects(ci, &ps, dg);
    return TC_OK;
}

/* ---- evaluation ---- */

/* The ten ordinates of the subtriangle opposite corner m, as b300 b030 b003
 * b210 b120 b201 b021 b102 b012 b111 with a = m+1, b = m+2 and c the centroid. */
const int tc__ct_sub[3][10] = {
    {CT_VVV, CT_WWW, CT_CCC, CT_VVW, CT_VWW, CT_CVV, CT_CWW, CT_CCV, CT_CCW, CT_CVW},
    {CT_WWW, CT_UUU, CT_CCC, CT_UWW, CT_UUW, CT_CWW, CT_CUU, CT_CCW, CT_CCU, CT_CUW},
    {CT_UUU, CT_VVV, CT_CCC, CT_UUV, CT_UVV, CT_CUU, CT_CVV, CT_CCU, CT_CCV, CT_CUV},
};

void tc__ct_eval_sub(const double o[TC_CT_ORDINATES], int sub, const double lam[3], const double dl1[2],
                     const double dl2[2], double *value, double *grad) {
    TC_ASSERT(sub >= 0 && sub < 3);
    const int *s = tc__ct_sub[sub];
    int a = (sub + 1) % 3, b = (sub + 2) % 3;
    double A = lam[a] - lam[sub], B = lam[b] - lam[sub], C = 3 * lam[sub];
    /* Difference form about the ordinate of the corner with the largest weight:
     * exact at the corners (the other weights are 0) and for constant data
     * (every difference is 0); the gradient is unchanged by the shift. */
    double ref = A >= B ? (A >= C ? o[s[0]] : o[s[2]]) : (B >= C ? o[s[1]] : o[s[2]]);
    double b300 = o[s[0]] - ref, b030 = o[s[1]] - ref, b003 = o[s[2]] - ref, b210 = o[s[3]] - ref;
    double b120 = o[s[4]] - ref, b201 = o[s[5]] - ref, b021 = o[s[6]] - ref, b102 = o[s[7]] - ref;
    double b012 = o[s[8]] - ref, b111 = o[s[9]] - ref;
    /* One de Casteljau step: the quadratics qa, qb, qc (a third of the partial
     * derivatives), then the value. */
    double qa = A * A * b300 + B * B * b120 + C * C * b102 + 2 * (A * B * b210 + A * C * b201 + B * C * b111);
    double qb = A * A * b210 + B * B * b030 + C * C * b012 + 2 * (A * B * b120 + A * C * b111 + B * C * b021);
    double qc = A * A * b201 + B * B * b021 + C * C * b003 + 2 * (A * B * b111 + A * C * b102 + B * C * b012);
    *value = ref + (A * qa + B * qb + C * qc);
    if (!grad) return;
    double D[3]; /* d value / d lam */
    D[a] = 3 * qa;
    D[b] = 3 * qb;
    D[sub] = 3 * (3 * qc - qa - qb);
    grad[0] = (D[1] - D[0]) * dl1[0] + (D[2] - D[0]) * dl2[0];
    grad[1] = (D[1] - D[0]) * dl1[1] + (D[2] - D[0]) * dl2[1];
}

void tc__ct_eval(const double *o, const tc__eval_point *at, double *value, double *grad) {
    const double *lam = at->lam;
    int sub = lam[0] <= lam[1] ? (lam[0] <= lam[2] ? 0 : 2) : (lam[1] <= lam[2] ? 1 : 2);
    tc__ct_eval_sub(o, sub, lam, at->dl1, at->dl2, value, grad);
}
