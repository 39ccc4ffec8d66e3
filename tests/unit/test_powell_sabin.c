/* test_powell_sabin.c — the powell-sabin 6-split on randomized meshes: split geometry, interpolation, C1
 * across smooth and C0 edges, at vertices and inside, reproduction, order, the C0 warning, C-1 jumps. */
#include <cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "core/geom.h"
#include "core/powell_sabin.h"
#include "io/api.h"
#include "meshgen.h"
#include "props.h"

/* Coefficient indices the tests read (the layout of powell_sabin.c). */
enum { L_ZETA = 19, L_ALPHA = 22 };

static tc_recon *ps_make_range(const tc_mesh *m, tc_tangents tan, tc_range range, tc_diags *dg) {
    tc_options o;
    tc_options_default(&o);
    o.method = TC_METHOD_POWELL_SABIN;
    o.tangents = tan;
    o.range = range;
    tc_recon *r = NULL;
    int st = tc_recon_new(m, &o, &r, dg);
    CHECK_MSG(st == TC_OK, "powell-sabin (%s): status %d: %s", tc_tangents_name(tan), st,
              dg && dg->count ? dg->items[0].message : "");
    return r;
}

static tc_recon *ps_make(const tc_mesh *m, tc_tangents tan, tc_diags *dg) {
    return ps_make_range(m, tan, TC_RANGE_LOCAL, dg);
}

/* The scheme itself, unlimited (range "free"): quadratics overshoot their corners. */
static tc_recon *ps_make_free(const tc_mesh *m, tc_tangents tan, tc_diags *dg) {
    return ps_make_range(m, tan, TC_RANGE_FREE, dg);
}

static const double *coef_of(const tc_recon *r, int32_t t, int ch) {
    int nc = tc_mesh_channel_count(tc_recon_mesh(r));
    return tc_recon_coefs(r) + ((size_t)t * (size_t)nc + (size_t)ch) * TC_PS_COEFS;
}

static const double *gxy(const tmesh *g, int32_t t, int k) { return g->xy + 2 * g->tri[3 * t + k % 3]; }

/* The incenter from the textbook formula: vertices weighted by the opposite edge lengths. */
static void incenter(const tmesh *g, int32_t t, double z[2]) {
    double w[3], s = 0;
    for (int i = 0; i < 3; i++) {
        const double *a = gxy(g, t, i + 1), *b = gxy(g, t, i + 2);
        s += w[i] = hypot(b[0] - a[0], b[1] - a[1]);
    }
    z[0] = z[1] = 0;
    for (int i = 0; i < 3; i++) z[0] += w[i] / s * gxy(g, t, i)[0], z[1] += w[i] / s * gxy(g, t, i)[1];
}

/* ---- split geometry ---- */

/* Checks t's stored geometry against the textbook: zeta against the incenter,
 * alpha = 1/2 on cut edges, else the crossing of the incenter segment with
 * the edge, strictly inside it and the same point from both sides. Returns
 * the worst mismatch relative to the edge length. */
static double split_check(const tc_recon *r, const tmesh *g, int32_t t, double tol) {
    const double *o = coef_of(r, t, 0);
    double z[2], worst = 0, zz[2] = {0, 0};
    incenter(g, t, z);
    for (int i = 0; i < 3; i++) zz[0] += o[L_ZETA + i] * gxy(g, t, i)[0], zz[1] += o[L_ZETA + i] * gxy(g, t, i)[1];
    worst = hypot(zz[0] - z[0], zz[1] - z[1]) / hypot(gxy(g, t, 1)[0] - gxy(g, t, 0)[0], gxy(g, t, 1)[1] - gxy(g, t, 0)[1]);
    for (int k = 0; k < 3; k++) {
        int32_t t2 = g->enbr[3 * t + k];
        double al = o[L_ALPHA + k];
        if (t2 < 0 || g->eflag[3 * t + k] == TC_CM1) {
            CHECK_MSG(al == 0.5, "triangle %d edge %d is cut: alpha %.17g, want 1/2", (int)t, k, al);
            continue;
        }
        const double *a = gxy(g, t, k), *b = gxy(g, t, k + 1);
        double e[2] = {b[0] - a[0], b[1] - a[1]}, z2[2], d[2], f[2];
        incenter(g, t2, z2);
        d[0] = z2[0] - z[0], d[1] = z2[1] - z[1];
        f[0] = z[0] - a[0], f[1] = z[1] - a[1];
        double s = tc__cross(f, d) / tc__cross(e, d), u = tc__cross(f, e) / tc__cross(e, d); /* a + s e = z + u d */
        CHECK_MSG(s > 0 && s < 1 && u > 0 && u < 1, "triangle %d edge %d: incenter segment crosses at s %.3g, u %.3g",
                  (int)t, k, s, u);
        CHECK_MSG(al > 0 && al < 1, "triangle %d edge %d: alpha %.17g", (int)t, k, al);
        worst = fmax(worst, fabs(al - s));
        /* The neighbour's split point of the same edge is the same point. */
        for (int k2 = 0; k2 < 3; k2++) {
            if (g->enbr[3 * t2 + k2] != t) continue;
            const double *p = gxy(g, t2, k2), *q = gxy(g, t2, k2 + 1);
            double a2 = coef_of(r, t2, 0)[L_ALPHA + k2];
            double rx = p[0] + a2 * (q[0] - p[0]) - (a[0] + al * e[0]), ry = p[1] + a2 * (q[1] - p[1]) - (a[1] + al * e[1]);
            worst = fmax(worst, hypot(rx, ry) / hypot(e[0], e[1]));
        }
    }
    CHECK_MSG(worst <= tol, "triangle %d: split geometry off by %.3g", (int)t, worst);
    return worst;
}

TEST(ps_split_points_on_incenter_segments) {
    trng r;
    trng_seed(&r, tc_test_seed() + 40);
    double worst = 0;
    for (int trial = 0; trial < 6; trial++) {
        tmesh g;
        random_flagged_mesh(&g, &r, trial % 2, 12);
        tmesh_sample(&g, 1, smooth_f, NULL, 1, 0, 0.3);
        tc_mesh *m = tmesh_build(&g);
        tc_recon *rec = m ? ps_make(m, TC_TANGENTS_GIVEN, NULL) : NULL;
        for (int32_t t = 0; rec && t < g.nt; t++) worst = fmax(worst, split_check(rec, &g, t, 1e-13));
        tc_recon_free(rec);
        tc_mesh_free(m);
        tmesh_free(&g);
    }
    fprintf(stderr, "  [split] meshes: worst relative mismatch with the incenter crossing %.2g\n", worst);
}

/* Angle at p of triangle (p, q, r). */
static double angle_at(const double *p, const double *q, const double *r) {
    double a[2] = {q[0] - p[0], q[1] - p[1]}, b[2] = {r[0] - p[0], r[1] - p[1]};
    return atan2(fabs(tc__cross(a, b)), tc__dot(a, b));
}

/* Both triangles of edge [0, 1] are flat (within 1e-6 of pi) at the same end:
 * the incircles touch the edge within ~1e-13 of that end, which the method
 * refuses as degenerate. */
static int flat_at_one_end(const double *xy) {
    for (int e = 0; e < 2; e++) {
        const double *p = xy + 2 * e, *q = xy + 2 * (1 - e);
        if (3.141592653589793 - angle_at(p, q, xy + 4) < 1e-6 && 3.141592653589793 - angle_at(p, q, xy + 6) < 1e-6) return 1;
    }
    return 0;
}

/* The proof's claim on arbitrary pairs: obtuse, far-reaching and sliver
 * triangles (apex heights down to 1e-7) on both sides of one edge. A pair is
 * refused only when it is flat at one end of the edge. */
TEST(ps_split_points_wild_pairs) {
    trng r;
    trng_seed(&r, tc_test_seed() + 41);
    double worst = 0;
    int refused = 0;
    for (int trial = 0; trial < 400; trial++) {
        double xy[8] = {0, 0, 1, 0, 0, 0, 0, 0};
        for (int s = 0; s < 2; s++) {
            xy[4 + 2 * s] = -4 + 9 * trng_uniform(&r);
            xy[5 + 2 * s] = (s ? -1 : 1) * pow(10, -7 * trng_uniform(&r)) * 2;
        }
        tmesh g;
        memset(&g, 0, sizeof g);
        int32_t tri[6] = {0, 1, 2, 1, 0, 3}, nbr[6] = {1, -1, -1, 0, -1, -1};
        int8_t flag[6] = {1, -1, -1, 1, -1, -1};
        double values[4] = {1, 2, 3, 4};
        g.nv = 4, g.nt = 2, g.nc = 1, g.xy = xy, g.tri = tri, g.values = values, g.enbr = nbr, g.eflag = flag;
        tc_mesh *m = tmesh_build(&g);
        tc_options o;
        tc_options_default(&o);
        o.method = TC_METHOD_POWELL_SABIN;
        tc_diags dg;
        tc_diags_init(&dg);
        tc_recon *rec = NULL;
        int st = m ? tc_recon_new(m, &o, &rec, &dg) : -1;
        if (st == TC_EINVAL) {
            refused++;
            CHECK_MSG(flat_at_one_end(xy), "C (%.17g, %.17g), D (%.17g, %.17g) refused: %s", xy[4], xy[5], xy[6], xy[7],
                      dg.count ? dg.items[0].message : "");
        } else {
            CHECK(st == TC_OK);
        }
        for (int32_t t = 0; rec && t < 2; t++) worst = fmax(worst, split_check(rec, &g, t, 1e-12));
        tc_diags_free(&dg);
        tc_recon_free(rec);
        tc_mesh_free(m);
    }
    CHECK(refused < 40);
    fprintf(stderr, "  [split] wild pairs: worst relative mismatch %.2g; %d of 400 refused (flat at one end)\n", worst,
            refused);
}

/* ---- continuity ---- */

typedef struct { double corner, plane, c0, c1, vertex, internal; } ps_report;

/* Fractions along a segment where the residual checks sample it. */
static const double S[] = {0.0, 0.137, 0.5, 0.771, 1.0};

/* At every corner: the value is the corner's, the gradient its wedge plane. */
static void corner_residuals(const tc_recon *r, const tmesh *g, double vs, double gs, ps_report *rep) {
    const tc_mesh *m = tc_recon_mesh(r);
    const double *cg = tc_recon_corner_gradients(r);
    int nc = g->nc;
    for (int32_t c = 0; c < 3 * g->nt; c++) {
        double val[TC_MAX_CHANNELS], grad[2 * TC_MAX_CHANNELS];
        const double *p = g->xy + 2 * g->tri[c];
        tc_eval_triangle(r, c / 3, p[0], p[1], val, grad);
        for (int ch = 0; ch < nc; ch++) {
            const double *w = cg + 2 * ((size_t)c * (size_t)nc + (size_t)ch);
            rep->corner = fmax(rep->corner, fabs(val[ch] - tc_mesh_corner_value(m, c / 3, c % 3)[ch]) / vs);
            rep->plane = fmax(rep->plane, hypot(grad[2 * ch] - w[0], grad[2 * ch + 1] - w[1]) / gs);
        }
    }
}

/* Gradients of t and its neighbour across edge k agree at both ends: a wedge
 * is connected through such edges, so this is C1 at the vertex within it. */
static double vertex_residual(const tc_recon *r, const tmesh *g, int32_t t, int k, double gs) {
    int32_t t2 = g->enbr[3 * t + k];
    double worst = 0;
    for (int e = 0; e < 2; e++) {
        const double *p = gxy(g, t, k + e);
        double v[TC_MAX_CHANNELS], g1[2 * TC_MAX_CHANNELS], g2[2 * TC_MAX_CHANNELS];
        tc_eval_triangle(r, t, p[0], p[1], v, g1);
        tc_eval_triangle(r, t2, p[0], p[1], v, g2);
        for (int ch = 0; ch < g->nc; ch++)
            worst = fmax(worst, hypot(g1[2 * ch] - g2[2 * ch], g1[2 * ch + 1] - g2[2 * ch + 1]) / gs);
    }
    return worst;
}

/* Pieces pa and pb of one channel's coefficients o at barycentrics L. */
static double piece_pair(const double *o, int pa, int pb, const double L[3], const double dl1[2], const double dl2[2],
                         double vs, double gs) {
    double va, vb, ga[2], gb[2];
    tc__ps_eval_piece(o, pa, L, dl1, dl2, &va, ga);
    tc__ps_eval_piece(o, pb, L, dl1, dl2, &vb, gb);
    return fmax(fabs(va - vb) / vs, hypot(ga[0] - gb[0], ga[1] - gb[1]) / gs);
}

/* Across the six inner edges: V_i Z between pieces 2i and 2(i-1)+1, R_k Z
 * between pieces 2k and 2k+1, points placed with the stored geometry. */
static double internal_residual(const tc_recon *r, double vs, double gs) {
    const tc_mesh *m = tc_recon_mesh(r);
    int nc = tc_mesh_channel_count(m);
    double worst = 0;
    for (int32_t t = 0; t < tc_mesh_triangle_count(m); t++) {
        double lam[3], dl1[2], dl2[2];
        tc__bary(m, t, 0, 0, lam, dl1, dl2); /* only dl1, dl2 are used */
        for (int ch = 0; ch < nc; ch++) {
            const double *o = coef_of(r, t, ch), *zeta = o + L_ZETA;
            for (int i = 0; i < 3; i++)
                for (size_t j = 0; j < sizeof S / sizeof S[0]; j++) {
                    double L[3], al = o[L_ALPHA + i];
                    for (int q = 0; q < 3; q++) L[q] = (1 - S[j]) * (q == i) + S[j] * zeta[q];
                    worst = fmax(worst, piece_pair(o, 2 * i, 2 * ((i + 2) % 3) + 1, L, dl1, dl2, vs, gs));
                    for (int q = 0; q < 3; q++)
                        L[q] = (1 - S[j]) * ((q == i) * (1 - al) + (q == (i + 1) % 3) * al) + S[j] * zeta[q];
                    worst = fmax(worst, piece_pair(o, 2 * i, 2 * i + 1, L, dl1, dl2, vs, gs));
                }
        }
    }
    return worst;
}

/* Every property at once, each relative residual <= tol; C0 edges count as
 * smooth (the scheme cannot keep a kink), C-1 edges and the boundary are cuts. */
static void ps_continuity(const tc_recon *r, const tmesh *g, double tol, ps_report *rep) {
    double vs, gs;
    recon_scales(r, &vs, &gs);
    memset(rep, 0, sizeof *rep);
    corner_residuals(r, g, vs, gs, rep);
    for (int32_t t = 0; t < g->nt; t++)
        for (int k = 0; k < 3; k++) {
            int32_t t2 = g->enbr[3 * t + k];
            if (t2 < t || g->eflag[3 * t + k] == TC_CM1) continue;
            double rv = 0, rg = 0;
            edge_residual(r, t, k, vs, gs, &rv, &rg);
            rep->c0 = fmax(rep->c0, rv);
            rep->c1 = fmax(rep->c1, rg);
            rep->vertex = fmax(rep->vertex, vertex_residual(r, g, t, k, gs));
        }
    rep->internal = internal_residual(r, vs, gs);
    CHECK_MSG(rep->corner <= tol, "interpolation residual %.3g", rep->corner);
    CHECK_MSG(rep->plane <= tol, "gradient at corners vs their wedge planes %.3g", rep->plane);
    CHECK_MSG(rep->c0 <= tol, "value residual across smooth (C1 and C0) edges %.3g", rep->c0);
    CHECK_MSG(rep->c1 <= tol, "gradient residual across smooth (C1 and C0) edges %.3g", rep->c1);
    CHECK_MSG(rep->vertex <= tol, "gradient residual at vertices within a wedge %.3g", rep->vertex);
    CHECK_MSG(rep->internal <= tol, "C1 residual across the inner edges of the 6-split %.3g", rep->internal);
}

static int has_c0_warning(const tc_diags *dg) {
    int n = 0;
    for (int i = 0; i < dg->count; i++)
        n += dg->items[i].severity == TC_SEV_WARNING && !strcmp(dg->items[i].path, "discontinuities.c0") &&
             strstr(dg->items[i].message, "powell-sabin cannot honour C0 flags; they are treated as C1") != NULL;
    return n;
}

TEST(ps_continuity_randomized_meshes) {
    trng r;
    trng_seed(&r, tc_test_seed() + 42);
    const tc_tangents sources[] = {TC_TANGENTS_GIVEN, TC_TANGENTS_MIDPOINTS, TC_TANGENTS_ESTIMATE, TC_TANGENTS_AUTO};
    ps_report worst = {0};
    for (int trial = 0; trial < 16; trial++) {
        tmesh g;
        random_flagged_mesh(&g, &r, trial % 2, 12 + 4 * trng_int(&r, 2));
        tc_tangents src = sources[trial % 4];
        tmesh_sample(&g, 1 + trng_int(&r, 3), smooth_f, NULL, src == TC_TANGENTS_GIVEN, src != TC_TANGENTS_GIVEN, 0.3);
        tc_mesh *m = tmesh_build(&g);
        tc_diags dg;
        tc_diags_init(&dg);
        tc_recon *rec = m ? ps_make(m, src, &dg) : NULL;
        if (rec) {
            ps_report rep;
            ps_continuity(rec, &g, 1e-10, &rep);
            CHECK_MSG(has_c0_warning(&dg) == 1, "trial %d: %d C0 warnings, want 1", trial, has_c0_warning(&dg));
            worst.corner = fmax(worst.corner, rep.corner), worst.plane = fmax(worst.plane, rep.plane);
            worst.c0 = fmax(worst.c0, rep.c0), worst.c1 = fmax(worst.c1, rep.c1);
            worst.vertex = fmax(worst.vertex, rep.vertex), worst.internal = fmax(worst.internal, rep.internal);
        }
        tc_diags_free(&dg);
        tc_recon_free(rec);
        tc_mesh_free(m);
        tmesh_free(&g);
    }
    fprintf(stderr, "  [ps continuity] worst relative residuals: corner %.2g, corner plane %.2g, value across edge %.2g, "
                    "gradient across edge %.2g, vertex %.2g, inner edges %.2g\n",
            worst.corner, worst.plane, worst.c0, worst.c1, worst.vertex, worst.internal);
}

/* ---- corners, pieces ---- */

static void rough_f(const void *ctx, double x, double y, int ch, double *v, double g[2]) {
    (void)ctx;
    *v = 1e6 * sin(977 * x + 311 * y + ch) + 1.0 / 3;
    g[0] = 1e7 * cos(53 * x - 17 * y);
    g[1] = -3e6 * sin(29 * x * y + ch);
}

/* At each corner the piece's value is the corner value bit for bit, with
 * rough data, jumps and steep planes: nothing multiplies it on the way. */
TEST(ps_corner_values_exact) {
    trng r;
    trng_seed(&r, tc_test_seed() + 43);
    int64_t bad = 0, n = 0;
    for (int trial = 0; trial < 4; trial++) {
        tmesh g;
        random_flagged_mesh(&g, &r, trial % 2, 12);
        tmesh_sample(&g, 2, rough_f, NULL, 1, 1, 12345.678);
        tc_mesh *m = tmesh_build(&g);
        tc_recon *rec = m ? ps_make(m, trial % 2 ? TC_TANGENTS_GIVEN : TC_TANGENTS_MIDPOINTS, NULL) : NULL;
        for (int32_t c = 0; rec && c < 3 * g.nt; c++) {
            double val[2], grad[4];
            const double *p = g.xy + 2 * g.tri[c];
            tc_eval_triangle(rec, c / 3, p[0], p[1], val, grad);
            for (int ch = 0; ch < 2; ch++, n++) bad += val[ch] != tc_mesh_corner_value(m, c / 3, c % 3)[ch];
        }
        tc_recon_free(rec);
        tc_mesh_free(m);
        tmesh_free(&g);
    }
    CHECK_MSG(n > 0 && bad == 0, "%lld of %lld corner values not exact", (long long)bad, (long long)n);
}

/* tc_eval_triangle evaluates the piece the point lies in: at random points
 * well inside each of the six pieces it gives exactly that piece's value. */
TEST(ps_evaluation_picks_the_containing_piece) {
    trng r;
    trng_seed(&r, tc_test_seed() + 44);
    tmesh g;
    random_flagged_mesh(&g, &r, 1, 12);
    tmesh_sample(&g, 1, smooth_f, NULL, 1, 0, 0.3);
    tc_mesh *m = tmesh_build(&g);
    tc_recon *rec = m ? ps_make(m, TC_TANGENTS_GIVEN, NULL) : NULL;
    int64_t bad = 0, n = 0;
    for (int32_t t = 0; rec && t < g.nt; t++) {
        const double *o = coef_of(rec, t, 0);
        for (int p = 0; p < 6; p++)
            for (int i = 0; i < 4; i++, n++) {
                int k = p / 2, vi = (k + p % 2) % 3;
                double w[3] = {0.05 + trng_uniform(&r), 0.05 + trng_uniform(&r), 0.05 + trng_uniform(&r)}, L[3] = {0};
                double sw = w[0] + w[1] + w[2], al = o[L_ALPHA + k], x = 0, y = 0;
                for (int q = 0; q < 3; q++)
                    L[q] = (w[0] * (q == vi) + w[1] * ((q == k) * (1 - al) + (q == (k + 1) % 3) * al) +
                            w[2] * o[L_ZETA + q]) / sw;
                for (int q = 0; q < 3; q++) x += L[q] * gxy(&g, t, q)[0], y += L[q] * gxy(&g, t, q)[1];
                double lam[3], dl1[2], dl2[2], v, vp, gv[2], gp[2];
                tc_eval_triangle(rec, t, x, y, &v, gv);
                tc__bary(m, t, x, y, lam, dl1, dl2);
                tc__ps_eval_piece(o, p, lam, dl1, dl2, &vp, gp);
                bad += v != vp || gv[0] != gp[0] || gv[1] != gp[1];
            }
    }
    CHECK_MSG(n > 0 && bad == 0, "%lld of %lld points evaluated on another piece", (long long)bad, (long long)n);
    tc_recon_free(rec);
    tc_mesh_free(m);
    tmesh_free(&g);
}

/* ---- reproduction and order ---- */

/* Quadratics with exact gradients, on flagged meshes too (C-1 sides each get
 * the same exact planes); and with estimated tangents (a quadratic fit). */
TEST(ps_quadratic_reproduced) {
    trng r;
    trng_seed(&r, tc_test_seed() + 45);
    double worst = 0, est = 0;
    for (int trial = 0; trial < 4; trial++) {
        tmesh g;
        random_flagged_mesh(&g, &r, trial % 2, 12);
        tmesh_sample(&g, 2, quadratic_data, NULL, 1, 0, 0);
        tc_mesh *m = tmesh_build(&g);
        tc_recon *rec = m ? ps_make_free(m, TC_TANGENTS_GIVEN, NULL) : NULL;
        double e = rec ? tri_reproduction_error(rec, quadratic_data, 500, &r, 1) : INFINITY;
        CHECK_MSG(e <= 1e-12, "trial %d: quadratic off by %.3g", trial, e);
        worst = fmax(worst, e);
        tc_recon_free(rec);
        tc_mesh_free(m);
        tmesh_free(&g);
    }
    tmesh g;
    tmesh_grid(&g, 12, 12, 0.25, -1, &r);
    tmesh_sample(&g, 1, quadratic_data, NULL, 0, 1, 0);
    tc_mesh *m = tmesh_build(&g);
    tc_recon *rec = m ? ps_make_free(m, TC_TANGENTS_ESTIMATE, NULL) : NULL;
    est = rec ? tri_reproduction_error(rec, quadratic_data, 500, &r, 1) : INFINITY;
    CHECK_MSG(est <= 1e-10, "quadratic with estimated tangents off by %.3g", est);
    tc_recon_free(rec);
    tc_mesh_free(m);
    tmesh_free(&g);
    fprintf(stderr, "  [ps quadratic] exact gradients worst %.2g, estimated tangents %.2g\n", worst, est);
}

TEST(ps_linear_reproduced_with_any_tangents) {
    trng r;
    trng_seed(&r, tc_test_seed() + 46);
    double worst = 0;
    for (int trial = 0; trial < 4; trial++) {
        tmesh g;
        random_flagged_mesh(&g, &r, trial % 2, 12);
        tmesh_sample(&g, 2, linear_data, NULL, 1, 1, 0);
        tc_mesh *m = tmesh_build(&g);
        for (int ti = 0; m && ti < 4; ti++) {
            tc_recon *rec = ps_make(m, (tc_tangents)ti, NULL);
            double e = rec ? tri_reproduction_error(rec, linear_data, 300, &r, 1) : INFINITY;
            CHECK_MSG(e <= 1e-12, "tangents %s: linear off by %.3g", tc_tangents_name((tc_tangents)ti), e);
            worst = fmax(worst, e);
            tc_recon_free(rec);
        }
        tc_mesh_free(m);
        tmesh_free(&g);
    }
    fprintf(stderr, "  [ps linear] worst relative error over tangent sources: %.2g\n", worst);
}



static double observed_order(tc_tangents tan, int with_mid) {
    double err[4];
    int ns[4] = {8, 16, 32, 64};
    for (int l = 0; l < 4; l++) {
        tmesh g;
        tmesh_grid(&g, ns[l], ns[l], 0, 0, NULL);
        tmesh_sample(&g, 1, wave_f, NULL, 1, with_mid, 0);
        tc_mesh *m = tmesh_build(&g);
        tc_recon *rec = m ? ps_make(m, tan, NULL) : NULL;
        err[l] = rec ? grid_max_error(rec, ns[l]) : NAN;
        tc_recon_free(rec);
        tc_mesh_free(m);
        tmesh_free(&g);
    }
    double order = log2(err[2] / err[3]);
    fprintf(stderr, "  [order] powell-sabin %-9s max error %.2e %.2e %.2e %.2e -> order %.2f\n", tc_tangents_name(tan),
            err[0], err[1], err[2], err[3], order);
    return order;
}

TEST(ps_convergence_order) {
    double o = observed_order(TC_TANGENTS_GIVEN, 0);
    CHECK_MSG(o >= 2.8, "powell-sabin with exact gradients: order %.2f < 2.8", o);
    o = observed_order(TC_TANGENTS_MIDPOINTS, 1);
    CHECK_MSG(o >= 2.5, "powell-sabin with midpoint tangents: order %.2f", o);
    o = observed_order(TC_TANGENTS_ESTIMATE, 0);
    CHECK_MSG(o >= 2.5, "powell-sabin with estimated tangents: order %.2f", o);
}

/* ---- flags ---- */

static void kink_f(const void *ctx, double x, double y, int ch, double *v, double g[2]) {
    (void)ctx, (void)ch;
    double d = y - 0.5;
    *v = 0.3 * x + fabs(d) + d * d;
    g[0] = 0.3;
    g[1] = (d < 0 ? -1 : 1) + 2 * d;
}

/* A kink along a C0 row: powell-sabin smooths it (C1 across the row) and says
 * so once; without C0 flags nothing is said. */
TEST(ps_c0_flags_warned_and_smoothed) {
    trng r;
    trng_seed(&r, tc_test_seed() + 47);
    for (int flagged = 0; flagged < 2; flagged++) {
        tmesh g;
        int32_t row[9];
        tmesh_grid(&g, 8, 8, 0.25, -1, &r);
        for (int i = 0; i <= 8; i++) row[i] = tmesh_gv(8, i, 4);
        if (flagged) CHECK(tmesh_add_line(&g, TC_C0, row, 9) == 0);
        tmesh_sample(&g, 1, kink_f, NULL, 0, 1, 0);
        tc_mesh *m = tmesh_build(&g);
        tc_diags dg;
        tc_diags_init(&dg);
        tc_recon *rec = m ? ps_make_free(m, TC_TANGENTS_MIDPOINTS, &dg) : NULL;
        drop_range_free_warnings(&dg);
        CHECK_MSG(has_c0_warning(&dg) == flagged && dg.count == flagged, "flagged %d: %d findings, first %s", flagged,
                  dg.count, dg.count ? dg.items[0].message : "");
        if (rec) {
            ps_report rep;
            ps_continuity(rec, &g, 1e-10, &rep);
        }
        tc_diags_free(&dg);
        tc_recon_free(rec);
        tc_mesh_free(m);
        tmesh_free(&g);
    }
}

/* Across every C-1 edge each side keeps its own corner values: at both ends
 * each side evaluates to its corner value, so the jump there is the data's,
 * and the jumps of the data survive along the edge. */
TEST(ps_cm1_jumps_kept) {
    trng r;
    trng_seed(&r, tc_test_seed() + 48);
    double biggest = 0, worst = 0;
    for (int trial = 0; trial < 4; trial++) {
        tmesh g;
        random_flagged_mesh(&g, &r, trial % 2, 12);
        tmesh_sample(&g, 1, smooth_f, NULL, trial % 2, !(trial % 2), 0.3);
        tc_mesh *m = tmesh_build(&g);
        tc_recon *rec = m ? ps_make(m, trial % 2 ? TC_TANGENTS_GIVEN : TC_TANGENTS_ESTIMATE, NULL) : NULL;
        for (int32_t c = 0; rec && c < 3 * g.nt; c++) {
            int32_t t = c / 3, k = c % 3, t2 = g.enbr[c];
            if (t2 < 0 || g.eflag[c] != TC_CM1) continue;
            for (int e = 0; e < 2; e++) { /* both ends: v = corner value on each side */
                int32_t v = g.tri[3 * t + (k + e) % 3];
                const double *p = g.xy + 2 * v;
                double v1, v2;
                tc_eval_triangle(rec, t, p[0], p[1], &v1, NULL);
                tc_eval_triangle(rec, t2, p[0], p[1], &v2, NULL);
                double z1 = tc_mesh_corner_value(m, t, (k + e) % 3)[0];
                double z2 = tc_mesh_corner_value(m, t2, g.tri[3 * t2] == v ? 0 : g.tri[3 * t2 + 1] == v ? 1 : 2)[0];
                worst = fmax(worst, fabs((v1 - v2) - (z1 - z2)));
                CHECK(v1 == z1 && v2 == z2);
            }
            const double *a = gxy(&g, t, k), *b = gxy(&g, t, k + 1);
            double v1, v2, x = 0.5 * (a[0] + b[0]), y = 0.5 * (a[1] + b[1]);
            tc_eval_triangle(rec, t, x, y, &v1, NULL);
            tc_eval_triangle(rec, t2, x, y, &v2, NULL);
            biggest = fmax(biggest, fabs(v1 - v2));
        }
        tc_recon_free(rec);
        tc_mesh_free(m);
        tmesh_free(&g);
    }
    CHECK_MSG(biggest > 0.2, "largest jump kept at a C-1 edge midpoint %.3g (data jumps by 0.3)", biggest);
    fprintf(stderr, "  [ps C-1] jumps at the ends match the data to %.2g; largest at a midpoint %.3g\n", worst, biggest);
}

static void quadratic2_f(const void *ctx, double x, double y, int ch, double *v, double g[2]) {
    (void)ctx;
    double b = -0.7 + 0.2 * ch;
    *v = 3.0 - 0.9 * x + 0.5 * y + b * x * x + 0.8 * x * y - 1.3 * y * y;
    g[0] = -0.9 + 2 * b * x + 0.8 * y;
    g[1] = 0.5 + 0.8 * x - 2.6 * y;
}

static int above_row(const tmesh *g, int32_t t, double y0) {
    return gxy(g, t, 0)[1] + gxy(g, t, 1)[1] + gxy(g, t, 2)[1] > 3 * y0;
}

/* Overrides every corner of the triangles above y0 (values and gradients) with quadratic2_f. */
static void second_quadratic_above(tmesh *g, double y0) {
    int nc = g->nc;
    g->cg_tri = calloc((size_t)g->nt, sizeof *g->cg_tri);
    g->cg = calloc((size_t)g->nt * 3 * (size_t)nc * 2, sizeof *g->cg);
    for (int32_t t = 0; t < g->nt; t++) {
        if (!above_row(g, t, y0)) continue;
        int32_t i = g->ncv++;
        g->cv_tri[i] = g->cg_tri[i] = t;
        g->ncg++;
        for (int k = 0; k < 3; k++)
            for (int ch = 0; ch < nc; ch++) {
                size_t at = ((size_t)i * 3 + (size_t)k) * (size_t)nc + (size_t)ch;
                quadratic2_f(NULL, gxy(g, t, k)[0], gxy(g, t, k)[1], ch, &g->cv[at], g->cg + at * 2);
            }
    }
}

/* A C-1 line right across the mesh with one quadratic below and another
 * above: each side is reconstructed on its own (its own values, its own
 * wedge planes), so both quadratics are reproduced exactly up to the cut. */
TEST(ps_cm1_sides_reconstructed_on_their_own) {
    trng r;
    trng_seed(&r, tc_test_seed() + 49);
    tmesh g;
    int32_t row[13];
    tmesh_grid(&g, 12, 12, 0.3, -1, &r);
    for (int i = 0; i <= 12; i++) row[i] = tmesh_gv(12, i, 4);
    CHECK(tmesh_add_line(&g, TC_CM1, row, 13) == 0);
    tmesh_sample(&g, 2, quadratic_data, NULL, 1, 0, 0);
    second_quadratic_above(&g, 4.0 / 12);
    tc_mesh *m = tmesh_build(&g);
    tc_recon *rec = m ? ps_make_free(m, TC_TANGENTS_GIVEN, NULL) : NULL;
    double worst = 0, vs, gs;
    if (rec) recon_scales(rec, &vs, &gs);
    for (int i = 0; rec && i < 2000; i++) {
        int32_t t = trng_int(&r, g.nt);
        double a = trng_uniform(&r), b = trng_uniform(&r), x = 0, y = 0;
        if (a + b > 1) a = 1 - a, b = 1 - b;
        double L[3] = {1 - a - b, a, b}, val[2], grad[4];
        for (int k = 0; k < 3; k++) x += L[k] * gxy(&g, t, k)[0], y += L[k] * gxy(&g, t, k)[1];
        tc_eval_triangle(rec, t, x, y, val, grad);
        for (int ch = 0; ch < 2; ch++) {
            double fv, fg[2];
            (above_row(&g, t, 4.0 / 12) ? quadratic2_f : quadratic_data)(NULL, x, y, ch, &fv, fg);
            worst = fmax(worst, fabs(val[ch] - fv) / vs);
            worst = fmax(worst, hypot(grad[2 * ch] - fg[0], grad[2 * ch + 1] - fg[1]) / gs);
        }
    }
    CHECK_MSG(worst <= 1e-12, "two quadratics across a C-1 line: off by %.3g", worst);
    fprintf(stderr, "  [ps C-1] two quadratics across a cut reproduced to %.2g\n", worst);
    tc_recon_free(rec);
    tc_mesh_free(m);
    tmesh_free(&g);
}

/* ---- layout, numerics, refusals ---- */

/* The coefficients are computed in local coordinates only: a dyadic grid and
 * the same grid moved by 2^30 (both exact) give the same bits. */
TEST(ps_translation_invariant_bit_for_bit) {
    tmesh g[2];
    tc_mesh *m[2];
    tc_recon *rec[2] = {NULL, NULL};
    for (int tan = 0; tan < 2; tan++) {
        for (int s = 0; s < 2; s++) {
            int32_t row[9];
            tmesh_grid(&g[s], 8, 8, 0, 0, NULL);
            for (int i = 0; i <= 8; i++) row[i] = tmesh_gv(8, i, 4);
            tmesh_add_line(&g[s], TC_CM1, row, 9);
            tmesh_sample(&g[s], 2, smooth_f, NULL, 1, 0, 0.3);
            for (int32_t i = 0; s && i < 2 * g[s].nv; i++) g[s].xy[i] += 0x1p30;
            m[s] = tmesh_build(&g[s]);
            rec[s] = m[s] ? ps_make(m[s], tan ? TC_TANGENTS_ESTIMATE : TC_TANGENTS_GIVEN, NULL) : NULL;
        }
        if (rec[0] && rec[1])
            CHECK(!memcmp(tc_recon_coefs(rec[0]), tc_recon_coefs(rec[1]),
                          (size_t)g[0].nt * 2 * TC_PS_COEFS * sizeof(double)));
        for (int s = 0; s < 2; s++) tc_recon_free(rec[s]), tc_mesh_free(m[s]), tmesh_free(&g[s]);
    }
}

/* The labels and the layout as /v1/ordinates reports them, with the warning. */
TEST(ps_ordinates_endpoint_labels) {
    static const char *const want[TC_PS_COEFS] = {
        "u", "v", "w", "u:uv", "v:uv", "v:vw", "w:vw", "w:wu", "u:wu", "uv", "vw", "wu", "u:z",
        "v:z", "w:z", "z:uv", "z:vw", "z:wu", "z", "zeta_u", "zeta_v", "zeta_w", "alpha_uv", "alpha_vw", "alpha_wu"};
    const char *body =
        "{\"vertices\": [[0,0],[0.5,0],[1,0],[0,0.5],[0.5,0.5],[1,0.5],[0,1],[0.5,1],[1,1]],"
        "\"triangles\": [[0,1,4],[0,4,3],[1,2,5],[1,5,4],[3,4,7],[3,7,6],[4,5,8],[4,8,7]],"
        "\"values\": [2,2.5,3,0.5,1,1.5,-1,-0.5,0], \"method\": \"powell-sabin\","
        "\"discontinuities\": {\"c0\": [[3,4,5]], \"c-1\": [[1,4,7]]}}";
    tc_api_result res;
    tc_strbuf out;
    tc_api_result_init(&res);
    tc_strbuf_init(&out);
    CHECK(tc_api_ordinates(body, strlen(body), NULL, &out, &res) == 200);
    cJSON *doc = out.buf ? cJSON_Parse(out.buf) : NULL;
    const cJSON *lab = cJSON_GetObjectItemCaseSensitive(doc, "labels");
    const cJSON *ord = cJSON_GetObjectItemCaseSensitive(doc, "ordinates");
    const cJSON *warn = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(doc, "warnings"), 0);
    CHECK(cJSON_GetArraySize(lab) == TC_PS_COEFS);
    for (int i = 0; i < TC_PS_COEFS && cJSON_GetArraySize(lab) == TC_PS_COEFS; i++)
        CHECK_MSG(!strcmp(cJSON_GetArrayItem(lab, i)->valuestring, want[i]), "label %d: %s", i,
                  cJSON_GetArrayItem(lab, i)->valuestring);
    CHECK(cJSON_GetArraySize(ord) == 8);
    const cJSON *t0 = cJSON_GetArrayItem(cJSON_GetArrayItem(ord, 0), 0);
    CHECK(cJSON_GetArraySize(t0) == TC_PS_COEFS);
    if (cJSON_GetArraySize(t0) == TC_PS_COEFS) { /* triangle [0,1,4]: corner values, zeta sums to 1 */
        CHECK(cJSON_GetArrayItem(t0, 0)->valuedouble == 2 && cJSON_GetArrayItem(t0, 2)->valuedouble == 1);
        double s = 0;
        for (int i = 19; i < 22; i++) s += cJSON_GetArrayItem(t0, i)->valuedouble;
        CHECK_NEAR(s, 1, 1e-15);
        CHECK(cJSON_GetArrayItem(t0, 23)->valuedouble == 0.5); /* edge [1,4] is C-1: its midpoint */
    }
    CHECK(warn && !strcmp(cJSON_GetObjectItemCaseSensitive(warn, "path")->valuestring, "discontinuities.c0"));
    cJSON_Delete(doc);
    tc_strbuf_free(&out);
    tc_api_result_free(&res);
}

static int build_pair(const double *xy, tc_diags *dg, tc_recon **rec, tc_mesh **m) {
    static const int32_t tris[6] = {0, 1, 2, 1, 0, 3};
    static const double values[4] = {1, 2, 3, 4};
    tc_mesh_desc d;
    memset(&d, 0, sizeof d);
    d.nverts = 4, d.xy = xy, d.ntris = 2, d.tris = tris, d.nchan = 1, d.values = values;
    *rec = NULL;
    if (tc_mesh_new(&d, m, dg) != TC_OK) return -1;
    tc_options o;
    tc_options_default(&o);
    o.method = TC_METHOD_POWELL_SABIN;
    return tc_recon_new(*m, &o, rec, dg);
}

/* A split that is degenerate at rounding level is refused naming the
 * triangle; a merely thin one is built and evaluates finite. */
TEST(ps_degenerate_split_refused) {
    /* Both triangles have an angle pi - 1e-9 at vertex 0: edge [0,1] would be split at ~1e-19. */
    double flat[8] = {0, 0, 1, 0, -1, 1e-9, -1, -1e-9};
    /* An edge of 1e-15 against a perimeter of 2 (valid: its area is above rounding from corner 0). */
    double needle[8] = {1, 0, 1, 1e-15, 0, 0, 3, 0.5};
    double *bad[2] = {flat, needle};
    const char *want[2] = {"edge 0 [0, 1] is split at", "the edge opposite corner 2"};
    for (int i = 0; i < 2; i++) {
        tc_diags dg;
        tc_diags_init(&dg);
        tc_mesh *m = NULL;
        tc_recon *rec;
        CHECK_MSG(build_pair(bad[i], &dg, &rec, &m) == TC_EINVAL && !rec, "case %d accepted", i);
        const tc_diag *e = NULL; /* the first error (warnings may come before it) */
        for (int k = 0; k < dg.count && !e; k++)
            if (dg.items[k].severity == TC_SEV_ERROR) e = &dg.items[k];
        CHECK_MSG(e && !strcmp(e->path, "triangles[0]"), "case %d: path %s", i, e ? e->path : "-");
        if (e) CHECK_STR_CONTAINS(e->message, want[i]);
        tc_mesh_free(m);
        tc_diags_free(&dg);
    }
    double thin[8] = {0, 0, 1, 0, -1, 1e-6, -1, -1e-6};
    tc_diags dg;
    tc_diags_init(&dg);
    tc_mesh *m = NULL;
    tc_recon *rec;
    CHECK(build_pair(thin, &dg, &rec, &m) == TC_OK);
    trng r;
    trng_seed(&r, 5);
    for (int i = 0; rec && i < 2000; i++) {
        double v, g[2], x = -1 + 2 * trng_uniform(&r), y = (2 * trng_uniform(&r) - 1) * 1e-6;
        tc_eval_triangle(rec, y < 0, x, y, &v, g);
        CHECK(isfinite(v) && isfinite(g[0]) && isfinite(g[1]) && fabs(v) < 10);
    }
    tc_recon_free(rec);
    tc_mesh_free(m);
    tc_diags_free(&dg);
}
