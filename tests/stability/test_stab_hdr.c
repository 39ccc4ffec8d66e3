/* test_stab_hdr.c — value ranges: 1e-12..1e12 in one mesh, subnormals, negative values, and
 * constant data, which every method must reproduce bit for bit at any point. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "props.h"
#include "quadgen.h"
#include "stab.h"

static const tc_tangents SOURCES[] = {TC_TANGENTS_GIVEN, TC_TANGENTS_MIDPOINTS, TC_TANGENTS_ESTIMATE};
#define NSRC 3

/* 10^(24x - 12) (1 + 0.3 sin 5y): 1e-12 at x = 0 to 1e12 at x = 1. */
static void hdr_f(const void *ctx, double x, double y, int ch, double *v, double g[2]) {
    (void)ctx, (void)ch;
    double e = pow(10, 24 * x - 12), s = 1 + 0.3 * sin(5 * y);
    *v = e * s;
    g[0] = 24 * log(10) * e * s, g[1] = e * 1.5 * cos(5 * y);
}

/* Subnormal: smooth data times 1e-310 (gradients too), so every number is subnormal or 0. */
static void subnormal_f(const void *ctx, double x, double y, int ch, double *v, double g[2]) {
    smooth_f(ctx, x, y, ch, v, g);
    *v *= 1e-310, g[0] *= 1e-310, g[1] *= 1e-310;
}

/* Negative and sign-changing: smooth data minus 0.4, times -3. */
static void negative_f(const void *ctx, double x, double y, int ch, double *v, double g[2]) {
    smooth_f(ctx, x, y, ch, v, g);
    *v = -3 * (*v - 0.4), g[0] *= -3, g[1] *= -3;
}

typedef struct {
    stab_acc c0[STAB_NVAR], c1[STAB_NVAR], over[STAB_NVAR];
} range_figs;

static void measure(const tc_mesh_desc *d, int v, tc_tangents src, range_figs *f) {
    tc_options o;
    stab_options(v, src, &o);
    srun x;
    char where[48];
    snprintf(where, sizeof where, "tangents %s", tc_tangents_name(src));
    if (srun_start(&x, d, &o)) {
        stab_acc_refusal(&f->c0[v], &x);
        srun_end(&x);
        return;
    }
    stab_cont c;
    stab_range r;
    int fin = stab_measure(x.r, 30, 9, &c, &r);
    stab_acc_fig(&f->c0[v], fin ? fmax(c.corner, c.c0) : INFINITY, where);
    if (stab_has_planes(v) && v != STAB_HERMITE)
        stab_acc_fig(&f->c1[v], fin ? fmax(c.c1, fmax(c.vertex, c.internal)) : INFINITY, where);
    stab_acc_fig(&f->over[v], stab_overshoot(&r), where);
    srun_end(&x);
}

/* The mesh of these cases: a jittered 8 x 8 grid with a C0 row and a C-1 crack (no jump:
 * a fixed jump means nothing across 24 decades), gradients and midpoints; and the same
 * cells as quads for hermite. */
static void range_meshes(tfunc fn, tmesh *gm, sdesc *q) {
    tmesh g;
    trng r;
    trng_seed(&r, 4242);
    tmesh_grid(&g, 8, 8, 0.2, -1, &r);
    int32_t row[9], col[5];
    for (int i = 0; i <= 8; i++) row[i] = tmesh_gv(8, i, 4);
    for (int j = 0; j <= 4; j++) col[j] = tmesh_gv(8, 4, j);
    tmesh_add_line(&g, TC_C0, row, 9);
    tmesh_add_line(&g, TC_CM1, col, 5);
    tmesh_sample(&g, 1, fn, NULL, 1, 1, 0);
    tc_mesh_desc d;
    tmesh_desc(&g, &d);
    tc_mesh_desc qd = d;
    int32_t quads[4 * 64];
    for (int j = 0; j < 8; j++)
        for (int i = 0; i < 8; i++) {
            int32_t a = tmesh_gv(8, i, j), *p = quads + 4 * (j * 8 + i);
            p[0] = a, p[1] = a + 1, p[2] = a + 10, p[3] = a + 9;
        }
    qd.ntris = 0, qd.tris = NULL, qd.nquads = 64, qd.quads = quads, qd.nmidpoints = 0, qd.ncorner_values = 0;
    sdesc_copy(q, &qd);
    sdesc_add_midpoints(q, fn, NULL);
    *gm = g;
}

static void range_case(const char *name, tfunc fn) {
    static range_figs f;
    stab_acc_init(f.c0, STAB_NVAR), stab_acc_init(f.c1, STAB_NVAR), stab_acc_init(f.over, STAB_NVAR);
    tmesh g;
    sdesc q;
    range_meshes(fn, &g, &q);
    tc_mesh_desc d;
    tmesh_desc(&g, &d);
    for (int v = 0; v < STAB_NVAR; v++)
        for (int s = 0; s < NSRC; s++) measure(v == STAB_HERMITE ? &q.d : &d, v, SOURCES[s], &f);
    STAB_REPORT(name, "C0 residual (interpolation, values across C0/C1 edges; local scale)", f.c0, 1e-9, 0);
    STAB_REPORT(name, "C1 residual (local scale)", f.c1, 1e-9, 0);
    STAB_REPORT(name, "overshoot beyond the data range / range", f.over, -1, STAB_INFO);
    sdesc_free(&q);
    tmesh_free(&g);
}

TEST(stab_hdr_range) { range_case("hdr-1e-12..1e12", hdr_f); }
TEST(stab_hdr_subnormal) { range_case("hdr-subnormal", subnormal_f); }
TEST(stab_hdr_negative) { range_case("hdr-negative", negative_f); }

/* ---- constant data ---- */

static double cval; /* the constant of the current run */

static void const_f(const void *ctx, double x, double y, int ch, double *v, double g[2]) {
    (void)ctx, (void)x, (void)y, (void)ch;
    *v = cval, g[0] = g[1] = 0;
}

static void qconst_f(const void *ctx, double x, double y, int ch, double *v, double g[2], double h[3]) {
    const_f(ctx, x, y, ch, v, g);
    h[0] = h[1] = h[2] = 0;
}

/* Folds one value and gradient into the errors: |v - c| / |c| and |g| / |c| (0 when exact). */
static void fold(double v, const double g[2], double *verr, double *gerr) {
    double scale = fmax(fabs(cval), DBL_TRUE_MIN);
    *verr = fmax(*verr, v == cval ? 0 : isfinite(v) ? fabs(v - cval) / scale : INFINITY);
    *gerr = fmax(*gerr, g[0] == 0 && g[1] == 0 ? 0 : isfinite(g[0] + g[1]) ? hypot(g[0], g[1]) / scale : INFINITY);
}

/* Located points over the mesh's box and every vertex. */
static void located_errors(const srun *x, double *verr, double *gerr) {
    const tc_mesh *m = x->m;
    int nc = tc_mesh_channel_count(m), n = 0;
    double xy[2 * 600], v[600 * 3], g[600 * 6];
    int32_t tri[600];
    trng r;
    trng_seed(&r, 31);
    for (; n < 400; n++) xy[2 * n] = 1.2 * trng_uniform(&r) - 0.1, xy[2 * n + 1] = 1.2 * trng_uniform(&r) - 0.1;
    for (int32_t i = 0; i < tc_mesh_vertex_count(m) && n < 600; i++, n++)
        memcpy(xy + 2 * n, tc_mesh_xy(m) + 2 * i, 2 * sizeof *xy);
    tc_eval_points(x->r, x->L, (size_t)n, xy, v, g, tri);
    for (int i = 0; i < n * nc; i++)
        if (tri[i / nc] >= 0) fold(v[i], g + 2 * i, verr, gerr);
}

/* Each piece at its centroid and extended past its first corner. */
static void piece_errors(const srun *x, double *verr, double *gerr) {
    const tc_mesh *m = x->m;
    const double *p = tc_mesh_xy(m);
    for (int32_t t = 0; t < tc_mesh_triangle_count(m); t++)
        for (int j = 0; j < 2; j++) {
            const int32_t *tv = tc_mesh_triangles(m) + 3 * t;
            double px = (p[2 * tv[0]] + p[2 * tv[1]] + p[2 * tv[2]]) / 3;
            double py = (p[2 * tv[0] + 1] + p[2 * tv[1] + 1] + p[2 * tv[2] + 1]) / 3, vv[3], gg[6];
            if (j) px = 1.5 * p[2 * tv[0]] - 0.5 * px, py = 1.5 * p[2 * tv[0] + 1] - 0.5 * py;
            tc_eval_triangle(x->r, t, px, py, vv, gg);
            for (int ch = 0; ch < tc_mesh_channel_count(m); ch++) fold(vv[ch], gg + 2 * ch, verr, gerr);
        }
}

/* Largest |value - c| / |c| and |gradient| / |c| over arbitrary points. */
static void constant_errors(const srun *x, double *verr, double *gerr) {
    *verr = *gerr = 0;
    located_errors(x, verr, gerr);
    piece_errors(x, verr, gerr);
}

static void constant_run(const tc_mesh_desc *d, int v, tc_tangents src, stab_acc *va, stab_acc *ga) {
    tc_options o;
    stab_options(v, src, &o);
    srun x;
    char where[64];
    snprintf(where, sizeof where, "c = %g, tangents %s", cval, tc_tangents_name(src));
    if (srun_start(&x, d, &o)) {
        stab_acc_refusal(va, &x);
    } else {
        double ve, ge;
        constant_errors(&x, &ve, &ge);
        stab_acc_fig(va, ve, where);
        stab_acc_fig(ga, ge, where);
    }
    srun_end(&x);
}

static void constant_case(const char *name, const double *cs, int ncs, int flags) {
    static stab_acc va[STAB_NVAR], ga[STAB_NVAR];
    stab_acc_init(va, STAB_NVAR), stab_acc_init(ga, STAB_NVAR);
    for (int i = 0; i < ncs; i++) {
        cval = cs[i];
        trng r;
        trng_seed(&r, 77);
        tmesh g;
        random_flagged_mesh(&g, &r, 1, 12);
        tmesh_sample(&g, 2, const_f, NULL, 1, 1, 0);
        tc_mesh_desc d;
        tmesh_desc(&g, &d);
        qmesh q;
        qgrid_opts qo = {.jitter = 0.3};
        qmesh_grid(&q, 5, 5, &qo, &r);
        qmesh_sample(&q, 2, qconst_f, NULL);
        tc_mesh_desc qd;
        qmesh_desc(&q, 1, 0, &qd);
        sdesc qs;
        sdesc_copy(&qs, &qd);
        sdesc_add_midpoints(&qs, const_f, NULL);
        for (int v = 0; v < STAB_NVAR; v++)
            for (int s = 0; s < NSRC; s++) constant_run(v == STAB_HERMITE ? &qs.d : &d, v, SOURCES[s], &va[v], &ga[v]);
        sdesc_free(&qs);
        qmesh_free(&q);
        tmesh_free(&g);
    }
    STAB_REPORT(name, "max |value - c| / |c| at arbitrary points (bit for bit: 0)", va, 0, flags);
    STAB_REPORT(name, "max |gradient| / |c| (exactly 0)", ga, 0, flags);
}

/* Every method, with flags (C0 rows, a C-1 crack, walks), two channels, every tangent source. */
TEST(stab_constant_exact) {
    static const double cs[] = {0.0, 0.1, -7.3, 1.0 / 3, 1e-300, 4.9e-324, 1e300, -1e300};
    constant_case("constant", cs, 8, STAB_NO_REFUSAL);
}

/* Near the top of the double range a refusal naming the element is allowed. */
TEST(stab_constant_near_max) {
    static const double cs[] = {1.7e308, -1.7e308};
    constant_case("constant-near-max", cs, 2, 0);
}
