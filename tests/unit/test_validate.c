/* test_validate.c — every validation rule of tc_mesh_new / tc_recon_new driven by a minimal input:
 * the status, *out == NULL, the JSON path of the first finding and its message, and that a corrected input passes. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "props.h"
#include "tocher.h"

/* ---- the base input: the unit square split along its diagonal (0, 2) ---------------- */

static const double SQ_XY[] = {0, 0, 1, 0, 1, 1, 0, 1};
static const int32_t SQ_TRI[] = {0, 1, 2, 0, 2, 3};
static const double SQ_VAL[] = {1, 2, 3, 4};

static tc_mesh_desc square(void) {
    tc_mesh_desc d;
    memset(&d, 0, sizeof d);
    d.nverts = 4, d.xy = SQ_XY;
    d.ntris = 2, d.tris = SQ_TRI;
    d.nchan = 1, d.values = SQ_VAL;
    return d;
}

/* A polyline set holding one polyline of n vertices (start must have room for 2). */
static tc_polylines line(int32_t *start, const int32_t *verts, int32_t n) {
    start[0] = 0, start[1] = n;
    return (tc_polylines){1, start, verts};
}

/* Checks the first finding of a failed call: an error at exactly `path` whose
 * message contains every string of the NULL-terminated `needles`. */
static void check_first(const char *file, int line_no, const tc_diags *dg, const char *path,
                        const char *const *needles) {
    if (dg->errors < 1 || dg->count < 1) {
        tc_test_fail(file, line_no, "no error reported");
        return;
    }
    const tc_diag *e = &dg->items[0];
    if (e->severity != TC_SEV_ERROR) tc_test_fail(file, line_no, "first finding is not an error");
    if (strcmp(e->path, path) != 0)
        tc_test_fail(file, line_no, "path '%s', expected '%s' (message: %s)", e->path, path, e->message);
    for (; *needles; needles++)
        if (!strstr(e->message, *needles))
            tc_test_fail(file, line_no, "message '%s' does not contain '%s'", e->message, *needles);
}

static void mesh_fails(const char *file, int line_no, const tc_mesh_desc *d, const char *path,
                       const char *const *needles) {
    tc_mesh *m = (tc_mesh *)&m;
    tc_diags dg;
    tc_diags_init(&dg);
    int st = tc_mesh_new(d, &m, &dg);
    if (st != TC_EINVAL) tc_test_fail(file, line_no, "status %d, expected TC_EINVAL", st);
    if (m != NULL) tc_test_fail(file, line_no, "*out is not NULL on failure");
    check_first(file, line_no, &dg, path, needles);
    if (st == TC_OK) tc_mesh_free(m);
    tc_diags_free(&dg);
}

/* Builds the mesh and expects success without errors; returns it (caller frees). */
static tc_mesh *mesh_ok(const char *file, int line_no, const tc_mesh_desc *d, tc_diags *dg) {
    tc_mesh *m = NULL;
    int st = tc_mesh_new(d, &m, dg);
    if (st != TC_OK || !m)
        tc_test_fail(file, line_no, "status %d, expected TC_OK (first finding: %s: %s)", st,
                     dg->count ? dg->items[0].path : "-", dg->count ? dg->items[0].message : "-");
    if (dg->errors) tc_test_fail(file, line_no, "%d errors on success", dg->errors);
    return m;
}

static void mesh_passes(const char *file, int line_no, const tc_mesh_desc *d) {
    tc_diags dg;
    tc_diags_init(&dg);
    tc_mesh_free(mesh_ok(file, line_no, d, &dg));
    if (dg.warnings) tc_test_fail(file, line_no, "%d unexpected warnings", dg.warnings);
    tc_diags_free(&dg);
}

/* The unlimited pipeline's findings (range "free"): what the range limiter
 * changes, and the inputs it makes acceptable, are tested in test_range.c. */
static tc_options opts(tc_method method, tc_tangents tangents, tc_wedges wedges) {
    tc_options o;
    tc_options_default(&o);
    o.method = method, o.tangents = tangents, o.wedges = wedges, o.range = TC_RANGE_FREE;
    return o;
}

static void recon_fails(const char *file, int line_no, const tc_mesh_desc *d, tc_options o, const char *path,
                        const char *const *needles) {
    tc_diags dg;
    tc_diags_init(&dg);
    tc_mesh *m = mesh_ok(file, line_no, d, &dg);
    if (m) {
        tc_recon *r = (tc_recon *)&r;
        int st = tc_recon_new(m, &o, &r, &dg);
        if (st != TC_EINVAL) tc_test_fail(file, line_no, "status %d, expected TC_EINVAL", st);
        if (r != NULL) tc_test_fail(file, line_no, "*out is not NULL on failure");
        check_first(file, line_no, &dg, path, needles);
        if (st == TC_OK) tc_recon_free(r);
    }
    tc_mesh_free(m);
    tc_diags_free(&dg);
}

/* Builds mesh and reconstruction, expects success and finite coefficients;
 * warnings are left in *dg for the caller. */
static void recon_passes(const char *file, int line_no, const tc_mesh_desc *d, tc_options o, tc_diags *dg) {
    tc_mesh *m = mesh_ok(file, line_no, d, dg);
    if (m) {
        tc_recon *r = NULL;
        int st = tc_recon_new(m, &o, &r, dg);
        if (st != TC_OK || !r) {
            tc_test_fail(file, line_no, "recon status %d, expected TC_OK (first finding: %s: %s)", st,
                         dg->count ? dg->items[0].path : "-", dg->count ? dg->items[0].message : "-");
        } else {
            size_t n = (size_t)tc_mesh_triangle_count(m) * (size_t)tc_mesh_channel_count(m) * (size_t)tc_recon_coef_count(r);
            for (size_t i = 0; i < n; i++)
                if (!isfinite(tc_recon_coefs(r)[i])) {
                    tc_test_fail(file, line_no, "coefficient %zu is %g", i, tc_recon_coefs(r)[i]);
                    break;
                }
        }
        tc_recon_free(r);
    }
    tc_mesh_free(m);
}

#define NEEDLES(...) ((const char *const[]){__VA_ARGS__, NULL})
#define FAILS(d, path, ...) mesh_fails(__FILE__, __LINE__, d, path, NEEDLES(__VA_ARGS__))
#define PASSES(d) mesh_passes(__FILE__, __LINE__, d)
#define RECON_FAILS(d, o, path, ...) recon_fails(__FILE__, __LINE__, d, o, path, NEEDLES(__VA_ARGS__))
#define RECON_PASSES(d, o, dg) recon_passes(__FILE__, __LINE__, d, o, dg)

/* ---- 1. sizes ---------------------------------------------------------------------- */

TEST(validate_no_vertices) {
    tc_mesh_desc d = square();
    d.nverts = 0;
    FAILS(&d, "vertices", "no vertices");
    d = square();
    d.xy = NULL;
    FAILS(&d, "vertices", "no vertices");
    d = square();
    PASSES(&d);
}

TEST(validate_no_triangles) {
    tc_mesh_desc d = square();
    d.ntris = 0;
    FAILS(&d, "triangles", "no triangles");
    d = square();
    d.tris = NULL;
    FAILS(&d, "triangles", "no triangles");
}

TEST(validate_channel_count) {
    tc_mesh_desc d = square();
    d.nchan = 0;
    FAILS(&d, "values", "0 channels", "1 to 16");
    double v17[4 * 17] = {0};
    d.nchan = 17, d.values = v17;
    FAILS(&d, "values", "17 channels", "1 to 16");
    double v16[4 * 16] = {0};
    d.nchan = 16, d.values = v16;
    PASSES(&d);
    d = square();
    d.values = NULL;
    FAILS(&d, "values", "no values");
}

/* ---- 2. numbers that are not finite ------------------------------------------------- */

TEST(validate_vertex_not_finite) {
    double xy[8];
    memcpy(xy, SQ_XY, sizeof xy);
    tc_mesh_desc d = square();
    d.xy = xy;
    xy[2 * 2 + 1] = NAN;
    FAILS(&d, "vertices[2][1]", "not finite");
    xy[2 * 2 + 1] = 1, xy[0] = -INFINITY;
    FAILS(&d, "vertices[0][0]", "not finite");
    xy[0] = 0;
    PASSES(&d);
}

TEST(validate_value_not_finite) {
    double v[4] = {1, 2, 3, NAN};
    tc_mesh_desc d = square();
    d.values = v;
    FAILS(&d, "values[3]", "not finite");
    double v2[8] = {1, 1, 2, INFINITY, 3, 3, 4, 4}; /* 2 channels: the path names the vertex */
    d.nchan = 2, d.values = v2;
    FAILS(&d, "values[1]", "not finite");
    v2[3] = 2;
    PASSES(&d);
}

TEST(validate_corner_value_not_finite) {
    int32_t tri = 1;
    double cv[3] = {1, INFINITY, 4};
    tc_mesh_desc d = square();
    d.ncorner_values = 1, d.corner_values_tri = &tri, d.corner_values = cv;
    FAILS(&d, "corner_values[0].values", "not finite");
    cv[1] = 3;
    PASSES(&d);
}

TEST(validate_gradient_not_finite) {
    double g[8] = {0, 0, 1, 0, 0, NAN, 0, 0};
    tc_mesh_desc d = square();
    d.gradients = g;
    FAILS(&d, "gradients[2]", "not finite");
    g[5] = 1;
    PASSES(&d);
}

TEST(validate_normal_not_finite) {
    double n[12] = {0, 0, 1, 0, 0, 1, 0, NAN, 1, 0, 0, 1};
    tc_mesh_desc d = square();
    d.normals = n;
    FAILS(&d, "normals[2]", "not finite");
    n[7] = 0.5;
    PASSES(&d);
}

TEST(validate_corner_gradient_not_finite) {
    int32_t tri = 0;
    double cg[6] = {0, 0, INFINITY, 0, 0, 0};
    tc_mesh_desc d = square();
    d.ncorner_gradients = 1, d.corner_gradients_tri = &tri, d.corner_gradients = cg;
    FAILS(&d, "corner_gradients[0].gradients[1]", "not finite");
    cg[2] = 1;
    PASSES(&d);
}

TEST(validate_midpoint_not_finite) {
    int32_t edge[2] = {0, 2};
    double z = NAN;
    tc_mesh_desc d = square();
    d.nmidpoints = 1, d.midpoint_edge = edge, d.midpoint_values = &z;
    FAILS(&d, "midpoints[0].value", "not finite");
    z = 2;
    PASSES(&d);
}

/* ---- 3-4. triangles -------------------------------------------------------------------- */

TEST(validate_triangle_index_range) {
    int32_t tri[6] = {0, 1, 2, 0, 2, 4};
    tc_mesh_desc d = square();
    d.tris = tri;
    FAILS(&d, "triangles[1][2]", "index 4", "4 vertices");
    tri[5] = 3, tri[1] = -1;
    FAILS(&d, "triangles[0][1]", "index -1", "4 vertices");
    tri[1] = 1;
    PASSES(&d);
}

TEST(validate_triangle_repeats_vertex) {
    int32_t tri[6] = {0, 1, 2, 0, 2, 0};
    tc_mesh_desc d = square();
    d.tris = tri;
    FAILS(&d, "triangles[1]", "appears twice", "[0, 2, 0]");
    tri[5] = 3;
    PASSES(&d);
}

/* Vertex 4 on the line through 0 and 1; then moved below it. */
TEST(validate_zero_area_collinear) {
    double xy[10] = {0, 0, 1, 0, 1, 1, 0, 1, 2, 0};
    int32_t tri[9] = {0, 1, 2, 0, 2, 3, 0, 4, 1};
    double v[5] = {1, 2, 3, 4, 5};
    tc_mesh_desc d = square();
    d.nverts = 5, d.xy = xy, d.ntris = 3, d.tris = tri, d.values = v;
    FAILS(&d, "triangles[2]", "zero-area", "0, 4, 1");
    xy[8] = 0.5, xy[9] = -1;
    PASSES(&d);
}

/* Vertex 4 on top of vertex 2 (a different index): no repeated index, but no area. */
TEST(validate_zero_area_coincident) {
    double xy[10] = {0, 0, 1, 0, 1, 1, 0, 1, 1, 1};
    int32_t tri[9] = {0, 1, 2, 0, 2, 3, 1, 4, 2};
    double v[5] = {1, 2, 3, 4, 5};
    tc_mesh_desc d = square();
    d.nverts = 5, d.xy = xy, d.ntris = 3, d.tris = tri, d.values = v;
    FAILS(&d, "triangles[2]", "zero-area", "1, 4, 2");
    xy[8] = 2, xy[9] = 0.5;
    PASSES(&d);
}

/* ---- 5-7. topology --------------------------------------------------------------------- */

TEST(validate_repeated_triangle) {
    int32_t tri[6] = {0, 1, 2, 2, 1, 0}; /* the other orientation */
    tc_mesh_desc d = square();
    d.ntris = 2, d.tris = tri;
    FAILS(&d, "triangles[1]", "repeats triangles[0]");
    tri[3] = 1, tri[4] = 2, tri[5] = 0; /* same orientation, rotated */
    FAILS(&d, "triangles[1]", "repeats triangles[0]");
    tri[3] = 0, tri[4] = 2, tri[5] = 3;
    PASSES(&d);
}

/* A repeat next to other triangles: the repeat is reported, at the later copy. */
TEST(validate_repeated_triangle_in_mesh) {
    int32_t tri[9] = {0, 1, 2, 0, 2, 3, 2, 0, 1};
    tc_mesh_desc d = square();
    d.ntris = 3, d.tris = tri;
    tc_mesh *m = (tc_mesh *)&m;
    tc_diags dg;
    tc_diags_init(&dg);
    CHECK(tc_mesh_new(&d, &m, &dg) == TC_EINVAL);
    CHECK(m == NULL);
    int found = 0;
    for (int i = 0; i < dg.count; i++)
        found |= !strcmp(dg.items[i].path, "triangles[2]") && strstr(dg.items[i].message, "repeats triangles[0]");
    CHECK_MSG(found, "no 'repeats triangles[0]' at triangles[2] among %d findings (first: %s: %s)", dg.count,
              dg.count ? dg.items[0].path : "-", dg.count ? dg.items[0].message : "-");
    tc_diags_free(&dg);
}

/* Edge (2, 0) of the square also used by a third triangle (0, 2, 4). */
TEST(validate_nonmanifold_edge) {
    double xy[10] = {0, 0, 1, 0, 1, 1, 0, 1, 2, 0.5};
    int32_t tri[9] = {0, 1, 2, 0, 2, 3, 0, 2, 4};
    double v[5] = {1, 2, 3, 4, 5};
    tc_mesh_desc d = square();
    d.nverts = 5, d.xy = xy, d.ntris = 3, d.tris = tri, d.values = v;
    FAILS(&d, "triangles[2]", "non-manifold edge [2, 0]", "3 triangles", "(0, 1, 2)");
    tri[6] = 1, tri[7] = 4, tri[8] = 2;
    PASSES(&d);
}

/* Vertex 3 moved below the diagonal: triangle 1 folds over triangle 0. */
TEST(validate_folded_triangles) {
    double xy[8] = {0, 0, 1, 0, 1, 1, 0.9, 0.1};
    tc_mesh_desc d = square();
    d.xy = xy;
    FAILS(&d, "triangles[1]", "overlaps triangles[0]", "shared edge [2, 0]");
    xy[6] = 0, xy[7] = 1;
    PASSES(&d);
}

TEST(validate_triangles_both_orientations_pass) {
    int32_t tri[6] = {0, 1, 2, 3, 2, 0}; /* counter-clockwise, then clockwise */
    tc_mesh_desc d = square();
    d.tris = tri;
    tc_diags dg;
    tc_diags_init(&dg);
    tc_mesh *m = mesh_ok(__FILE__, __LINE__, &d, &dg);
    if (m) {
        int nk = -1;
        CHECK(tc_mesh_neighbor(m, 0, 2, &nk) == 1 && nk == 1);
        CHECK(tc_mesh_edge_flag(m, 0, 2) == TC_C1);
    }
    tc_mesh_free(m);
    tc_options o;
    tc_options_default(&o);
    RECON_PASSES(&d, o, &dg);
    CHECK(dg.count == 0);
    tc_diags_free(&dg);
}

/* A crack along x = 1/2 from the bottom to the centre: vertices 1 and 2 coincide,
 * each side has its own triangles, vertex 7 (the centre) is shared. */
TEST(validate_crack_of_duplicated_vertices_passes) {
    const double xy[16] = {0, 0, 0.5, 0, 0.5, 0, 1, 0, 0, 1, 0.5, 1, 1, 1, 0.5, 0.5};
    const int32_t tri[18] = {0, 1, 7, 0, 7, 4, 4, 7, 5, 2, 3, 7, 3, 6, 7, 7, 6, 5};
    const double v[8] = {1, 2, 5, 3, 1, 1.5, 2, 1.75}; /* a jump across the crack */
    tc_mesh_desc d = square();
    d.nverts = 8, d.xy = xy, d.ntris = 6, d.tris = tri, d.values = v;
    tc_diags dg;
    tc_diags_init(&dg);
    tc_mesh *m = mesh_ok(__FILE__, __LINE__, &d, &dg);
    CHECK(dg.count == 0);
    if (m) CHECK(tc_mesh_neighbor(m, 0, 1, NULL) == -1 && tc_mesh_neighbor(m, 3, 2, NULL) == -1);
    tc_mesh_free(m);
    RECON_PASSES(&d, opts(TC_METHOD_CLOUGH_TOCHER, TC_TANGENTS_AUTO, TC_WEDGES_CORRECTED), &dg);
    RECON_PASSES(&d, opts(TC_METHOD_CLOUGH_TOCHER, TC_TANGENTS_AUTO, TC_WEDGES_LITERAL), &dg);
    CHECK(dg.errors == 0);
    tc_diags_free(&dg);
}

/* ---- 8. values that disagree across a C0 / C1 edge -------------------------------------- */

TEST(validate_corner_values_disagree) {
    int32_t tri = 1, st[2];
    const int32_t diag[2] = {0, 2};
    double cv[3] = {1, 7, 4}; /* triangle 1 = (0, 2, 3); vertex 2 is 3 in triangle 0 */
    tc_mesh_desc d = square();
    d.ncorner_values = 1, d.corner_values_tri = &tri, d.corner_values = cv;
    FAILS(&d, "corner_values[0]", "C1 edge [2, 0]", "vertex 2", "3 (triangle 0)", "7 (triangle 1)", "c-1");
    d.c0 = line(st, diag, 2);
    FAILS(&d, "corner_values[0]", "C0 edge [2, 0]", "vertex 2", "3 (triangle 0)", "7 (triangle 1)", "c-1");
    d.c0 = (tc_polylines){0, NULL, NULL};
    d.cm1 = line(st, diag, 2);
    PASSES(&d);
    d.cm1 = (tc_polylines){0, NULL, NULL};
    cv[1] = 3;
    PASSES(&d);
}

/* value_tolerance: a front-end printing 6 significant digits makes the two
 * sides of a C1 edge differ by ~1e-6 of the scale. Within the tolerance the
 * corner values of the vertex are replaced by their mean (a warning names
 * the vertex); beyond it the mesh is refused naming the edge and both values;
 * 0 (a zero-filled description) is the strict 1e-12 of old. */
TEST(validate_value_tolerance_averages_or_refuses) {
    int32_t tri = 1;
    double cv[3] = {1, 3 + 3e-6, 4}; /* triangle 1 = (0, 2, 3): vertex 2 is 3 in triangle 0 */
    tc_mesh_desc d = square();
    d.ncorner_values = 1, d.corner_values_tri = &tri, d.corner_values = cv;
    FAILS(&d, "corner_values[0]", "C1 edge [2, 0]", "vertex 2", "3 (triangle 0)", "3.000003 (triangle 1)",
          "7.5e-07 of the channel's scale", "value_tolerance 1e-12");
    d.value_tolerance = 1e-6; /* 3e-6 / 4 = 7.5e-7 of the scale: within */
    tc_diags dg;
    tc_diags_init(&dg);
    tc_mesh *m = mesh_ok(__FILE__, __LINE__, &d, &dg);
    CHECK(dg.warnings == 1 && dg.count == 1);
    if (dg.count) {
        CHECK(!strcmp(dg.items[0].path, "vertices[2]"));
        CHECK_STR_CONTAINS(dg.items[0].message, "differed at 1 vertices, by up to 7.5e-07");
    }
    if (m) { /* both corners at vertex 2 now hold the mean, bit for bit; the others are untouched */
        double mean = 3 + 1.5e-6;
        CHECK(tc_mesh_corner_value(m, 0, 2)[0] == tc_mesh_corner_value(m, 1, 1)[0]);
        CHECK_NEAR(tc_mesh_corner_value(m, 0, 2)[0], mean, 1e-15);
        CHECK(tc_mesh_corner_value(m, 1, 0)[0] == 1 && tc_mesh_corner_value(m, 0, 0)[0] == 1);
        CHECK(tc_mesh_corner_value(m, 1, 2)[0] == 4);
    }
    tc_mesh_free(m);
    tc_diags_free(&dg);
    d.value_tolerance = 5e-7; /* beyond: refused, with the tolerance in the message */
    FAILS(&d, "corner_values[0]", "C1 edge [2, 0]", "vertex 2", "value_tolerance 5e-07");
    d.value_tolerance = -1;
    FAILS(&d, "value_tolerance", "must be 0 to 1");
    d.value_tolerance = NAN;
    FAILS(&d, "value_tolerance", "must be 0 to 1");
}

/* Corners joined through C0/C1 edges are averaged as one group; a C-1 edge
 * parts the groups, each keeping its own mean, so the jump stays. The
 * reconstruction is then exactly continuous across the C1 edges. */
TEST(validate_value_tolerance_groups_stop_at_cm1_edges) {
    /* a fan of 4 triangles around vertex 4 (the centre of the square) */
    const double xy[] = {0, 0, 1, 0, 1, 1, 0, 1, 0.5, 0.5};
    const int32_t tris[] = {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4};
    const double v[] = {1, 2, 3, 4, 10};
    const int32_t ct[] = {0, 1, 2, 3}, cut[] = {4, 2}, st[] = {0, 2}, cut2[] = {0, 4};
    double cv[12] = {1, 2, 10, 2, 3, 10 + 2e-6, 3, 4, 20, 4, 1, 20 + 4e-6}; /* a jump 10 -> 20 at vertex 4 */
    tc_mesh_desc d;
    tc_mesh_desc_init(&d); /* value_tolerance 1e-4 */
    d.nverts = 5, d.xy = xy, d.ntris = 4, d.tris = tris, d.nchan = 1, d.values = v;
    d.ncorner_values = 4, d.corner_values_tri = ct, d.corner_values = cv;
    d.cm1 = (tc_polylines){1, st, cut}; /* edge 4-2 cuts triangles 1 | 2 */
    FAILS(&d, "corner_values[3]", "C1 edge [4, 0]", "vertex 4", "0.5 of the channel's scale"); /* 0-4 joins 10, 20 */
    int32_t lines_start[3] = {0, 2, 4};
    int32_t lines[4] = {cut[0], cut[1], cut2[0], cut2[1]};
    d.cm1 = (tc_polylines){2, lines_start, lines}; /* and edge 0-4: two groups {0, 1}, {2, 3} */
    tc_diags dg;
    tc_diags_init(&dg);
    tc_mesh *m = mesh_ok(__FILE__, __LINE__, &d, &dg);
    CHECK(dg.warnings == 1);
    if (dg.count) CHECK_STR_CONTAINS(dg.items[0].message, "differed at 1 vertices");
    if (m) {
        CHECK(tc_mesh_corner_value(m, 0, 2)[0] == tc_mesh_corner_value(m, 1, 2)[0]);
        CHECK(tc_mesh_corner_value(m, 2, 2)[0] == tc_mesh_corner_value(m, 3, 2)[0]);
        CHECK_NEAR(tc_mesh_corner_value(m, 0, 2)[0], 10 + 1e-6, 1e-14);
        CHECK_NEAR(tc_mesh_corner_value(m, 2, 2)[0], 20 + 2e-6, 1e-14);
        tc_recon *r = NULL;
        CHECK(tc_recon_new(m, NULL, &r, NULL) == TC_OK);
        for (int i = 0; r && i <= 8; i++) { /* along the C1 edge 4-1 from both sides: exactly equal */
            double x = 0.5 + 0.5 * i / 8, y = 0.5 - 0.5 * i / 8, z0, z1;
            tc_eval_triangle(r, 0, x, y, &z0, NULL);
            tc_eval_triangle(r, 1, x, y, &z1, NULL);
            CHECK_MSG(fabs(z0 - z1) <= 1e-15 * 20, "at %g, %g: %.17g vs %.17g", x, y, z0, z1);
        }
        tc_recon_free(r);
    }
    tc_mesh_free(m);
    tc_diags_free(&dg);
}

/* Midpoint samples given for each side of a C1 edge: within the tolerance
 * they are averaged (a warning); a larger difference stays as given (the
 * validator allows a jump in per-side samples). */
TEST(validate_value_tolerance_midpoint_sides) {
    const int32_t edge[4] = {0, 2, 2, 0};
    int32_t side[2] = {0, 1};
    double z[2] = {2, 2 + 1e-6};
    tc_mesh_desc d = square();
    d.value_tolerance = 1e-4;
    d.nmidpoints = 2, d.midpoint_edge = edge, d.midpoint_values = z, d.midpoint_tri = side;
    tc_diags dg;
    tc_diags_init(&dg);
    tc_mesh *m = mesh_ok(__FILE__, __LINE__, &d, &dg);
    CHECK(dg.warnings == 1);
    if (dg.count) {
        CHECK(!strcmp(dg.items[0].path, "midpoints[1]"));
        CHECK_STR_CONTAINS(dg.items[0].message, "both sides of 1 C0/C1 edges differed");
    }
    tc_mesh_free(m);
    tc_diags_free(&dg);
    z[1] = 2.5;
    PASSES(&d);
}

/* ---- 9. discontinuity polylines -------------------------------------------------------- */

TEST(validate_polyline_too_short) {
    int32_t st[2];
    const int32_t one[1] = {0}, two[2] = {0, 2};
    tc_mesh_desc d = square();
    d.c0 = line(st, one, 1);
    FAILS(&d, "discontinuities.c0[0]", "at least 2 vertices");
    d.c0 = line(st, two, 2);
    PASSES(&d);
}

TEST(validate_polyline_repeats_vertex) {
    int32_t st[2];
    const int32_t rep[3] = {0, 2, 2}, ok[2] = {0, 2};
    tc_mesh_desc d = square();
    d.cm1 = line(st, rep, 3);
    FAILS(&d, "discontinuities.c-1[0][1]", "segment [2, 2]", "repeats a vertex");
    d.cm1 = line(st, ok, 2);
    PASSES(&d);
}

TEST(validate_polyline_vertex_range) {
    int32_t st[2], verts[2] = {0, 9};
    tc_mesh_desc d = square();
    d.c0 = line(st, verts, 2);
    FAILS(&d, "discontinuities.c0[0][1]", "index 9", "4 vertices");
    verts[0] = -2;
    FAILS(&d, "discontinuities.c0[0][0]", "index -2", "4 vertices");
    verts[0] = 0, verts[1] = 2;
    PASSES(&d);
}

TEST(validate_polyline_not_an_edge) {
    int32_t st[2], verts[3] = {2, 1, 3}; /* (1, 3) is the other diagonal */
    tc_mesh_desc d = square();
    d.cm1 = line(st, verts, 3);
    FAILS(&d, "discontinuities.c-1[0][1]", "segment [1, 3]", "not an edge");
    verts[2] = 0;
    PASSES(&d);
}

TEST(validate_edge_flagged_c0_and_cm1) {
    int32_t st0[2], st1[2];
    const int32_t a[2] = {0, 2}, b[2] = {2, 0};
    tc_mesh_desc d = square();
    d.c0 = line(st0, a, 2);
    d.cm1 = line(st1, b, 2);
    FAILS(&d, "discontinuities.c-1[0][0]", "edge [2, 0]", "both c0 and c-1", "discontinuities.c0[0]");
    d.cm1 = (tc_polylines){0, NULL, NULL};
    PASSES(&d);
}

/* ---- 10. normals and gradients --------------------------------------------------------- */

TEST(validate_normal_points_down) {
    double n[12] = {0, 0, 1, 0, 0, -1, 0, 0, 1, 0, 0, 1};
    tc_mesh_desc d = square();
    d.normals = n;
    FAILS(&d, "normals[1]", "N.z = -1", "> 0");
    n[5] = 0;
    FAILS(&d, "normals[1]", "N.z = 0", "> 0");
    n[5] = 1;
    PASSES(&d);
    double n2[24] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0.5, 0, -0.5, 0, 0, 1, 0, 0, 1};
    double v2[8] = {1, 1, 2, 2, 3, 3, 4, 4};
    d.nchan = 2, d.values = v2, d.normals = n2;
    FAILS(&d, "normals[2][1]", "N.z = -0.5");
    n2[17] = 0.5;
    PASSES(&d);
}

TEST(validate_normal_too_horizontal) {
    double n[12] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 1, 0, 1e-320}; /* -nx/nz overflows */
    tc_mesh_desc d = square();
    d.normals = n;
    FAILS(&d, "normals[3]", "horizontal");
    n[11] = 1e-3;
    PASSES(&d);
}

TEST(validate_gradients_and_normals) {
    const double g[8] = {0}, n[12] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    tc_mesh_desc d = square();
    d.gradients = g, d.normals = n;
    FAILS(&d, "normals", "either gradients or normals");
    d.gradients = NULL;
    PASSES(&d);
    d.gradients = g, d.normals = NULL;
    PASSES(&d);
}

/* ---- 11-13. per-corner data and midpoints ---------------------------------------------- */

TEST(validate_corner_values_triangle) {
    int32_t tri[2] = {2, 1};
    const double cv[6] = {1, 3, 4, 1, 3, 4};
    tc_mesh_desc d = square();
    d.ncorner_values = 1, d.corner_values_tri = tri, d.corner_values = cv;
    FAILS(&d, "corner_values[0].triangle", "index 2", "2 triangles");
    tri[0] = -1;
    FAILS(&d, "corner_values[0].triangle", "index -1", "2 triangles");
    tri[0] = 1, d.ncorner_values = 2;
    FAILS(&d, "corner_values[1].triangle", "triangle 1 already has corner values (corner_values[0])");
    d.ncorner_values = 1;
    PASSES(&d);
}

TEST(validate_corner_gradients_triangle) {
    int32_t tri = 5;
    const double cg[6] = {0};
    tc_mesh_desc d = square();
    d.ncorner_gradients = 1, d.corner_gradients_tri = &tri, d.corner_gradients = cg;
    FAILS(&d, "corner_gradients[0].triangle", "index 5", "2 triangles");
    tri = -3;
    FAILS(&d, "corner_gradients[0].triangle", "index -3", "2 triangles");
    tri = 1;
    PASSES(&d);
}

TEST(validate_midpoint_edge) {
    int32_t edge[2] = {0, 7};
    const double z = 2;
    tc_mesh_desc d = square();
    d.nmidpoints = 1, d.midpoint_edge = edge, d.midpoint_values = &z;
    FAILS(&d, "midpoints[0].edge", "[0, 7]", "out of range", "4 vertices");
    edge[0] = -1, edge[1] = 2;
    FAILS(&d, "midpoints[0].edge", "[-1, 2]", "out of range");
    edge[0] = 1, edge[1] = 3;
    FAILS(&d, "midpoints[0].edge", "[1, 3] is not an edge");
    edge[0] = 3, edge[1] = 3;
    FAILS(&d, "midpoints[0].edge", "[3, 3] is not an edge");
    edge[0] = 1, edge[1] = 2;
    PASSES(&d);
}

TEST(validate_midpoint_triangle) {
    const int32_t edge[2] = {0, 1};
    int32_t side = 1; /* triangle 1 = (0, 2, 3) has no edge (0, 1) */
    const double z = 1.5;
    tc_mesh_desc d = square();
    d.nmidpoints = 1, d.midpoint_edge = edge, d.midpoint_values = &z, d.midpoint_tri = &side;
    FAILS(&d, "midpoints[0].triangle", "triangle 1 does not have edge [0, 1]");
    side = 2;
    FAILS(&d, "midpoints[0].triangle", "triangle 2 does not have edge [0, 1]");
    side = 0;
    PASSES(&d);
}

TEST(validate_midpoint_side_twice) {
    const int32_t edge[4] = {0, 2, 2, 0};
    int32_t side[2] = {-1, 1}; /* both sides, then side 1 again */
    const double z[2] = {2, 2.5};
    tc_mesh_desc d = square();
    d.nmidpoints = 2, d.midpoint_edge = edge, d.midpoint_values = z, d.midpoint_tri = side;
    FAILS(&d, "midpoints[1]", "already has a sample (midpoints[0])");
    side[0] = 0, side[1] = 0;
    FAILS(&d, "midpoints[1]", "already has a sample (midpoints[0])");
    side[1] = 1; /* one sample per side: a jump in the samples is allowed */
    PASSES(&d);
}

/* ---- 14. unused vertex ----------------------------------------------------------------- */

TEST(validate_unused_vertex_warns) {
    const double xy[10] = {0, 0, 1, 0, 1, 1, 0, 1, 5, 5};
    const double v[5] = {1, 2, 3, 4, 5};
    tc_mesh_desc d = square();
    d.nverts = 5, d.xy = xy, d.values = v;
    tc_diags dg;
    tc_diags_init(&dg);
    tc_mesh *m = mesh_ok(__FILE__, __LINE__, &d, &dg);
    CHECK(m != NULL);
    CHECK(dg.errors == 0 && dg.warnings == 1 && dg.count == 1);
    if (dg.count) {
        CHECK(dg.items[0].severity == TC_SEV_WARNING);
        CHECK_MSG(!strcmp(dg.items[0].path, "vertices[4]"), "path '%s'", dg.items[0].path);
        CHECK_STR_CONTAINS(dg.items[0].message, "vertex 4");
        CHECK_STR_CONTAINS(dg.items[0].message, "no triangle");
    }
    tc_mesh_free(m);
    tc_diags_free(&dg);
    d.nverts = 4; /* without the stray vertex: no warning */
    PASSES(&d);
}

/* Coordinates near the double range: a triangle's area (and so its aspect)
 * overflows to NaN. The sliver warning names that triangle in words; it used
 * to name triangle -1 (an assertion; found by the fuzzer, with a zero-area
 * triangle dropped before it). */
TEST(validate_sliver_aspect_overflow_warns_in_words) {
    const double xy[10] = {1, 0, 1, 5, 1e308, 1, 1, 1, 2, 2};
    const double v[5] = {0, 1, 1, 2, 3};
    const int32_t tri[12] = {0, 1, 1, 1, 3, 2, 2, 4, 3, 0, 3, 4};
    tc_mesh_desc d;
    tc_mesh_desc_init(&d);
    d.nverts = 5, d.xy = xy, d.values = v, d.nchan = 1, d.ntris = 4, d.tris = tri;
    d.degenerate = TC_DEGENERATE_DROP;
    tc_diags dg;
    tc_diags_init(&dg);
    tc_mesh *m = NULL;
    tc_mesh_new(&d, &m, &dg);
    int named = 0;
    for (int i = 0; i < dg.count; i++)
        if (strstr(dg.items[i].message, "aspect ratio")) {
            named = 1;
            CHECK_MSG(strstr(dg.items[i].path, "triangles[") && !strstr(dg.items[i].path, "-1"), "path '%s'",
                      dg.items[i].path);
            CHECK_MSG(!strstr(dg.items[i].message, "nan") && !strstr(dg.items[i].message, "inf"), "%s",
                      dg.items[i].message);
        }
    CHECK_MSG(named || m == NULL, "no sliver warning and the mesh was built");
    tc_mesh_free(m);
    tc_diags_free(&dg);
}

/* A third vertex a subnormal distance off the shared edge's line: seen from
 * one end of the edge it lies on the line, from the other it does not, so the
 * two triangles disagree on whether they overlap. Such a mesh may be refused,
 * but never without a message (it was: rc 1, 0 errors; found by the fuzzer):
 * either triangle that sees the overlap reports it. Either order of the
 * triangles, both offsets, and the fuzzer's folded case. */
TEST(validate_subnormal_offset_never_silent) {
    const double offsets[2] = {1e-300, 1.1e-319};
    for (int o = 0; o < 3; o++)
        for (int swap = 0; swap < 2; swap++) {
            double xy[8] = {0, 0, 1, 0, 0, 1, 1, o < 2 ? offsets[o] : 0};
            if (o == 2) xy[2] = 1, xy[3] = 8, xy[4] = 0, xy[5] = 1.1e-319, xy[6] = 1, xy[7] = 1; /* folded */
            const double v[4] = {0, 1, 1, 2};
            const int32_t a[6] = {0, 1, 2, 1, 3, 2}, b[6] = {1, 3, 2, 0, 1, 2};
            tc_mesh_desc d;
            tc_mesh_desc_init(&d);
            d.nverts = 4, d.xy = xy, d.values = v, d.nchan = 1, d.ntris = 2, d.tris = swap ? b : a;
            tc_diags dg;
            tc_diags_init(&dg);
            tc_mesh *m = NULL;
            int rc = tc_mesh_new(&d, &m, &dg);
            CHECK_MSG(rc == TC_OK ? dg.errors == 0 : dg.errors > 0 && strstr(dg.items[0].message, "overlaps"),
                      "case %d, order %d: rc %d with %d errors", o, swap, rc, dg.errors);
            tc_mesh_free(m);
            tc_diags_free(&dg);
        }
}

/* Two triangles running their shared edge [3, 2] the same way, both counter-clockwise: a fold,
 * whose third vertices (0, 0) and (1, 0) lie below the edge's line. Vertex 2 a subnormal above
 * the x axis puts (0, 0) within rounding of that line: a cross product taken from the edge's
 * start saw it on the line, the two on opposite sides, and linked them (the fuzzer's input;
 * the wedges came out inconsistent). The sides now come from the triangles' orientations, as
 * the fans walk them: refused, with the offset 1e-3 as with 1.1e-319, in either order. */
TEST(validate_fold_within_rounding_of_the_edge) {
    const double offsets[2] = {1e-3, 1.1e-319};
    for (int o = 0; o < 2; o++)
        for (int swap = 0; swap < 2; swap++) {
            double xy[8] = {0, 0, 1, 0, 0, offsets[o], 1, 1};
            int32_t tri[6] = {0, 3, 2, 1, 3, 2};
            if (swap) tri[0] = 1, tri[3] = 0;
            tc_mesh_desc d = square();
            d.xy = xy, d.tris = tri;
            FAILS(&d, "triangles[1]", "overlaps triangles[0]", "shared edge [3, 2]");
        }
}

/* ---- 15. errors of tc_recon_new -------------------------------------------------------- */

TEST(validate_recon_tangents_given_missing) {
    const double g[8] = {0.5, 0, 0.5, 0, 0.5, 0, 0.5, 0};
    uint8_t mask[4] = {1, 1, 1, 0}; /* vertex 3: corner 2 of triangle 1 */
    tc_mesh_desc d = square();
    d.gradients = g, d.gradients_mask = mask;
    tc_options given = opts(TC_METHOD_CLOUGH_TOCHER, TC_TANGENTS_GIVEN, TC_WEDGES_CORRECTED);
    RECON_FAILS(&d, given, "triangles[1]", "corner 2", "vertex 3", "no gradient or normal");
    tc_diags dg;
    tc_diags_init(&dg);
    RECON_PASSES(&d, opts(TC_METHOD_CLOUGH_TOCHER, TC_TANGENTS_AUTO, TC_WEDGES_CORRECTED), &dg);
    mask[3] = 1;
    RECON_PASSES(&d, given, &dg);
    drop_range_free_warnings(&dg);
    CHECK(dg.count == 0);
    tc_diags_free(&dg);
}

/* Midpoint samples on four of the five edges: (2, 3) has none. */
TEST(validate_recon_tangents_midpoints_missing) {
    const int32_t edge[10] = {0, 1, 1, 2, 2, 0, 3, 0, 2, 3};
    const double z[5] = {1.5, 2.5, 2, 2.5, 3.5};
    tc_mesh_desc d = square();
    d.nmidpoints = 4, d.midpoint_edge = edge, d.midpoint_values = z;
    tc_options mid = opts(TC_METHOD_CLOUGH_TOCHER, TC_TANGENTS_MIDPOINTS, TC_WEDGES_CORRECTED);
    RECON_FAILS(&d, mid, "midpoints", "edge [2, 3]", "no midpoint sample");
    tc_diags dg;
    tc_diags_init(&dg);
    d.nmidpoints = 5;
    RECON_PASSES(&d, mid, &dg);
    CHECK(dg.count == 0);
    tc_diags_free(&dg);
}

TEST(validate_recon_linear4_missing_midpoints_warns) {
    const int32_t edge[10] = {0, 1, 1, 2, 2, 0, 3, 0, 2, 3};
    const double z[5] = {1.5, 2.5, 2, 2.5, 3.5};
    tc_mesh_desc d = square();
    d.nmidpoints = 4, d.midpoint_edge = edge, d.midpoint_values = z;
    tc_options lin4 = opts(TC_METHOD_LINEAR4, TC_TANGENTS_AUTO, TC_WEDGES_CORRECTED);
    tc_diags dg;
    tc_diags_init(&dg);
    RECON_PASSES(&d, lin4, &dg);
    CHECK(dg.errors == 0 && dg.warnings == 1 && dg.count == 1);
    if (dg.count) {
        CHECK(dg.items[0].severity == TC_SEV_WARNING);
        /* the triangle and the edge it lacks, and what to send */
        CHECK_MSG(!strcmp(dg.items[0].path, "triangles[1]"), "path '%s'", dg.items[0].path);
        CHECK_STR_CONTAINS(dg.items[0].message, "1 triangle edge side has no midpoint sample (edges [2, 3])");
        CHECK_STR_CONTAINS(dg.items[0].message, "\"midpoints\"");
    }
    tc_diags_clear(&dg);
    d.nmidpoints = 5;
    RECON_PASSES(&d, lin4, &dg);
    CHECK(dg.count == 0 && dg.warnings == 0);
    tc_diags_free(&dg);
}

/* ---- 16. many errors ------------------------------------------------------------------- */

TEST(validate_many_errors_bounded) {
    int32_t tri[300];
    for (int t = 0; t < 100; t++) tri[3 * t] = 0, tri[3 * t + 1] = 1, tri[3 * t + 2] = 4 + t;
    tc_mesh_desc d = square();
    d.ntris = 100, d.tris = tri;
    tc_mesh *m = (tc_mesh *)&m;
    tc_diags dg;
    tc_diags_init(&dg);
    CHECK(tc_mesh_new(&d, &m, &dg) == TC_EINVAL);
    CHECK(m == NULL);
    CHECK_MSG(dg.errors == 100 && dg.warnings == 0, "%d errors, %d warnings", dg.errors, dg.warnings);
    CHECK_MSG(dg.count == TC_DIAGS_KEEP, "%d findings kept", dg.count);
    for (int i = 0; i < dg.count && i < TC_DIAGS_KEEP; i++) {
        char path[48], idx[24];
        snprintf(path, sizeof path, "triangles[%d][2]", i);
        snprintf(idx, sizeof idx, "index %d ", 4 + i);
        CHECK_MSG(!strcmp(dg.items[i].path, path), "item %d path '%s'", i, dg.items[i].path);
        CHECK_STR_CONTAINS(dg.items[i].message, idx);
    }
    tc_diags_free(&dg);
    CHECK(tc_mesh_new(&d, &m, NULL) == TC_EINVAL && m == NULL); /* diags are optional */
}

/* ---- 17. wedges "literal": Figure 6's Project singular --------------------------------- */

/* A 2x2 grid of cells over [-1,1]^2, centre vertex 4. The line y = 0 through 4
 * is C-1 on its left half (3-4) and C0 on its right half (4-5), so 4 is a C-1
 * vertex with exactly two collinear delimiters: two 180-degree wedges, upper and
 * lower, coupled across 4-5. Given tangent planes: gradient a = (1, a_y) on
 * every corner of the upper triangles, (-10, 0) on the lower ones.
 *
 * Literal step 4 for the upper wedge (side A = the C0 edge to +x with the coupled
 * plane c = Avg(a, lower), Figure 6's average of unit normals; side B = the C-1
 * edge to -x with its own plane a) projects N = (-a, 1) onto the plane
 * containing D = (-2, 0, -(a_x + c_x)). Its z component P_z falls from 1.2 at
 * a_y = 0 through 0 (the paper's 1 + a s = 0) to -0.19 at a_y = 10. Only P_z = 0
 * is singular: past it the projected normal points down, but it is still a
 * plane's, with gradient -P_xy / P_z (issue 14: the past-vertical side was
 * refused). The test computes P on its own and bisects a_y for P_z = 0. */
typedef struct {
    double pz, g[2];
} literal_project;

static literal_project literal_project_at(double a_y) {
    const double a[2] = {1, a_y}, lo[2] = {-10, 0};
    double n1[3] = {-a[0], -a[1], 1}, n2[3] = {-lo[0], -lo[1], 1}, s[3];
    double l1 = sqrt(n1[0] * n1[0] + n1[1] * n1[1] + 1), l2 = sqrt(n2[0] * n2[0] + n2[1] * n2[1] + 1);
    for (int i = 0; i < 3; i++) s[i] = n1[i] / l1 + n2[i] / l2;
    double c_x = -s[0] / s[2];
    double D[3] = {-2, 0, -(a[0] + c_x)}, N[3] = {-a[0], -a[1], 1};
    double q = (N[0] * D[0] + N[1] * D[1] + N[2] * D[2]) / (D[0] * D[0] + D[1] * D[1] + D[2] * D[2]);
    double P[3] = {N[0] - q * D[0], N[1] - q * D[1], N[2] - q * D[2]};
    return (literal_project){P[2], {-P[0] / P[2], -P[1] / P[2]}};
}

TEST(validate_literal_project_singular_only_when_vertical) {
    const double xy[18] = {-1, -1, 0, -1, 1, -1, -1, 0, 0, 0, 1, 0, -1, 1, 0, 1, 1, 1};
    const int32_t tri[24] = {0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4, 3, 4, 7, 3, 7, 6, 4, 5, 8, 4, 8, 7};
    const double v[9] = {1, 1.2, 1.4, 1.1, 1.3, 1.5, 1.2, 1.4, 1.6};
    const int32_t cg_tri[8] = {0, 1, 2, 3, 4, 5, 6, 7};
    const int32_t cm1v[2] = {3, 4}, c0v[2] = {4, 5};
    int32_t st0[2], st1[2];
    double cg[8][3][2];
    tc_mesh_desc d = square();
    d.nverts = 9, d.xy = xy, d.ntris = 8, d.tris = tri, d.values = v;
    d.ncorner_gradients = 8, d.corner_gradients_tri = cg_tri, d.corner_gradients = &cg[0][0][0];
    d.cm1 = line(st1, cm1v, 2);
    d.c0 = line(st0, c0v, 2);
    tc_options lit = opts(TC_METHOD_CLOUGH_TOCHER, TC_TANGENTS_GIVEN, TC_WEDGES_LITERAL);
    double lo_y = 0, hi_y = 10; /* P_z > 0 at lo_y, < 0 at hi_y */
    CHECK(literal_project_at(lo_y).pz > 0 && literal_project_at(hi_y).pz < 0);
    for (int i = 0; i < 200 && hi_y - lo_y > 0; i++) {
        double mid = 0.5 * (lo_y + hi_y);
        if (mid == lo_y || mid == hi_y) break;
        *(literal_project_at(mid).pz > 0 ? &lo_y : &hi_y) = mid;
    }
    const double cases[3] = {0, 10, lo_y}; /* up, past vertical, vertical to rounding */
    for (int i = 0; i < 3; i++) {
        for (int t = 0; t < 8; t++)
            for (int k = 0; k < 3; k++) {
                int up = t >= 4; /* triangles 4..7 are the upper cells */
                cg[t][k][0] = up ? 1 : -10;
                cg[t][k][1] = up ? cases[i] : 0;
            }
        if (i == 2) {
            RECON_FAILS(&d, lit, "vertices[4]", "vertex 4", "Project is singular", "corrected");
            continue;
        }
        tc_diags dg;
        tc_diags_init(&dg);
        tc_mesh *m = NULL;
        tc_recon *r = NULL;
        CHECK(tc_mesh_new(&d, &m, &dg) == TC_OK && tc_recon_new(m, &lit, &r, &dg) == TC_OK);
        literal_project want = literal_project_at(cases[i]);
        const double *g = r ? tc_recon_corner_gradients(r) + 2 * (3 * 6 + 0) : NULL; /* triangle 6 = (4, 5, 8), at 4 */
        CHECK_MSG(g && fabs(g[0] - want.g[0]) <= 1e-12 * fabs(want.g[1]) && fabs(g[1] - want.g[1]) <= 1e-12 * fabs(want.g[1]),
                  "a_y = %g: plane (%.17g, %.17g), Project gives (%.17g, %.17g) (P_z %.3g)", cases[i], g ? g[0] : NAN,
                  g ? g[1] : NAN, want.g[0], want.g[1], want.pz);
        tc_recon_free(r);
        tc_mesh_free(m);
        tc_diags_free(&dg);
    }
}

/* cross_boundary "salesin" with wedges "literal" on the unit square with flat
 * values and the same given gradient (s, 0) at every corner: on an edge e the
 * control polygon's middle leg falls by rise = -2 g.e while the averaged plane
 * rises by g.e, so Project's normal has P_z = 0 exactly where |e|^2 = 2 (g.e)^2:
 * the diagonal (1, 1) at s = 1, the sides at s = 1/sqrt 2. Below that P_z > 0;
 * past it (s = 2: every edge) the normal points down and is still a plane's
 * (accepted; refused before issue 14); at s = 1 the diagonal is vertical. */
TEST(validate_salesin_literal_project_singular_only_when_vertical) {
    const double flat[4] = {1, 1, 1, 1};
    double g[8];
    tc_mesh_desc d = square();
    d.values = flat, d.gradients = g;
    tc_options o = opts(TC_METHOD_CLOUGH_TOCHER, TC_TANGENTS_GIVEN, TC_WEDGES_LITERAL);
    o.cross_boundary = TC_CROSS_SALESIN;
    const double slopes[3] = {0.5, 2, 1};
    for (int i = 0; i < 3; i++) {
        for (int k = 0; k < 4; k++) g[2 * k] = slopes[i], g[2 * k + 1] = 0;
        if (slopes[i] == 1) {
            RECON_FAILS(&d, o, "triangles[0]", "salesin", "singular on edge 2");
            continue;
        }
        tc_diags dg;
        tc_diags_init(&dg);
        RECON_PASSES(&d, o, &dg);
        tc_diags_free(&dg);
    }
    tc_diags dg;
    tc_diags_init(&dg);
    o.wedges = TC_WEDGES_CORRECTED;
    RECON_PASSES(&d, o, &dg);
    tc_diags_free(&dg);
}

/* A triangle that shares only a vertex with a closed fan around it lies on
 * top of one of the fan's triangles: no shared edge shows it, so the edge tests
 * let it through and the methods that ignore flags built a full-turn wedge at
 * a vertex the mesh calls a boundary one (found by make fuzz; TC_ASSERT in
 * tc__wedges_build). Refused, naming the triangle and the vertex. Two open
 * fans meeting at a vertex (a bowtie) do not overlap and pass, in either
 * orientation of their triangles. */
TEST(validate_triangle_on_a_closed_fan) {
    const double xy[14] = {0, 0, 1, 0, 1, 1, 0, 1, 0.5, 0.5, 0.6, 0.9, 0.4, 0.9};
    const int32_t tri[15] = {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4, 4, 5, 6};
    const double v[7] = {0, 0, 0, 0, 1, 0.5, 0.5};
    tc_mesh_desc d = square();
    d.nverts = 7, d.xy = xy, d.ntris = 5, d.tris = tri, d.values = v;
    FAILS(&d, "triangles[4]", "overlaps the triangles around vertex 4", "full turn");
    /* The same with the extra triangle first, so its (open) walk at vertex 4 comes first. */
    const int32_t first[15] = {4, 5, 6, 0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4};
    d.tris = first;
    FAILS(&d, "triangles[0]", "overlaps the triangles around vertex 4", "full turn");
    d.tris = tri;
    d.nverts = 5, d.ntris = 4; /* the closed fan alone */
    PASSES(&d);
    const double bxy[10] = {0, 0, 1, 0.2, 1, -0.2, -1, 0.2, -1, -0.2};
    const int32_t btri[6] = {0, 2, 1, 0, 4, 3}, bcw[6] = {0, 1, 2, 0, 3, 4};
    const double bv[5] = {1, 0, 0, 0, 0};
    d.nverts = 5, d.xy = bxy, d.ntris = 2, d.tris = btri, d.values = bv;
    PASSES(&d);
    d.tris = bcw;
    PASSES(&d);
}

/* Values near the double range: the ordinates overflow, and the refusal says
 * so in words ("-inf" and "nan" printed as numbers told nobody anything:
 * issue 14), naming the cause that fits the method. */
TEST(validate_overflow_said_in_words) {
    const double huge[4] = {1e308, -1e308, 1e308, -1e308};
    tc_mesh_desc d = square();
    d.values = huge;
    tc_options o = opts(TC_METHOD_CONSTANT, TC_TANGENTS_AUTO, TC_WEDGES_CORRECTED);
    RECON_FAILS(&d, o, "triangles[0]", "ordinate mean overflows the double range", "its values are too large");
    o.method = TC_METHOD_LINEAR;
    RECON_FAILS(&d, o, "triangles[0]", "is 1e+308, beyond 1e+300", "its values are too large");
    o.method = TC_METHOD_CLOUGH_TOCHER;
    RECON_FAILS(&d, o, "triangles[0]", "beyond 1e+300", "tangent planes");
    for (int m = 0; m < tc_method_count(); m++) {
        tc_mesh *mesh = NULL;
        tc_recon *r = NULL;
        tc_diags dg;
        tc_diags_init(&dg);
        o.method = (tc_method)m;
        if (tc_mesh_new(&d, &mesh, &dg) == TC_OK && tc_recon_new(mesh, &o, &r, &dg) != TC_OK)
            for (int i = 0; i < dg.count; i++)
                CHECK_MSG(!strstr(dg.items[i].message, "inf") && !strstr(dg.items[i].message, "nan"),
                          "%s: %s", tc_method_name((tc_method)m), dg.items[i].message);
        tc_recon_free(r);
        tc_mesh_free(mesh);
        tc_diags_free(&dg);
    }
}

/* ---- each finding reported once; the rejections added after the first catalogue ---- */

static int count_errors(const tc_mesh_desc *d, const tc_options *o) {
    tc_diags dg;
    tc_diags_init(&dg);
    tc_mesh *m = NULL;
    tc_recon *r = NULL;
    if (tc_mesh_new(d, &m, &dg) == TC_OK && o) tc_recon_new(m, o, &r, &dg);
    int n = dg.errors;
    tc_recon_free(r);
    tc_mesh_free(m);
    tc_diags_free(&dg);
    return n;
}

TEST(validate_findings_reported_once) {
    int32_t tri[6] = {0, 1, 2, 2, 1, 0};
    tc_mesh_desc d = square();
    d.tris = tri;
    CHECK_MSG(count_errors(&d, NULL) == 1, "a repeated triangle: %d errors", count_errors(&d, NULL));
    /* tangents "midpoints" with the interior edge (0, 2) unsampled: one error, not one per corner. */
    const int32_t edge[8] = {0, 1, 1, 2, 2, 3, 3, 0};
    const double z[4] = {1.5, 2.5, 3.5, 2.5};
    d = square();
    d.nmidpoints = 4, d.midpoint_edge = edge, d.midpoint_values = z;
    tc_options mid = opts(TC_METHOD_CLOUGH_TOCHER, TC_TANGENTS_MIDPOINTS, TC_WEDGES_CORRECTED);
    CHECK_MSG(count_errors(&d, &mid) == 1, "one missing interior edge: %d errors", count_errors(&d, &mid));
}

/* Finite but huge tangent planes overflow the ordinates: refused, naming the
 * triangle, never Inf/NaN with TC_OK. */
TEST(validate_steep_tangents_overflow_refused) {
    const double g[8] = {1.7e308, 1.7e308, 0, 0, 0, 0, 0, 0};
    tc_mesh_desc d = square();
    d.gradients = g;
    for (int c = 0; c < 3; c++) {
        tc_options o = opts(TC_METHOD_CLOUGH_TOCHER, TC_TANGENTS_GIVEN, TC_WEDGES_CORRECTED);
        o.cross_boundary = (tc_cross)c;
        RECON_FAILS(&d, o, "triangles[0]", "overflow");
    }
    const double gok[8] = {1e3, 1e3, 0, 0, 0, 0, 0, 0};
    d.gradients = gok;
    tc_diags dg;
    tc_diags_init(&dg);
    RECON_PASSES(&d, opts(TC_METHOD_CLOUGH_TOCHER, TC_TANGENTS_GIVEN, TC_WEDGES_CORRECTED), &dg);
    tc_diags_free(&dg);
    const double big[4] = {1e301, 2, 3, 4}; /* values near the double range: refused for every method */
    d = square();
    d.values = big;
    RECON_FAILS(&d, opts(TC_METHOD_LINEAR, TC_TANGENTS_AUTO, TC_WEDGES_CORRECTED), "triangles[0]", "overflow");
}

TEST(validate_corner_gradients_triangle_twice) {
    const int32_t t[2] = {1, 1};
    double g[12] = {0};
    tc_mesh_desc d = square();
    d.ncorner_gradients = 2, d.corner_gradients_tri = t, d.corner_gradients = g;
    FAILS(&d, "corner_gradients[1].triangle", "triangle 1 already has corner gradients", "corner_gradients[0]");
    d.ncorner_gradients = 1;
    PASSES(&d);
}

TEST(validate_midpoint_side_negative) {
    const int32_t edge[2] = {0, 1}, side[1] = {-5};
    const double z[1] = {1.5};
    tc_mesh_desc d = square();
    d.nmidpoints = 1, d.midpoint_edge = edge, d.midpoint_tri = side, d.midpoint_values = z;
    FAILS(&d, "midpoints[0].triangle", "-5", "out of range");
    const int32_t both[1] = {-1};
    d.midpoint_tri = both;
    PASSES(&d);
}

TEST(validate_boundary_edge_flagged_c0_and_cm1) {
    const int32_t seg[2] = {0, 1};
    int32_t s0[2], s1[2];
    tc_mesh_desc d = square();
    d.c0 = line(s0, seg, 2);
    d.cm1 = line(s1, seg, 2);
    FAILS(&d, "discontinuities.c-1[0][0]", "flagged both c0 and c-1");
    d.cm1.count = 0;
    PASSES(&d);
}

/* ---- gaps found by mutation testing ------------------------------------------------------ */

/* An edge shared by four triangles is reported once, from the lowest, naming the
 * third triangle; the message lists the first three and says there are more
 * (", ...") rather than pretending the list is complete. */
TEST(validate_nonmanifold_edge_of_four_says_more) {
    const double xy[12] = {0, 0, 1, 0, 1, 1, 0, 1, 2, 0, 0, 2};
    const int32_t tri[12] = {0, 1, 2, 0, 2, 3, 0, 2, 4, 2, 0, 5};
    const double v[6] = {1, 2, 3, 4, 5, 6};
    tc_mesh_desc d = square();
    d.nverts = 6, d.xy = xy, d.ntris = 4, d.tris = tri, d.values = v;
    FAILS(&d, "triangles[2]", "non-manifold edge [2, 0]", "shared by 4 triangles (0, 1, 2, ...)");
}

/* Two separate closed fans, each with an extra triangle on its centre: the
 * refusal names the first bad vertex (4, not 11) and counts the triangles of
 * the closed turn (4), not every triangle at the vertex (5). */
TEST(validate_closed_fan_first_vertex_and_count) {
    double xy[28];
    const double one[14] = {0, 0, 1, 0, 1, 1, 0, 1, 0.5, 0.5, 0.6, 0.9, 0.4, 0.9};
    int32_t tri[30];
    const int32_t fan[15] = {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4, 4, 5, 6};
    double v[14];
    for (int i = 0; i < 14; i++) xy[i] = one[i], xy[14 + i] = one[i] + (i % 2 ? 0 : 3), v[i] = i % 7 == 4;
    for (int i = 0; i < 15; i++) tri[i] = fan[i], tri[15 + i] = fan[i] + 7;
    tc_mesh_desc d = square();
    d.nverts = 14, d.xy = xy, d.ntris = 10, d.tris = tri, d.values = v;
    FAILS(&d, "triangles[4]", "around vertex 4:", "4 of them close a full turn");
}

/* A polyline vertex equal to the vertex count is out of range (the bound is
 * exclusive), and in a second polyline the path counts from that polyline's
 * own start: discontinuities.c0[1][1], not the index into the flat array. */
TEST(validate_polyline_vertex_range_bounds) {
    int32_t st[2], verts[2] = {0, 4};
    tc_mesh_desc d = square();
    d.c0 = line(st, verts, 2);
    FAILS(&d, "discontinuities.c0[0][1]", "index 4", "4 vertices");
    int32_t start[3] = {0, 2, 4};
    const int32_t two[4] = {0, 2, 2, 9};
    d.c0 = (tc_polylines){2, start, two};
    FAILS(&d, "discontinuities.c0[1][1]", "index 9", "4 vertices");
}

/* value_tolerance is accepted on the closed range [0, 1]: exactly 1 passes, just
 * above it is refused. */
TEST(validate_value_tolerance_range_ends) {
    tc_mesh_desc d = square();
    d.value_tolerance = 1;
    PASSES(&d);
    d.value_tolerance = 0;
    PASSES(&d);
    d.value_tolerance = 1.0000001;
    FAILS(&d, "value_tolerance", "must be 0 to 1");
}

/* Vertex 0 unused (the triangles use 1..4): warned like any other vertex. */
TEST(validate_unused_first_vertex_warns) {
    const double xy[10] = {5, 5, 0, 0, 1, 0, 1, 1, 0, 1};
    const int32_t tri[6] = {1, 2, 3, 1, 3, 4};
    const double v[5] = {0, 1, 2, 3, 4};
    tc_mesh_desc d = square();
    d.nverts = 5, d.xy = xy, d.tris = tri, d.values = v;
    tc_diags dg;
    tc_diags_init(&dg);
    tc_mesh *m = mesh_ok(__FILE__, __LINE__, &d, &dg);
    CHECK(dg.errors == 0 && dg.warnings == 1 && dg.count == 1);
    if (dg.count) {
        CHECK_MSG(!strcmp(dg.items[0].path, "vertices[0]"), "path '%s'", dg.items[0].path);
        CHECK_STR_CONTAINS(dg.items[0].message, "vertex 0 is used by no triangle");
    }
    tc_mesh_free(m);
    tc_diags_free(&dg);
}

/* A corner the mask leaves out is not read: a non-finite number there is no
 * error, whatever the mask says for the element's other corners. */
TEST(validate_corner_gradient_mask_per_corner) {
    int32_t tri = 0;
    double cg[6] = {0, 0, INFINITY, 0, 0, 0};
    uint8_t mask[3] = {1, 0, 1};
    tc_mesh_desc d = square();
    d.ncorner_gradients = 1, d.corner_gradients_tri = &tri, d.corner_gradients = cg, d.corner_gradients_mask = mask;
    PASSES(&d);
    mask[1] = 1;
    FAILS(&d, "corner_gradients[0].gradients[1]", "not finite");
}

/* The sliver warning names the first of the worst: two slivers of exactly the
 * same shape (one a translate of the other by exact offsets) report triangles[0].
 * And a sliver whose aspect overflows (coordinates near the double range) is
 * "beyond the double range", never a number. */
TEST(validate_sliver_warning_names_first_worst) {
    const double xy[12] = {0, 0, 1, 0, 0.5, 1e-5, 2, 0, 3, 0, 2.5, 1e-5};
    const int32_t tri[6] = {0, 1, 2, 3, 4, 5};
    const double v[6] = {1, 2, 3, 1, 2, 3};
    tc_mesh_desc d = square();
    d.nverts = 6, d.xy = xy, d.ntris = 2, d.tris = tri, d.values = v;
    tc_diags dg;
    tc_diags_init(&dg);
    tc_mesh *m = mesh_ok(__FILE__, __LINE__, &d, &dg);
    CHECK(dg.warnings == 1 && dg.count == 1);
    if (dg.count) {
        CHECK_MSG(!strcmp(dg.items[0].path, "triangles[0]"), "path '%s'", dg.items[0].path);
        CHECK_STR_CONTAINS(dg.items[0].message, "2 triangles have an aspect ratio above 1e+04");
    }
    tc_mesh_free(m);
    tc_diags_free(&dg);
    const double big[10] = {1, 0, 1, 5, 1e308, 1, 1, 1, 2, 2};
    const double bv[5] = {0, 1, 1, 2, 3};
    const int32_t btri[12] = {0, 1, 1, 1, 3, 2, 2, 4, 3, 0, 3, 4};
    d.nverts = 5, d.xy = big, d.ntris = 4, d.tris = btri, d.values = bv;
    d.degenerate = TC_DEGENERATE_DROP;
    tc_diags_init(&dg);
    m = mesh_ok(__FILE__, __LINE__, &d, &dg);
    int named = 0;
    for (int i = 0; i < dg.count; i++)
        if (strstr(dg.items[i].message, "aspect ratio")) {
            named = 1;
            CHECK_STR_CONTAINS(dg.items[i].message, "beyond the double range");
        }
    CHECK(named);
    tc_mesh_free(m);
    tc_diags_free(&dg);
}

/* Counts at the int32 limits are refused with TC_ELIMIT before any array is
 * read (the arrays here are tiny: reading them as that long would crash):
 * INT32_MAX vertices, INT32_MAX / 3 triangles, INT32_MAX / 6 quads. */
TEST(validate_count_limits_refused_unread) {
    tc_mesh_desc d = square();
    tc_mesh *m = (tc_mesh *)&m;
    d.nverts = INT32_MAX;
    CHECK(tc_mesh_new(&d, &m, NULL) == TC_ELIMIT && m == NULL);
    d = square();
    d.ntris = INT32_MAX / 3;
    CHECK(tc_mesh_new(&d, &m, NULL) == TC_ELIMIT && m == NULL);
    d = square();
    d.ntris = 0, d.nquads = INT32_MAX / 6, d.quads = SQ_TRI;
    CHECK(tc_mesh_new(&d, &m, NULL) == TC_ELIMIT && m == NULL);
    d = square();
    PASSES(&d);
}
