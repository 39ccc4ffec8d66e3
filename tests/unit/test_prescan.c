/* test_prescan.c — tests of tc_prescan (io/prescan.h): it counts the elements of the
 * limited arrays by their key path, whatever their elements, strings or nesting, stops at
 * the first one over with its full count, and ignores arrays that are not named by keys. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "io/api.h"
#include "io/prescan.h"
#include "io/strbuf.h"

static const tc_scan_limit LIMITS[] = {{"vertices", 3}, {"triangles", 2}, {"points", 2}, {"reference.points", 1}};
enum { NL = sizeof LIMITS / sizeof LIMITS[0] };

/* The index tc_prescan returns for json, with the count in *n. */
static int scan(const char *json, int64_t *n) {
    *n = -7;
    return tc_prescan(json, strlen(json), LIMITS, NL, n);
}

TEST(prescan_within_limits) {
    int64_t n;
    CHECK(scan("{\"vertices\":[[0,0],[1,0],[0,1]],\"triangles\":[[0,1,2]],\"points\":[]}", &n) == -1);
    CHECK(scan("{\"reference\":{\"points\":[[0,0]]},\"points\":[1,2]}", &n) == -1);
    CHECK(scan("", &n) == -1);
    CHECK(scan("[1,2,3,4,5]", &n) == -1); /* a root array is not a named field */
    CHECK(tc_prescan(NULL, 0, LIMITS, NL, &n) == -1);
}

TEST(prescan_counts_elements_of_any_kind) {
    int64_t n;
    CHECK(scan("{\"points\":[[0,0],{\"a\":[1,2,3]},\"x,]\\\"[\",true]}", &n) == 2);
    CHECK(n == 4);
    CHECK(scan("{\"points\" : [ -1.5e3 , null , [ ] ]}", &n) == 2);
    CHECK(n == 3);
    CHECK(scan("{\"triangles\":[[0,1,2],[1,2,3],[2,3,4],[3,4,5],[4,5,6]],\"vertices\":[]}", &n) == 1);
    CHECK(n == 5);
}

TEST(prescan_paths_are_object_keys_only) {
    int64_t n;
    CHECK(scan("{\"reference\":{\"points\":[[0,0],[1,1]]}}", &n) == 3);
    CHECK(n == 2);
    /* "points" inside an array element, or deeper than the root, is another field */
    CHECK(scan("{\"methods\":[{\"points\":[1,2,3,4]}],\"mesh\":{\"points\":[1,2,3]}}", &n) == -1);
    /* a key that looks like a limited one inside a string value is a string */
    CHECK(scan("{\"name\":\"\\\"points\\\":[1,2,3]\",\"points\":[1]}", &n) == -1);
    /* the first array over its limit is the one named */
    CHECK(scan("{\"points\":[1,2,3],\"vertices\":[1,2,3,4,5]}", &n) == 2);
    CHECK(n == 3);
}

TEST(prescan_survives_broken_and_deep_input) {
    int64_t n;
    CHECK(scan("{\"points\":[1,2,3", &n) == 2); /* truncated: still counted as far as it goes */
    CHECK(n == 3);
    CHECK(scan("{\"points\":\"unterminated", &n) == -1);
    CHECK(scan("]]]}}}{\"points\":[1,2]", &n) == -1);
    char deep[4096] = "{\"points\":[";
    size_t k = strlen(deep);
    for (int i = 0; i < 1000; i++) deep[k++] = '[';
    for (int i = 0; i < 1000; i++) deep[k++] = ']';
    memcpy(deep + k, ",1,2]}", 7);
    CHECK(scan(deep, &n) == 2);
    CHECK(n == 3);
}

/* Through the API: the 413 names the field and counts as within_limits does. */
TEST(prescan_api_refuses_before_parsing) {
    const char *mesh = "{\"vertices\":[[0,0],[1,0],[0,1]],\"triangles\":[[0,1,2]],\"values\":[1,2,3],"
                       "\"points\":[[0.1,0.1],[0.2,0.2],[0.3,0.3]]}";
    tc_api_limits lim = {.max_points = 2, .render_threads = 1};
    tc_strbuf out;
    tc_strbuf_init(&out);
    tc_api_result res = {0};
    CHECK(tc_api_evaluate(mesh, strlen(mesh), NULL, 0, &lim, &out, &res) == 413);
    CHECK(res.diags.count >= 1 && !strcmp(res.diags.items[0].path, "points"));
    CHECK(res.diags.count >= 1 && strstr(res.diags.items[0].message, "3 points; this server accepts at most 2"));
    tc_diags_free(&res.diags);
    tc_strbuf_free(&out);
    /* refused before the parser runs: the syntax error after the array is never reached */
    const char *broken = "{\"points\":[[0,0],[1,1],[2,2]], oops";
    tc_api_result r1 = {0};
    tc_strbuf_init(&out);
    CHECK(tc_api_evaluate(broken, strlen(broken), NULL, 0, &lim, &out, &r1) == 413);
    tc_diags_free(&r1.diags);
    tc_strbuf_free(&out);
    const char *quads = "{\"vertices\":[[0,0],[1,0],[1,1],[0,1]],\"quads\":[[0,1,2,3],[0,1,2,3]],\"values\":[1,2,3,4]}";
    tc_api_limits tl = {.max_triangles = 3, .render_threads = 1};
    tc_api_result r2 = {0};
    tc_strbuf_init(&out);
    CHECK(tc_api_ordinates(quads, strlen(quads), &tl, &out, &r2) == 413);
    CHECK(r2.diags.count >= 1 && strstr(r2.diags.items[0].message, "4 triangles (2 per quad)"));
    tc_diags_free(&r2.diags);
    tc_strbuf_free(&out);
    /* a typed array's shape beyond any count: the doubled count saturates (it overflowed: fuzz_api) */
    const char *huge = "{\"vertices\":[[0,0],[1,0],[1,1],[0,1]],\"quads\":{\"dtype\":\"int32\",\"shape\":[1e309,4],"
                       "\"data\":\"\"},\"values\":[1,2,3,4]}";
    tc_api_result r3 = {0};
    tc_strbuf_init(&out);
    CHECK(tc_api_ordinates(huge, strlen(huge), &tl, &out, &r3) == 413);
    CHECK(r3.diags.count >= 1 && !strcmp(r3.diags.items[0].path, "quads"));
    CHECK(r3.diags.count >= 1 && strstr(r3.diags.items[0].message, "9223372036854775807 triangles (2 per quad)"));
    tc_diags_free(&r3.diags);
    tc_strbuf_free(&out);
}

/* A limited array given as a typed array counts its shape's first length, data unread. */
TEST(prescan_typed_arrays_count_their_shape) {
    int64_t n;
    CHECK(scan("{\"points\":{\"dtype\":\"float64\",\"data\":\"!!not base64\",\"shape\":[3,2]}}", &n) == 2);
    CHECK(n == 3);
    CHECK(scan("{\"points\":{\"shape\":[2,2],\"dtype\":\"float64\",\"data\":\"\"}}", &n) == -1);
    CHECK(scan("{\"reference\":{\"points\":{\"shape\": [ 11000000 , 2 ],\"data\":\"\"}}}", &n) == 3);
    CHECK(n == 11000000);
    CHECK(scan("{\"vertices\":{\"shape\":[4e0,2]}}", &n) == 0); /* a length spelt as a float */
    CHECK(n == 4);
    /* "shape" elsewhere, or the second length, counts nothing */
    CHECK(scan("{\"points\":{\"shape\":[1,99]},\"mesh\":{\"shape\":[99]},\"shape\":[99]}", &n) == -1);
    CHECK(scan("{\"triangles\":{\"dtype\":\"int32\",\"shape\":[3,3]}}", &n) == 1);
    CHECK(n == 3);
}

/* Strings are skipped by their closing quote (memchr) and the run of backslashes before it:
 * an even run ends the string, an odd one escapes the quote. Text that only looks like a
 * limited array inside a string is never counted; a long base64-like string is skipped. */
TEST(prescan_strings_end_at_an_unescaped_quote) {
    int64_t n;
    CHECK(scan("{\"a\":\"x\\\\\",\"points\":[1,2,3]}", &n) == 2); /* "x\\": the quote ends it */
    CHECK(n == 3);
    CHECK(scan("{\"a\":\"x\\\\\\\",\\\"points\\\":[1,2,3]\"}", &n) == -1); /* "x\\\"...: escaped */
    CHECK(scan("{\"a\":\"\\\"\\\"\",\"points\":[1,2,3,4]}", &n) == 2);
    CHECK(n == 4);
    CHECK(scan("{\"points\":[\"\\\\\\\\\",\"],[\",\"\\\"\"]}", &n) == 2); /* three strings */
    CHECK(n == 3);
    CHECK(scan("{\"a\":\"never closed \\\\\\\" [1,2,3]", &n) == -1);
    CHECK(scan("{\"points\":[1,\"open", &n) == -1);
    size_t big = 1 << 20;
    char *s = malloc(big + 64);
    if (!s) return;
    strcpy(s, "{\"data\":\"");
    size_t k = strlen(s);
    for (size_t i = 0; i < big; i++) s[k++] = "AB+/\\\\"[i % 4]; /* no quote: letters and '/' */
    strcpy(s + k, "\",\"points\":[1,2,3]}");
    CHECK(tc_prescan(s, strlen(s), LIMITS, NL, &n) == 2);
    CHECK(n == 3);
    free(s);
}

/* The byte count is the first check of a limit, the parsed request's count the backstop: a key
 * the byte scanner does not read as "reference" (written with an escape, which it does not
 * decode) gets past the first and must be caught by the second, which names the same path
 * ("reference.points", not "points") and counts the same things. */
TEST(prescan_api_backstop_names_reference_points) {
    const char *body = "{\"vertices\":[[0,0],[1,0],[0,1]],\"triangles\":[[0,1,2]],\"values\":[1,2,3],"
                       "\"refer\\u0065nce\":{\"points\":[[0.1,0.1],[0.2,0.2],[0.3,0.3]],\"values\":[1,2,3]}}";
    tc_api_limits lim = {.max_points = 2, .render_threads = 1};
    tc_strbuf out;
    tc_strbuf_init(&out);
    tc_api_result res = {0};
    CHECK(tc_api_compare(body, strlen(body), &lim, &out, &res) == 413);
    CHECK_MSG(res.diags.count >= 1 && !strcmp(res.diags.items[0].path, "reference.points"), "path '%s'",
              res.diags.count ? res.diags.items[0].path : "");
    CHECK(res.diags.count >= 1 && strstr(res.diags.items[0].message, "3 reference points; this server accepts at most 2"));
    tc_diags_free(&res.diags);
    tc_strbuf_free(&out);
}
