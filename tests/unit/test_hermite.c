/* test_hermite.c — bicubic Hermite patches: layout, interpolation, continuity (C0 everywhere, C1 on
 * parallelograms, the general-quad jump measured), reproduction, the inverse map, the twists. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "core/hermite.h"
#include "quadgen.h"

/* ---- test functions: value, gradient, hessian ---- */

/* A bicubic polynomial in the axes (u, v) of a frame rotated by angle[0]
 * about the origin; coefficients vary with the channel. */
static void bicubic_f(const void *ctx, double x, double y, int ch, double *v, double g[2], double h[3]) {
    double th = *(const double *)ctx, c = cos(th), s = sin(th);
    double u = c * x + s * y, w = -s * x + c * y, P = 0, Pu = 0, Pw = 0, Puu = 0, Puw = 0, Pww = 0;
    for (int i = 0; i <= 3; i++)
        for (int j = 0; j <= 3; j++) {
            double a = 0.1 * (1 + ((i * 7 + j * 3 + ch * 5) % 11)) * ((i + j) % 2 ? -1 : 1);
            double ui = pow(u, i), wj = pow(w, j);
            double ui1 = i ? i * pow(u, i - 1) : 0, wj1 = j ? j * pow(w, j - 1) : 0;
            double ui2 = i > 1 ? i * (i - 1) * pow(u, i - 2) : 0, wj2 = j > 1 ? j * (j - 1) * pow(w, j - 2) : 0;
            P += a * ui * wj, Pu += a * ui1 * wj, Pw += a * ui * wj1;
            Puu += a * ui2 * wj, Puw += a * ui1 * wj1, Pww += a * ui * wj2;
        }
    *v = P;
    g[0] = Pu * c - Pw * s, g[1] = Pu * s + Pw * c;
    h[0] = Puu * c * c - 2 * Puw * c * s + Pww * s * s;
    h[1] = Puu * c * s + Puw * (c * c - s * s) - Pww * s * c;
    h[2] = Puu * s * s + 2 * Puw * s * c + Pww * c * c;
}

/* a + bx + cy + dxy: bilinear in x and y. */
static void bilinear_f(const void *ctx, double x, double y, int ch, double *v, double g[2], double h[3]) {
    (void)ctx;
    double a = 1 + ch, b = 0.7 - 0.2 * ch, c = -1.3, d = 2.1 + 0.4 * ch;
    *v = a + b * x + c * y + d * x * y;
    g[0] = b + d * y, g[1] = c + d * x;
    h[0] = 0, h[1] = d, h[2] = 0;
}

static void quadratic_f(const void *ctx, double x, double y, int ch, double *v, double g[2], double h[3]) {
    (void)ctx;
    double a = 0.9 + 0.3 * ch;
    *v = 1.0 + 0.4 * x - 0.3 * y + a * x * x - 1.1 * x * y + 0.6 * y * y;
    g[0] = 0.4 + 2 * a * x - 1.1 * y, g[1] = -0.3 - 1.1 * x + 1.2 * y;
    h[0] = 2 * a, h[1] = -1.1, h[2] = 1.2;
}

static void linear_f(const void *ctx, double x, double y, int ch, double *v, double g[2], double h[3]) {
    (void)ctx;
    g[0] = 0.7 - 0.2 * ch, g[1] = -1.3 + 0.5 * ch;
    *v = 2.0 + ch + g[0] * x + g[1] * y;
    h[0] = h[1] = h[2] = 0;
}

/* Smooth, not a polynomial: the same function test_ct_props.c uses. */
static void smooth_q(const void *ctx, double x, double y, int ch, double *v, double g[2], double h[3]) {
    (void)ctx;
    double a = 1.0 + 0.3 * ch, X = 2 * a * x + 1, Y = 3 * y - 0.5 * a;
    *v = sin(X) * cos(Y) + 0.5 * x * y;
    g[0] = 2 * a * cos(X) * cos(Y) + 0.5 * y;
    g[1] = -3 * sin(X) * sin(Y) + 0.5 * x;
    h[0] = -4 * a * a * sin(X) * cos(Y);
    h[1] = -6 * a * cos(X) * sin(Y) + 0.5;
    h[2] = -9 * sin(X) * cos(Y);
}

/* ---- helpers ---- */

static tc_options hermite_opts(tc_tangents tangents, tc_twist twist) {
    tc_options o;
    tc_options_default(&o);
    o.method = TC_METHOD_HERMITE, o.tangents = tangents, o.twist = twist;
    return o;
}

/* The unlimited patches (range "free"), for the properties of the scheme itself:
 * bicubics overshoot their corners, so their reproduction is not the limiter's. */
static tc_options hermite_free(tc_tangents tangents, tc_twist twist) {
    tc_options o = hermite_opts(tangents, twist);
    o.range = TC_RANGE_FREE;
    return o;
}

/* Mesh and reconstruction of q (with gradients / hessians as asked), or fails the test. */
static tc_recon *build(const qmesh *q, int grads, int hess, tc_options o, tc_mesh **mout) {
    tc_mesh_desc d;
    qmesh_desc(q, grads, hess, &d);
    tc_diags dg;
    tc_diags_init(&dg);
    tc_mesh *m = NULL;
    tc_recon *r = NULL;
    int st = tc_mesh_new(&d, &m, &dg);
    CHECK_MSG(st == TC_OK, "tc_mesh_new: %d (%s: %s)", st, dg.count ? dg.items[0].path : "",
              dg.count ? dg.items[0].message : "");
    if (m) {
        st = tc_recon_new(m, &o, &r, &dg);
        CHECK_MSG(st == TC_OK, "tc_recon_new: %d (%s: %s)", st, dg.count ? dg.items[0].path : "",
                  dg.count ? dg.items[0].message : "");
    }
    tc_diags_free(&dg);
    *mout = m;
    return r;
}

static void x_of(const double *xy, const int32_t *q, double s, double t, double x[2]) {
    for (int i = 0; i < 2; i++)
        x[i] = (1 - s) * (1 - t) * xy[2 * q[0] + i] + s * (1 - t) * xy[2 * q[1] + i] + s * t * xy[2 * q[2] + i] +
               (1 - s) * t * xy[2 * q[3] + i];
}

/* Worst relative error of value (and gradient) against f at npts random
 * points of random quads: vs, gs are the scales. */
static double reproduction_error(const tc_recon *r, const qmesh *q, qfunc f, const void *ctx, int npts, trng *rng,
                                 double *grad_err) {
    double vs = 0, gs = 0, worst = 0, gworst = 0;
    for (int32_t v = 0; v < q->nv * q->nc; v++) {
        vs = fmax(vs, fabs(q->values[v]));
        gs = fmax(gs, hypot(q->grads[2 * v], q->grads[2 * v + 1]));
    }
    for (int i = 0; i < npts; i++) {
        int32_t qi = trng_int(rng, q->nq);
        double x[2], val[TC_MAX_CHANNELS], grad[2 * TC_MAX_CHANNELS];
        x_of(q->xy, q->quad + 4 * qi, trng_uniform(rng), trng_uniform(rng), x);
        tc_eval_triangle(r, 2 * qi + trng_int(rng, 2), x[0], x[1], val, grad);
        for (int ch = 0; ch < q->nc; ch++) {
            double fv, fg[2], fh[3];
            f(ctx, x[0], x[1], ch, &fv, fg, fh);
            worst = fmax(worst, fabs(val[ch] - fv) / vs);
            gworst = fmax(gworst, hypot(grad[2 * ch] - fg[0], grad[2 * ch + 1] - fg[1]) / gs);
        }
    }
    if (grad_err) *grad_err = gworst;
    return worst;
}

/* Continuity across shared quad edges: the worst value and gradient
 * differences between the two patches at 9 points along each edge. */
typedef struct {
    const tc_recon *r;
    int nc;
    double dv, dg;
} jump_ctx;

static void edge_jump(void *ctx, int32_t ta, int32_t tb, const double p[2], const double q[2]) {
    jump_ctx *j = ctx;
    for (int k = 1; k <= 9; k++) {
        double u = k / 10.0, x = p[0] + u * (q[0] - p[0]), y = p[1] + u * (q[1] - p[1]);
        double va[TC_MAX_CHANNELS], vb[TC_MAX_CHANNELS], ga[2 * TC_MAX_CHANNELS], gb[2 * TC_MAX_CHANNELS];
        tc_eval_triangle(j->r, ta, x, y, va, ga);
        tc_eval_triangle(j->r, tb, x, y, vb, gb);
        for (int ch = 0; ch < j->nc; ch++) {
            j->dv = fmax(j->dv, fabs(va[ch] - vb[ch]));
            j->dg = fmax(j->dg, hypot(ga[2 * ch] - gb[2 * ch], ga[2 * ch + 1] - gb[2 * ch + 1]));
        }
    }
}

/* Value and slope scales of sampled data (largest |value|, largest |gradient|). */
static void data_scales(const qmesh *q, double *vs, double *gs) {
    *vs = *gs = 0;
    for (int32_t v = 0; v < q->nv * q->nc; v++) {
        *vs = fmax(*vs, fabs(q->values[v]));
        *gs = fmax(*gs, hypot(q->grads[2 * v], q->grads[2 * v + 1]));
    }
}

static void measure_jumps(const tc_recon *r, const qmesh *q, double *dv, double *dg) {
    const tc_mesh *m = tc_recon_mesh(r);
    jump_ctx j = {r, tc_mesh_channel_count(m), 0, 0};
    double vs, gs;
    qmesh_shared_edges(m, edge_jump, &j);
    data_scales(q, &vs, &gs);
    *dv = j.dv / vs, *dg = j.dg / gs;
}

static const qgrid_opts PLAIN = {0, 0, {0, 0, 0, 0}, {0, 0}};

/* ---- the method and its layout ---- */

TEST(hermite_needs_quads) {
    static const double xy[] = {0, 0, 1, 0, 1, 1};
    static const int32_t tri[] = {0, 1, 2};
    static const double val[] = {1, 2, 3};
    tc_mesh_desc d;
    memset(&d, 0, sizeof d);
    d.nverts = 3, d.xy = xy, d.ntris = 1, d.tris = tri, d.nchan = 1, d.values = val;
    tc_mesh *m = NULL;
    CHECK(tc_mesh_new(&d, &m, NULL) == TC_OK);
    tc_options o = hermite_opts(TC_TANGENTS_AUTO, TC_TWIST_ESTIMATE);
    tc_recon *r = (tc_recon *)&r;
    tc_diags dg;
    tc_diags_init(&dg);
    CHECK(tc_recon_new(m, &o, &r, &dg) == TC_EINVAL);
    CHECK(r == NULL);
    CHECK(dg.count >= 1);
    if (dg.count >= 1) {
        CHECK(!strcmp(dg.items[0].path, "triangles"));
        CHECK_STR_CONTAINS(dg.items[0].message, "hermite needs quads");
    }
    tc_diags_free(&dg);
    tc_mesh_free(m);
}

/* 22 coefficients per split triangle, the same for both halves of a quad:
 * b00 .. b33 then the corners b, c, d relative to a; b00, b30, b33, b03 are
 * the corner values. */
TEST(hermite_ordinates_layout) {
    trng rng;
    trng_seed(&rng, tc_test_seed() + 301);
    qmesh q;
    qgrid_opts o = PLAIN;
    o.jitter = 0.2;
    qmesh_grid(&q, 3, 2, &o, &rng);
    qmesh_sample(&q, 2, smooth_q, NULL);
    tc_mesh *m = NULL;
    tc_recon *r = build(&q, 0, 0, hermite_opts(TC_TANGENTS_ESTIMATE, TC_TWIST_ESTIMATE), &m);
    if (r) {
        CHECK(tc_recon_coef_count(r) == TC_HERMITE_COEFS && TC_HERMITE_COEFS == 22);
        CHECK(!strcmp(tc_recon_coef_label(r, 0), "b00") && !strcmp(tc_recon_coef_label(r, 7), "b13"));
        CHECK(!strcmp(tc_recon_coef_label(r, 15), "b33") && !strcmp(tc_recon_coef_label(r, 16), "xb"));
        CHECK(!strcmp(tc_recon_coef_label(r, 21), "yd"));
        size_t per = 2 * (size_t)TC_HERMITE_COEFS;
        const double *c = tc_recon_coefs(r);
        for (int32_t qi = 0; qi < q.nq; qi++) {
            const double *o0 = c + 2 * (size_t)qi * per, *o1 = o0 + per;
            const int32_t *v = q.quad + 4 * qi;
            CHECK(!memcmp(o0, o1, per * sizeof *o0));
            for (int ch = 0; ch < 2; ch++) {
                const double *o2 = o0 + ch * TC_HERMITE_COEFS;
                CHECK(o2[0] == q.values[2 * v[0] + ch] && o2[12] == q.values[2 * v[1] + ch]);
                CHECK(o2[15] == q.values[2 * v[2] + ch] && o2[3] == q.values[2 * v[3] + ch]);
                for (int k = 1; k < 4; k++)
                    for (int i = 0; i < 2; i++)
                        CHECK(o2[TC_HERMITE_GEOM + 2 * (k - 1) + i] == q.xy[2 * v[k] + i] - q.xy[2 * v[0] + i]);
            }
        }
    }
    tc_recon_free(r);
    tc_mesh_free(m);
    qmesh_free(&q);
}

/* ---- interpolation and continuity ---- */

TEST(hermite_interpolates_corners) {
    trng rng;
    trng_seed(&rng, tc_test_seed() + 302);
    const tc_twist twists[] = {TC_TWIST_ESTIMATE, TC_TWIST_ZERO};
    for (int ti = 0; ti < 2; ti++) {
        qmesh q;
        qgrid_opts o = PLAIN;
        o.jitter = 0.25;
        qmesh_grid(&q, 5, 4, &o, &rng);
        qmesh_sample(&q, 3, smooth_q, NULL);
        tc_mesh *m = NULL;
        tc_recon *r = build(&q, 0, 0, hermite_opts(TC_TANGENTS_ESTIMATE, twists[ti]), &m);
        int bad = 0;
        for (int32_t qi = 0; r && qi < q.nq; qi++)
            for (int k = 0; k < 4; k++) {
                int32_t v = q.quad[4 * qi + k];
                for (int h = 0; h < 2; h++) {
                    double val[3];
                    tc_eval_triangle(r, 2 * qi + h, q.xy[2 * v], q.xy[2 * v + 1], val, NULL);
                    for (int ch = 0; ch < 3; ch++) bad += val[ch] != q.values[3 * v + ch];
                }
            }
        CHECK_MSG(bad == 0, "%d corner values not reproduced exactly", bad);
        tc_recon_free(r);
        tc_mesh_free(m);
        qmesh_free(&q);
    }
}

/* The value along a patch edge depends only on the values and the slopes
 * along it at its ends, which neighbours share: C0 on any convex quads. */
TEST(hermite_c0_across_quad_edges) {
    trng rng;
    trng_seed(&rng, tc_test_seed() + 303);
    double worst = 0;
    for (int rep = 0; rep < 4; rep++) {
        qmesh q;
        qgrid_opts o = PLAIN;
        o.jitter = 0.2, o.uneven = rep % 2;
        qmesh_grid(&q, 4 + rep, 5, &o, &rng);
        qmesh_sample(&q, 2, smooth_q, NULL);
        tc_mesh *m = NULL;
        tc_recon *r = build(&q, rep % 2, rep == 3, hermite_opts(rep % 2 ? TC_TANGENTS_GIVEN : TC_TANGENTS_ESTIMATE,
                                                               rep == 2 ? TC_TWIST_ZERO : TC_TWIST_ESTIMATE), &m);
        if (r) {
            double dv, dg;
            measure_jumps(r, &q, &dv, &dg);
            worst = fmax(worst, dv);
        }
        tc_recon_free(r);
        tc_mesh_free(m);
        qmesh_free(&q);
    }
    CHECK_MSG(worst <= 1e-12, "value jump across a shared edge: %.3g of the value scale", worst);
}

/* The parallelogram grids of an affine map: neighbours across an edge share
 * its direction and their transversal directions are parallel, and every
 * twist is x_s' H x_t with one H per vertex (given, or estimated per wedge,
 * or 0), so the cross derivatives match along the whole edge: C1. */
TEST(hermite_c1_on_parallelograms) {
    trng rng;
    trng_seed(&rng, tc_test_seed() + 304);
    const qgrid_opts grids[] = {
        {0, 0, {0, 0, 0, 0}, {0, 0}},                      /* unit squares */
        {0, 1, {1.3, 0.4, -0.2, 0.7}, {0.3, -1.1}},        /* uneven, sheared */
        {0, 1, {0.5, -0.866, 0.866, 0.5}, {1e3, 2e3}},     /* uneven, rotated, far from 0 */
    };
    const tc_twist twists[] = {TC_TWIST_ESTIMATE, TC_TWIST_ZERO, TC_TWIST_ESTIMATE};
    double worst = 0;
    for (int gi = 0; gi < 3; gi++)
        for (int ti = 0; ti < 3; ti++)
            for (int tan = 0; tan < 2; tan++) {
                qmesh q;
                qmesh_grid(&q, 5, 4, &grids[gi], &rng);
                qmesh_sample(&q, 2, smooth_q, NULL);
                tc_mesh *m = NULL;
                int hess = ti == 2; /* given hessians win over the twist option */
                tc_recon *r = build(&q, tan, hess,
                                    hermite_opts(tan ? TC_TANGENTS_GIVEN : TC_TANGENTS_ESTIMATE, twists[ti]), &m);
                if (r) {
                    double dv, dg;
                    measure_jumps(r, &q, &dv, &dg);
                    CHECK_MSG(dg <= 1e-10, "grid %d twist %d tangents %d: gradient jump %.3g", gi, ti, tan, dg);
                    worst = fmax(worst, dg);
                }
                tc_recon_free(r);
                tc_mesh_free(m);
                qmesh_free(&q);
            }
    fprintf(stderr, "  [hermite C1] parallelogram grids: worst gradient jump %.2g of the slope scale\n", worst);
}

/* On general convex quads the transversal derivative along an edge is a
 * rational function of the edge parameter from each side, and the twists of
 * the two sides need not be compatible: Hermite is C0 there, not C1. The jump
 * is measured (it is a discretisation error: it shrinks under refinement). */
TEST(hermite_gradient_jump_general_quads) {
    trng rng;
    trng_seed(&rng, tc_test_seed() + 305);
    const char *names[] = {"estimate", "zero", "hessians"};
    double prev[3] = {0, 0, 0};
    for (int n = 4; n <= 32; n *= 2) {
        double jump[3];
        for (int ti = 0; ti < 3; ti++) {
            trng_seed(&rng, tc_test_seed() + 305); /* the same mesh for every twist */
            qmesh q;
            qgrid_opts o = PLAIN;
            o.jitter = 0.25;
            qmesh_grid(&q, n, n, &o, &rng);
            qmesh_sample(&q, 1, smooth_q, NULL);
            tc_mesh *m = NULL;
            tc_recon *r = build(&q, 1, ti == 2, hermite_opts(TC_TANGENTS_GIVEN, ti == 1 ? TC_TWIST_ZERO : TC_TWIST_ESTIMATE), &m);
            double dv = 0;
            jump[ti] = NAN;
            if (r) measure_jumps(r, &q, &dv, &jump[ti]);
            CHECK(isfinite(jump[ti]) && dv <= 1e-12);
            tc_recon_free(r);
            tc_mesh_free(m);
            qmesh_free(&q);
        }
        fprintf(stderr, "  [hermite jump] general quads (jitter 0.25) %2dx%-2d, exact gradients: max gradient jump "
                        "/ max |grad| = %.3g (twist estimate), %.3g (zero), %.3g (hessians)",
                n, n, jump[0], jump[1], jump[2]);
        if (n > 4)
            fprintf(stderr, "; order %.2f %.2f %.2f", log2(prev[0] / jump[0]), log2(prev[1] / jump[1]),
                    log2(prev[2] / jump[2]));
        fputc('\n', stderr);
        for (int ti = 0; ti < 3; ti++) {
            CHECK_MSG(jump[ti] > 1e-9, "twist %s: no measurable jump on general quads?", names[ti]);
            prev[ti] = jump[ti];
        }
    }
    CHECK_MSG(prev[0] < 0.05, "the jump should shrink under refinement (%.3g at 32x32)", prev[0]);
}

/* Parallelograms whose transversal directions differ across an edge (rows
 * leaning alternately left and right, a herringbone): the cross derivative
 * along the shared edge is a different cubic from each side unless the twists
 * satisfy a compatibility they generally do not, even exact ones. Measured. */
TEST(hermite_gradient_jump_herringbone) {
    for (int n = 4; n <= 16; n *= 2) {
        trng rng;
        trng_seed(&rng, tc_test_seed() + 314);
        qmesh q;
        qmesh_grid(&q, n, n, &PLAIN, &rng);
        for (int32_t v = 0; v < q.nv; v++) q.xy[2 * v] += (v / (n + 1)) % 2 ? 0.3 / n : 0;
        qmesh_sample(&q, 1, smooth_q, NULL);
        double jump[2];
        for (int hess = 0; hess < 2; hess++) {
            tc_mesh *m = NULL;
            tc_recon *r = build(&q, 1, hess, hermite_opts(TC_TANGENTS_GIVEN, TC_TWIST_ESTIMATE), &m);
            double dv = 0;
            jump[hess] = NAN;
            if (r) measure_jumps(r, &q, &dv, &jump[hess]);
            CHECK(dv <= 1e-12 && jump[hess] > 1e-9);
            tc_recon_free(r);
            tc_mesh_free(m);
        }
        fprintf(stderr, "  [hermite jump] herringbone parallelograms %2dx%-2d: max gradient jump / max |grad| = %.3g "
                        "(twist estimate), %.3g (hessians)\n", n, n, jump[0], jump[1]);
        qmesh_free(&q);
    }
}

/* ---- polynomial reproduction ---- */

/* On rectangles a bicubic in the rectangle's axes is bicubic in (s, t), and
 * exact values, gradients and hessians give its exact Hermite data. */
TEST(hermite_bicubic_reproduced_on_rectangles) {
    trng rng;
    trng_seed(&rng, tc_test_seed() + 306);
    const double angles[] = {0, 0.7};
    for (int ai = 0; ai < 2; ai++) {
        double th = angles[ai], c = cos(th), s = sin(th);
        qgrid_opts o = {0, 1, {c, -s, s, c}, {0, 0}}; /* uneven cells, then the frame's rotation */
        qmesh q;
        qmesh_grid(&q, 4, 3, &o, &rng);
        qmesh_sample(&q, 2, bicubic_f, &th);
        tc_mesh *m = NULL;
        tc_recon *r = build(&q, 1, 1, hermite_free(TC_TANGENTS_GIVEN, TC_TWIST_ESTIMATE), &m);
        if (r) {
            double ge, ve = reproduction_error(r, &q, bicubic_f, &th, 2000, &rng, &ge);
            CHECK_MSG(ve <= 1e-12 && ge <= 1e-12, "angle %g: value error %.3g, gradient error %.3g", th, ve, ge);
        }
        tc_recon_free(r);
        tc_mesh_free(m);
        qmesh_free(&q);
    }
}

/* A quadratic (bilinear ones included) composed with a bilinear map is
 * biquadratic in (s, t): exact Hermite data reproduce it on any convex quad.
 * The estimated twist is exact for it (planes of a quadratic change linearly),
 * zero twist only where x_s' H x_t vanishes. Linear data: every twist. */
TEST(hermite_quadratics_reproduced_with_twist_estimate) {
    trng rng;
    trng_seed(&rng, tc_test_seed() + 307);
    struct {
        qfunc f;
        const char *name;
    } fs[] = {{bilinear_f, "bilinear"}, {quadratic_f, "quadratic"}, {linear_f, "linear"}};
    for (int fi = 0; fi < 3; fi++)
        for (int jit = 0; jit < 2; jit++) {
            qmesh q;
            qgrid_opts o = {jit ? 0.3 : 0, 1, {0.8, 0.3, -0.1, 1.2}, {5, -3}};
            qmesh_grid(&q, 4, 5, &o, &rng);
            qmesh_sample(&q, 2, fs[fi].f, NULL);
            for (int ti = 0; ti < 2; ti++) {
                tc_mesh *m = NULL;
                tc_recon *r =
                    build(&q, 1, 0, hermite_opts(TC_TANGENTS_GIVEN, ti ? TC_TWIST_ZERO : TC_TWIST_ESTIMATE), &m);
                if (r) {
                    double ge, ve = reproduction_error(r, &q, fs[fi].f, NULL, 1000, &rng, &ge);
                    if (ti == 0 || fi == 2)
                        CHECK_MSG(ve <= 1e-12 && ge <= 1e-12, "%s, jitter %d, twist %s: value error %.3g, gradient %.3g",
                                  fs[fi].name, jit, ti ? "zero" : "estimate", ve, ge);
                    else
                        CHECK_MSG(ve > 1e-6, "%s, twist zero: exact (%.3g)? it should miss x_s'Hx_t", fs[fi].name, ve);
                }
                tc_recon_free(r);
                tc_mesh_free(m);
            }
            qmesh_free(&q);
        }
}

/* With estimated tangent planes (least squares per wedge, exact for
 * quadratics where the fit has six samples: not at the boundary, where it may
 * fall back to a plane) the twist estimate still makes a bilinear function
 * exact on the quads whose corners and their neighbours all have such a fit. */
TEST(hermite_bilinear_with_estimated_planes) {
    trng rng;
    trng_seed(&rng, tc_test_seed() + 308);
    qmesh q;
    qgrid_opts o = PLAIN;
    o.jitter = 0.2;
    qmesh_grid(&q, 7, 7, &o, &rng);
    qmesh_sample(&q, 1, bilinear_f, NULL);
    tc_mesh *m = NULL;
    tc_recon *r = build(&q, 0, 0, hermite_opts(TC_TANGENTS_ESTIMATE, TC_TWIST_ESTIMATE), &m);
    double worst = 0;
    for (int32_t qi = 0; r && qi < q.nq; qi++) {
        int i = qi % q.nx, j = qi / q.nx;
        if (i < 2 || j < 2 || i > q.nx - 3 || j > q.ny - 3) continue; /* two rings from the boundary */
        for (int k = 0; k < 20; k++) {
            double x[2], val, grad[2], fv, fg[2], fh[3];
            x_of(q.xy, q.quad + 4 * qi, trng_uniform(&rng), trng_uniform(&rng), x);
            tc_eval_triangle(r, 2 * qi, x[0], x[1], &val, grad);
            bilinear_f(NULL, x[0], x[1], 0, &fv, fg, fh);
            worst = fmax(worst, fabs(val - fv));
        }
    }
    CHECK_MSG(worst <= 1e-11, "bilinear with estimated planes, interior quads: error %.3g", worst);
    tc_recon_free(r);
    tc_mesh_free(m);
    qmesh_free(&q);
}

/* ---- the inverse of the bilinear map ---- */

/* x(s, t) relative to P[0] = 0, as the patch evaluates it. */
static void map_at(const double P[4][2], double s, double t, double x[2]) {
    for (int i = 0; i < 2; i++) x[i] = s * P[1][i] + t * P[3][i] + s * t * (P[2][i] - P[1][i] - P[3][i]);
}

TEST(hermite_inverse_map_roundtrip) {
    trng rng;
    trng_seed(&rng, tc_test_seed() + 309);
    struct {
        const char *name;
        double P[4][2];
        double tol; /* on (s, t): the map's conditioning limits it near degenerate corners */
    } quads[] = {
        {"unit square", {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, 1e-14},
        {"parallelogram", {{0, 0}, {2, 0.5}, {2.7, 1.9}, {0.7, 1.4}}, 1e-14},
        {"near-parallelogram", {{0, 0}, {1, 0}, {1 + 1e-13, 1}, {0, 1}}, 1e-14},
        {"general", {{0, 0}, {1.3, -0.2}, {1.1, 0.9}, {-0.1, 1.4}}, 1e-14},
        {"aspect 1e4 rectangle", {{0, 0}, {1e4, 0}, {1e4, 1}, {0, 1}}, 1e-12},
        {"aspect 1e4 trapezoid", {{0, 0}, {1, 0}, {0.7, 1e-4}, {0.2, 1e-4}}, 1e-10},
        {"nearly triangular", {{0, 0}, {1, 0}, {0, 1}, {-1e-6, 0.5}}, 1e-6},
        {"tiny", {{0, 0}, {1e-200, 0}, {1.2e-200, 1e-200}, {0, 0.9e-200}}, 1e-14},
    };
    for (size_t qi = 0; qi < sizeof quads / sizeof quads[0]; qi++) {
        double worst = 0, L = 0;
        for (int k = 1; k < 4; k++) L = fmax(L, hypot(quads[qi].P[k][0], quads[qi].P[k][1]));
        int nan = 0;
        for (int i = 0; i < 4000; i++) {
            double s = trng_uniform(&rng), t = trng_uniform(&rng), x[2], st[2];
            if (i < 16) s = (i % 4) / 3.0, t = (i / 4) / 3.0; /* the corners and edges exactly */
            map_at(quads[qi].P, s, t, x);
            tc__bilinear_inverse(quads[qi].P, x, st);
            nan += !isfinite(st[0]) || !isfinite(st[1]);
            worst = fmax(worst, fmax(fabs(st[0] - s), fabs(st[1] - t)));
        }
        /* far outside: finite, whatever the answer */
        for (int i = 0; i < 200; i++) {
            double x[2] = {L * 1e6 * (2 * trng_uniform(&rng) - 1), L * 1e6 * (2 * trng_uniform(&rng) - 1)}, st[2];
            tc__bilinear_inverse(quads[qi].P, x, st);
            nan += !isfinite(st[0]) || !isfinite(st[1]);
        }
        CHECK_MSG(nan == 0, "%s: %d non-finite parameters", quads[qi].name, nan);
        CHECK_MSG(worst <= quads[qi].tol, "%s: round trip off by %.3g (tolerance %.1g)", quads[qi].name, worst,
                  quads[qi].tol);
        fprintf(stderr, "  [hermite inverse] %-22s worst |(s,t) - x^-1(x(s,t))| = %.2g\n", quads[qi].name, worst);
    }
    /* the four corners come back exactly */
    const double P[4][2] = {{0, 0}, {1.3, -0.2}, {1.1, 0.9}, {-0.1, 1.4}}, want[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (int k = 0; k < 4; k++) {
        double st[2];
        tc__bilinear_inverse(P, P[k], st);
        CHECK(st[0] == want[k][0] && st[1] == want[k][1]);
    }
}

/* Evaluation anywhere, on degenerate-looking quads and far outside: finite. */
TEST(hermite_never_nan) {
    static const double xy[] = {0, 0, 1, 0, 0, 1, -1e-7, 0.5, 2, 0, 2, 1e-4};
    static const int32_t quads[] = {0, 1, 2, 3, 1, 4, 5, 2};
    static const double val[] = {1, 2, 3, 4, 5, 6};
    tc_mesh_desc d;
    memset(&d, 0, sizeof d);
    d.nverts = 6, d.xy = xy, d.nquads = 2, d.quads = quads, d.nchan = 1, d.values = val;
    tc_mesh *m = NULL;
    tc_diags dg;
    tc_diags_init(&dg);
    int st = tc_mesh_new(&d, &m, &dg);
    CHECK_MSG(st == TC_OK, "%s: %s", dg.count ? dg.items[0].path : "", dg.count ? dg.items[0].message : "");
    trng rng;
    trng_seed(&rng, tc_test_seed() + 310);
    for (int ti = 0; m && ti < 2; ti++) {
        tc_options o = hermite_opts(TC_TANGENTS_ESTIMATE, ti ? TC_TWIST_ZERO : TC_TWIST_ESTIMATE);
        tc_recon *r = NULL;
        CHECK(tc_recon_new(m, &o, &r, NULL) == TC_OK);
        int bad = 0;
        for (int i = 0; r && i < 20000; i++) {
            double span = i < 10000 ? 3 : 1e8, x = span * (2 * trng_uniform(&rng) - 1), y = span * (2 * trng_uniform(&rng) - 1);
            double v, g[2];
            tc_eval_triangle(r, trng_int(&rng, 4), x, y, &v, g);
            bad += !isfinite(v) || !isfinite(g[0]) || !isfinite(g[1]);
        }
        CHECK_MSG(bad == 0, "%d non-finite evaluations", bad);
        tc_recon_free(r);
    }
    tc_diags_free(&dg);
    tc_mesh_free(m);
}

/* ---- flags ---- */

/* f = |x - 1/2| + [y > 1/2] + smooth, with a C0 line on x = 1/2 and a C-1 line
 * on y = 1/2 (the jump given as per-quad corner values): C0 across the C0
 * edges with the kink kept, the jump across the C-1 edges kept. */
static void kink_f(const void *ctx, double x, double y, int ch, double *v, double g[2], double h[3]) {
    (void)ctx, (void)ch;
    *v = fabs(x - 0.5) + (y > 0.5) + 0.3 * x * y;
    g[0] = g[1] = h[0] = h[1] = h[2] = 0; /* not used: planes are estimated per side */
}

TEST(hermite_kinks_and_jumps_kept) {
    enum { N = 4 };
    trng rng;
    trng_seed(&rng, tc_test_seed() + 311);
    qmesh q;
    qmesh_grid(&q, N, N, &PLAIN, &rng); /* vertices exactly at (i/N, j/N) */
    qmesh_sample(&q, 1, kink_f, NULL);
    /* per-quad corner values: corners on y = 1/2 take the side of their quad */
    int32_t cvq[N * N];
    double cv[N * N * 4];
    int ncv = 0;
    for (int32_t qi = 0; qi < q.nq; qi++) {
        const int32_t *c = q.quad + 4 * qi;
        double cy = 0;
        for (int k = 0; k < 4; k++) cy += q.xy[2 * c[k] + 1] / 4;
        int touches = 0;
        for (int k = 0; k < 4; k++) touches |= q.xy[2 * c[k] + 1] == 0.5;
        if (!touches) continue;
        cvq[ncv] = qi;
        for (int k = 0; k < 4; k++) {
            double x = q.xy[2 * c[k]], y = q.xy[2 * c[k] + 1];
            cv[4 * ncv + k] = fabs(x - 0.5) + (y > 0.5 || (y == 0.5 && cy > 0.5)) + 0.3 * x * y;
        }
        ncv++;
    }
    int32_t c0v[N + 1], cm1v[N + 1], c0s[2] = {0, N + 1}, cm1s[2] = {0, N + 1};
    for (int k = 0; k <= N; k++) c0v[k] = k * (N + 1) + N / 2, cm1v[k] = (N / 2) * (N + 1) + k;
    tc_mesh_desc d;
    qmesh_desc(&q, 0, 0, &d);
    d.ncorner_values = ncv, d.corner_values_tri = cvq, d.corner_values = cv;
    d.c0 = (tc_polylines){1, c0s, c0v};
    d.cm1 = (tc_polylines){1, cm1s, cm1v};
    tc_mesh *m = NULL;
    tc_diags dg;
    tc_diags_init(&dg);
    int st = tc_mesh_new(&d, &m, &dg);
    CHECK_MSG(st == TC_OK, "%s: %s", dg.count ? dg.items[0].path : "", dg.count ? dg.items[0].message : "");
    tc_options o = hermite_opts(TC_TANGENTS_ESTIMATE, TC_TWIST_ESTIMATE);
    tc_recon *r = NULL;
    if (m) CHECK(tc_recon_new(m, &o, &r, &dg) == TC_OK);
    double c0_value = 0, c0_kink = INFINITY, cm1_jump = INFINITY;
    for (int32_t t = 0; r && t < tc_mesh_triangle_count(m); t++)
        for (int k = 0; k < 3; k++) {
            int nk;
            int32_t t2 = tc_mesh_neighbor(m, t, k, &nk);
            tc_continuity f = tc_mesh_edge_flag(m, t, k);
            if (t2 < t || f == TC_C1) continue;
            const int32_t *tv = tc_mesh_triangles(m) + 3 * t;
            const double *p = tc_mesh_xy(m) + 2 * tv[k], *pq = tc_mesh_xy(m) + 2 * tv[(k + 1) % 3];
            for (int i = 1; i <= 9; i++) {
                double u = i / 10.0, x = p[0] + u * (pq[0] - p[0]), y = p[1] + u * (pq[1] - p[1]), va, vb, ga[2], gb[2];
                tc_eval_triangle(r, t, x, y, &va, ga);
                tc_eval_triangle(r, t2, x, y, &vb, gb);
                if (f == TC_C0) {
                    c0_value = fmax(c0_value, fabs(va - vb));
                    c0_kink = fmin(c0_kink, fabs(ga[0] - gb[0]));
                } else {
                    cm1_jump = fmin(cm1_jump, fabs(va - vb));
                }
            }
        }
    CHECK_MSG(c0_value <= 1e-12, "value jump across C0 edges: %.3g", c0_value);
    CHECK_MSG(c0_kink > 1.0, "the kink (d/dx jumps by 2) is flattened: smallest jump %.3g", c0_kink);
    CHECK_MSG(cm1_jump > 0.5, "the jump (1) is lost: smallest %.3g", cm1_jump);
    fprintf(stderr, "  [hermite flags] C0 value jump %.2g, smallest kink %.3g (data 2), smallest C-1 jump %.3g (data 1)\n",
            c0_value, c0_kink, cm1_jump);
    tc_recon_free(r);
    tc_diags_free(&dg);
    tc_mesh_free(m);
    qmesh_free(&q);
}

/* A sliver column 3e-5 wide beside cells 0.1 wide, the data steep inside it:
 * the estimated second derivatives there are ~1e8 and would make twists of
 * ~1e6 on the wide cells. The steep planes alone already make any cubic on the
 * wide cells overshoot (as clough-tocher does); the limiter keeps the twist
 * from adding to that: twist estimate stays within 2x of twist zero. */
static void steep_f(const void *ctx, double x, double y, int ch, double *v, double g[2], double h[3]) {
    (void)ctx, (void)ch;
    *v = 0.5 * tanh((x - 0.500015) / 1e-5) + y * y;
    g[0] = g[1] = h[0] = h[1] = h[2] = 0;
}

TEST(hermite_twist_limited_beside_slivers) {
    static const double xs[] = {0, 0.4, 0.5, 0.50003, 0.6, 1}, ys[] = {0, 0.3, 0.7, 1};
    double worst[2] = {0, 0};
    for (int ti = 0; ti < 2; ti++) {
        trng rng;
        trng_seed(&rng, tc_test_seed() + 313);
        qmesh q;
        qmesh_grid(&q, 5, 3, &PLAIN, &rng);
        for (int32_t v = 0; v < q.nv; v++) q.xy[2 * v] = xs[v % 6], q.xy[2 * v + 1] = ys[v / 6];
        qmesh_sample(&q, 1, steep_f, NULL);
        tc_mesh *m = NULL;
        tc_recon *r = build(&q, 0, 0, hermite_opts(TC_TANGENTS_ESTIMATE, ti ? TC_TWIST_ZERO : TC_TWIST_ESTIMATE), &m);
        for (int32_t qi = 0; r && qi < q.nq; qi++)
            for (int k = 0; k < 200; k++) {
                double x[2], val, fv, fg[2], fh[3];
                x_of(q.xy, q.quad + 4 * qi, trng_uniform(&rng), trng_uniform(&rng), x);
                tc_eval_triangle(r, 2 * qi, x[0], x[1], &val, NULL);
                steep_f(NULL, x[0], x[1], 0, &fv, fg, fh);
                worst[ti] = fmax(worst[ti], fabs(val - fv));
            }
        tc_recon_free(r);
        tc_mesh_free(m);
        qmesh_free(&q);
    }
    fprintf(stderr, "  [hermite limiter] sliver column beside wide cells: max error %.3g (twist estimate), %.3g (zero)\n",
            worst[0], worst[1]);
    CHECK_MSG(worst[0] <= 2 * worst[1], "the estimated twists add to the overshoot: %.3g against %.3g", worst[0],
              worst[1]);
}

/* ---- the twist choices, measured ---- */

/* Errors of twist estimate and zero (and exact hessians) on smooth data under
 * refinement, on rectangles, parallelograms and general quads, with exact
 * gradients (the twist is then the only approximation at the corners) and
 * with estimated planes. The numbers go into docs/design-notes.md. */
TEST(hermite_twist_estimate_vs_zero) {
    const char *grid_names[] = {"rectangles", "parallelograms", "general quads"};
    const qgrid_opts grids[] = {{0, 1, {0, 0, 0, 0}, {0, 0}}, {0, 1, {1, 0.5, 0, 1}, {0, 0}}, {0.25, 0, {0, 0, 0, 0}, {0, 0}}};
    for (int gi = 0; gi < 3; gi++)
        for (int tan = 0; tan < 2; tan++) {
            double prev[3] = {0, 0, 0};
            for (int n = 4; n <= 32; n *= 2) {
                double err[3];
                for (int ti = 0; ti < 3; ti++) {
                    trng rng;
                    trng_seed(&rng, tc_test_seed() + 312);
                    qmesh q;
                    qmesh_grid(&q, n, n, &grids[gi], &rng);
                    qmesh_sample(&q, 1, smooth_q, NULL);
                    tc_mesh *m = NULL;
                    tc_recon *r = build(&q, tan == 0, ti == 2,
                                        hermite_free(tan == 0 ? TC_TANGENTS_GIVEN : TC_TANGENTS_ESTIMATE,
                                                     ti == 1 ? TC_TWIST_ZERO : TC_TWIST_ESTIMATE), &m);
                    err[ti] = r ? reproduction_error(r, &q, smooth_q, NULL, 4000, &rng, NULL) : NAN;
                    tc_recon_free(r);
                    tc_mesh_free(m);
                    qmesh_free(&q);
                }
                fprintf(stderr, "  [hermite twist] %-14s %-9s %2dx%-2d max error / max |f|: estimate %.3g, zero %.3g, "
                                "hessians %.3g",
                        grid_names[gi], tan == 0 ? "gradients" : "estimate", n, n, err[0], err[1], err[2]);
                if (n > 4)
                    fprintf(stderr, "; order %.2f %.2f %.2f", log2(prev[0] / err[0]), log2(prev[1] / err[1]),
                            log2(prev[2] / err[2]));
                fputc('\n', stderr);
                if (n == 32 && tan == 0)
                    CHECK_MSG(err[0] < err[1], "%s: twist estimate (%.3g) no better than zero (%.3g)",
                              grid_names[gi], err[0], err[1]);
                for (int ti = 0; ti < 3; ti++) prev[ti] = err[ti];
            }
        }
}
