/* test_request.c — unit tests of the JSON request reader (src/io/request*.c, reader.c).
 * Every rule of the request format (README.md, api/openapi.yaml) as read by tc_request_parse:
 * parsed arrays, status, path, message. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "image/image.h"
#include "io/request.h"

/* A valid 1-channel mesh: the unit square split along its diagonal (0, 2). */
#define SQUARE "\"vertices\": [[0,0],[1,0],[1,1],[0,1]], \"triangles\": [[0,1,2],[0,2,3]]"
#define MESH1 SQUARE ", \"values\": [0, 1, 2, 3]"
#define MESH3 SQUARE ", \"values\": [[0,1,2],[1,2,3],[2,3,4],[3,4,5]]"

static int parse_str(const char *json, unsigned expect, tc_request **r, tc_diags *d) {
    tc_diags_init(d);
    return tc_request_parse(json, strlen(json), expect, r, d);
}

/* Parses json, expects failure with `status`, the first finding at `path`
 * (exactly) whose message contains `msg`; reports at the caller's line. */
static void check_error_at(const char *file, int line, const char *json, unsigned expect,
                           int status, const char *path, const char *msg) {
    tc_request *r = (tc_request *)1;
    tc_diags d;
    int st = parse_str(json, expect, &r, &d);
    if (st != status) tc_test_fail(file, line, "status %d, expected %d", st, status);
    if (r != NULL) tc_test_fail(file, line, "*out is not NULL on error");
    if (d.count < 1 || d.errors < 1) {
        tc_test_fail(file, line, "no error reported");
    } else {
        const tc_diag *e = &d.items[0];
        if (e->severity != TC_SEV_ERROR) tc_test_fail(file, line, "first finding is not an error");
        if (strcmp(e->path, path) != 0)
            tc_test_fail(file, line, "path '%s', expected '%s' (message: %s)", e->path, path,
                         e->message);
        if (!strstr(e->message, msg))
            tc_test_fail(file, line, "message '%s' does not contain '%s'", e->message, msg);
    }
    tc_request_free(r == (tc_request *)1 ? NULL : r);
    tc_diags_free(&d);
}
#define CHECK_ERROR(json, expect, status, path, msg) \
    check_error_at(__FILE__, __LINE__, json, expect, status, path, msg)
#define MALFORMED(json, path, msg) CHECK_ERROR(json, TC_REQ_MESH, TC_REQ_MALFORMED, path, msg)
#define INVALID(json, path, msg) CHECK_ERROR(json, TC_REQ_MESH, TC_REQ_INVALID, path, msg)

/* Index of the first finding with this path, or -1. */
static int find_diag(const tc_diags *d, const char *path) {
    for (int i = 0; i < d->count; i++)
        if (strcmp(d->items[i].path, path) == 0) return i;
    return -1;
}

/* ---- good requests --------------------------------------------------------------- */

static const char full_request[] =
    "{\"vertices\": [[0,0],[2,0],[2,2],[0,2]],\n"
    " \"triangles\": [[0,1,2],[0,2,3]],\n"
    " \"values\": [[1,10],[2,20],[3,30],[4,40]],\n"
    " \"corner_values\": [{\"triangle\": 1, \"values\": [[5,50],[6,60],[7,70]]}],\n"
    " \"gradients\": [[[1,2],[3,4]], [[5,6],[7,8]], [[9,10],[11,12]], [[13,14],[15,16]]],\n"
    " \"corner_gradients\": [{\"triangle\": 0, \"gradients\": [[[0.5,1.5],[2.5,3.5]], null,"
    " [[-1,-2],[-3,-4]]]}],\n"
    " \"midpoints\": [{\"edge\": [0,2], \"value\": [2.5,25], \"triangle\": 1},"
    " {\"edge\": [1,2], \"value\": [0.25,0.5]}],\n"
    " \"discontinuities\": {\"c0\": [[0,2]], \"c-1\": [[1,2,3],[3,0]]},\n"
    " \"method\": \"linear4\", \"cross_boundary\": \"affine\", \"wedges\": \"literal\",\n"
    " \"tangents\": \"given\",\n"
    " \"points\": [[0.5,0.25],[1e-3,-7]], \"with_gradients\": true}";

TEST(request_full_two_channels) {
    tc_request *r = NULL;
    tc_diags d;
    int st = parse_str(full_request, TC_REQ_MESH | TC_REQ_POINTS, &r, &d);
    CHECK(st == TC_REQ_OK);
    CHECK(d.count == 0);
    if (!r) return;
    const tc_mesh_desc *m = &r->desc;
    CHECK(r->has_mesh == 1 && r->values_plain == 0);
    CHECK(m->nverts == 4 && m->ntris == 2 && m->nchan == 2);
    static const double xy[] = {0, 0, 2, 0, 2, 2, 0, 2};
    for (int i = 0; i < 8; i++) CHECK(m->xy[i] == xy[i]);
    static const int32_t tris[] = {0, 1, 2, 0, 2, 3};
    for (int i = 0; i < 6; i++) CHECK(m->tris[i] == tris[i]);
    static const double z[] = {1, 10, 2, 20, 3, 30, 4, 40};
    for (int i = 0; i < 8; i++) CHECK(m->values[i] == z[i]);

    CHECK(m->ncorner_values == 1 && m->corner_values_tri[0] == 1);
    static const double cz[] = {5, 50, 6, 60, 7, 70};
    for (int i = 0; i < 6; i++) CHECK(m->corner_values[i] == cz[i]);

    CHECK(m->gradients_mask == NULL); /* every vertex has one */
    for (int i = 0; i < 16; i++) CHECK(m->gradients[i] == i + 1);
    CHECK(m->normals == NULL && m->normals_mask == NULL);

    CHECK(m->ncorner_gradients == 1 && m->corner_gradients_tri[0] == 0);
    CHECK(m->corner_gradients_mask != NULL);
    if (m->corner_gradients_mask) {
        CHECK(m->corner_gradients_mask[0] == 1 && m->corner_gradients_mask[1] == 0 &&
              m->corner_gradients_mask[2] == 1);
    }
    static const double cg[] = {0.5, 1.5, 2.5, 3.5, 0, 0, 0, 0, -1, -2, -3, -4};
    for (int i = 0; i < 12; i++) CHECK(m->corner_gradients[i] == cg[i]);

    CHECK(m->nmidpoints == 2);
    static const int32_t me[] = {0, 2, 1, 2};
    for (int i = 0; i < 4; i++) CHECK(m->midpoint_edge[i] == me[i]);
    CHECK(m->midpoint_tri[0] == 1 && m->midpoint_tri[1] == -1);
    static const double mz[] = {2.5, 25, 0.25, 0.5};
    for (int i = 0; i < 4; i++) CHECK(m->midpoint_values[i] == mz[i]);

    CHECK(m->c0.count == 1 && m->c0.start[0] == 0 && m->c0.start[1] == 2);
    CHECK(m->c0.verts[0] == 0 && m->c0.verts[1] == 2);
    CHECK(m->cm1.count == 2);
    static const int32_t cs[] = {0, 3, 5}, cv[] = {1, 2, 3, 3, 0};
    for (int i = 0; i < 3; i++) CHECK(m->cm1.start[i] == cs[i]);
    for (int i = 0; i < 5; i++) CHECK(m->cm1.verts[i] == cv[i]);

    CHECK(r->opt.method == TC_METHOD_LINEAR4);
    CHECK(r->opt.cross_boundary == TC_CROSS_AFFINE);
    CHECK(r->opt.wedges == TC_WEDGES_LITERAL);
    CHECK(r->opt.tangents == TC_TANGENTS_GIVEN);
    CHECK(r->npoints == 2 && r->with_gradients == 1);
    static const double pts[] = {0.5, 0.25, 1e-3, -7};
    for (int i = 0; i < 4; i++) CHECK(r->points[i] == pts[i]);
    tc_request_free(r);
    tc_diags_free(&d);
}

TEST(request_plain_values_and_defaults) {
    tc_request *r = NULL;
    tc_diags d;
    CHECK(parse_str("{" MESH1 "}", TC_REQ_MESH, &r, &d) == TC_REQ_OK);
    if (!r) return;
    CHECK(r->values_plain == 1 && r->desc.nchan == 1 && r->has_mesh == 1);
    for (int i = 0; i < 4; i++) CHECK(r->desc.values[i] == i);
    tc_options def;
    tc_options_default(&def);
    CHECK(r->opt.method == def.method && r->opt.cross_boundary == def.cross_boundary &&
          r->opt.wedges == def.wedges && r->opt.tangents == def.tangents);
    CHECK(r->npoints == 0 && r->points == NULL && r->with_gradients == 0);
    CHECK(r->desc.gradients == NULL && r->desc.ncorner_values == 0 && r->desc.nmidpoints == 0);
    CHECK(r->desc.c0.count == 0 && r->desc.cm1.count == 0);
    tc_request_free(r);
    tc_diags_free(&d);
}

TEST(request_values_one_element_arrays_are_one_channel) {
    tc_request *r = NULL;
    tc_diags d;
    CHECK(parse_str("{" SQUARE ", \"values\": [[0],[1],[2],[3]]}", TC_REQ_MESH, &r, &d) == TC_REQ_OK);
    if (r) CHECK(r->values_plain == 0 && r->desc.nchan == 1 && r->desc.values[3] == 3);
    tc_request_free(r);
    tc_diags_free(&d);
}

TEST(request_sparse_gradients_with_null) {
    tc_request *r = NULL;
    tc_diags d;
    CHECK(parse_str("{" MESH1 ", \"gradients\": [[1,2], null, [3,4], [[5,6]]]}", TC_REQ_MESH, &r,
                    &d) == TC_REQ_OK);
    if (!r) return;
    const tc_mesh_desc *m = &r->desc;
    CHECK(m->gradients != NULL && m->gradients_mask != NULL);
    if (m->gradients_mask) {
        CHECK(m->gradients_mask[0] == 1 && m->gradients_mask[1] == 0 && m->gradients_mask[2] == 1 &&
              m->gradients_mask[3] == 1);
    }
    static const double g[] = {1, 2, 0, 0, 3, 4, 5, 6};
    for (int i = 0; i < 8; i++) CHECK(m->gradients[i] == g[i]);
    tc_request_free(r);
    tc_diags_free(&d);
}

TEST(request_normals_per_channel_with_null) {
    tc_request *r = NULL;
    tc_diags d;
    const char *json = "{" MESH3 ", \"normals\": [null, [[0,0,1],[0,0.6,0.8],[1,2,3]],"
                       " [[0,0,1],[0,0,1],[0,0,1]], null]}";
    CHECK(parse_str(json, TC_REQ_MESH, &r, &d) == TC_REQ_OK);
    if (!r) return;
    const tc_mesh_desc *m = &r->desc;
    CHECK(m->gradients == NULL && m->normals != NULL && m->normals_mask != NULL);
    if (m->normals_mask) {
        CHECK(m->normals_mask[0] == 0 && m->normals_mask[1] == 1 && m->normals_mask[2] == 1 &&
              m->normals_mask[3] == 0);
    }
    /* vertex 1, channel 1 = [0, 0.6, 0.8]; vertex 1 channel 2 = [1, 2, 3] */
    CHECK(m->normals[9 + 3] == 0 && m->normals[9 + 4] == 0.6 && m->normals[9 + 5] == 0.8);
    CHECK(m->normals[9 + 8] == 3);
    tc_request_free(r);
    tc_diags_free(&d);
}

TEST(request_parts_not_expected_are_still_parsed) {
    tc_request *r = NULL;
    tc_diags d;
    /* a mesh file that also carries points, read as a mesh */
    CHECK(parse_str("{" MESH1 ", \"points\": [[0.5,0.5]]}", TC_REQ_MESH, &r, &d) == TC_REQ_OK);
    if (r) CHECK(r->npoints == 1 && r->points[0] == 0.5 && r->has_mesh == 1);
    tc_request_free(r);
    tc_diags_free(&d);
    /* points only, no mesh: fine when only points are expected */
    r = NULL;
    CHECK(parse_str("{\"points\": [[1,2]]}", TC_REQ_POINTS, &r, &d) == TC_REQ_OK);
    if (r) CHECK(r->has_mesh == 0 && r->desc.nverts == 0 && r->npoints == 1 && r->points[1] == 2);
    tc_request_free(r);
    tc_diags_free(&d);
    /* empty points are allowed */
    r = NULL;
    CHECK(parse_str("{" MESH1 ", \"points\": []}", TC_REQ_MESH | TC_REQ_POINTS, &r, &d) == TC_REQ_OK);
    if (r) CHECK(r->npoints == 0 && r->points == NULL);
    tc_request_free(r);
    tc_diags_free(&d);
}

TEST(request_index_range_left_to_core) {
    /* negative and too-large indices are the core's to report (it names them too) */
    tc_request *r = NULL;
    tc_diags d;
    CHECK(parse_str("{\"vertices\": [[0,0],[1,0],[1,1]], \"triangles\": [[-1,1,7]],"
                    " \"values\": [1,2,3], \"discontinuities\": {\"c0\": [[0,9]]}}",
                    TC_REQ_MESH, &r, &d) == TC_REQ_OK);
    if (r) CHECK(r->desc.tris[0] == -1 && r->desc.tris[2] == 7 && r->desc.c0.verts[1] == 9);
    tc_request_free(r);
    tc_diags_free(&d);
}

TEST(request_integral_numbers_are_indices) {
    tc_request *r = NULL;
    tc_diags d;
    CHECK(parse_str("{" SQUARE ", \"values\": [0,1,2,3], \"midpoints\": [{\"edge\": [0, 2.0e0],"
                    " \"value\": 1}]}", TC_REQ_MESH, &r, &d) == TC_REQ_OK);
    if (r) CHECK(r->desc.midpoint_edge[1] == 2);
    tc_request_free(r);
    tc_diags_free(&d);
}

TEST(request_not_nul_terminated) {
    /* the reader must stay within len: parse an exact-size copy, then a prefix of a
     * longer string whose tail would be invalid */
    const char *json = "{" MESH1 "}";
    size_t n = strlen(json);
    char *buf = malloc(n);
    CHECK(buf != NULL);
    if (!buf) return;
    memcpy(buf, json, n);
    tc_request *r = NULL;
    tc_diags d;
    tc_diags_init(&d);
    CHECK(tc_request_parse(buf, n, TC_REQ_MESH, &r, &d) == TC_REQ_OK);
    tc_request_free(r);
    free(buf);
    r = NULL;
    const char *longer = "{\"points\": [[1,2]]} garbage";
    CHECK(tc_request_parse(longer, 19, TC_REQ_POINTS, &r, &d) == TC_REQ_OK);
    tc_request_free(r);
    tc_diags_free(&d);
}

TEST(request_trailing_whitespace_ok) {
    tc_request *r = NULL;
    tc_diags d;
    CHECK(parse_str("\n  {" MESH1 "}\r\n\t ", TC_REQ_MESH, &r, &d) == TC_REQ_OK);
    tc_request_free(r);
    tc_diags_free(&d);
}

TEST(request_null_diags_and_free_null) {
    tc_request *r = NULL;
    const char *ok = "{" MESH1 "}";
    CHECK(tc_request_parse(ok, strlen(ok), TC_REQ_MESH, &r, NULL) == TC_REQ_OK);
    tc_request_free(r);
    r = (tc_request *)1;
    const char *bad = "{\"vertices\": 1}";
    CHECK(tc_request_parse(bad, strlen(bad), TC_REQ_MESH, &r, NULL) == TC_REQ_MALFORMED);
    CHECK(r == NULL);
    tc_request_free(NULL); /* a no-op */
}

/* ---- unknown fields ------------------------------------------------------------ */

TEST(request_unknown_field_warns) {
    tc_request *r = NULL;
    tc_diags d;
    CHECK(parse_str("{" MESH1 ", \"colour\": \"red\"}", TC_REQ_MESH, &r, &d) == TC_REQ_OK);
    CHECK(r != NULL);
    CHECK(d.count == 1 && d.warnings == 1 && d.errors == 0);
    if (d.count == 1) {
        CHECK(d.items[0].severity == TC_SEV_WARNING);
        CHECK(strcmp(d.items[0].path, "colour") == 0);
        CHECK_STR_CONTAINS(d.items[0].message, "unknown field 'colour' ignored");
    }
    tc_request_free(r);
    tc_diags_free(&d);
}

TEST(request_misspelt_field_warns_with_suggestion) {
    tc_request *r = NULL;
    tc_diags d;
    int st = parse_str("{\"vertices\": [[0,0],[1,0],[1,1]], \"trianlges\": [[0,1,2]],"
                       " \"values\": [1,2,3]}", TC_REQ_MESH, &r, &d);
    CHECK(st == TC_REQ_MALFORMED); /* triangles then is missing */
    CHECK(r == NULL);
    int w = find_diag(&d, "trianlges");
    CHECK(w >= 0);
    if (w >= 0) {
        CHECK(d.items[w].severity == TC_SEV_WARNING);
        CHECK_STR_CONTAINS(d.items[w].message, "unknown field 'trianlges' ignored");
        CHECK_STR_CONTAINS(d.items[w].message, "did you mean 'triangles'");
    }
    int e = find_diag(&d, "triangles");
    CHECK(e >= 0);
    if (e >= 0) CHECK_STR_CONTAINS(d.items[e].message, "missing required field 'triangles'");
    tc_request_free(r);
    tc_diags_free(&d);
}

/* "quads" is the mesh's other form (test_quads.c reads it): never both. */
TEST(request_quads_and_triangles_are_exclusive) {
    INVALID("{" MESH1 ", \"quads\": []}", "quads", "give either triangles or quads, not both");
}

/* The render fields: parsed when valid, each bad one reported at its path. */
TEST(request_render_fields) {
    tc_request *r = NULL;
    tc_diags d;
    CHECK(parse_str("{" MESH1 ", \"viewport\": {\"x0\": -1, \"y0\": 0, \"x1\": 2.5, \"y1\": 1, \"width\": 64,"
                    " \"height\": 32}, \"format\": \"exr-half\", \"exposure\": -1.5, \"overlay\": true,"
                    " \"linear\": true, \"background\": 0.25}",
                    TC_REQ_MESH | TC_REQ_VIEWPORT, &r, &d) == TC_REQ_OK);
    CHECK(d.count == 0);
    if (r) {
        CHECK(r->has_viewport && r->viewport.x0 == -1 && r->viewport.x1 == 2.5 && r->viewport.width == 64 &&
              r->viewport.height == 32);
        CHECK(r->format == TC_IMG_EXR_HALF && r->exposure == -1.5 && r->overlay && r->linear);
        CHECK(r->has_background && r->background[0] == 0.25);
    }
    tc_request_free(r);
    tc_diags_free(&d);
    static const struct { const char *json, *path, *msg; int status; } bad[] = {
        {"\"viewport\": {}", "viewport.x0", "missing required field 'x0'", TC_REQ_MALFORMED},
        {"\"viewport\": [0, 0, 1, 1, 8, 8]", "viewport", "expected an object", TC_REQ_MALFORMED},
        {"\"viewport\": {\"x0\": 1, \"y0\": 0, \"x1\": 1, \"y1\": 1, \"width\": 8, \"height\": 8}", "viewport.x1",
         "must be greater than x0", TC_REQ_INVALID},
        {"\"viewport\": {\"x0\": 0, \"y0\": 0, \"x1\": 1, \"y1\": 1, \"width\": 0, \"height\": 8}",
         "viewport.width", "must be 1 to", TC_REQ_INVALID},
        {"\"viewport\": {\"x0\": 0, \"y0\": 0, \"x1\": 1, \"y1\": 1, \"width\": 8.5, \"height\": 8}",
         "viewport.width", "must be an integer", TC_REQ_MALFORMED},
        {"\"format\": \"jpeg\"", "format", "unknown format 'jpeg'", TC_REQ_INVALID},
        {"\"format\": 3", "format", "expected a string", TC_REQ_MALFORMED},
        {"\"exposure\": 100", "exposure", "out of range", TC_REQ_INVALID},
        {"\"overlay\": 1", "overlay", "expected true or false", TC_REQ_MALFORMED},
        {"\"background\": [1, 2]", "background", "expected an array of 1 numbers", TC_REQ_MALFORMED},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char json[512];
        snprintf(json, sizeof json, "{" MESH1 ", %s}", bad[i].json);
        r = NULL;
        int st = parse_str(json, TC_REQ_MESH, &r, &d);
        CHECK_MSG(st == bad[i].status && !r, "%s: status %d", bad[i].json, st);
        CHECK_MSG(d.count >= 1 && !strcmp(d.items[0].path, bad[i].path), "%s: path '%s', want '%s'", bad[i].json,
                  d.count ? d.items[0].path : "", bad[i].path);
        if (d.count) CHECK_STR_CONTAINS(d.items[0].message, bad[i].msg);
        tc_request_free(r);
        tc_diags_free(&d);
    }
    /* The viewport is required only when the caller expects it. */
    CHECK(parse_str("{" MESH1 "}", TC_REQ_MESH | TC_REQ_VIEWPORT, &r, &d) == TC_REQ_MALFORMED);
    CHECK(d.count >= 1 && !strcmp(d.items[0].path, "viewport"));
    tc_request_free(r);
    tc_diags_free(&d);
}

TEST(request_unknown_discontinuity_key_warns) {
    tc_request *r = NULL;
    tc_diags d;
    CHECK(parse_str("{" MESH1 ", \"discontinuities\": {\"c1\": [[0,2]], \"c-1\": [[0,2]]}}",
                    TC_REQ_MESH, &r, &d) == TC_REQ_OK);
    CHECK(d.count == 1 && d.warnings == 1);
    if (d.count == 1) {
        CHECK(strcmp(d.items[0].path, "discontinuities.c1") == 0);
        CHECK_STR_CONTAINS(d.items[0].message, "unknown field 'c1' ignored");
    }
    if (r) CHECK(r->desc.c0.count == 0 && r->desc.cm1.count == 1);
    tc_request_free(r);
    tc_diags_free(&d);
}

TEST(request_duplicate_field_malformed) {
    MALFORMED("{" MESH1 ", \"method\": \"linear\", \"method\": \"constant\"}", "method",
              "given more than once");
}

TEST(request_field_names_are_case_sensitive) {
    /* cJSON's own lookup ignores case; the reader must not */
    tc_request *r = NULL;
    tc_diags d;
    CHECK(parse_str("{" MESH1 ", \"Method\": \"linear\"}", TC_REQ_MESH, &r, &d) == TC_REQ_OK);
    if (r) CHECK(r->opt.method == TC_METHOD_CLOUGH_TOCHER);
    CHECK(d.warnings == 1 && find_diag(&d, "Method") == 0);
    tc_request_free(r);
    tc_diags_free(&d);
}

/* ---- JSON syntax ------------------------------------------------------------------ */

TEST(request_syntax_error_line_column) {
    /* the stray 'x' is on line 3, column 8 */
    CHECK_ERROR("{\"vertices\": [[0,0],\n"
                "  [1,0],\n"
                "  [1,1]x],\n"
                " \"triangles\": [[0,1,2]], \"values\": [1,2,3]}",
                TC_REQ_MESH, TC_REQ_MALFORMED, "", "line 3, column 8");
    CHECK_ERROR("{\"a\": tru}", TC_REQ_MESH, TC_REQ_MALFORMED, "", "line 1, column 7");
    CHECK_ERROR("{\"a\": tru}", TC_REQ_MESH, TC_REQ_MALFORMED, "", "not valid JSON");
}

TEST(request_syntax_nan_literal_malformed) {
    MALFORMED("{" SQUARE ", \"values\": [0, NaN, 2, 3]}", "", "not valid JSON");
}

TEST(request_syntax_trailing_text_malformed) {
    MALFORMED("{" MESH1 "} {}", "", "unexpected text after the JSON value");
    MALFORMED("{" MESH1 "}\n x", "", "line 2, column 2");
}

TEST(request_syntax_empty_and_truncated) {
    MALFORMED("", "", "empty request");
    MALFORMED("{\"vertices\": [[0,0]", "", "not valid JSON");
}

TEST(request_root_not_object_malformed) {
    MALFORMED("[1, 2]", "", "expected a JSON object");
}

/* ---- required parts --------------------------------------------------------------- */

TEST(request_missing_required_mesh_parts) {
    MALFORMED("{" SQUARE "}", "values", "missing required field 'values'");
    MALFORMED("{\"triangles\": [[0,1,2]], \"values\": [1,2,3]}", "vertices",
              "missing required field 'vertices'");
    /* mesh data without a mesh makes the mesh required even when not expected */
    CHECK_ERROR("{\"points\": [[0,0]], \"gradients\": [[1,2]]}", TC_REQ_POINTS, TC_REQ_MALFORMED,
                "vertices", "missing required field 'vertices'");
}

TEST(request_missing_points_malformed) {
    CHECK_ERROR("{" MESH1 "}", TC_REQ_MESH | TC_REQ_POINTS, TC_REQ_MALFORMED, "points",
                "missing required field 'points'");
}

/* ---- shapes: MALFORMED ----------------------------------------------------------- */

TEST(request_vertices_shape) {
    MALFORMED("{\"vertices\": {}, \"triangles\": [], \"values\": []}", "vertices",
              "expected an array of points");
    MALFORMED("{\"vertices\": [[0,0],[1,0],[1,1],[0,1,5]], \"triangles\": [[0,1,2]],"
              " \"values\": [0,1,2,3]}", "vertices[3]", "expected an array of 2 numbers [x, y]");
    MALFORMED("{\"vertices\": [[0,0],[1,0],[1,1],[0,\"1\"]], \"triangles\": [[0,1,2]],"
              " \"values\": [0,1,2,3]}", "vertices[3][1]", "expected a number, got a string");
    MALFORMED("{\"vertices\": [[0,0],[1,0],[1,1],7], \"triangles\": [[0,1,2]],"
              " \"values\": [0,1,2,3]}", "vertices[3]", "expected an array of 2 numbers");
}

TEST(request_triangles_shape) {
    MALFORMED("{\"vertices\": [[0,0],[1,0],[1,1]], \"triangles\": [[0,1,2],[0,1]],"
              " \"values\": [1,2,3]}", "triangles[1]", "expected an array of 3 vertex indices");
    MALFORMED("{\"vertices\": [[0,0],[1,0],[1,1]], \"triangles\": [0,1,2],"
              " \"values\": [1,2,3]}", "triangles[0]", "expected an array of 3");
}

TEST(request_fractional_index_malformed) {
    MALFORMED("{\"vertices\": [[0,0],[1,0],[1,1]], \"triangles\": [[0,1,1.5]],"
              " \"values\": [1,2,3]}", "triangles[0][2]", "must be an integer");
    MALFORMED("{\"vertices\": [[0,0],[1,0],[1,1]], \"triangles\": [[0,1,2147483648]],"
              " \"values\": [1,2,3]}", "triangles[0][2]", "must be an integer");
    MALFORMED("{\"vertices\": [[0,0],[1,0],[1,1]], \"triangles\": [[0,true,2]],"
              " \"values\": [1,2,3]}", "triangles[0][1]", "expected a number");
}

TEST(request_values_shape) {
    MALFORMED("{" SQUARE ", \"values\": [0, 1, \"2\", 3]}", "values[2]", "expected a number");
    MALFORMED("{" SQUARE ", \"values\": [{}, 1, 2, 3]}", "values[0]", "expected a number or an array");
    MALFORMED("{" SQUARE ", \"values\": [[0,1],[1,1],[2,null],[3,1]]}", "values[2][1]",
              "expected a number, got null");
    MALFORMED("{" SQUARE ", \"values\": 3}", "values", "expected an array");
}

TEST(request_corner_values_shape) {
    MALFORMED("{" MESH1 ", \"corner_values\": [[1, 2, 3]]}", "corner_values[0]", "expected an object");
    MALFORMED("{" MESH1 ", \"corner_values\": [{\"triangle\": 0, \"values\": [1, 2]}]}",
              "corner_values[0].values", "expected an array of 3 corner values");
    MALFORMED("{" MESH1 ", \"corner_values\": [{\"triangle\": 0, \"values\": [1,2,3]},"
              " {\"values\": [1, 2, 3]}]}", "corner_values[1].triangle",
              "missing required field 'triangle'");
    MALFORMED("{" MESH1 ", \"corner_values\": [{\"triangle\": 0.5, \"values\": [1,2,3]}]}",
              "corner_values[0].triangle", "must be an integer");
}

TEST(request_gradients_shape) {
    MALFORMED("{" MESH1 ", \"gradients\": [[1,2], [1], [3,4], [5,6]]}", "gradients[1]",
              "expected an array of 2 numbers [gx, gy]");
    MALFORMED("{" MESH1 ", \"gradients\": [[1,2], \"x\", [3,4], [5,6]]}", "gradients[1]",
              "expected [gx, gy]");
    MALFORMED("{" MESH3 ", \"gradients\": [null, null, [[1,2],[3,4],[5]], null]}", "gradients[2][2]",
              "expected an array of 2 numbers [gx, gy]");
}

TEST(request_normals_shape) {
    MALFORMED("{" MESH1 ", \"normals\": [[0,0,1], [0,1], null, null]}", "normals[1]",
              "expected an array of 3 numbers [nx, ny, nz]");
}

TEST(request_corner_gradients_shape) {
    MALFORMED("{" MESH1 ", \"corner_gradients\": [{\"triangle\": 1, \"gradients\": [[1,2], [1,2,3],"
              " null]}]}", "corner_gradients[0].gradients[1]", "expected an array of 2 numbers");
    MALFORMED("{" MESH1 ", \"corner_gradients\": [{\"triangle\": 1, \"gradients\": [[1,2]]}]}",
              "corner_gradients[0].gradients", "expected an array of 3 corner gradients");
}

TEST(request_midpoints_shape) {
    MALFORMED("{" MESH1 ", \"midpoints\": [{\"edge\": [0, 2], \"value\": 1},"
              " {\"edge\": [0], \"value\": 1}]}", "midpoints[1].edge",
              "expected an array of 2 vertex indices");
    MALFORMED("{" MESH1 ", \"midpoints\": [{\"edge\": [0, 2]}]}", "midpoints[0].value",
              "missing required field 'value'");
    MALFORMED("{" MESH1 ", \"midpoints\": [{\"edge\": [0, 2], \"value\": 1, \"triangle\": \"0\"}]}",
              "midpoints[0].triangle", "expected a number");
}

TEST(request_discontinuities_shape) {
    MALFORMED("{" MESH1 ", \"discontinuities\": {\"c0\": [[0]]}}", "discontinuities.c0[0]",
              "at least 2 vertices");
    MALFORMED("{" MESH1 ", \"discontinuities\": {\"c-1\": [[0, 2, 3.25]]}}",
              "discontinuities.c-1[0][2]", "must be an integer");
    MALFORMED("{" MESH1 ", \"discontinuities\": {\"c0\": [[0, 2], 5]}}", "discontinuities.c0[1]",
              "expected a polyline");
    MALFORMED("{" MESH1 ", \"discontinuities\": [[0, 2]]}", "discontinuities", "expected an object");
}

TEST(request_option_types_malformed) {
    MALFORMED("{" MESH1 ", \"method\": 3}", "method", "expected a string");
    MALFORMED("{" MESH1 ", \"tangents\": null}", "tangents", "expected a string");
    MALFORMED("{" MESH1 ", \"with_gradients\": \"yes\"}", "with_gradients", "expected true or false");
}

TEST(request_points_shape) {
    CHECK_ERROR("{\"points\": [[0,0],[1]]}", TC_REQ_POINTS, TC_REQ_MALFORMED, "points[1]",
                "expected an array of 2 numbers [x, y]");
}

/* ---- values: INVALID ---------------------------------------------------------------- */

TEST(request_values_channel_mismatch_invalid) {
    INVALID("{" SQUARE ", \"values\": [[0,1,2],[1,2,3],[2,3],[3,4,5]]}", "values[2]",
            "2 channels, expected 3 (as values[0])");
    INVALID("{" SQUARE ", \"values\": [0, 1, [2, 3], 3]}", "values[2]",
            "2 channels, expected 1 (as values[0])");
    INVALID("{" SQUARE ", \"values\": [[0,1],[1,1],5,[3,1]]}", "values[2]",
            "1 channel, expected 2 (as values[0])");
}

TEST(request_values_channel_count_range_invalid) {
    INVALID("{" SQUARE ", \"values\": [[], [], [], []]}", "values[0]", "0 channels, expected 1 to 16");
    INVALID("{\"vertices\": [[0,0],[1,0],[1,1]], \"triangles\": [[0,1,2]], \"values\":"
            " [[1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17],"
            "[1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17],[1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17]]}",
            "values[0]", "17 channels, expected 1 to 16");
}

TEST(request_values_count_invalid) {
    INVALID("{" SQUARE ", \"values\": [0, 1, 2]}", "values",
            "values has 3 entries, expected 4 (one per vertex)");
    INVALID("{" SQUARE ", \"values\": [0, 1, 2, 3, 4]}", "values",
            "values has 5 entries, expected 4 (one per vertex)");
}

TEST(request_sixteen_channels_ok) {
    tc_request *r = NULL;
    tc_diags d;
    CHECK(parse_str("{\"vertices\": [[0,0],[1,0],[1,1]], \"triangles\": [[0,1,2]], \"values\":"
                    " [[1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16],"
                    "[1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16],[1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16]]}",
                    TC_REQ_MESH, &r, &d) == TC_REQ_OK);
    if (r) CHECK(r->desc.nchan == 16 && r->desc.values[16 * 2 + 15] == 16);
    tc_request_free(r);
    tc_diags_free(&d);
}

TEST(request_corner_values_channels_invalid) {
    INVALID("{" MESH3 ", \"corner_values\": [{\"triangle\": 0, \"values\": [[1,2,3],[1,2],[1,2,3]]}]}",
            "corner_values[0].values[1]", "2 channels, expected 3 (as values[0])");
    INVALID("{" MESH3 ", \"corner_values\": [{\"triangle\": 0, \"values\": [1, 2, 3]}]}",
            "corner_values[0].values[0]", "1 channel, expected 3 (as values[0])");
}

TEST(request_gradients_channels_and_count_invalid) {
    INVALID("{" MESH3 ", \"gradients\": [[1,2], null, null, null]}", "gradients[0]",
            "is 1 channel, expected 3 (as values[0])");
    INVALID("{" MESH3 ", \"gradients\": [null, null, [[1,2],[3,4]], null]}", "gradients[2]",
            "2 channels, expected 3 (as values[0])");
    INVALID("{" MESH1 ", \"gradients\": [[1,2], [3,4], [5,6]]}", "gradients",
            "gradients has 3 entries, expected 4 (one per vertex)");
    INVALID("{" MESH1 ", \"normals\": [[0,0,1]]}", "normals",
            "normals has 1 entries, expected 4 (one per vertex)");
    INVALID("{" MESH3 ", \"corner_gradients\": [{\"triangle\": 0, \"gradients\": [null,"
            " [[1,2],[3,4],[5,6],[7,8]], null]}]}", "corner_gradients[0].gradients[1]",
            "4 channels, expected 3 (as values[0])");
}

TEST(request_gradients_and_normals_invalid) {
    INVALID("{" MESH1 ", \"gradients\": [[1,2],[1,2],[1,2],[1,2]],"
            " \"normals\": [[0,0,1],[0,0,1],[0,0,1],[0,0,1]]}", "normals",
            "give either gradients or normals");
}

TEST(request_midpoint_channels_invalid) {
    INVALID("{" MESH3 ", \"midpoints\": [{\"edge\": [0, 2], \"value\": [1, 2]}]}",
            "midpoints[0].value", "2 channels, expected 3 (as values[0])");
}

TEST(request_unknown_names_invalid) {
    INVALID("{" MESH1 ", \"method\": \"bicubic\"}", "method",
            "unknown method 'bicubic'; expected one of: clough-tocher, clough-tocher-c1, linear");
    INVALID("{" MESH1 ", \"cross_boundary\": \"Normal\"}", "cross_boundary",
            "expected one of: normal, salesin, affine");
    INVALID("{" MESH1 ", \"wedges\": \"fixed\"}", "wedges", "expected one of: corrected, literal");
    INVALID("{" MESH1 ", \"tangents\": \"none\"}", "tangents",
            "expected one of: auto, given, midpoints, estimate");
}

TEST(request_non_finite_invalid) {
    INVALID("{\"vertices\": [[0,0],[1e999,0],[1,1]], \"triangles\": [[0,1,2]], \"values\": [1,2,3]}",
            "vertices[1][0]", "number is not finite");
    INVALID("{" SQUARE ", \"values\": [[0,1],[1,1],[2,-1e999],[3,1]]}", "values[2][1]",
            "number is not finite");
    INVALID("{" MESH1 ", \"gradients\": [null, [0, 1e400], null, null]}", "gradients[1][1]",
            "number is not finite");
    CHECK_ERROR("{\"points\": [[0,0],[1e999,1]]}", TC_REQ_POINTS, TC_REQ_INVALID, "points[1][0]",
                "number is not finite");
}

/* ---- several findings ------------------------------------------------------------- */

TEST(request_collects_many_findings) {
    tc_request *r = NULL;
    tc_diags d;
    int st = parse_str("{\"vertices\": [[0,0],[1,\"x\"],[1,1]], \"triangles\": [[0,1,2.5]],"
                       " \"values\": [1, 1e999, 3], \"method\": \"nope\"}", TC_REQ_MESH, &r, &d);
    CHECK(st == TC_REQ_MALFORMED); /* malformed wins over invalid */
    CHECK(r == NULL);
    CHECK(d.errors == 4);
    CHECK(find_diag(&d, "vertices[1][1]") >= 0);
    CHECK(find_diag(&d, "triangles[0][2]") >= 0);
    CHECK(find_diag(&d, "values[1]") >= 0);
    CHECK(find_diag(&d, "method") >= 0);
    tc_request_free(r);
    tc_diags_free(&d);
}

TEST(request_invalid_only_is_invalid) {
    tc_request *r = NULL;
    tc_diags d;
    int st = parse_str("{" SQUARE ", \"values\": [1, 1e999, 3, 4], \"method\": \"nope\"}",
                       TC_REQ_MESH, &r, &d);
    CHECK(st == TC_REQ_INVALID && d.errors == 2);
    tc_request_free(r);
    tc_diags_free(&d);
}

TEST(request_many_errors_are_capped) {
    /* 1000 bad vertices: every one counted, only TC_DIAGS_KEEP kept */
    size_t cap = 16 * 1000 + 256;
    char *json = malloc(cap);
    CHECK(json != NULL);
    if (!json) return;
    size_t n = (size_t)snprintf(json, cap, "{\"vertices\": [");
    for (int i = 0; i < 1000; i++) n += (size_t)snprintf(json + n, cap - n, "%s[%d]", i ? "," : "", i);
    n += (size_t)snprintf(json + n, cap - n, "], \"triangles\": [], \"values\": []}");
    tc_request *r = NULL;
    tc_diags d;
    tc_diags_init(&d);
    CHECK(tc_request_parse(json, n, TC_REQ_MESH, &r, &d) == TC_REQ_MALFORMED);
    CHECK(d.count == TC_DIAGS_KEEP);
    CHECK(d.errors >= 1000);
    if (d.count > 5) CHECK(strcmp(d.items[5].path, "vertices[5]") == 0);
    free(json);
    tc_diags_free(&d);
}

/* ---- scale and memory ------------------------------------------------------------- */

/* A g x g grid of vertices as a request (2 triangles per cell), in a new string. */
static char *grid_request(int g, size_t *len) {
    size_t cap = (size_t)g * (size_t)g * 120 + 256, n = 0;
    char *s = malloc(cap);
    if (!s) return NULL;
    n += (size_t)snprintf(s + n, cap - n, "{\"vertices\": [");
    for (int j = 0; j < g; j++)
        for (int i = 0; i < g; i++)
            n += (size_t)snprintf(s + n, cap - n, "%s[%d,%d]", i + j ? "," : "", i, j);
    n += (size_t)snprintf(s + n, cap - n, "], \"triangles\": [");
    for (int j = 0; j + 1 < g; j++)
        for (int i = 0; i + 1 < g; i++) {
            int v = j * g + i;
            n += (size_t)snprintf(s + n, cap - n, "%s[%d,%d,%d],[%d,%d,%d]", i + j ? "," : "", v,
                                  v + 1, v + g + 1, v, v + g + 1, v + g);
        }
    n += (size_t)snprintf(s + n, cap - n, "], \"values\": [");
    for (int k = 0; k < g * g; k++) n += (size_t)snprintf(s + n, cap - n, "%s%d.5", k ? "," : "", k);
    n += (size_t)snprintf(s + n, cap - n, "]}");
    *len = n;
    return s;
}

TEST(request_grid_mesh) {
    size_t len;
    char *json = grid_request(120, &len);
    CHECK(json != NULL);
    if (!json) return;
    tc_request *r = NULL;
    tc_diags d;
    tc_diags_init(&d);
    CHECK(tc_request_parse(json, len, TC_REQ_MESH, &r, &d) == TC_REQ_OK);
    if (r) {
        const tc_mesh_desc *m = &r->desc;
        CHECK(m->nverts == 120 * 120 && m->ntris == 2 * 119 * 119 && m->nchan == 1);
        CHECK(m->xy[2 * 121] == 1 && m->xy[2 * 121 + 1] == 1);
        int t = 2 * 119 * 119 - 1; /* last triangle: cell (118, 118), second half */
        int v = 118 * 120 + 118;
        CHECK(m->tris[3 * t] == v && m->tris[3 * t + 1] == v + 121 && m->tris[3 * t + 2] == v + 120);
        CHECK(m->values[14399] == 14399.5);
    }
    tc_request_free(r);
    tc_diags_free(&d);
    free(json);
}

TEST(request_out_of_memory_paths) {
    /* fail each allocation of a full request in turn: NOMEM, nothing leaks (ASan) */
    int nomem = 0, ok = 0;
    for (long k = 1; k <= 40; k++) {
        tc_request *r = (tc_request *)1;
        tc_diags d;
        tc_diags_init(&d);
        tc_request__fail_alloc_after(k);
        int st = tc_request_parse(full_request, strlen(full_request), TC_REQ_MESH, &r, &d);
        tc_request__fail_alloc_after(0);
        if (st == TC_REQ_NOMEM) {
            CHECK(ok == 0); /* every allocation up to the last one can fail */
            nomem++;
            CHECK(r == NULL);
            CHECK(d.errors >= 1);
        } else {
            CHECK(st == TC_REQ_OK);
            ok++;
        }
        tc_request_free(r == (tc_request *)1 ? NULL : r);
        tc_diags_free(&d);
    }
    CHECK(nomem >= 15); /* the request itself and its arrays (19 today) */
    CHECK(ok >= 1);
}
