/* test_compare.c — /v1/compare through the JSON API: each method's error against
 * reference samples, per-method failures reported in place, bad requests refused. */
#include <cJSON.h>
#include <math.h>
#include <string.h>

#include "check.h"
#include "io/api.h"

/* A 2x2-cell grid with z = 2 + x - 3y and a reference of that same plane,
 * offset by +0.5 at one point (so every method's max error is exactly 0.5
 * there, except constant, which does not reproduce planes). */
#define GRID                                                                                          \
    "\"vertices\": [[0,0],[0.5,0],[1,0],[0,0.5],[0.5,0.5],[1,0.5],[0,1],[0.5,1],[1,1]],"                \
    "\"triangles\": [[0,1,4],[0,4,3],[1,2,5],[1,5,4],[3,4,7],[3,7,6],[4,5,8],[4,8,7]],"                 \
    "\"values\": [2,2.5,3,0.5,1,1.5,-1,-0.5,0],"                                                      \
    "\"gradients\": [[1,-3],[1,-3],[1,-3],[1,-3],[1,-3],[1,-3],[1,-3],[1,-3],[1,-3]],"                 \
    "\"reference\": {\"points\": [[0.25,0.25],[0.6,0.3],[0.9,0.8],[2,2]], \"values\": [2.0,1.7,0.5,9]}"

static cJSON *run(const char *body, int want_status, tc_api_result *res) {
    tc_strbuf out;
    tc_strbuf_init(&out);
    tc_api_result_init(res);
    int st = tc_api_compare(body, strlen(body), NULL, &out, res);
    CHECK_MSG(st == want_status, "status %d, want %d (%s)", st, want_status,
              res->diags.count ? res->diags.items[0].message : "");
    cJSON *doc = st == 200 ? cJSON_Parse(out.buf) : NULL;
    if (st == 200) CHECK(doc != NULL);
    tc_strbuf_free(&out);
    return doc;
}

TEST(compare_errors_per_method) {
    tc_api_result res;
    cJSON *doc = run("{" GRID ", \"methods\": [\"linear\", \"clough-tocher\", {\"method\": \"clough-tocher\","
                     " \"cross_boundary\": \"affine\", \"tangents\": \"given\"}, \"constant\"]}",
                     200, &res);
    const cJSON *results = cJSON_GetObjectItemCaseSensitive(doc, "results");
    CHECK(cJSON_GetArraySize(results) == 4);
    for (int i = 0; doc && i < 3; i++) { /* the planar methods: only the offset point errs */
        const cJSON *e = cJSON_GetArrayItem(results, i);
        CHECK_NEAR(cJSON_GetObjectItemCaseSensitive(e, "max_abs")->valuedouble, 0.5, 1e-12);
        CHECK_NEAR(cJSON_GetObjectItemCaseSensitive(e, "rms")->valuedouble, sqrt(0.25 / 3), 1e-12);
        CHECK_NEAR(cJSON_GetObjectItemCaseSensitive(e, "mean_rel")->valuedouble, 0.5 / 3 / 9, 1e-12); /* full scale: max |ref| */
        CHECK(cJSON_GetObjectItemCaseSensitive(e, "compared")->valueint == 3);
        CHECK(cJSON_GetObjectItemCaseSensitive(e, "outside")->valueint == 1);
        CHECK(cJSON_GetObjectItemCaseSensitive(e, "build_ms")->valuedouble >= 0);
    }
    const cJSON *c = cJSON_GetArrayItem(results, 3);
    CHECK(c && cJSON_GetObjectItemCaseSensitive(c, "max_abs")->valuedouble > 0.6);
    const cJSON *a = cJSON_GetArrayItem(results, 2);
    CHECK(a && !strcmp(cJSON_GetObjectItemCaseSensitive(a, "cross_boundary")->valuestring, "affine"));
    cJSON_Delete(doc);
    tc_api_result_free(&res);
}

/* Without "methods", every method runs; one that cannot run on this mesh
 * (tangents "midpoints" and no midpoint samples) carries an error in its entry. */
TEST(compare_default_methods_and_failures_in_place) {
    tc_api_result res;
    cJSON *doc = run("{" GRID "}", 200, &res);
    CHECK(cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(doc, "results")) == 7); /* every method */
    cJSON_Delete(doc);
    tc_api_result_free(&res);
    doc = run("{" GRID ", \"methods\": [{\"method\": \"clough-tocher\", \"tangents\": \"midpoints\"}, \"linear\"]}", 200,
              &res);
    const cJSON *r0 = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(doc, "results"), 0);
    const cJSON *err = cJSON_GetObjectItemCaseSensitive(r0, "error");
    CHECK(err && strstr(cJSON_GetObjectItemCaseSensitive(err, "message")->valuestring, "no midpoint sample"));
    CHECK(!cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(doc, "results"), 1),
                                            "error"));
    cJSON_Delete(doc);
    tc_api_result_free(&res);
}

TEST(compare_bad_requests) {
    static const struct { const char *body, *path; int status; } bad[] = {
        {"{" GRID ", \"methods\": [\"cubic\"]}", "methods[0]", 422},
        {"{" GRID ", \"methods\": \"linear\"}", "methods", 400},
        {"{\"vertices\": [[0,0],[1,0],[0,1]], \"triangles\": [[0,1,2]], \"values\": [1,2,3]}", "reference", 400},
        {"{\"vertices\": [[0,0],[1,0],[0,1]], \"triangles\": [[0,1,2]], \"values\": [1,2,3],"
         " \"reference\": {\"points\": [[0.1,0.1]], \"values\": [1, 2]}}", "reference.values", 422},
        {"{\"vertices\": [[0,0],[1,0],[0,1]], \"triangles\": [[0,1,2]], \"values\": [1,2,3],"
         " \"reference\": {\"points\": [[0.1,0.1]], \"values\": [1], \"scale\": 0}}", "reference.scale", 422},
        {"{\"vertices\": [[0,0],[1,0],[2,0]], \"triangles\": [[0,1,2]], \"values\": [1,2,3],"
         " \"reference\": {\"points\": [[0.1,0.1]], \"values\": [1]}}", "triangles[0]", 422},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        tc_api_result res;
        run(bad[i].body, bad[i].status, &res);
        CHECK_MSG(res.diags.count && !strcmp(res.diags.items[0].path, bad[i].path), "case %zu: path '%s', want '%s'",
                  i, res.diags.count ? res.diags.items[0].path : "", bad[i].path);
        tc_api_result_free(&res);
    }
}
