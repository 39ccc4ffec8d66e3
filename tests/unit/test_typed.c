/* test_typed.c — typed arrays in requests (io/typed.h): every numeric field read from a
 * typed array gives the JSON form's doubles bit for bit (and the same canonical text, so
 * the same stored-mesh id); each refusal names its path; answers with "encoding": "base64". */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "io/api.h"
#include "io/base64.h"
#include "io/request.h"
#include "io/request_write.h"

#include <cJSON.h>

/* ---- writing typed arrays ---------------------------------------------------------- */

/* {"dtype": dtype, "shape": [...], "data": base64(bytes)} appended to b. */
static void typed(tc_strbuf *b, const char *dtype, const char *shape, const void *bytes, size_t n) {
    tc_strbuf_printf(b, "{\"dtype\":\"%s\",\"shape\":%s,\"data\":\"", dtype, shape);
    tc_base64_append(b, bytes, n);
    tc_strbuf_puts(b, "\"}");
}

/* The canonical text of a parsed request (what stored-mesh ids hash), NULL on a parse failure. */
static char *canonical(const char *json, tc_request **keep) {
    tc_request *r = NULL;
    tc_diags d;
    tc_diags_init(&d);
    int st = tc_request_parse(json, strlen(json), TC_REQ_MESH, &r, &d);
    if (st != TC_REQ_OK) {
        fprintf(stderr, "parse: %d %s: %s\n", st, d.count ? d.items[0].path : "", d.count ? d.items[0].message : "");
        tc_diags_free(&d);
        return NULL;
    }
    tc_diags_free(&d);
    tc_strbuf b;
    tc_strbuf_init(&b);
    tc_json_request(&b, &r->desc, &r->opt);
    if (keep) *keep = r;
    else tc_request_free(r);
    return tc_strbuf_detach(&b, NULL);
}

/* Doubles that print long (17 digits), tiny, huge and negative. */
static const double XY[8] = {0.1, 1.0 / 3, 2.0000000000000004, 5e-324, 3, 1.7976931348623157e308, -0.7, 1e-300};
static const int32_t TRIS[6] = {0, 1, 2, 0, 2, 3};
static const double VALS[8] = {0.1, 0.2, 0.30000000000000004, -1e300, 4.9e-324, 7, 1e21, 123456789.125};
static const float CV[6] = {0.5f, 1.25f, -3.0f, 1e-7f, 65504.0f, 0.1f}; /* float32: widened exactly */
static const double GRAD[16] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 1.0 / 7};
static const uint32_t EDGE[2] = {0, 2};
static const int32_t VALUE_I[2] = {-5, 2147483647};
static const int32_t C0[2] = {0, 2};
static const int32_t CM1[3] = {1, 2, 3};
static const float PTS[4] = {0.5f, 0.25f, 1e-3f, -7.0f};

/* The JSON text of the float32 numbers above, as doubles (exactly). */
static void json_floats(tc_strbuf *b, const float *x, int n) {
    tc_strbuf_putc(b, '[');
    for (int i = 0; i < n; i++) {
        if (i) tc_strbuf_putc(b, ',');
        tc_strbuf_double(b, (double)x[i]);
    }
    tc_strbuf_putc(b, ']');
}

static void nested(tc_strbuf *b, const double *x, int n, int k) {
    tc_strbuf_putc(b, '[');
    for (int i = 0; i < n; i++) {
        tc_strbuf_puts(b, i ? ",[" : "[");
        for (int j = 0; j < k; j++) {
            if (j) tc_strbuf_putc(b, ',');
            tc_strbuf_double(b, x[i * k + j]);
        }
        tc_strbuf_putc(b, ']');
    }
    tc_strbuf_putc(b, ']');
}

/* The two-channel request of every field, as JSON numbers (typed = 0) or typed arrays. */
static char *full_request(int as_typed) {
    tc_strbuf b;
    tc_strbuf_init(&b);
    tc_strbuf_puts(&b, "{\"vertices\":");
    if (as_typed) typed(&b, "float64", "[4,2]", XY, sizeof XY);
    else nested(&b, XY, 4, 2);
    tc_strbuf_puts(&b, ",\"triangles\":");
    if (as_typed) typed(&b, "int32", "[2,3]", TRIS, sizeof TRIS);
    else tc_strbuf_puts(&b, "[[0,1,2],[0,2,3]]");
    tc_strbuf_puts(&b, ",\"values\":");
    if (as_typed) typed(&b, "float64", "[4,2]", VALS, sizeof VALS);
    else nested(&b, VALS, 4, 2);
    tc_strbuf_puts(&b, ",\"corner_values\":[{\"triangle\":1,\"values\":");
    if (as_typed) typed(&b, "float32", "[3,2]", CV, sizeof CV);
    else {
        tc_strbuf_putc(&b, '[');
        for (int k = 0; k < 3; k++) tc_strbuf_puts(&b, k ? "," : ""), json_floats(&b, CV + 2 * k, 2);
        tc_strbuf_putc(&b, ']');
    }
    tc_strbuf_puts(&b, "}],\"gradients\":");
    if (as_typed) typed(&b, "float64", "[4,2,2]", GRAD, sizeof GRAD);
    else {
        tc_strbuf_putc(&b, '[');
        for (int v = 0; v < 4; v++) tc_strbuf_puts(&b, v ? "," : ""), nested(&b, GRAD + 4 * v, 2, 2);
        tc_strbuf_putc(&b, ']');
    }
    tc_strbuf_puts(&b, ",\"corner_gradients\":[{\"triangle\":0,\"gradients\":");
    if (as_typed) typed(&b, "float64", "[3,2,2]", GRAD, 12 * sizeof(double));
    else {
        tc_strbuf_putc(&b, '[');
        for (int k = 0; k < 3; k++) tc_strbuf_puts(&b, k ? "," : ""), nested(&b, GRAD + 4 * k, 2, 2);
        tc_strbuf_putc(&b, ']');
    }
    tc_strbuf_puts(&b, "}],\"midpoints\":[{\"edge\":");
    if (as_typed) typed(&b, "uint32", "[2]", EDGE, sizeof EDGE);
    else tc_strbuf_puts(&b, "[0,2]");
    tc_strbuf_puts(&b, ",\"value\":");
    if (as_typed) typed(&b, "int32", "[2]", VALUE_I, sizeof VALUE_I);
    else tc_strbuf_puts(&b, "[-5,2147483647]");
    tc_strbuf_puts(&b, ",\"triangle\":1}],\"discontinuities\":{\"c0\":");
    if (as_typed) typed(&b, "int32", "[1,2]", C0, sizeof C0);
    else tc_strbuf_puts(&b, "[[0,2]]");
    tc_strbuf_puts(&b, ",\"c-1\":[");
    if (as_typed) typed(&b, "int32", "[3]", CM1, sizeof CM1);
    else tc_strbuf_puts(&b, "[1,2,3]");
    tc_strbuf_puts(&b, "]},\"points\":");
    if (as_typed) typed(&b, "float32", "[2,2]", PTS, sizeof PTS);
    else {
        tc_strbuf_puts(&b, "[");
        json_floats(&b, PTS, 2);
        tc_strbuf_putc(&b, ',');
        json_floats(&b, PTS + 2, 2);
        tc_strbuf_puts(&b, "]");
    }
    tc_strbuf_puts(&b, ",\"method\":\"linear4\"}");
    return tc_strbuf_detach(&b, NULL);
}

TEST(typed_every_field_equals_json_form) {
    char *j = full_request(0), *t = full_request(1);
    tc_request *rj = NULL, *rt = NULL;
    char *cj = canonical(j, &rj), *ct = canonical(t, &rt);
    CHECK(cj && ct);
    if (cj && ct) CHECK_MSG(!strcmp(cj, ct), "canonical texts differ:\n%s\n--- typed:\n%s", cj, ct);
    if (rj && rt) {
        CHECK(!memcmp(rt->desc.xy, XY, sizeof XY)); /* the doubles themselves, bit for bit */
        CHECK(!memcmp(rt->desc.xy, rj->desc.xy, sizeof XY));
        CHECK(!memcmp(rt->desc.values, VALS, sizeof VALS));
        CHECK(!memcmp(rt->desc.tris, TRIS, sizeof TRIS));
        CHECK(rt->desc.nchan == 2 && !rt->values_plain && rj->desc.nchan == 2);
        CHECK(!memcmp(rt->desc.gradients, rj->desc.gradients, sizeof GRAD) && rt->desc.gradients_mask == NULL);
        CHECK(!memcmp(rt->desc.corner_values, rj->desc.corner_values, 6 * sizeof(double)));
        CHECK(rt->desc.corner_values[3] == (double)1e-7f);
        CHECK(rt->desc.midpoint_values[1] == 2147483647.0 && rt->desc.midpoint_edge[1] == 2);
        CHECK(rt->desc.cm1.count == 1 && rt->desc.cm1.start[1] == 3 && rt->desc.c0.count == 1);
        CHECK(rt->npoints == 2 && !memcmp(rt->points, rj->points, 4 * sizeof(double)));
        CHECK(rt->points[2] == (double)1e-3f);
    }
    tc_request_free(rj), tc_request_free(rt);
    free(cj), free(ct), free(j), free(t);
}

/* One channel: values [n] read as plain numbers; normals and hessians [n, 3] and
 * [n, 1, 3]; quads; reference points and values. */
TEST(typed_one_channel_fields) {
    static const double vals[4] = {0, 1, 2, 3}, nrm[12] = {0, 0, 1, 0.1, 0, 1, 0, 0.2, 1, 0, 0, 1};
    static const uint32_t quad[4] = {0, 1, 2, 3};
    tc_strbuf b;
    tc_strbuf_init(&b);
    tc_strbuf_puts(&b, "{\"vertices\":[[0,0],[1,0],[1,1],[0,1]],\"quads\":");
    typed(&b, "uint32", "[1,4]", quad, sizeof quad);
    tc_strbuf_puts(&b, ",\"values\":");
    typed(&b, "float64", "[4]", vals, sizeof vals);
    tc_strbuf_puts(&b, ",\"normals\":");
    typed(&b, "float64", "[4,3]", nrm, sizeof nrm);
    tc_strbuf_puts(&b, ",\"hessians\":");
    typed(&b, "float64", "[4,1,3]", nrm, sizeof nrm);
    tc_strbuf_puts(&b, "}");
    char *ct = canonical(b.buf, NULL);
    const char *json = "{\"vertices\":[[0,0],[1,0],[1,1],[0,1]],\"quads\":[[0,1,2,3]],\"values\":[0,1,2,3],"
                       "\"normals\":[[0,0,1],[0.1,0,1],[0,0.2,1],[0,0,1]],"
                       "\"hessians\":[[0,0,1],[0.1,0,1],[0,0.2,1],[0,0,1]]}";
    char *cj = canonical(json, NULL);
    CHECK(ct && cj && !strcmp(ct, cj));
    free(ct), free(cj);

    tc_request *r = NULL;
    tc_diags d;
    tc_diags_init(&d);
    tc_strbuf_reset(&b);
    tc_strbuf_puts(&b, "{\"vertices\":[[0,0],[1,0],[1,1],[0,1]],\"triangles\":[[0,1,2]],\"values\":");
    typed(&b, "float32", "[4]", (const float[]){0, 1, 2, 3}, 16);
    tc_strbuf_puts(&b, ",\"reference\":{\"points\":");
    typed(&b, "float64", "[2,2]", XY, 4 * sizeof(double));
    tc_strbuf_puts(&b, ",\"values\":");
    typed(&b, "float64", "[2]", VALS, 2 * sizeof(double));
    tc_strbuf_puts(&b, "}}");
    CHECK(tc_request_parse(b.buf, b.len, TC_REQ_MESH | TC_REQ_REFERENCE, &r, &d) == TC_REQ_OK);
    if (r) {
        CHECK(r->values_plain && r->desc.nchan == 1 && r->desc.values[3] == 3);
        CHECK(r->nreference == 2 && !memcmp(r->reference_points, XY, 4 * sizeof(double)));
        CHECK(!memcmp(r->reference_values, VALS, 2 * sizeof(double)));
    }
    tc_request_free(r);
    tc_diags_free(&d);
    tc_strbuf_free(&b);
}

/* ---- refusals, each at its path -------------------------------------------------- */

/* A request of the unit square whose `field` is replaced by `text`, which must fail with
 * `status`, first finding at `path` containing `msg`. */
static void refused(const char *file, int line, const char *field, const char *text, int status, const char *path,
                    const char *msg) {
    char json[2048];
    const char *v = strcmp(field, "vertices") ? "[[0,0],[1,0],[1,1],[0,1]]" : text;
    const char *t = strcmp(field, "triangles") ? "[[0,1,2],[0,2,3]]" : text;
    const char *z = strcmp(field, "values") ? "[0,1,2,3]" : text;
    snprintf(json, sizeof json, "{\"vertices\":%s,\"triangles\":%s,\"values\":%s%s%s%s}", v, t, z,
             strcmp(field, "vertices") && strcmp(field, "triangles") && strcmp(field, "values") ? ",\"" : "",
             strcmp(field, "vertices") && strcmp(field, "triangles") && strcmp(field, "values") ? field : "",
             strcmp(field, "vertices") && strcmp(field, "triangles") && strcmp(field, "values") ? text : "");
    tc_request *r = NULL;
    tc_diags d;
    tc_diags_init(&d);
    int st = tc_request_parse(json, strlen(json), TC_REQ_MESH | TC_REQ_POINTS * !strcmp(field, "points\":"), &r, &d);
    if (st != status) tc_test_fail(file, line, "status %d, expected %d", st, status);
    if (!d.count) tc_test_fail(file, line, "nothing reported");
    else if (strcmp(d.items[0].path, path) || !strstr(d.items[0].message, msg))
        tc_test_fail(file, line, "%s: %s; expected %s: ...%s...", d.items[0].path, d.items[0].message, path, msg);
    tc_request_free(r);
    tc_diags_free(&d);
}
#define REFUSED(field, text, status, path, msg) refused(__FILE__, __LINE__, field, text, status, path, msg)

/* base64 of n little-endian bytes, for the texts below. */
static const char *b64(const void *x, size_t n, char *buf) {
    tc_base64_encode(x, n, buf);
    buf[tc_base64_encoded_len(n)] = '\0';
    return buf;
}

TEST(typed_refusals_name_their_path) {
    char t[1024], e[512];
    double v12[12] = {0};
    snprintf(t, sizeof t, "{\"dtype\":\"float64\",\"shape\":[4,3],\"data\":\"%s\"}", b64(v12, 96, e));
    REFUSED("vertices", t, TC_REQ_MALFORMED, "vertices", "shape [4, 3]: expected [n, 2]");
    snprintf(t, sizeof t, "{\"dtype\":\"float64\",\"shape\":[2,3],\"data\":\"%s\"}", b64(v12, 48, e));
    REFUSED("triangles", t, TC_REQ_MALFORMED, "triangles", "dtype float64: expected int32 or uint32");
    REFUSED("triangles", "{\"dtype\":\"int64\",\"shape\":[0,3],\"data\":\"\"}", TC_REQ_MALFORMED, "triangles",
            "dtype 'int64' unknown");
    REFUSED("values", "{\"dtype\":\"float64\",\"shape\":[4],\"data\":\"AAAA*AAA\"}", TC_REQ_MALFORMED, "values",
            "data: 6 bytes, expected 32");
    snprintf(t, sizeof t, "{\"dtype\":\"float32\",\"shape\":[4],\"data\":\"%s\"}", b64(v12, 16, e));
    t[strlen(t) - 5] = '!';
    REFUSED("values", t, TC_REQ_MALFORMED, "values", "data: bad base64 at character 21");
    snprintf(t, sizeof t, "{\"dtype\":\"float64\",\"shape\":[4,2],\"data\":\"%s\"}", b64(v12, 40, e));
    REFUSED("vertices", t, TC_REQ_MALFORMED, "vertices", "data: 40 bytes, expected 64 (shape [4, 2] of float64");
    REFUSED("vertices", "{\"dtype\":\"float64\",\"shape\":[4,2],\"data\":\"AAA\"}", TC_REQ_MALFORMED, "vertices",
            "not a multiple of 4");
    REFUSED("vertices", "{\"dtype\":\"float64\",\"shape\":[4,2]}", TC_REQ_MALFORMED, "vertices",
            "data: expected a base64 string, got nothing");
    REFUSED("vertices", "{\"shape\":[4,2],\"data\":\"\"}", TC_REQ_MALFORMED, "vertices", "dtype: expected");
    REFUSED("vertices", "{\"dtype\":\"float64\",\"shape\":[],\"data\":\"\"}", TC_REQ_MALFORMED, "vertices",
            "shape: expected an array of 1 to 4 lengths");
    REFUSED("vertices", "{\"dtype\":\"float64\",\"shape\":[4,-2],\"data\":\"\"}", TC_REQ_MALFORMED, "vertices",
            "shape[1]: expected a length");
    double xy[8] = {0, 0, 1, 0, 1, 1, 0, 1};
    xy[2] = NAN;
    snprintf(t, sizeof t, "{\"dtype\":\"float64\",\"shape\":[4,2],\"data\":\"%s\"}", b64(xy, 64, e));
    REFUSED("vertices", t, TC_REQ_INVALID, "vertices[1][0]", "NaN in a typed array");
    float z[4] = {0, 1, INFINITY, 3};
    snprintf(t, sizeof t, "{\"dtype\":\"float32\",\"shape\":[4],\"data\":\"%s\"}", b64(z, 16, e));
    REFUSED("values", t, TC_REQ_INVALID, "values[2]", "infinity in a typed array");
    uint32_t tri[6] = {0, 1, 2, 0, 2, 0xFFFFFFFFu};
    snprintf(t, sizeof t, "{\"dtype\":\"uint32\",\"shape\":[2,3],\"data\":\"%s\"}", b64(tri, 24, e));
    REFUSED("triangles", t, TC_REQ_MALFORMED, "triangles[1][2]", "must be an integer (a 32-bit index), got 4294967295");
    snprintf(t, sizeof t, "{\"dtype\":\"float64\",\"shape\":[3],\"data\":\"%s\"}", b64(v12, 24, e));
    REFUSED("values", t, TC_REQ_INVALID, "values", "has 3 entries, expected 4");
    snprintf(t, sizeof t, "{\"dtype\":\"float64\",\"shape\":[4,2,2],\"data\":\"%s\"}", b64(v12, 0, e));
    REFUSED("gradients\":", "[]", TC_REQ_INVALID, "gradients", "has 0 entries");
    snprintf(t, sizeof t, "[{\"edge\":{\"dtype\":\"float64\",\"shape\":[2],\"data\":\"%s\"},\"value\":1}]",
             b64(v12, 16, e));
    REFUSED("midpoints\":", t, TC_REQ_MALFORMED, "midpoints[0].edge", "dtype float64: expected int32 or uint32");
    snprintf(t, sizeof t, "{\"c0\":[[0,2],{\"dtype\":\"int32\",\"shape\":[1],\"data\":\"%s\"}]}", b64(v12, 4, e));
    REFUSED("discontinuities\":", t, TC_REQ_MALFORMED, "discontinuities.c0[1]", "at least 2 vertices");
    double g[8] = {1, 2, 3, 4, 5, 6, 7, 8};
    snprintf(t, sizeof t, "{\"dtype\":\"float64\",\"shape\":[4,1,2],\"data\":\"%s\"}", b64(g, 64, e));
    REFUSED("values", "[[0,0],[1,1],[2,2],[3,3]],\"gradients\":{\"dtype\":\"float64\",\"shape\":[4,2],\"data\":\"\"}",
            TC_REQ_MALFORMED, "gradients", "shape [4, 2]: expected [n, 2, 2] (2 channels, as values)");
    REFUSED("values", "[[0,0],[1,1],[2,2],[3,3]],\"encoding\":\"hex\"", TC_REQ_INVALID, "encoding",
            "unknown encoding 'hex'");
}

/* The edges of a typed array's header: a length of exactly 2^53 is a length (the largest
 * integer every smaller one of which a double holds; the field then refuses it as too many
 * entries), 2^53 + 2 is not; a shape of exactly TC_TYPED_MAXDIM lengths is a shape (the field
 * then refuses its rank), one more is not. Each refusal comes from the check that owns it,
 * with its own message. */
TEST(typed_header_limits_are_inclusive) {
    REFUSED("values", "{\"dtype\":\"float64\",\"shape\":[9007199254740992],\"data\":\"\"}", TC_REQ_INVALID,
            "values", "too many entries (9007199254740992, at most 2147483647)");
    REFUSED("values", "{\"dtype\":\"float64\",\"shape\":[9007199254740994],\"data\":\"\"}", TC_REQ_MALFORMED,
            "values", "shape[0]: expected a length");
    REFUSED("values", "{\"dtype\":\"float64\",\"shape\":[4,1,1,1],\"data\":\"\"}", TC_REQ_MALFORMED, "values",
            "shape [4, 1, 1, 1]: expected [n] or [n, C]");
    REFUSED("values", "{\"dtype\":\"float64\",\"shape\":[4,1,1,1,1],\"data\":\"\"}", TC_REQ_MALFORMED, "values",
            "shape: expected an array of 1 to 4 lengths");
}

/* A shape whose element count times the element size (8 bytes at most) would not fit in a
 * size_t is refused as too many elements when the header is read: [2^31, 2^30] is 2^61
 * elements, 2^64 bytes, which wraps to 0 and would match empty data. [2^30, 2^30] (2^63 bytes)
 * still fits, and goes on to the field's own checks (too many channels here). */
TEST(typed_shape_byte_count_overflow) {
    REFUSED("values", "{\"dtype\":\"float64\",\"shape\":[2147483648,1073741824],\"data\":\"\"}", TC_REQ_INVALID,
            "values", "shape: too many elements");
    REFUSED("values", "{\"dtype\":\"float32\",\"shape\":[2147483648,1073741824],\"data\":\"\"}", TC_REQ_INVALID,
            "values", "shape: too many elements");
    REFUSED("values", "{\"dtype\":\"float64\",\"shape\":[1073741824,1073741824],\"data\":\"\"}", TC_REQ_INVALID,
            "values", "channels, expected 1 to");
}

/* ---- answers with "encoding": "base64" --------------------------------------------- */

/* The float64 array a typed answer member holds, checked for its shape; NULL if malformed. */
static double *typed_member(const cJSON *root, const char *name, const size_t *shape, int ndim, size_t *count) {
    const cJSON *t = cJSON_GetObjectItemCaseSensitive(root, name);
    const cJSON *dt = cJSON_GetObjectItemCaseSensitive(t, "dtype"), *sh = cJSON_GetObjectItemCaseSensitive(t, "shape");
    const cJSON *data = cJSON_GetObjectItemCaseSensitive(t, "data");
    if (!cJSON_IsString(dt) || strcmp(dt->valuestring, "float64") || !cJSON_IsArray(sh) || !cJSON_IsString(data))
        return NULL;
    if (cJSON_GetArraySize(sh) != ndim) return NULL;
    size_t n = 1;
    for (int k = 0; k < ndim; k++) {
        if (cJSON_GetArrayItem(sh, k)->valuedouble != (double)shape[k]) return NULL;
        n *= shape[k];
    }
    size_t len = strlen(data->valuestring), bad;
    const char *why;
    if (tc_base64_decoded_len(data->valuestring, len) != n * 8) return NULL;
    double *x = malloc(n * 8 + 8);
    if (x && tc_base64_decode(data->valuestring, len, x, &bad, &why)) free(x), x = NULL;
    *count = n;
    return x;
}

/* Flattens a JSON answer's nested numbers (null -> NaN, repeated `width` times). */
static size_t flatten(const cJSON *v, double *out, size_t k, int width) {
    if (cJSON_IsNumber(v)) return out[k] = v->valuedouble, k + 1;
    if (cJSON_IsNull(v)) {
        for (int i = 0; i < width; i++) out[k++] = NAN;
        return k;
    }
    for (const cJSON *e = v->child; e; e = e->next) k = flatten(e, out, k, width);
    return k;
}

/* Same bits, NaN matching NaN (the JSON null). */
static int same(double a, double b) { return isnan(a) ? isnan(b) : !memcmp(&a, &b, sizeof a); }

static cJSON *answer(int status_want, const char *body, int ordinates) {
    tc_strbuf out;
    tc_api_result res;
    tc_api_result_init(&res);
    tc_strbuf_init(&out);
    int st = ordinates ? tc_api_ordinates(body, strlen(body), NULL, &out, &res)
                       : tc_api_evaluate(body, strlen(body), NULL, 0, NULL, &out, &res);
    CHECK_MSG(st == status_want, "status %d: %s", st, res.diags.count ? res.diags.items[0].message : "");
    cJSON *root = st == 200 ? cJSON_Parse(out.buf) : NULL;
    tc_strbuf_free(&out);
    tc_api_result_free(&res);
    return root;
}

/* Ordinates: [T, C, K] float64, the JSON form's doubles bit for bit, NaN rows for a
 * dropped triangle (null in JSON). */
TEST(typed_ordinates_answer_equals_json) {
    const char *mesh = "\"vertices\":[[0,0],[1,0],[1,1],[0,1],[2,2]],\"triangles\":[[0,1,2],[0,2,3],[0,2,4]],"
                       "\"values\":[[0.1,1],[1,2],[2.5,3],[3,4.75],[1e-9,5]],\"degenerate\":\"drop\"";
    static const char *const methods[] = {"clough-tocher", "powell-sabin", "linear"};
    for (size_t m = 0; m < 3; m++) {
        char j[1024], t[1024];
        snprintf(j, sizeof j, "{%s,\"method\":\"%s\"}", mesh, methods[m]);
        snprintf(t, sizeof t, "{%s,\"method\":\"%s\",\"encoding\":\"base64\"}", mesh, methods[m]);
        cJSON *rj = answer(200, j, 1), *rt = answer(200, t, 1);
        if (!rj || !rt) {
            cJSON_Delete(rj), cJSON_Delete(rt);
            continue;
        }
        size_t K = (size_t)cJSON_GetArraySize(cJSON_GetObjectItem(rj, "labels")), n = 0;
        size_t shape[3] = {3, 2, K};
        double *x = typed_member(rt, "ordinates", shape, 3, &n);
        double *y = calloc(3 * 2 * K, sizeof *y);
        size_t k = flatten(cJSON_GetObjectItem(rj, "ordinates"), y, 0, (int)(2 * K));
        CHECK_MSG(x && k == n, "%s: typed ordinates missing or of another size (%zu vs %zu)", methods[m], k, n);
        int bad = 0;
        for (size_t i = 0; x && i < n && i < k; i++) bad += !same(x[i], y[i]);
        CHECK_MSG(!bad, "%s: %d ordinates differ", methods[m], bad);
        CHECK(x && isnan(x[2 * 2 * K]) && !isnan(x[0])); /* triangle 2 is degenerate: dropped */
        CHECK(cJSON_GetObjectItem(rj, "labels") && cJSON_GetObjectItem(rt, "labels"));
        free(x), free(y);
        cJSON_Delete(rj), cJSON_Delete(rt);
    }
}

/* Evaluate: values [n] (plain) or [n, C], gradients [n, 2] or [n, C, 2], NaN outside. */
TEST(typed_evaluate_answer_equals_json) {
    static const char *const vals[] = {"[0,1,2.5,3]", "[[0,1],[1,2],[2,3],[3,4]]"};
    for (int c = 0; c < 2; c++) {
        char j[1024], t[1024];
        const char *pts = "\"points\":[[0.5,0.25],[0.1,0.7],[5,5],[0.999,0.001]],\"with_gradients\":true";
        snprintf(j, sizeof j, "{\"vertices\":[[0,0],[1,0],[1,1],[0,1]],\"triangles\":[[0,1,2],[0,2,3]],"
                 "\"values\":%s,%s}", vals[c], pts);
        snprintf(t, sizeof t, "{\"vertices\":[[0,0],[1,0],[1,1],[0,1]],\"triangles\":[[0,1,2],[0,2,3]],"
                 "\"values\":%s,%s,\"encoding\":\"base64\"}", vals[c], pts);
        cJSON *rj = answer(200, j, 0), *rt = answer(200, t, 0);
        if (!rj || !rt) {
            cJSON_Delete(rj), cJSON_Delete(rt);
            continue;
        }
        size_t nc = (size_t)c + 1, n = 0, ng = 0;
        size_t vs[2] = {4, nc}, gs[3] = {4, nc, 2}, gs1[2] = {4, 2};
        double *v = typed_member(rt, "values", vs, c ? 2 : 1, &n);
        double *g = c ? typed_member(rt, "gradients", gs, 3, &ng) : typed_member(rt, "gradients", gs1, 2, &ng);
        double yv[8], yg[16];
        size_t kv = flatten(cJSON_GetObjectItem(rj, "values"), yv, 0, (int)nc);
        size_t kg = flatten(cJSON_GetObjectItem(rj, "gradients"), yg, 0, (int)(2 * nc));
        CHECK_MSG(v && g && kv == n && kg == ng, "channels %zu: shapes", nc);
        for (size_t i = 0; v && i < n && i < kv; i++) CHECK(same(v[i], yv[i]));
        for (size_t i = 0; g && i < ng && i < kg; i++) CHECK(same(g[i], yg[i]));
        CHECK(v && isnan(v[2 * nc]));
        const cJSON *o = cJSON_GetObjectItem(rt, "outside");
        CHECK(cJSON_GetArraySize(o) == 1 && cJSON_GetArrayItem(o, 0)->valueint == 2);
        free(v), free(g);
        cJSON_Delete(rj), cJSON_Delete(rt);
    }
}

/* Every allocation of a typed request may fail: NOMEM, nothing leaked (ASan in `make
 * check`), until enough succeed; scratch buffers of float32 data included. */
TEST(typed_request_out_of_memory) {
    char *t = full_request(1);
    int nomem = 0, ok = 0;
    for (long k = 1; k <= 60 && !ok; k++) {
        tc_request *r = (tc_request *)1;
        tc_diags d;
        tc_diags_init(&d);
        tc_request__fail_alloc_after(k);
        int st = tc_request_parse(t, strlen(t), TC_REQ_MESH, &r, &d);
        tc_request__fail_alloc_after(0);
        if (st == TC_REQ_NOMEM) {
            nomem++;
            CHECK(r == NULL && d.errors >= 1);
        } else {
            CHECK_MSG(st == TC_REQ_OK, "status %d at failure %ld", st, k);
            ok++;
        }
        tc_request_free(r == (tc_request *)1 ? NULL : r);
        tc_diags_free(&d);
    }
    CHECK(ok == 1 && nomem >= 15);
    free(t);
}

/* A grid of n x n cells (2 n^2 triangles) with C channels of 17-digit values, plus
 * `ndrop` collinear triangles (dropped: "degenerate": "drop") spread over the list, so the
 * typed answer's rows are renumbered across several of its staging chunks. */
static char *grid_body(int n, int C, int ndrop, int base64) {
    tc_strbuf b;
    tc_strbuf_init(&b);
    tc_strbuf_puts(&b, "{\"vertices\":[");
    for (int j = 0; j <= n; j++)
        for (int i = 0; i <= n; i++)
            tc_strbuf_printf(&b, "%s[%d,%d]", i || j ? "," : "", i, j);
    tc_strbuf_puts(&b, "],\"triangles\":[");
    int ntri = 2 * n * n, k = 0, every = ndrop ? ntri / ndrop : 0;
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            int v = j * (n + 1) + i;
            for (int h = 0; h < 2; h++, k++) {
                if (every && k % every == every / 2) tc_strbuf_puts(&b, k ? ",[0,1,2]" : "[0,1,2]"); /* y = 0: collinear */
                tc_strbuf_printf(&b, "%s[%d,%d,%d]", k || (every && every / 2 == 0) ? "," : "", v, h ? v + n + 2 : v + 1,
                                 h ? v + n + 1 : v + n + 2);
            }
        }
    tc_strbuf_puts(&b, "],\"values\":[");
    for (int v = 0; v < (n + 1) * (n + 1); v++) {
        tc_strbuf_puts(&b, v ? ",[" : "[");
        for (int c = 0; c < C; c++) tc_strbuf_printf(&b, "%s%.17g", c ? "," : "", -1.2345678901234567e-7 * (v + 1) / (c + 3));
        tc_strbuf_putc(&b, ']');
    }
    tc_strbuf_printf(&b, "],\"degenerate\":\"drop\"%s}", base64 ? ",\"encoding\":\"base64\"" : "");
    return tc_strbuf_detach(&b, NULL);
}

/* The typed ordinates are encoded straight from the coefficients (every triangle kept) or
 * through staging chunks (dropped ones renumber the rows): both are the JSON form's doubles
 * bit for bit, over many chunks, 1 and 2 channels. */
TEST(typed_ordinates_chunked_equal_json) {
    for (int C = 1; C <= 2; C++)
        for (int ndrop = 0; ndrop <= 5; ndrop += 5) {
            char *j = grid_body(24, C, ndrop, 0), *t = grid_body(24, C, ndrop, 1);
            cJSON *rj = answer(200, j, 1), *rt = answer(200, t, 1);
            free(j), free(t);
            size_t T = 2 * 24 * 24 + (size_t)ndrop, K = 19, n = 0;
            size_t shape[3] = {T, (size_t)C, K};
            double *x = rt ? typed_member(rt, "ordinates", shape, 3, &n) : NULL;
            double *y = calloc(T * (size_t)C * K, sizeof *y);
            size_t k = rj ? flatten(cJSON_GetObjectItem(rj, "ordinates"), y, 0, (int)((size_t)C * K)) : 0;
            CHECK_MSG(x && k == n && n == T * (size_t)C * K, "C %d drop %d: typed ordinates of another size", C, ndrop);
            int bad = 0, nan_rows = 0;
            for (size_t i = 0; x && i < n && i < k; i++) bad += !same(x[i], y[i]);
            for (size_t i = 0; x && i < T; i++) nan_rows += isnan(x[i * (size_t)C * K]);
            CHECK_MSG(!bad, "C %d drop %d: %d ordinates differ", C, ndrop, bad);
            CHECK_MSG(nan_rows == ndrop, "C %d: %d NaN rows, %d dropped", C, nan_rows, ndrop);
            free(x), free(y);
            cJSON_Delete(rj), cJSON_Delete(rt);
        }
}

/* The JSON answer's size is reserved before the numbers are printed (bounded from T x C x K):
 * the buffer grows a few times, not once per doubling of a ~1 MB answer. */
TEST(ordinates_answer_reserved_once) {
    char *j = grid_body(24, 2, 5, 0);
    tc_strbuf out;
    tc_api_result res;
    tc_api_result_init(&res);
    tc_strbuf_init(&out);
    long g0 = tc_strbuf__grows();
    CHECK(tc_api_ordinates(j, strlen(j), NULL, &out, &res) == 200);
    long grew = tc_strbuf__grows() - g0;
    CHECK_MSG(out.len > 500000, "answer of %zu bytes", out.len);
    CHECK_MSG(grew <= 3, "the answer's buffer grew %ld times", grew);
    /* The same answer appended after other content (no hand-over): the same bytes. */
    tc_strbuf pre;
    tc_api_result res2;
    tc_api_result_init(&res2);
    tc_strbuf_init(&pre);
    tc_strbuf_puts(&pre, "prefix");
    CHECK(tc_api_ordinates(j, strlen(j), NULL, &pre, &res2) == 200);
    CHECK(pre.len == out.len + 6 && !memcmp(pre.buf + 6, out.buf, out.len));
    tc_strbuf_free(&out), tc_strbuf_free(&pre);
    tc_api_result_free(&res), tc_api_result_free(&res2);
    free(j);
}
