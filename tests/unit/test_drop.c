/* test_drop.c — degenerate "drop": zero-area and repeated-vertex triangles left out
 * with a warning, the request's numbering kept in every message, entry and answer. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <cJSON.h>

#include "check.h"
#include "io/api.h"
#include "meshgen.h"
#include "props.h"

/* The unit square (0, 1, 2, 3) as triangles 0 = [0, 1, 2] and 2 = [0, 2, 3],
 * with vertex 4 = (0.5, 0) on its bottom edge: triangle 1 = [0, 4, 1] has zero
 * area, triangle 3 = [2, 2, 3] repeats a vertex. */
static const double XY[] = {0, 0, 1, 0, 1, 1, 0, 1, 0.5, 0};
static const int32_t TRIS[] = {0, 1, 2, 0, 4, 1, 0, 2, 3, 2, 2, 3};
static const double VAL[] = {1, 2, 3, 4, 1.5};

static tc_mesh_desc desc5(void) {
    tc_mesh_desc d;
    tc_mesh_desc_init(&d);
    d.nverts = 5, d.xy = XY, d.ntris = 4, d.tris = TRIS, d.nchan = 1, d.values = VAL;
    d.degenerate = TC_DEGENERATE_DROP;
    return d;
}

/* The finding at `path` whose message contains `text`: its severity, or -1. */
static int finding(const tc_diags *dg, const char *path, const char *text) {
    for (int i = 0; i < dg->count; i++)
        if (!strcmp(dg->items[i].path, path) && strstr(dg->items[i].message, text)) return (int)dg->items[i].severity;
    return -1;
}

static void show(const tc_diags *dg) {
    for (int i = 0; i < dg->count; i++) fprintf(stderr, "    %s: %s\n", dg->items[i].path, dg->items[i].message);
}

TEST(drop_removes_exactly_the_degenerate_triangles) {
    tc_mesh_desc d = desc5();
    tc_diags dg;
    tc_diags_init(&dg);
    tc_mesh *m = NULL;
    CHECK(tc_mesh_new(&d, &m, &dg) == TC_OK && dg.errors == 0);
    CHECK(finding(&dg, "triangles[1]", "2 degenerate triangles (zero area or a vertex repeated) dropped") ==
          TC_SEV_WARNING);
    CHECK(finding(&dg, "triangles[1]", "dropped (degenerate \"drop\"): 1, 3;") == TC_SEV_WARNING);
    CHECK(finding(&dg, "vertices[4]", "vertex 4 is used by no triangle") == TC_SEV_WARNING);
    if (m) {
        CHECK(tc_mesh_triangle_count(m) == 2 && tc_mesh_given_triangle_count(m) == 4);
        static const int32_t of_given[] = {0, -1, 1, -1};
        for (int32_t i = 0; i < 4; i++) CHECK(tc_mesh_triangle_of_given(m, i) == of_given[i]);
        CHECK(tc_mesh_triangle_of_given(m, 4) == -1 && tc_mesh_triangle_of_given(m, -1) == -1);
        CHECK(tc_mesh_given_triangle(m, 0) == 0 && tc_mesh_given_triangle(m, 1) == 2);
        CHECK(!memcmp(tc_mesh_triangles(m) + 3, TRIS + 6, 3 * sizeof(int32_t)));
    }
    tc_mesh_free(m);
    tc_diags_free(&dg);
    /* refused as before without "drop" (and by a zero-filled description) */
    d.degenerate = TC_DEGENERATE_REFUSE;
    tc_diags_init(&dg);
    CHECK(tc_mesh_new(&d, &m, &dg) == TC_EINVAL && !m && dg.errors == 2);
    CHECK(finding(&dg, "triangles[1]", "zero-area triangle") == TC_SEV_ERROR);
    CHECK(finding(&dg, "triangles[3]", "a vertex appears twice in [2, 2, 3]") == TC_SEV_ERROR);
    tc_diags_free(&dg);
}

/* Entries naming a dropped triangle are ignored with a warning at their
 * path; entries naming a kept one land on it; errors about other triangles
 * name the request's index. */
TEST(drop_keeps_the_request_numbering) {
    tc_mesh_desc d = desc5();
    const int32_t cvt[] = {1, 2}, cgt[] = {3}, medge[] = {0, 4, 0, 2, 0, 2}, mtri[] = {-1, 1, 2};
    const double cv[] = {9, 9, 9, 1, 3, 4}, cg[6] = {0}, mv[] = {7, 8, 2.5};
    const int32_t ls[] = {0, 2}, lv[] = {0, 4};
    d.ncorner_values = 2, d.corner_values_tri = cvt, d.corner_values = cv;
    d.ncorner_gradients = 1, d.corner_gradients_tri = cgt, d.corner_gradients = cg;
    d.nmidpoints = 3, d.midpoint_edge = medge, d.midpoint_tri = mtri, d.midpoint_values = mv;
    d.cm1 = (tc_polylines){1, ls, lv};
    tc_diags dg;
    tc_diags_init(&dg);
    tc_mesh *m = NULL;
    CHECK(tc_mesh_new(&d, &m, &dg) == TC_OK && dg.errors == 0);
    CHECK(finding(&dg, "corner_values[0].triangle", "triangle 1 was dropped as degenerate") == TC_SEV_WARNING);
    CHECK(finding(&dg, "corner_gradients[0].triangle", "triangle 3 was dropped") == TC_SEV_WARNING);
    CHECK(finding(&dg, "midpoints[0].edge", "[0, 4] is an edge only of triangles dropped") == TC_SEV_WARNING);
    CHECK(finding(&dg, "midpoints[1].triangle", "triangle 1 was dropped") == TC_SEV_WARNING);
    CHECK(finding(&dg, "discontinuities.c-1[0][0]", "[0, 4] is an edge only of triangles dropped") ==
          TC_SEV_WARNING);
    if (dg.errors) show(&dg);
    if (m) { /* corner_values[1] names given triangle 2, the mesh's triangle 1 */
        CHECK(tc_mesh_corner_value(m, 1, 0)[0] == 1 && tc_mesh_corner_value(m, 1, 1)[0] == 3);
        CHECK(tc_mesh_corner_value(m, 0, 0)[0] == 1);
    }
    tc_mesh_free(m);
    tc_diags_free(&dg);
    /* A disagreement across the diagonal names triangle 2 (the request's), not 1. */
    const double bad[] = {9, 9, 9, 1, 3.5, 4};
    d.corner_values = bad, d.ncorner_values = 2;
    d.nmidpoints = 0, d.ncorner_gradients = 0, d.cm1.count = 0;
    const int32_t one[] = {2};
    d.corner_values_tri = one, d.ncorner_values = 1, d.corner_values = bad + 3;
    tc_diags_init(&dg);
    CHECK(tc_mesh_new(&d, &m, &dg) == TC_EINVAL && !m);
    CHECK(finding(&dg, "corner_values[0]", "3 (triangle 0) vs 3.5 (triangle 2)") == TC_SEV_ERROR);
    tc_diags_free(&dg);
}

/* Non-manifold edges and overlaps stay errors, named by the request's index. */
TEST(drop_leaves_other_errors_with_their_indices) {
    const int32_t tris[] = {0, 1, 2, 0, 4, 1, 0, 2, 3, 2, 2, 3, 3, 2, 0};
    tc_mesh_desc d = desc5();
    d.ntris = 5, d.tris = tris; /* triangle 4 repeats triangle 2 */
    tc_diags dg;
    tc_diags_init(&dg);
    tc_mesh *m = NULL;
    CHECK(tc_mesh_new(&d, &m, &dg) == TC_EINVAL && !m);
    CHECK(finding(&dg, "triangles[4]", "repeats triangles[2]") == TC_SEV_ERROR);
    tc_diags_free(&dg);
    const int32_t all_bad[] = {0, 4, 1, 2, 2, 3};
    d.ntris = 2, d.tris = all_bad;
    tc_diags_init(&dg);
    CHECK(tc_mesh_new(&d, &m, &dg) == TC_EINVAL && !m);
    CHECK(finding(&dg, "triangles", "every triangle is degenerate (2 dropped)") == TC_SEV_ERROR);
    tc_diags_free(&dg);
}

/* A degenerate quad is refused even with "drop" (a hole in the patch grid). */
TEST(drop_does_not_apply_to_quads) {
    const double xy[] = {0, 0, 1, 0, 2, 0, 1, 1};
    const int32_t quads[] = {0, 1, 2, 3};
    const double v[] = {0, 1, 2, 3};
    tc_mesh_desc d;
    tc_mesh_desc_init(&d);
    d.nverts = 4, d.xy = xy, d.nquads = 1, d.quads = quads, d.nchan = 1, d.values = v;
    d.degenerate = TC_DEGENERATE_DROP;
    tc_diags dg;
    tc_diags_init(&dg);
    tc_mesh *m = NULL;
    CHECK(tc_mesh_new(&d, &m, &dg) == TC_EINVAL && !m);
    CHECK(finding(&dg, "quads[0]", "degenerate quad") == TC_SEV_ERROR);
    tc_diags_free(&dg);
}

/* A jittered grid with degenerate triangles slipped in reconstructs exactly
 * as the grid without them: every coefficient bit for bit, for every method. */
TEST(drop_equals_the_mesh_without_them) {
    trng rng;
    trng_seed(&rng, tc_test_seed() + 91);
    tmesh g;
    tmesh_grid(&g, 6, 6, 0.2, -1, &rng);
    tmesh_sample(&g, 2, smooth_f, NULL, 0, 1, 0);
    tc_mesh_desc clean;
    tmesh_desc(&g, &clean);
    int32_t nt = clean.ntris, nbad = 4, ngiven = nt + nbad;
    int32_t *tris = malloc(3 * (size_t)ngiven * sizeof *tris);
    int32_t slots[] = {0, 5, 17, ngiven - 1}; /* where the degenerate ones go, in the given order */
    const int32_t bad[4][3] = {{tmesh_gv(6, 0, 0), tmesh_gv(6, 1, 0), tmesh_gv(6, 2, 0)}, /* collinear */
                               {7, 7, 9}, {3, 10, 10}, {tmesh_gv(6, 6, 6), tmesh_gv(6, 6, 4), tmesh_gv(6, 6, 5)}};
    for (int32_t i = 0, t = 0, b = 0; i < ngiven; i++) {
        if (b < nbad && i == slots[b]) memcpy(tris + 3 * i, bad[b++], sizeof bad[0]);
        else memcpy(tris + 3 * i, clean.tris + 3 * t++, 3 * sizeof *tris);
    }
    tc_mesh_desc d = clean;
    d.ntris = ngiven, d.tris = tris, d.degenerate = TC_DEGENERATE_DROP;
    tc_mesh *a = NULL, *b = NULL;
    tc_diags dg;
    tc_diags_init(&dg);
    CHECK(tc_mesh_new(&d, &a, &dg) == TC_OK && tc_mesh_new(&clean, &b, NULL) == TC_OK);
    CHECK(finding(&dg, "triangles[0]", "4 degenerate triangles") == TC_SEV_WARNING);
    CHECK(finding(&dg, "triangles[0]", ": 0, 5, 17, 75;") == TC_SEV_WARNING);
    for (int mi = 0; a && b && mi < tc_method_count(); mi++) {
        if (tc_method_quads_only((tc_method)mi)) continue;
        tc_options o;
        tc_options_default(&o);
        o.method = (tc_method)mi;
        tc_recon *ra = NULL, *rb = NULL;
        CHECK(tc_recon_new(a, &o, &ra, NULL) == TC_OK && tc_recon_new(b, &o, &rb, NULL) == TC_OK);
        size_t n = (size_t)nt * 2 * (size_t)(ra ? tc_recon_coef_count(ra) : 0);
        CHECK_MSG(ra && rb && tc_mesh_triangle_count(a) == nt &&
                      !memcmp(tc_recon_coefs(ra), tc_recon_coefs(rb), n * sizeof(double)),
                  "%s differs with the degenerate triangles dropped", tc_method_name(o.method));
        tc_recon_free(ra);
        tc_recon_free(rb);
    }
    tc_mesh_free(a);
    tc_mesh_free(b);
    tc_diags_free(&dg);
    free(tris);
    tmesh_free(&g);
}

/* /v1/ordinates keeps the request's numbering: null for a dropped triangle. */
TEST(drop_ordinates_answer_has_null_entries) {
    const char *body = "{\"vertices\": [[0,0],[1,0],[1,1],[0,1],[0.5,0]], \"values\": [1,2,3,4,1.5],"
                       " \"triangles\": [[0,1,2],[0,4,1],[0,2,3],[2,2,3]], \"degenerate\": \"drop\", \"method\": \"linear\"}";
    tc_strbuf out;
    tc_strbuf_init(&out);
    tc_api_result res;
    tc_api_result_init(&res);
    CHECK(tc_api_ordinates(body, strlen(body), NULL, &out, &res) == 200);
    cJSON *doc = cJSON_ParseWithLength(out.buf, out.len);
    const cJSON *ord = cJSON_GetObjectItemCaseSensitive(doc, "ordinates");
    CHECK(cJSON_GetArraySize(ord) == 4);
    CHECK(cJSON_IsArray(cJSON_GetArrayItem(ord, 0)) && cJSON_IsNull(cJSON_GetArrayItem(ord, 1)));
    CHECK(cJSON_IsArray(cJSON_GetArrayItem(ord, 2)) && cJSON_IsNull(cJSON_GetArrayItem(ord, 3)));
    const cJSON *t2 = cJSON_GetArrayItem(cJSON_GetArrayItem(ord, 2), 0);
    CHECK(t2 && cJSON_GetArrayItem(t2, 2)->valuedouble == 4); /* [0, 2, 3]: w = vertex 3 */
    CHECK(!cJSON_GetObjectItemCaseSensitive(doc, "degenerate")); /* a mesh option: not echoed */
    cJSON_Delete(doc);
    tc_api_result_free(&res);
    tc_strbuf_free(&out);
}

/* ---- gaps found by mutation testing ------------------------------------------------------ */

/* Segments on edges of the dropped zero-area triangle 1 = [0, 4, 1], found from
 * either end and whichever corner the other end is (here the third, vertex 1):
 * each is ignored with a warning naming triangles[1]. A segment on an edge of a
 * kept triangle that a dropped one also has ([0, 1]: kept triangle 0's first
 * edge) is flagged as usual, with no such warning. */
TEST(drop_segment_on_dropped_edge_any_corner) {
    tc_mesh_desc d = desc5();
    int32_t start[4] = {0, 2, 4, 6};
    const int32_t verts[6] = {4, 1, 1, 4, 0, 1};
    d.c0 = (tc_polylines){3, start, verts};
    tc_diags dg;
    tc_diags_init(&dg);
    tc_mesh *m = NULL;
    CHECK(tc_mesh_new(&d, &m, &dg) == TC_OK && dg.errors == 0);
    CHECK(finding(&dg, "discontinuities.c0[0][0]", "segment [4, 1] is an edge only of triangles dropped as "
                                                    "degenerate (triangles[1]): ignored") == TC_SEV_WARNING);
    CHECK(finding(&dg, "discontinuities.c0[1][0]", "segment [1, 4] is an edge only of triangles dropped as "
                                                    "degenerate (triangles[1]): ignored") == TC_SEV_WARNING);
    for (int i = 0; i < dg.count; i++) /* whatever its path: [0, 1] is flagged, not ignored */
        CHECK_MSG(!strstr(dg.items[i].message, "segment [0, 1]"), "%s: %s", dg.items[i].path, dg.items[i].message);
    if (dg.errors) show(&dg);
    tc_mesh_free(m);
    tc_diags_free(&dg);
}

/* More than eight dropped triangles: the warning lists the first eight given
 * indices, then ", ...", and counts them all. */
TEST(drop_warning_lists_eight) {
    int32_t tris[3 * 11] = {0, 1, 2, 0, 2, 3};
    for (int i = 2; i < 11; i++) tris[3 * i] = 0, tris[3 * i + 1] = 0, tris[3 * i + 2] = 1;
    tc_mesh_desc d = desc5();
    d.nverts = 4, d.ntris = 11, d.tris = tris;
    tc_diags dg;
    tc_diags_init(&dg);
    tc_mesh *m = NULL;
    CHECK(tc_mesh_new(&d, &m, &dg) == TC_OK && dg.errors == 0);
    CHECK(finding(&dg, "triangles[2]", "9 degenerate triangles") == TC_SEV_WARNING);
    CHECK(finding(&dg, "triangles[2]", ": 2, 3, 4, 5, 6, 7, 8, 9, ...;") == TC_SEV_WARNING);
    if (dg.errors) show(&dg);
    tc_mesh_free(m);
    tc_diags_free(&dg);
}
