/* powell_sabin.c — the C1 quadratic Powell-Sabin 6-split: each triangle cut at its incenter and at one
 * point per edge into six quadratic Bézier pieces, built from corner values and wedge tangent planes. */

/* The split. Triangle (u, v, w) = (V0, V1, V2); edge k joins V_k and V_{k+1}. Z is the incenter, with
 * barycentrics zeta_i = |edge opposite V_i| / perimeter. Edge k is split at R_k = (1 - a_k) V_k + a_k V_{k+1}:
 * on a smooth interior edge (C1, or C0 since a quadratic C1 scheme cannot keep a kink) R_k is where the
 * segment Z Z' to the neighbour's incenter crosses the edge; on the boundary and on C-1 edges (each side
 * reconstructed on its own) it is the midpoint. The six pieces are (V_k, R_k, Z) and (V_{k+1}, R_k, Z);
 * piece 2k + h lies on edge k next to V_{k+h}.
 *
 * Why Z Z' crosses the edge strictly inside it: the incircle touches the edge line at its touch point T,
 * at parameter tau = (|ab| + |ac| - |bc|) / (2 |ab|) from a, strictly in (0, 1) by the strict triangle
 * inequality, and Z is the inradius rho away from T along the perpendicular. Z' stands rho' away from T'
 * on the other side (the mesh has no folds), so by similar triangles the crossing point divides T T' as
 * rho : rho', R = (rho' T + rho T') / (rho + rho'): a convex combination of two points strictly inside the
 * edge. split_canonical computes exactly this, tau without cancellation.
 *
 * The ordinates (quadratic Bézier form on each piece; "p:q" is the ordinate at the midpoint of p and q).
 *  - V_i: the corner value. i:ij and i:z: on V_i's tangent plane, z_i + g_i.(X - V_i)/2 for X = R or Z,
 *    which makes the gradient of every piece at V_i the wedge's plane (C1 at the vertex, within a wedge).
 *  - R_k = (1 - a) k:k(k+1) + a (k+1):k(k+1) and z:R_k = (1 - a) k:z + a (k+1):z, and z = sum zeta_i i:z.
 *    These are the C1 conditions across the inner edges R_k Z: the barycentrics of V_{k+1} in
 *    (R_k, Z, V_k) are (1/a, 0, -(1-a)/a), and Farin's condition on the two ordinates next to the edge
 *    reads exactly so. Then every ordinate at (Z + X)/2 is an affine function G(X) (G fits the three i:z;
 *    z = G(Z), z:R_k = G(R_k)), and every ordinate at (V_i + X)/2 is V_i's plane: both are affine, which
 *    is Farin's condition across the inner edges V_i Z as well. So the triangle's piece is C1 inside.
 *  - Across a smooth edge, Z' = mu R + (1 - mu) Z (collinear); the ordinates on the edge (corner values,
 *    the vertex planes, R) are shared, and the two conditions are again the affine identities above, with
 *    the same mu seen from both ends of the edge: C1 across it. Quadratics with exact gradients satisfy
 *    every relation, so they are reproduced.
 *
 * Coefficient layout per triangle and channel (TC_PS_COEFS = 25; u = the triangle's first vertex):
 *    0  u v w                 corner values
 *    3  u:uv v:uv v:vw w:vw w:wu u:wu    edge points next to a vertex (midpoints of V_i R)
 *    9  uv vw wu              the split points R_k
 *   12  u:z v:z w:z           midpoints of V_i Z
 *   15  z:uv z:vw z:wu        midpoints of R_k Z
 *   18  z                     the incenter Z
 *   19  zeta_u zeta_v zeta_w  geometry, not ordinates: Z's barycentrics
 *   22  alpha_uv alpha_vw alpha_wu      geometry: R_k's parameter along edge k (wu runs from w to u)
 * The geometry is repeated in every channel so a channel's block evaluates on its own. */
#include <float.h>
#include <math.h>
#include <stdio.h>

#include "core/alloc.h"
#include "core/fhypot.h"
#include "core/geom.h"
#include "core/mesh.h"
#include "core/pipeline.h"
#include "core/powell_sabin.h"
#include "core/recon.h"
#include "core/wedge.h"

enum { PS_V = 0, PS_NEAR = 3, PS_R = 9, PS_VZ = 12, PS_RZ = 15, PS_Z = 18, PS_ZETA = TC_PS_ORDINATES, PS_ALPHA = 22 };

/* The ordinate next to V_{k+h} on edge k: midpoint of V_{k+h} and R_k. */
#define PS_NEAR_OF(k, h) (PS_NEAR + 2 * (k) + (h))

const char *const tc__ps_labels[TC_PS_COEFS] = {
    "u",      "v",      "w",      "u:uv",   "v:uv",   "v:vw",     "w:vw",     "w:wu",    "u:wu",
    "uv",     "vw",     "wu",     "u:z",    "v:z",    "w:z",      "z:uv",     "z:vw",    "z:wu",
    "z",      "zeta_u", "zeta_v", "zeta_w", "alpha_uv", "alpha_vw", "alpha_wu"};

/* A piece whose share of its triangle is at the rounding of the geometry is
 * degenerate (the same 16 eps as the mesh's zero-area test). */
#define PS_TINY (16 * DBL_EPSILON)

typedef struct {
    double r[3][2];   /* corners relative to corner 0 */
    double zeta[3];   /* barycentrics of the incenter */
    double alpha[3];  /* R_k = (1 - alpha_k) V_k + alpha_k V_{k+1} */
} ps_geom;

/* ---- split geometry ---- */

/* |e||f| (1 + cos angle(e, f)). For an obtuse angle the sum cancels; there
 * (|e||f|)^2 - (e.f)^2 = (e x f)^2 turns it into a quotient of positive terms. */
static double one_plus_cos(const double e[2], const double f[2]) {
    double ef = tc__hypot(e[0], e[1]) * tc__hypot(f[0], f[1]), d = tc__dot(e, f);
    if (d >= 0) return ef + d;
    double c = tc__cross(e, f);
    return c / (ef - d) * c;
}

/* Triangle (a, b, c) given by e = b - a, f = c - a: its inradius and the
 * parameter from a to b of the incircle's touch point on ab,
 * tau = (|ab| + |ac| - |bc|) / (2|ab|) = |ac| (1 + cos a) / perimeter. */
static void incircle_touch(const double e[2], const double f[2], double *rho, double *tau) {
    double h[2] = {f[0] - e[0], f[1] - e[1]};
    double le = tc__hypot(e[0], e[1]), per = le + tc__hypot(f[0], f[1]) + tc__hypot(h[0], h[1]);
    *rho = fabs(tc__cross(e, f)) / per;
    *tau = one_plus_cos(e, f) / (le * per);
}

/* Where the segment between the incenters of triangles (lo, hi, c) and
 * (lo, hi, d) crosses edge lo -> hi, as a parameter from lo: the touch points
 * weighted by the other side's inradius (see the top of the file). Symmetric
 * in c and d bit for bit, so both triangles of the edge compute the same R. */
static double split_canonical(const struct tc_mesh *m, int32_t lo, int32_t hi, int32_t c, int32_t d) {
    const double *o = tc__vxy(m, lo);
    double e[2], f[2], g[2], rc, tc, rd, td;
    tc__sub(e, tc__vxy(m, hi), o);
    tc__sub(f, tc__vxy(m, c), o);
    tc__sub(g, tc__vxy(m, d), o);
    incircle_touch(e, f, &rc, &tc);
    incircle_touch(e, g, &rd, &td);
    return (rd * tc + rc * td) / (rc + rd);
}

/* alpha of edge k of t: the midpoint where the edge is cut (boundary, and the
 * flags the method honours: C-1), else the incenter crossing, computed from the
 * lower-numbered end. */
static double split_param(const struct tc_mesh *m, int honour, int32_t t, int k) {
    int32_t e = 3 * t + k, t2 = m->nbr[e];
    if (tc__eff_flag(m, honour, e) == TC_CM1) return 0.5;
    int32_t a = m->tri[e], b = m->tri[3 * t + (k + 1) % 3], c = m->tri[3 * t + (k + 2) % 3];
    int32_t d = m->tri[3 * t2 + (m->nbr_k[e] + 2) % 3];
    return a < b ? split_canonical(m, a, b, c, d) : 1.0 - split_canonical(m, b, a, c, d);
}

static int degenerate(const struct tc_mesh *m, int32_t t, const ps_geom *g, tc_diags *dg) {
    char path[48];
    tc__elem_path(m, t, path, sizeof path);
    for (int i = 0; i < 3; i++)
        if (!(g->zeta[i] >= PS_TINY))
            return tc_diags_add(dg, TC_SEV_ERROR, path,
                                "powell-sabin: the 6-split is degenerate, the edge opposite corner %d is %.3g of "
                                "the perimeter", i, g->zeta[i]);
    for (int k = 0; k < 3; k++)
        if (!(g->alpha[k] >= PS_TINY && 1 - g->alpha[k] >= PS_TINY))
            return tc_diags_add(dg, TC_SEV_ERROR, path,
                                "powell-sabin: the 6-split is degenerate, edge %d [%d, %d] is split at %.3g of its "
                                "length (this triangle or its neighbour is too thin there)",
                                k, (int)m->tri[3 * t + k], (int)m->tri[3 * t + (k + 1) % 3], g->alpha[k]);
    return TC_OK;
}

/* Local corners, incenter barycentrics and split parameters of triangle t;
 * TC_EINVAL (naming t) if a piece is degenerate. */
static int geometry(const struct tc_mesh *m, int honour, int32_t t, ps_geom *g, tc_diags *dg) {
    const int32_t *v = m->tri + 3 * (size_t)t;
    double len[3], per = 0;
    g->r[0][0] = g->r[0][1] = 0;
    tc__sub(g->r[1], tc__vxy(m, v[1]), tc__vxy(m, v[0]));
    tc__sub(g->r[2], tc__vxy(m, v[2]), tc__vxy(m, v[0]));
    for (int k = 0; k < 3; k++) {
        double e[2];
        tc__sub(e, g->r[(k + 1) % 3], g->r[k]);
        per += len[k] = tc__hypot(e[0], e[1]);
    }
    for (int i = 0; i < 3; i++) g->zeta[i] = len[(i + 1) % 3] / per;
    for (int k = 0; k < 3; k++) g->alpha[k] = split_param(m, honour, t, k);
    return degenerate(m, t, g, dg);
}

/* ---- ordinates ---- */

/* The value at V_i + d/2 of the tangent plane of corner i (value z, gradient gi). */
static double half_step(double z, const double gi[2], const double d[2]) {
    return z + 0.5 * (gi[0] * d[0] + gi[1] * d[1]);
}

/* o[TC_PS_COEFS] of one channel from corner values z[3] and planes gr[3][2]. */
static void ordinates(const ps_geom *g, const double z[3], const double *const gr[3], double *o) {
    for (int i = 0; i < 3; i++) {
        double dz[2] = {0, 0}; /* Z - V_i = sum_j zeta_j (V_j - V_i) */
        for (int j = 0; j < 3; j++) {
            dz[0] += g->zeta[j] * (g->r[j][0] - g->r[i][0]);
            dz[1] += g->zeta[j] * (g->r[j][1] - g->r[i][1]);
        }
        o[PS_V + i] = z[i];
        o[PS_VZ + i] = half_step(z[i], gr[i], dz);
        o[PS_ZETA + i] = g->zeta[i];
    }
    for (int k = 0; k < 3; k++) {
        int j = (k + 1) % 3;
        double a = g->alpha[k], e[2], to_r[2], back[2];
        tc__sub(e, g->r[j], g->r[k]);
        to_r[0] = a * e[0], to_r[1] = a * e[1];                     /* R_k - V_k */
        back[0] = -(1 - a) * e[0], back[1] = -(1 - a) * e[1];       /* R_k - V_j */
        o[PS_NEAR_OF(k, 0)] = half_step(z[k], gr[k], to_r);
        o[PS_NEAR_OF(k, 1)] = half_step(z[j], gr[j], back);
        /* Affine combinations in difference form: exact when the ends agree. */
        o[PS_R + k] = o[PS_NEAR_OF(k, 0)] + a * (o[PS_NEAR_OF(k, 1)] - o[PS_NEAR_OF(k, 0)]);
        o[PS_RZ + k] = o[PS_VZ + k] + a * (o[PS_VZ + j] - o[PS_VZ + k]);
        o[PS_ALPHA + k] = a;
    }
    o[PS_Z] = o[PS_VZ] + (g->zeta[1] * (o[PS_VZ + 1] - o[PS_VZ]) + g->zeta[2] * (o[PS_VZ + 2] - o[PS_VZ]));
}

static void triangle(const struct tc_recon *r, int32_t t, const ps_geom *g) {
    const struct tc_mesh *m = r->m;
    int nc = m->nc;
    for (int ch = 0; ch < nc; ch++) {
        double z[3];
        const double *gr[3];
        for (int i = 0; i < 3; i++) {
            size_t c = 3 * (size_t)t + (size_t)i;
            z[i] = m->cz[c * (size_t)nc + (size_t)ch];
            gr[i] = r->planes + 2 * (c * (size_t)nc + (size_t)ch);
        }
        ordinates(g, z, gr, r->coef + tc__ix(t, nc, ch) * TC_PS_COEFS);
    }
}

/* ---- evaluation ---- */

/* Coordinates (a, b, c) of the point lam in the sector (V_k, V_{k+1}, Z): c is
 * Z's weight lam_w / zeta_w (w the corner opposite edge k). */
static void sector_coords(const double *o, int k, const double lam[3], double abc[3]) {
    const double *zeta = o + PS_ZETA;
    int j = (k + 1) % 3, w = (k + 2) % 3;
    abc[2] = lam[w] / zeta[w];
    abc[0] = lam[k] - zeta[k] * abc[2];
    abc[1] = lam[j] - zeta[j] * abc[2];
}

/* Quadratic on (V, R, Z) with ordinates b[6] = V, R, Z, V:R, V:Z, R:Z at
 * barycentrics s: the value, and its derivatives d[3] by s (2 q_i), of the
 * quadratic less b[0]. Worked as offsets from b[0] (the s sum to 1, so a
 * constant moves every d alike and the gradient not at all): constant data
 * comes out exact even subnormal, and at s = (1, 0, 0) the value is b[0]. */
static double quadratic(const double b[6], const double s[3], double d[3]) {
    double r = b[1] - b[0], z = b[2] - b[0], vr = b[3] - b[0], vz = b[4] - b[0], rz = b[5] - b[0];
    double q0 = s[1] * vr + s[2] * vz;
    double q1 = s[0] * vr + s[1] * r + s[2] * rz;
    double q2 = s[0] * vz + s[1] * rz + s[2] * z;
    d[0] = 2 * q0, d[1] = 2 * q1, d[2] = 2 * q2;
    return b[0] + (s[0] * q0 + s[1] * q1 + s[2] * q2);
}

void tc__ps_eval_piece(const double *o, int piece, const double lam[3], const double dl1[2], const double dl2[2],
                       double *value, double *grad) {
    int k = piece / 2, h = piece % 2, j = (k + 1) % 3, w = (k + 2) % 3, vi = h ? j : k;
    const double *zeta = o + PS_ZETA;
    double al = o[PS_ALPHA + k], be = 1 - al, abc[3], s[3], d[3], D[3];
    sector_coords(o, k, lam, abc);
    /* R_k = be V_k + al V_j: the sector's (a, b) become (vertex, R) weights. */
    s[0] = h ? abc[1] - abc[0] * (al / be) : abc[0] - abc[1] * (be / al);
    s[1] = h ? abc[0] / be : abc[1] / al;
    s[2] = abc[2];
    double b[6] = {o[PS_V + vi], o[PS_R + k], o[PS_Z], o[PS_NEAR_OF(k, h)], o[PS_VZ + vi], o[PS_RZ + k]};
    *value = quadratic(b, s, d);
    if (!grad) return;
    /* Chain rule: s from (a, b, c), then (a, b, c) from lam. */
    double da = h ? (d[1] - al * d[0]) / be : d[0];
    double db = h ? d[0] : (d[1] - be * d[0]) / al;
    D[k] = da;
    D[j] = db;
    D[w] = (d[2] - zeta[k] * da - zeta[j] * db) / zeta[w];
    grad[0] = (D[1] - D[0]) * dl1[0] + (D[2] - D[0]) * dl2[0];
    grad[1] = (D[1] - D[0]) * dl1[1] + (D[2] - D[0]) * dl2[1];
}

/* The sector holding the point is the one opposite the corner with the least
 * lam_i / zeta_i (its Z weight is that ratio and the others stay >= 0); in
 * it, the side of the line Z R_k. Corners land on their own piece with
 * barycentrics exactly (1, 0, 0), so the value there is the corner value. */
void tc__ps_eval(const double *o, const tc__eval_point *at, double *value, double *grad) {
    const double *lam = at->lam, *zeta = o + PS_ZETA;
    int w = 0;
    for (int i = 1; i < 3; i++)
        if (lam[i] * zeta[w] < lam[w] * zeta[i]) w = i;
    int k = (w + 1) % 3;
    double abc[3], al = o[PS_ALPHA + k];
    sector_coords(o, k, lam, abc);
    int h = !(al * abc[0] >= (1 - al) * abc[1]);
    tc__ps_eval_piece(o, 2 * k + h, lam, at->dl1, at->dl2, value, grad);
}

/* ---- the method ---- */

/* The range limiter's view of corner i of triangle t: its plane sets the
 * ordinates half way to the split points of its two edges and to Z (the rest
 * are affine combinations of these, with weights in [0, 1]). */
static int ps_dirs(const void *ctx, int32_t c, double d[TC_PLANE_DIRS_MAX][2]) {
    const ps_geom *g = (const ps_geom *)ctx + c / 3;
    int i = c % 3, j = (i + 1) % 3, h = (i + 2) % 3;
    double a = g->alpha[i], b = 1 - g->alpha[h];
    d[0][0] = 0.5 * a * (g->r[j][0] - g->r[i][0]), d[0][1] = 0.5 * a * (g->r[j][1] - g->r[i][1]);
    d[1][0] = 0.5 * b * (g->r[h][0] - g->r[i][0]), d[1][1] = 0.5 * b * (g->r[h][1] - g->r[i][1]);
    d[2][0] = d[2][1] = 0;
    for (int k = 0; k < 3; k++) {
        d[2][0] += 0.5 * g->zeta[k] * (g->r[k][0] - g->r[i][0]);
        d[2][1] += 0.5 * g->zeta[k] * (g->r[k][1] - g->r[i][1]);
    }
    return 3;
}

/* A C1 quadratic cannot keep a kink: the method's row honours C-1 only, so
 * its wedges are cut by C-1 edges and the boundary and corner values stay per
 * side (recon.c warns about the C0 flags it reads as C1). The split comes
 * first: the range limiter needs it to know which ordinates a plane sets. */
int tc__ps_build(struct tc_recon *r, tc_diags *dg) {
    const struct tc_mesh *m = r->m;
    ps_geom *geo = tc__malloc((size_t)m->nt, sizeof *geo);
    if (!geo) return TC_ENOMEM;
    int rc = TC_OK;
    for (int32_t t = 0; t < m->nt && rc == TC_OK; t++)
        if (geometry(m, r->method->honour, t, &geo[t], dg) != TC_OK) rc = TC_EINVAL;
    tc__plane_use use = {ps_dirs, geo, 0};
    if (rc == TC_OK) rc = tc__planes_build(r, &use, dg);
    for (int32_t t = 0; t < m->nt && rc == TC_OK; t++) triangle(r, t, &geo[t]);
    tc__free(geo);
    return rc;
}
