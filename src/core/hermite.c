/* hermite.c — bicubic Hermite patches over quads (Bastos, Sousa & Ferreira): corner data and
 * twists from shared tangent planes, Bézier ordinates, evaluation through the inverse bilinear map. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/alloc.h"
#include "core/fhypot.h"
#include "core/hermite.h"
#include "core/lsq.h"
#include "core/minmax.h"
#include "core/pipeline.h"
#include "core/recon.h"
#include "core/wedge.h"

const char *const tc__hermite_labels[TC_HERMITE_COEFS] = {
    "b00", "b01", "b02", "b03", "b10", "b11", "b12", "b13", "b20", "b21", "b22",
    "b23", "b30", "b31", "b32", "b33", "xb",  "yb",  "xc",  "yc",  "xd",  "yd"};

/* Quad corner k sits at (s, t) = (KS[k], KT[k]) of the parameter square. */
static const int KS[4] = {0, 1, 1, 0}, KT[4] = {0, 0, 1, 1};

/* ---- the bilinear map and its inverse ---- */

/* Residual x(s, t) - x of the map s B + t D + st E, and its length. */
static double map_residual(const double B[2], const double D[2], const double E[2], const double x[2], double s,
                           double t, double r[2]) {
    r[0] = s * B[0] + t * D[0] + s * t * E[0] - x[0];
    r[1] = s * B[1] + t * D[1] + s * t * E[1] - x[1];
    return tc__hypot(r[0], r[1]);
}

/* Newton's method on the map, keeping only steps that shrink the residual,
 * so a good start is never made worse. Returns the final residual. */
static double polish(const double B[2], const double D[2], const double E[2], const double x[2], double *s,
                     double *t) {
    double r[2], res = map_residual(B, D, E, x, *s, *t, r);
    for (int it = 0; it < 4 && res > 0; it++) {
        double js[2] = {B[0] + *t * E[0], B[1] + *t * E[1]}, jt[2] = {D[0] + *s * E[0], D[1] + *s * E[1]};
        double det = tc__cross(js, jt), r1[2];
        if (!(fabs(det) > 0)) break;
        double s1 = *s - tc__cross(r, jt) / det, t1 = *t - tc__cross(js, r) / det;
        double res1 = map_residual(B, D, E, x, s1, t1, r1);
        if (!(res1 < res)) break;
        *s = s1, *t = t1, res = res1, r[0] = r1[0], r[1] = r1[1];
    }
    return res;
}

/* Real roots of a2 r^2 + a1 r + a0 without cancellation (q has the sign of
 * a1, so a0/q stays accurate when a2 -> 0: the near-parallelogram case). A
 * negative discriminant is read as zero: the point lies beyond the map's
 * fold, and the double root is the parameter of the nearest folded point. */
static int roots(double a2, double a1, double a0, double r[2]) {
    double disc = a1 * a1 - 4 * a2 * a0;
    double q = -0.5 * (a1 + copysign(sqrt(disc > 0 ? disc : 0), a1));
    int n = 0;
    if (q != 0) r[n++] = a0 / q;
    if (a2 != 0) r[n++] = q != 0 ? q / a2 : 0;
    return n;
}

/* How far (s, t) lies outside [0, 1]^2 (0 inside). */
static double outside(double s, double t) {
    return tc__fmax(0, tc__fmax(-s, s - 1)) + tc__fmax(0, tc__fmax(-t, t - 1));
}

typedef struct {
    double s, t, res, out;
    int ok;
} candidate;

/* A candidate (s, t) whose residual is at most this, times max(1, |x|), on the
 * quad scaled to size ~1 is an exact solution: the map and Newton's polish take a
 * few dozen roundings of numbers of size ~1, so an exact root lands within tens
 * of ulps, while a wrong root of the quadratics misses by the quad's size. */
#define INVERSE_EXACT (64 * DBL_EPSILON)

/* A parameter this little outside [0, 1] is rounding of a point on the square's
 * side (the roots' terms are of size ~1, each rounded by ~1e-16; a few dozen of
 * them stay below 1e-14): it is placed on the side, so points of the quad are
 * never evaluated as its extension. Far below any distance an extension is asked
 * at. The value hermite.h states. */
#define SQUARE_SNAP 1e-10

/* Keeps c in *best if it is a better answer: an exact solution (residual at
 * rounding level) beats an inexact one, then the nearer to the square wins. */
static void consider(candidate *best, candidate c, double tol) {
    if (!isfinite(c.s) || !isfinite(c.t) || !isfinite(c.res)) return;
    c.out = outside(c.s, c.t);
    c.ok = 1;
    int exact = c.res <= tol, best_exact = best->ok && best->res <= tol;
    if (!best->ok || exact > best_exact || (exact == best_exact && (exact ? c.out < best->out : c.res < best->res)))
        *best = c;
}

/* The candidates from one of the two quadratics: `swap` solves for s first
 * (the t-quadratic with the roles of B and D exchanged). */
static void candidates_from(const double B[2], const double D[2], const double E[2], const double x[2], int swap,
                            double tol, candidate *best) {
    const double *U = swap ? D : B, *V = swap ? B : D; /* x = u U + v V + uv E */
    double r[2];
    /* (x - vV) x (U + vE) = 0: the quadratic in v. */
    int n = roots(-tc__cross(V, E), tc__cross(x, E) - tc__cross(V, U), tc__cross(x, U), r);
    for (int i = 0; i < n; i++) {
        double v = r[i], w[2] = {U[0] + v * E[0], U[1] + v * E[1]}, y[2] = {x[0] - v * V[0], x[1] - v * V[1]};
        double u = tc__dot(y, w) / tc__dot(w, w);
        candidate c = {swap ? v : u, swap ? u : v, 0, 0, 0};
        c.res = polish(B, D, E, x, &c.s, &c.t);
        consider(best, c, tol);
    }
}

void tc__bilinear_inverse(const double P[4][2], const double d[2], double par[2]) {
    for (int k = 0; k < 4; k++)
        if (d[0] == P[k][0] && d[1] == P[k][1]) { /* corners exactly: interpolation is exact */
            par[0] = KS[k], par[1] = KT[k];
            return;
        }
    /* Scaled so the quad has size ~1: tolerances are relative and no product overflows. */
    double L = 0;
    for (int k = 1; k < 4; k++) L = tc__fmax(L, tc__fmax(fabs(P[k][0]), fabs(P[k][1])));
    double B[2] = {P[1][0] / L, P[1][1] / L}, D[2] = {P[3][0] / L, P[3][1] / L};
    double E[2] = {(P[2][0] - P[1][0] - P[3][0]) / L, (P[2][1] - P[1][1] - P[3][1]) / L};
    double x[2] = {d[0] / L, d[1] / L}, tol = INVERSE_EXACT * tc__fmax(1, tc__hypot(x[0], x[1]));
    candidate best = {0, 0, INFINITY, INFINITY, 0};
    candidates_from(B, D, E, x, 0, tol, &best);
    candidates_from(B, D, E, x, 1, tol, &best);
    if (!best.ok) { /* every root overflowed: start Newton from the parallelogram's answer */
        candidate c = {tc__cross(x, D) / tc__cross(B, D), tc__cross(B, x) / tc__cross(B, D), 0, 0, 0};
        if (!isfinite(c.s) || !isfinite(c.t)) c.s = c.t = 0;
        c.res = polish(B, D, E, x, &c.s, &c.t);
        consider(&best, c, tol);
    }
    par[0] = best.ok ? best.s : 0, par[1] = best.ok ? best.t : 0;
    for (int i = 0; i < 2; i++) { /* rounding just outside the square lands on its side */
        if (par[i] < 0 && par[i] >= -SQUARE_SNAP) par[i] = 0;
        if (par[i] > 1 && par[i] <= 1 + SQUARE_SNAP) par[i] = 1;
    }
}

/* ---- evaluation ---- */

/* Cubic Bernstein polynomials at u and their derivatives. At u = 0 and u = 1
 * they are exactly (1, 0, 0, 0) and (0, 0, 0, 1), so corners are exact. */
static void bernstein(double u, double b[4], double db[4]) {
    double v = 1 - u;
    b[0] = v * v * v, b[1] = 3 * u * v * v, b[2] = 3 * u * u * v, b[3] = u * u * u;
    db[0] = -3 * v * v, db[1] = 3 * v * (v - 2 * u), db[2] = 3 * u * (2 * v - u), db[3] = 3 * u * u;
}

/* The map's Jacobian columns x_s, x_t at (s, t). */
static void jacobian(const double P[4][2], double s, double t, double xs[2], double xt[2]) {
    for (int i = 0; i < 2; i++) {
        double e = P[2][i] - P[1][i] - P[3][i];
        xs[i] = P[1][i] + t * e;
        xt[i] = P[3][i] + s * e;
    }
}

/* |sin| of the angle between x_s and x_t below which the Jacobian counts as
 * singular: inverting it amplifies rounding by 1/sin, so below 1e-12 (geom.h's
 * TC_COLLINEAR_TOL, the same test on edge directions) the gradient would be
 * mostly rounding; there the map is folded, which happens only in extension. */
#define JACOBIAN_MIN_SIN 1e-12

void tc__hermite_eval(const double *o, const tc__eval_point *at, double *value, double *grad) {
    const double *g = o + TC_HERMITE_GEOM;
    const double P[4][2] = {{0, 0}, {g[0], g[1]}, {g[2], g[3]}, {g[4], g[5]}};
    double par[2], bs[4], dbs[4], bt[4], dbt[4], v = 0, fs = 0, ft = 0;
    tc__bilinear_inverse(P, at->d, par);
    bernstein(par[0], bs, dbs);
    bernstein(par[1], bt, dbt);
    /* Offsets from the nearest corner's value (the weights sum to 1, the
     * derivative weights to 0): constant data exact even subnormal, and that
     * corner's value exactly at the corner. */
    double base = o[4 * (par[0] > 0.5 ? 3 : 0) + (par[1] > 0.5 ? 3 : 0)];
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            double b = o[4 * i + j] - base;
            v += bs[i] * bt[j] * b;
            fs += dbs[i] * bt[j] * b;
            ft += bs[i] * dbt[j] * b;
        }
    *value = base + v;
    if (!grad) return;
    /* grad f = J^-T (f_s, f_t). The Jacobian is non-singular on the square of a
     * convex quad; beyond it (extension) it may not be, so a singular one is
     * taken at the nearest point of the square instead. */
    double xs[2], xt[2];
    jacobian(P, par[0], par[1], xs, xt);
    double det = tc__cross(xs, xt);
    if (!(fabs(det) > JACOBIAN_MIN_SIN * tc__hypot(xs[0], xs[1]) * tc__hypot(xt[0], xt[1]))) {
        jacobian(P, tc__fmin(1, tc__fmax(0, par[0])), tc__fmin(1, tc__fmax(0, par[1])), xs, xt);
        det = tc__cross(xs, xt);
    }
    grad[0] = (fs * xt[1] - ft * xs[1]) / det;
    grad[1] = (ft * xs[0] - fs * xt[0]) / det;
}

/* ---- twists ---- */

/* Relative rank tolerance of the twist fit (tc__lsq_solve's rtol): rows are unit
 * directions, so a column below 1e-9 of the largest means the wedge's
 * neighbours do not determine H, not a small second derivative; the fit then
 * fails and H is 0. The bound the tangent fit uses (tanfit.c's FIT_RTOL). */
#define TWIST_RTOL 1e-9

/* Per wedge and channel the symmetric H = [hxx hxy; hxy hyy] that best maps
 * the offsets d_j of the wedge's neighbouring corners (the other corners of
 * its faces, each side of a delimiter being its own corner) to the change of
 * their tangent planes: min sum |(g_j - g_v) - H d_j|^2 / |d_j|^2. Rows are
 * unit directions, so scale does not matter. Exact when the planes are
 * exact for a quadratic; one H per wedge, shared by all its quad corners. */
static void wedge_hessian(const struct tc_mesh *m, const tc__wedge_set *ws, const tc__wedge *w, const double *planes,
                          double *H) {
    double A[TC_LSQ_MAXROWS][TC_LSQ_MAXCOLS] = {{0}}, Bm[TC_LSQ_MAXROWS][TC_LSQ_MAXRHS], X[TC_LSQ_MAXCOLS][TC_LSQ_MAXRHS];
    int32_t seen[TC_LSQ_MAXROWS / 2];
    int rows = 0, nc = m->nc;
    const double *gv = planes + (size_t)ws->corners[w->first] * 2 * (size_t)nc, *pv = tc__vxy(m, w->v);
    for (int32_t i = 0; i < w->count && rows + 2 <= TC_LSQ_MAXROWS; i++) {
        int32_t c = ws->corners[w->first + i], t = c / 3;
        for (int j = 1; j <= 2 && rows + 2 <= TC_LSQ_MAXROWS; j++) {
            int32_t cj = 3 * t + (c % 3 + j) % 3, dup = 0;
            for (int q = 0; q < rows / 2; q++) dup |= seen[q] == ws->of_corner[cj];
            if (dup) continue;
            seen[rows / 2] = ws->of_corner[cj];
            double dj[2];
            tc__sub(dj, tc__vxy(m, m->tri[cj]), pv);
            double len = tc__hypot(dj[0], dj[1]), u[2] = {dj[0] / len, dj[1] / len};
            const double *gj = planes + (size_t)cj * 2 * (size_t)nc;
            A[rows][0] = u[0], A[rows][1] = u[1], A[rows][2] = 0;
            A[rows + 1][0] = 0, A[rows + 1][1] = u[0], A[rows + 1][2] = u[1];
            for (int ch = 0; ch < nc; ch++) {
                Bm[rows][ch] = (gj[2 * ch] - gv[2 * ch]) / len;
                Bm[rows + 1][ch] = (gj[2 * ch + 1] - gv[2 * ch + 1]) / len;
            }
            rows += 2;
        }
    }
    int ok = tc__lsq_solve(A, rows, 3, Bm, nc, TWIST_RTOL, X) == 0; /* a face's two edges give rank 3 */
    for (int ch = 0; ch < nc; ch++)
        for (int k = 0; k < 3; k++) H[3 * ch + k] = ok && isfinite(X[k][ch]) ? X[k][ch] : 0;
}

/* What the twists are made of: given hessians (per vertex, always first),
 * else per-wedge estimates (twist estimate) or none (H = 0, twist zero). */
typedef struct {
    const struct tc_mesh *m;
    const double *planes;  /* [3nt][nc][2] corner planes */
    tc__wedge_set ws;   /* the wedges the planes were built on */
    double *H;         /* [nw][nc][3] estimated, or NULL */
    double *keep;      /* [nw][nc] the share of x_s' H x_t kept (range limiter), or NULL: all */
} twists;

static int twists_build(const struct tc_recon *r, twists *tw) {
    const struct tc_mesh *m = r->m;
    memset(tw, 0, sizeof *tw);
    tw->m = m, tw->planes = r->planes;
    int rc = tc__wedges_build_on(m, r->method->honour, r->opt.threads, &tw->ws);
    if (rc != TC_OK || r->opt.twist != TC_TWIST_ESTIMATE) return rc;
    tw->H = tc__malloc((size_t)tw->ws.nw * (size_t)m->nc, 3 * sizeof *tw->H);
    if (!tw->H) return TC_ENOMEM;
    for (int32_t w = 0; w < tw->ws.nw; w++)
        wedge_hessian(m, &tw->ws, &tw->ws.w[w], r->planes, tw->H + (size_t)w * (size_t)m->nc * 3);
    return TC_OK;
}

static void twists_free(twists *tw) {
    tc__wedges_free(&tw->ws);
    tc__free(tw->H);
    tc__free(tw->keep);
}

/* The second derivatives at corner c (a corner id) in channel ch, or NULL (H = 0). */
static const double *hessian_at(const twists *tw, int32_t c, int ch) {
    const struct tc_mesh *m = tw->m;
    int32_t v = m->tri[c];
    if (m->hess && (!m->hess_has || m->hess_has[v])) return m->hess + tc__ix(v, m->nc, ch) * 3;
    if (tw->H) return tw->H + tc__ix(tw->ws.of_corner[c], m->nc, ch) * 3;
    return NULL;
}

/* ---- the patch of one quad ---- */

typedef struct {
    double P[4][2];   /* corners relative to a */
    double xs[4][2];  /* x_s at each corner: an edge vector of the quad */
    double xt[4][2];  /* x_t at each corner */
    double E[2];      /* x_st = a - b + c - d, zero on a parallelogram */
    int32_t corner[4];/* the corner id (3t+k) holding each quad corner's data */
} quad_geom;

static void quad_geometry(const struct tc_mesh *m, int32_t q, quad_geom *G) {
    const int32_t *v = m->quad + 4 * (size_t)q;
    const double *a = tc__vxy(m, v[0]);
    for (int k = 0; k < 4; k++) tc__sub(G->P[k], tc__vxy(m, v[k]), a);
    for (int i = 0; i < 2; i++) {
        G->E[i] = G->P[0][i] - G->P[1][i] + G->P[2][i] - G->P[3][i];
        double ab = G->P[1][i] - G->P[0][i], dc = G->P[2][i] - G->P[3][i];
        double ad = G->P[3][i] - G->P[0][i], bc = G->P[2][i] - G->P[1][i];
        G->xs[0][i] = ab, G->xs[1][i] = ab, G->xs[2][i] = dc, G->xs[3][i] = dc;
        G->xt[0][i] = ad, G->xt[1][i] = bc, G->xt[2][i] = bc, G->xt[3][i] = ad;
    }
    int32_t t0 = 3 * (2 * q), t1 = 3 * (2 * q + 1);
    G->corner[0] = t0, G->corner[1] = t0 + 1, G->corner[2] = t0 + 2, G->corner[3] = t1 + 2;
}

/* u' H w for the symmetric H = [hxx hxy; hxy hyy] held as (hxx, hxy, hyy). */
static double form(const double H[3], const double u[2], const double w[2]) {
    return u[0] * (H[0] * w[0] + H[1] * w[1]) + u[1] * (H[1] * w[0] + H[2] * w[1]);
}

/* f_st = x_s' H x_t + g . x_st: the cross derivative of f(x(s, t)), exact for
 * exact H and g; with H = 0 only the map's own curvature is kept, so linear
 * data stay exact on every quad. The range limiter keeps a share of the
 * second-order part per wedge (twists_keep). */
static double twist_of(const twists *tw, const quad_geom *G, int k, int ch, const double g[2]) {
    int32_t c = G->corner[k];
    const double *H = hessian_at(tw, c, ch);
    double t = tc__dot(g, G->E), keep = tw->keep ? tw->keep[tc__ix(tw->ws.of_corner[c], tw->m->nc, ch)] : 1;
    return H ? t + keep * form(H, G->xs[k], G->xt[k]) : t;
}

/* The 16 ordinates of channel ch: per corner, f, f + f_s/3, f + f_t/3 and the
 * inner f + f_s/3 + f_t/3 + f_st/9, each step taken towards the square's inside. */
static void patch(const twists *tw, const quad_geom *G, int ch, double *o) {
    const struct tc_mesh *m = tw->m;
    int nc = m->nc;
    for (int k = 0; k < 4; k++) {
        int32_t c = G->corner[k];
        const double *g = tw->planes + tc__ix(c, nc, ch) * 2;
        double f = m->cz[tc__ix(c, nc, ch)], fs = tc__dot(g, G->xs[k]), ft = tc__dot(g, G->xt[k]);
        double fst = twist_of(tw, G, k, ch, g);
        int i = 3 * KS[k], j = 3 * KT[k], si = KS[k] ? -1 : 1, sj = KT[k] ? -1 : 1;
        o[4 * i + j] = f;
        o[4 * (i + si) + j] = f + si * fs / 3;
        o[4 * i + j + sj] = f + sj * ft / 3;
        o[4 * (i + si) + j + sj] = f + (si * fs + sj * ft) / 3 + si * sj * fst / 9;
    }
    for (int k = 1; k < 4; k++) o[TC_HERMITE_GEOM + 2 * (k - 1)] = G->P[k][0], o[TC_HERMITE_GEOM + 2 * k - 1] = G->P[k][1];
}

static void fill(const twists *tw, double *coef) {
    const struct tc_mesh *m = tw->m;
    size_t per_tri = (size_t)m->nc * TC_HERMITE_COEFS;
    for (int32_t q = 0; q < m->nq; q++) {
        quad_geom G;
        quad_geometry(m, q, &G);
        double *o = coef + (size_t)(2 * q) * per_tri;
        for (int ch = 0; ch < m->nc; ch++) patch(tw, &G, ch, o + (size_t)ch * TC_HERMITE_COEFS);
        memcpy(o + per_tri, o, per_tri * sizeof *o); /* both halves carry the patch */
    }
}

/* ---- the twist limiter ---- */

/* (g_j - g_k) . x: how much the slope along x changes from corner k's plane
 * to corner j's, in channel ch. */
static double plane_change(const twists *tw, const quad_geom *G, int k, int j, int ch, const double x[2]) {
    const double *gk = tw->planes + tc__ix(G->corner[k], tw->m->nc, ch) * 2;
    const double *gj = tw->planes + tc__ix(G->corner[j], tw->m->nc, ch) * 2;
    return (gj[0] - gk[0]) * x[0] + (gj[1] - gk[1]) * x[1];
}

/* The finite-difference twist of the quad at corner k: |(g_s - g) . x_t| +
 * |(g_t - g) . x_s|, g_s and g_t the planes at the ends of the quad's s- and
 * t-edges from k. Each term equals x_s' H x_t for a quadratic on any convex quad. */
static double fd_twist(const twists *tw, const quad_geom *G, int k, int ch) {
    static const int partner_s[4] = {1, 0, 3, 2}, partner_t[4] = {3, 2, 1, 0};
    return fabs(plane_change(tw, G, k, partner_s[k], ch, G->xt[k])) +
           fabs(plane_change(tw, G, k, partner_t[k], ch, G->xs[k]));
}

/* An estimated H is a second derivative at a point; on a quad much larger than
 * the scale its neighbours resolve (a sliver beside a big cell) x_s' H x_t
 * can exceed anything the quad's own data support and the patch overshoots
 * by orders of magnitude (1e5 on the stiff scene's disc meshes). Each wedge's
 * H is therefore scaled down (never up) until, at every quad corner in it,
 * |x_s' H x_t| <= max(2 fd, fdmax): fd that corner's finite-difference twist,
 * fdmax the largest of the wedge's (so one corner where the twist happens to
 * vanish cannot flatten its neighbours'). For a quadratic fd = 2 |x_s' H x_t|
 * on any convex quad, so the bound never binds; on smooth, resolved data it
 * does not either (the unit tests' figures are unchanged by it). Scaling H per
 * wedge keeps one bilinear form per vertex: parallelograms stay C1.
 * Pass 0 gathers fdmax per wedge and channel, pass 1 the scale. */
static void limit_pass(const twists *tw, int pass, double *fdmax, double *scale) {
    const struct tc_mesh *m = tw->m;
    for (int32_t q = 0; q < m->nq; q++) {
        quad_geom G;
        quad_geometry(m, q, &G);
        for (int k = 0; k < 4; k++)
            for (int ch = 0; ch < m->nc; ch++) {
                size_t w = tc__ix(tw->ws.of_corner[G.corner[k]], m->nc, ch);
                double fd = fd_twist(tw, &G, k, ch);
                if (pass == 0) {
                    fdmax[w] = tc__fmax(fdmax[w], fd);
                    continue;
                }
                double t = fabs(form(tw->H + 3 * w, G.xs[k], G.xt[k])), bound = tc__fmax(2 * fd, fdmax[w]);
                if (t > bound) scale[w] = tc__fmin(scale[w], bound / t);
            }
    }
}

static void limit_twists(twists *tw) {
    size_t n = (size_t)tw->ws.nw * (size_t)tw->m->nc;
    double *fdmax = tc__calloc(n, sizeof *fdmax), *scale = tc__malloc(n, sizeof *scale);
    if (fdmax && scale) { /* else unlimited: still finite */
        for (size_t i = 0; i < n; i++) scale[i] = 1;
        limit_pass(tw, 0, fdmax, scale);
        limit_pass(tw, 1, fdmax, scale);
        for (size_t w = 0; w < n; w++)
            for (size_t i = 0; i < 3; i++) tw->H[3 * w + i] *= scale[w];
    }
    tc__free(fdmax);
    tc__free(scale);
}

/* ---- the range limiter ---- */

/* Quad corner k's steps into the square: +1 from s = 0 (t = 0), -1 from 1. */
static void corner_signs(int k, double *si, double *sj) {
    *si = KS[k] ? -1 : 1;
    *sj = KT[k] ? -1 : 1;
}

/* The plane of a quad corner sets three ordinates: f + si f_s/3, f + sj f_t/3
 * and the inner one's plane part, f + (si f_s + sj f_t)/3 + si sj g.x_st/9. */
static int hermite_dirs(const void *ctx, int32_t c, double d[TC_PLANE_DIRS_MAX][2]) {
    const struct tc_mesh *m = ctx;
    int32_t t = c / 3;
    int k = tc__quad_corner_of(t, c % 3);
    quad_geom G;
    quad_geometry(m, t / 2, &G);
    double si, sj;
    corner_signs(k, &si, &sj);
    for (int i = 0; i < 2; i++) {
        d[0][i] = si * G.xs[k][i] / 3;
        d[1][i] = sj * G.xt[k][i] / 3;
        d[2][i] = d[0][i] + d[1][i] + si * sj * G.E[i] / 9;
    }
    return 3;
}

/* The inner ordinate of quad corner k is its plane part (inside the bound
 * once the planes are limited) plus si sj keep x_s'Hx_t / 9: per wedge and
 * channel, the largest keep in [0, 1] that holds every inner ordinate in, and
 * in part[] the largest second-order part (what keep < 1 moves by 1 - keep). */
static void keep_pass(twists *tw, const tc__bounds *b, double *keep, double *largest) {
    const struct tc_mesh *m = tw->m;
    int nc = m->nc;
    for (int32_t q = 0; q < m->nq; q++) {
        quad_geom G;
        quad_geometry(m, q, &G);
        for (int k = 0; k < 4; k++)
            for (int ch = 0; ch < nc; ch++) {
                int32_t c = G.corner[k];
                const double *H = hessian_at(tw, c, ch), *g = tw->planes + tc__ix(c, nc, ch) * 2;
                if (!H) continue;
                double si, sj, f = m->cz[tc__ix(c, nc, ch)];
                corner_signs(k, &si, &sj);
                double base = f + (si * tc__dot(g, G.xs[k]) + sj * tc__dot(g, G.xt[k])) / 3 + si * sj * tc__dot(g, G.E) / 9;
                double part = si * sj * form(H, G.xs[k], G.xt[k]) / 9;
                size_t i = tc__ix(2 * q, nc, ch), w = tc__ix(tw->ws.of_corner[c], nc, ch);
                largest[w] = tc__fmax(largest[w], fabs(part));
                double room = part > 0 ? b->hi[i] - base : b->lo[i] - base; /* same sign as part, or 0 */
                if (tc__outside(base + part, b->lo[i], b->hi[i], b->tol[ch]) > 0)
                    keep[w] = tc__fmin(keep[w], tc__fmax(0, room / part));
            }
    }
}

static int limit_twists_to_range(const struct tc_recon *r, twists *tw, tc_diags *dg) {
    const struct tc_mesh *m = r->m;
    size_t n = (size_t)tw->ws.nw * (size_t)m->nc;
    tc__bounds b;
    int rc = tc__bounds_build(m, &tw->ws, m->cz, r->planes, r->opt.tangents, r->opt.range, 1, &b);
    tw->keep = rc == TC_OK ? tc__malloc(n, sizeof *tw->keep) : NULL;
    double *largest = rc == TC_OK ? tc__calloc(n, sizeof *largest) : NULL;
    if (rc == TC_OK && (!tw->keep || !largest)) rc = TC_ENOMEM;
    if (rc == TC_OK) {
        for (size_t i = 0; i < n; i++) tw->keep[i] = 1;
        keep_pass(tw, &b, tw->keep, largest);
        tc__range_stats rs;
        tc__range_stats_init(&rs);
        for (size_t i = 0; i < n; i++) /* reported where an inner ordinate moved materially */
            if ((1 - tw->keep[i]) * largest[i] > TC_RANGE_MATERIAL * b.span[i % (size_t)m->nc])
                tc__range_note(&rs.twists, 1 - tw->keep[i], tw->ws.w[i / (size_t)m->nc].v, -1);
        tc__range_warn(m, &rs, r->opt.range, dg);
    }
    tc__free(largest);
    tc__bounds_free(&b);
    return rc;
}

/* Tangent planes as for clough-tocher (given / midpoints / estimate, one per
 * wedge, wedges split at every flagged edge): the values along a patch edge
 * depend only on its ends' values and slopes along it, which the coupled
 * planes of a C0 edge share, so C0 edges keep their kink and C-1 their jump. */
int tc__hermite_build(struct tc_recon *r, tc_diags *dg) {
    tc__plane_use use = {hermite_dirs, r->m, 1};
    int rc = tc__planes_build(r, &use, dg);
    if (rc != TC_OK) return rc;
    twists tw;
    rc = twists_build(r, &tw);
    if (rc == TC_OK && tw.H) limit_twists(&tw);
    if (rc == TC_OK && r->opt.range != TC_RANGE_FREE) rc = limit_twists_to_range(r, &tw, dg);
    if (rc == TC_OK) fill(&tw, r->coef);
    twists_free(&tw);
    return rc;
}
