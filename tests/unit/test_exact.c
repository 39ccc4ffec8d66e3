/* test_exact.c — polynomial reproduction and convergence: linear data by every
 * method but constant, quadratics by normal/affine with exact gradients, and
 * the observed order of accuracy under refinement. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "meshgen.h"
#include "props.h"

static void const_f(const void *ctx, double x, double y, int ch, double *v, double g[2]) {
    (void)ctx, (void)x, (void)y;
    *v = 3.25 - ch;
    g[0] = g[1] = 0;
}

static tc_recon *make_opts(const tc_mesh *m, tc_method method, tc_cross cross, tc_wedges wedges, tc_tangents tan,
                           tc_average avg, tc_range range) {
    tc_options o = {.method = method, .cross_boundary = cross, .wedges = wedges, .tangents = tan, .average = avg,
                    .range = range};
    tc_recon *r = NULL;
    tc_diags dg;
    tc_diags_init(&dg);
    CHECK_MSG(tc_recon_new(m, &o, &r, &dg) == TC_OK, "%s/%s/%s/%s: %s", tc_method_name(method),
              tc_cross_name(cross), tc_wedges_name(wedges), tc_tangents_name(tan),
              dg.count ? dg.items[0].message : "");
    tc_diags_free(&dg);
    return r;
}

/* The default range "local": linear data never leave a triangle's corner range,
 * so the limiter must leave them exact. */
static tc_recon *make(const tc_mesh *m, tc_method method, tc_cross cross, tc_wedges wedges, tc_tangents tan) {
    return make_opts(m, method, cross, wedges, tan, TC_AVERAGE_AREA, TC_RANGE_LOCAL);
}

/* The free cubic (range "free"): quadratics overshoot their corners, so their
 * reproduction is a property of the unlimited interpolant. */
static tc_recon *make_free(const tc_mesh *m, tc_method method, tc_cross cross, tc_wedges wedges, tc_tangents tan,
                           tc_average avg) {
    return make_opts(m, method, cross, wedges, tan, avg, TC_RANGE_FREE);
}

/* Every combination of options on flagged random meshes reproduces a linear
 * function (value and gradient) to 1e-12 relative; constant reproduces a constant. */
TEST(exact_linear_reproduced_by_every_method) {
    trng r;
    trng_seed(&r, tc_test_seed() + 10);
    const tc_method methods[] = {TC_METHOD_CLOUGH_TOCHER, TC_METHOD_CLOUGH_TOCHER_C1, TC_METHOD_LINEAR,
                                 TC_METHOD_LINEAR4};
    double worst = 0;
    for (int trial = 0; trial < 4; trial++) {
        tmesh g;
        random_flagged_mesh(&g, &r, trial % 2, 12);
        tmesh_sample(&g, 2, linear_data, NULL, 1, 1, 0);
        tc_mesh *m = tmesh_build(&g);
        for (int mi = 0; m && mi < 4; mi++)
            for (int ci = 0; ci < 3; ci++)
                for (int wi = 0; wi < 2; wi++)
                    for (int ti = 0; ti < 4; ti++) {
                        if (methods[mi] >= TC_METHOD_LINEAR && (ci || wi || ti)) continue;
                        tc_recon *rec = make(m, methods[mi], (tc_cross)ci, (tc_wedges)wi, (tc_tangents)ti);
                        if (!rec) continue;
                        double e = tri_reproduction_error(rec, linear_data, 300, &r, 1);
                        worst = fmax(worst, e);
                        CHECK_MSG(e <= 1e-12, "%s cross %s wedges %s tangents %s: linear off by %.3g",
                                  tc_method_name(methods[mi]), tc_cross_name((tc_cross)ci),
                                  tc_wedges_name((tc_wedges)wi), tc_tangents_name((tc_tangents)ti), e);
                        tc_recon_free(rec);
                    }
        tc_mesh_free(m);
        tmesh_free(&g);
    }
    fprintf(stderr, "  [linear reproduction] worst relative error over all methods/options: %.2g\n", worst);
}

TEST(exact_constant_reproduced_by_constant) {
    trng r;
    trng_seed(&r, tc_test_seed() + 11);
    tmesh g;
    random_flagged_mesh(&g, &r, 1, 12);
    tmesh_sample(&g, 3, const_f, NULL, 1, 1, 0);
    tc_mesh *m = tmesh_build(&g);
    tc_recon *rec = m ? make(m, TC_METHOD_CONSTANT, 0, 0, 0) : NULL;
    if (rec) CHECK(tri_reproduction_error(rec, const_f, 500, &r, 1) == 0);
    tc_recon_free(rec);
    /* ...and it does not reproduce a linear function: the check above can fail. */
    tmesh_free(&g);
    tc_mesh_free(m);
    random_flagged_mesh(&g, &r, 0, 12);
    tmesh_sample(&g, 1, linear_data, NULL, 0, 0, 0);
    m = tmesh_build(&g);
    rec = m ? make(m, TC_METHOD_CONSTANT, 0, 0, 0) : NULL;
    if (rec) CHECK(tri_reproduction_error(rec, linear_data, 500, &r, 0) > 1e-3);
    tc_recon_free(rec);
    tc_mesh_free(m);
    tmesh_free(&g);
}

/* normal and affine reproduce quadratics given exact gradients, on flagged
 * meshes too (the data is smooth, so every wedge plane is the exact one); so
 * does salesin with average "area" (its cross-boundary plane is the mean of the
 * two end gradients, a quadratic's gradient at the edge midpoint) but not with
 * the paper's averaged unit normals — which keeps the check honest. */
TEST(exact_quadratic_reproduced_with_exact_gradients) {
    trng r;
    trng_seed(&r, tc_test_seed() + 12);
    double worst = 0, salesin = 0;
    for (int trial = 0; trial < 4; trial++) {
        tmesh g;
        random_flagged_mesh(&g, &r, trial % 2, 12);
        tmesh_sample(&g, 2, quadratic_data, NULL, 1, 0, 0);
        tc_mesh *m = tmesh_build(&g);
        for (int ci = 0; m && ci < 3; ci++)
            for (int mi = 0; mi < 2; mi++) {
                tc_method method = mi ? TC_METHOD_CLOUGH_TOCHER_C1 : TC_METHOD_CLOUGH_TOCHER;
                tc_recon *rec = make_free(m, method, (tc_cross)ci, TC_WEDGES_CORRECTED, TC_TANGENTS_GIVEN, TC_AVERAGE_AREA);
                if (!rec) continue;
                double e = tri_reproduction_error(rec, quadratic_data, 400, &r, 1);
                worst = fmax(worst, e);
                CHECK_MSG(e <= 1e-12, "%s/%s: quadratic off by %.3g", tc_method_name(method),
                          tc_cross_name((tc_cross)ci), e);
                tc_recon_free(rec);
                rec = make_free(m, method, (tc_cross)ci, TC_WEDGES_CORRECTED, TC_TANGENTS_GIVEN, TC_AVERAGE_NORMALS);
                if (rec && ci == TC_CROSS_SALESIN) salesin = fmax(salesin, tri_reproduction_error(rec, quadratic_data, 400, &r, 1));
                tc_recon_free(rec);
            }
        tc_mesh_free(m);
        tmesh_free(&g);
    }
    CHECK_MSG(salesin > 1e-6, "salesin with unit-normal averaging is not quadratic-exact; error %.3g", salesin);
    fprintf(stderr, "  [quadratic reproduction] normal/affine/salesin worst %.2g; salesin with average normals %.2g "
                    "(not exact, as expected)\n", worst, salesin);
}

TEST(exact_quadratic_with_estimated_tangents_on_interior) {
    trng r;
    trng_seed(&r, tc_test_seed() + 13);
    tmesh g;
    tmesh_grid(&g, 12, 12, 0.25, -1, &r);
    tmesh_sample(&g, 1, quadratic_data, NULL, 0, 1, 0);
    tc_mesh *m = tmesh_build(&g);
    tc_recon *rec = m ? make_free(m, TC_METHOD_CLOUGH_TOCHER, TC_CROSS_NORMAL, 0, TC_TANGENTS_ESTIMATE, TC_AVERAGE_AREA)
                      : NULL;
    if (rec) {
        double e = tri_reproduction_error(rec, quadratic_data, 500, &r, 1);
        CHECK_MSG(e <= 1e-10, "quadratic fit should make the estimate exact, error %.3g", e);
    }
    tc_recon_free(rec);
    tc_mesh_free(m);
    tmesh_free(&g);
}

/* ---- convergence ---- */



static double observed_order(tc_method method, tc_cross cross, tc_tangents tan, int with_mid) {
    double err[4];
    int ns[4] = {8, 16, 32, 64};
    for (int l = 0; l < 4; l++) {
        tmesh g;
        tmesh_grid(&g, ns[l], ns[l], 0, 0, NULL);
        tmesh_sample(&g, 1, wave_f, NULL, 1, with_mid, 0);
        tc_mesh *m = tmesh_build(&g);
        tc_recon *rec = m ? make(m, method, cross, TC_WEDGES_CORRECTED, tan) : NULL;
        err[l] = rec ? grid_max_error(rec, ns[l]) : NAN;
        tc_recon_free(rec);
        tc_mesh_free(m);
        tmesh_free(&g);
    }
    double order = log2(err[2] / err[3]);
    fprintf(stderr, "  [order] %-16s %-7s %-9s max error %.2e %.2e %.2e %.2e -> order %.2f\n", tc_method_name(method),
            method <= TC_METHOD_CLOUGH_TOCHER_C1 ? tc_cross_name(cross) : "", tc_tangents_name(tan), err[0], err[1],
            err[2], err[3], order);
    return order;
}

TEST(exact_convergence_orders) {
    for (int ci = 0; ci < 3; ci++) {
        double o = observed_order(TC_METHOD_CLOUGH_TOCHER, (tc_cross)ci, TC_TANGENTS_GIVEN, 0);
        CHECK_MSG(o >= 2.8, "cubic (%s, exact gradients) order %.2f < 2.8", tc_cross_name((tc_cross)ci), o);
    }
    double o = observed_order(TC_METHOD_CLOUGH_TOCHER, TC_CROSS_NORMAL, TC_TANGENTS_MIDPOINTS, 1);
    CHECK_MSG(o >= 2.5, "cubic with midpoint tangents order %.2f", o);
    o = observed_order(TC_METHOD_CLOUGH_TOCHER, TC_CROSS_NORMAL, TC_TANGENTS_ESTIMATE, 0);
    CHECK_MSG(o >= 2.5, "cubic with estimated tangents order %.2f", o);
    o = observed_order(TC_METHOD_LINEAR, 0, 0, 0);
    CHECK_MSG(o >= 1.8 && o <= 2.2, "linear order %.2f, expected about 2", o);
    o = observed_order(TC_METHOD_LINEAR4, 0, 0, 1);
    CHECK_MSG(o >= 1.8 && o <= 2.2, "linear4 order %.2f, expected about 2", o);
    o = observed_order(TC_METHOD_CONSTANT, 0, 0, 0);
    CHECK_MSG(o >= 0.8 && o <= 1.2, "constant order %.2f, expected about 1", o);
}
