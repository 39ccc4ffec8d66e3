/* test_scene_errors.c — the reason tocher exists, measured on exact scenes: on
 * the discontinuity meshes of the penumbra, point-shadow and box scenes,
 * clough-tocher with flags has a lower RMS error than linear and than
 * clough-tocher-c1 on the same mesh, and `corrected` wedges are no worse than `literal`;
 * and tangent planes estimated from the vertex samples stay within 2x of the
 * paper's midpoint tangents. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "check.h"
#include "scenes/meshing.h"
#include "scenes/scene.h"

/* RMS error of one method over a G x G grid of points (cell centres). */
static double rms_of(const tc_mesh *m, const tc_locator *L, tc_method method, tc_wedges wedges, tc_average avg,
                     const double *xy, const double *ref, size_t n) {
    tc_options o;
    tc_options_default(&o);
    o.method = method;
    o.wedges = wedges;
    o.average = avg;
    tc_recon *r = NULL;
    tc_diags dg;
    tc_diags_init(&dg);
    int st = tc_recon_new(m, &o, &r, &dg);
    CHECK_MSG(st == TC_OK, "%s: %s", tc_method_name(method), dg.count ? dg.items[0].message : "");
    tc_diags_free(&dg);
    if (!r) return INFINITY;
    tc_error_stats e;
    CHECK(tc_compare(r, L, n, xy, ref, 0, &e) == TC_OK);
    CHECK(e.outside == 0);
    tc_recon_free(r);
    return e.rms;
}

static void check_scene(tc_scene_id id, int density) {
    enum { G = 120 };
    tc_scene s;
    tc_scene_mesh_opts mo;
    tc_scene_mesh *sm = NULL;
    tc_mesh *m = NULL;
    tc_locator *L = NULL;
    CHECK(tc_scene_init(&s, id) == TC_OK);
    tc_scene_mesh_opts_default(&mo);
    mo.density = density;
    CHECK(tc_scene_mesh_new(&s, &mo, &sm) == TC_OK);
    if (sm) CHECK(tc_mesh_new(&sm->desc, &m, NULL) == TC_OK);
    if (m) CHECK(tc_locator_new(m, &L) == TC_OK);
    double *xy = malloc(2 * G * G * sizeof *xy), *ref = malloc(G * G * sizeof *ref);
    for (int j = 0; j < G; j++)
        for (int i = 0; i < G; i++) {
            double x = (i + 0.5) / G, y = (j + 0.5) / G;
            xy[2 * (j * G + i)] = x, xy[2 * (j * G + i) + 1] = y;
            ref[j * G + i] = tc_scene_value(&s, x, y);
        }
    if (L) {
        double ct = rms_of(m, L, TC_METHOD_CLOUGH_TOCHER, TC_WEDGES_CORRECTED, TC_AVERAGE_AREA, xy, ref, G * G);
        /* Figure 6's defects alone: corrected and literal with the paper's averaging. */
        double ctn = rms_of(m, L, TC_METHOD_CLOUGH_TOCHER, TC_WEDGES_CORRECTED, TC_AVERAGE_NORMALS, xy, ref, G * G);
        double lit = rms_of(m, L, TC_METHOD_CLOUGH_TOCHER, TC_WEDGES_LITERAL, TC_AVERAGE_NORMALS, xy, ref, G * G);
        double lin = rms_of(m, L, TC_METHOD_LINEAR, TC_WEDGES_CORRECTED, TC_AVERAGE_AREA, xy, ref, G * G);
        double c1 = rms_of(m, L, TC_METHOD_CLOUGH_TOCHER_C1, TC_WEDGES_CORRECTED, TC_AVERAGE_AREA, xy, ref, G * G);
        fprintf(stderr, "  [%s, disc N=%d, %d triangles] RMS: clough-tocher %.3g (average normals %.3g), literal %.3g, "
                "linear %.3g, c1 %.3g\n", tc_scene_name(id), density, (int)tc_mesh_triangle_count(m), ct, ctn, lit, lin, c1);
        CHECK_MSG(ct < lin, "%s: clough-tocher %.3g not below linear %.3g", tc_scene_name(id), ct, lin);
        CHECK_MSG(ct < c1, "%s: clough-tocher %.3g not below clough-tocher-c1 %.3g", tc_scene_name(id), ct, c1);
        CHECK_MSG(ctn <= lit * (1 + 1e-9), "%s: corrected %.3g worse than literal %.3g", tc_scene_name(id), ctn, lit);
    }
    free(xy), free(ref);
    tc_locator_free(L);
    tc_mesh_free(m);
    tc_scene_mesh_free(sm);
}

TEST(scene_errors_flags_beat_linear_and_c1) {
    const tc_scene_id ids[] = {TC_SCENE_PENUMBRA, TC_SCENE_POINT_SHADOW, TC_SCENE_BOX};
    for (int k = 0; k < 3; k++)
        for (int n = 4; n <= 16; n *= 2) check_scene(ids[k], n);
}

/* ---- estimated tangent planes against the paper's midpoint samples ---- */

/* Mean relative error (Bastos & Oliveira's: |error| / the scene's scale) of
 * clough-tocher over a G x G grid, tangents from midpoint samples or estimated
 * from the vertex samples alone (the midpoints withheld). */
static double mean_rel_of(const tc_scene *s, const tc_scene_mesh *sm, tc_tangents tangents, const double *xy,
                          const double *ref, size_t n) {
    tc_mesh_desc d = sm->desc;
    if (tangents == TC_TANGENTS_ESTIMATE) d.nmidpoints = 0, d.midpoint_edge = NULL, d.midpoint_tri = NULL;
    tc_mesh *m = NULL;
    tc_locator *L = NULL;
    tc_recon *r = NULL;
    tc_options o;
    tc_options_default(&o);
    o.tangents = tangents;
    double out = INFINITY;
    CHECK(tc_mesh_new(&d, &m, NULL) == TC_OK);
    if (m) CHECK(tc_locator_new(m, &L) == TC_OK && tc_recon_new(m, &o, &r, NULL) == TC_OK);
    tc_error_stats e;
    if (r && tc_compare(r, L, n, xy, ref, s->scale, &e) == TC_OK) out = e.mean_rel;
    tc_recon_free(r);
    tc_locator_free(L);
    tc_mesh_free(m);
    return out;
}

/* Issue 12: estimated planes used to be dominated by thin elements at a
 * penumbra's corners and fitted too few samples on narrow wedges (disc N = 16:
 * penumbra 4.75x the midpoint tangents' error, point-shadow 3.76x, square-light
 * 2.73x, stiff 141x). From N = 16 on they are within 2x with a third of the
 * samples. Not guarded here: the box, 1.96x (2.32x before), whose error sits at
 * the footprint's corners where the function has no gradient (exact gradients
 * are 1.37x the midpoint tangents' error there), too close to 2 to guard; and
 * the coarsest meshes, where a wedge spans one or two cells and the vertex
 * samples cannot resolve what the midpoints do (docs/design-notes.md). */
TEST(scene_errors_estimated_tangents_within_2x_of_midpoints) {
    enum { G = 200 };
    static const struct {
        tc_scene_id id;
        int density;
    } cases[] = {{TC_SCENE_SQUARE_LIGHT, 16}, {TC_SCENE_PENUMBRA, 16}, {TC_SCENE_PENUMBRA, 32},
                 {TC_SCENE_POINT_SHADOW, 16}, {TC_SCENE_STIFF, 16}};
    double *xy = malloc(2 * G * G * sizeof *xy), *ref = malloc(G * G * sizeof *ref);
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        tc_scene s;
        tc_scene_mesh_opts mo;
        tc_scene_mesh *sm = NULL;
        CHECK(tc_scene_init(&s, cases[k].id) == TC_OK);
        tc_scene_mesh_opts_default(&mo);
        mo.density = cases[k].density;
        CHECK(tc_scene_mesh_new(&s, &mo, &sm) == TC_OK);
        if (!sm) continue;
        for (int j = 0; j < G; j++)
            for (int i = 0; i < G; i++) {
                double x = (i + 0.5) / G, y = (j + 0.5) / G;
                xy[2 * (j * G + i)] = x, xy[2 * (j * G + i) + 1] = y;
                ref[j * G + i] = tc_scene_value(&s, x, y);
            }
        double mid = mean_rel_of(&s, sm, TC_TANGENTS_MIDPOINTS, xy, ref, G * G);
        double est = mean_rel_of(&s, sm, TC_TANGENTS_ESTIMATE, xy, ref, G * G);
        fprintf(stderr, "  [%s, disc N=%d] mean relative error: midpoint tangents %.3g, estimated %.3g (%.2fx)\n",
                tc_scene_name(cases[k].id), cases[k].density, mid, est, est / mid);
        CHECK_MSG(est <= 2 * mid, "%s disc N=%d: estimated tangents %.3g, %.2fx the midpoint tangents' %.3g",
                  tc_scene_name(cases[k].id), cases[k].density, est, est / mid, mid);
        tc_scene_mesh_free(sm);
    }
    free(xy), free(ref);
}
