/* test_api.c — unit tests of the JSON API (src/io/api.c): request bytes -> response bytes
 * for ordinates and evaluate, problem documents, determinism and exact number round-trips. */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cJSON.h>

#include "check.h"
#include "image/image.h"
#include "io/api.h"
#include "io/request.h"

/* ---- helpers ------------------------------------------------------------------- */

static int same_bits(double a, double b) { return memcmp(&a, &b, sizeof a) == 0; }

/* Reads api/examples/<name>, found relative to this source file (so the test
 * works from the repository root and from anywhere __FILE__ is absolute). */
static char *read_example(const char *name, size_t *len) {
    const char *me = __FILE__, *cut = strstr(me, "tests/unit/test_api.c");
    size_t plen = cut ? (size_t)(cut - me) : 0;
    char path[1024];
    snprintf(path, sizeof path, "%.*sapi/examples/%s", (int)plen, me, name);
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    size_t cap = 1 << 16, n = 0;
    char *buf = malloc(cap + 1);
    while (buf) {
        n += fread(buf + n, 1, cap - n, f);
        if (n < cap) break;
        char *g = realloc(buf, (cap *= 2) + 1);
        if (!g) free(buf);
        buf = g;
    }
    fclose(f);
    if (buf) buf[n] = '\0';
    *len = n;
    return buf;
}

/* The core's own reconstruction of a request, built without the API layer. */
typedef struct {
    tc_request *req;
    tc_mesh *mesh;
    tc_recon *recon;
    tc_locator *L;
} ref;

static int ref_build(ref *r, const char *body, size_t len, unsigned expect) {
    memset(r, 0, sizeof *r);
    if (tc_request_parse(body, len, expect, &r->req, NULL) != TC_REQ_OK) return -1;
    if (tc_mesh_new(&r->req->desc, &r->mesh, NULL) != TC_OK) return -1;
    if (tc_recon_new(r->mesh, &r->req->opt, &r->recon, NULL) != TC_OK) return -1;
    if (tc_locator_new(r->mesh, &r->L) != TC_OK) return -1;
    return 0;
}

static void ref_free(ref *r) {
    tc_locator_free(r->L);
    tc_recon_free(r->recon);
    tc_mesh_free(r->mesh);
    tc_request_free(r->req);
}

/* Every number and null of one response member, in text order, each number
 * read back from its printed text with strtod. */
#define NL_MAX 8192
typedef struct {
    size_t n;
    double v[NL_MAX];
    unsigned char null[NL_MAX];
} numlist;

/* Length of a JSON number (RFC 8259 grammar) at s, or 0 if there is none. */
static size_t json_number_len(const char *s) {
    const char *p = s;
    if (*p == '-') p++;
    if (*p == '0') p++;
    else if (*p >= '1' && *p <= '9') while (*p >= '0' && *p <= '9') p++;
    else return 0;
    if (*p == '.') {
        p++;
        if (!(*p >= '0' && *p <= '9')) return 0;
        while (*p >= '0' && *p <= '9') p++;
    }
    if (*p == 'e' || *p == 'E') {
        p++;
        if (*p == '+' || *p == '-') p++;
        if (!(*p >= '0' && *p <= '9')) return 0;
        while (*p >= '0' && *p <= '9') p++;
    }
    return (size_t)(p - s);
}

/* Scans the value of the first "member": in text (a number, null, or nested
 * arrays of them). Returns 0, or -1 (with a test failure) on a missing member,
 * a token that is not a JSON number/null/bracket/comma, or overflow. */
static int scan_member(const char *text, const char *member, numlist *nl) {
    char key[64];
    snprintf(key, sizeof key, "\"%s\":", member);
    nl->n = 0;
    const char *p = text ? strstr(text, key) : NULL;
    if (!p) {
        tc_test_fail(__FILE__, __LINE__, "member %s not found", key);
        return -1;
    }
    p += strlen(key);
    int depth = 0;
    do {
        while (*p == ' ' || *p == '\n' || *p == '\t' || *p == '\r') p++;
        if (*p == '[') depth++, p++;
        else if (*p == ']') depth--, p++;
        else if (*p == ',' && depth > 0) p++;
        else if (nl->n >= NL_MAX) {
            tc_test_fail(__FILE__, __LINE__, "too many numbers in %s", member);
            return -1;
        } else if (!strncmp(p, "null", 4)) {
            nl->null[nl->n] = 1, nl->v[nl->n++] = 0;
            p += 4;
        } else {
            size_t k = json_number_len(p);
            char *end = NULL;
            double d = k ? strtod(p, &end) : 0;
            if (!k || end != p + k) {
                tc_test_fail(__FILE__, __LINE__, "%s: not a JSON number at '%.20s'", member, p);
                return -1;
            }
            nl->null[nl->n] = 0, nl->v[nl->n++] = d;
            p += k;
        }
    } while (depth > 0);
    return 0;
}

/* Compares a scanned point member against the core: n points of nc channels of
 * width numbers each; points with tri < 0 must be a single null. */
static void check_points_bits(const char *file, int line, const numlist *nl, size_t n, int nc, int width,
                              const double *x, const int32_t *tri) {
    size_t k = 0, bad = 0;
    for (size_t i = 0; i < n; i++) {
        if (tri[i] < 0) {
            if (k >= nl->n || !nl->null[k]) {
                if (bad++ < 3) tc_test_fail(file, line, "point %zu (outside) is not null", i);
            }
            k++;
            continue;
        }
        for (int j = 0; j < nc * width; j++, k++) {
            double want = x[i * (size_t)nc * (size_t)width + (size_t)j];
            if (k >= nl->n || nl->null[k] || !same_bits(nl->v[k], want)) {
                if (bad++ < 3)
                    tc_test_fail(file, line, "point %zu number %d: printed %.17g, core %.17g", i, j,
                                 k < nl->n ? nl->v[k] : -1.0, want);
            }
        }
    }
    if (k != nl->n) tc_test_fail(file, line, "%zu items printed, expected %zu", nl->n, k);
}
#define CHECK_POINTS_BITS(nl, n, nc, width, x, tri) \
    check_points_bits(__FILE__, __LINE__, nl, n, nc, width, x, tri)

static int run_ordinates(const char *body, tc_strbuf *out, tc_api_result *res) {
    tc_api_result_init(res);
    tc_strbuf_init(out);
    return tc_api_ordinates(body, strlen(body), NULL, out, res);
}

static int run_evaluate(const char *body, const char *points, tc_strbuf *out, tc_api_result *res) {
    tc_api_result_init(res);
    tc_strbuf_init(out);
    return tc_api_evaluate(body, strlen(body), points, points ? strlen(points) : 0, NULL, out, res);
}

static void done(tc_strbuf *out, tc_api_result *res, cJSON *root) {
    cJSON_Delete(root);
    tc_strbuf_free(out);
    tc_api_result_free(res);
}

static const char *str_item(const cJSON *o, const char *name) {
    const cJSON *s = cJSON_GetObjectItemCaseSensitive(o, name);
    return cJSON_IsString(s) ? s->valuestring : NULL;
}

/* ---- ordinates ---------------------------------------------------------------- */

static const char *const labels19[TC_CT_ORDINATES] = {"uuu", "vvv", "www", "uuv", "uuw", "uvv", "uww",
                                                      "vvw", "vww", "cuu", "cvv", "cww", "ccu", "ccv",
                                                      "ccw", "cuv", "cuw", "cvw", "ccc"};

/* Checks an ordinates response against the core's coefficients, bit for bit. */
static void check_ordinates_doc(const char *file, int line, const char *body, size_t len, const tc_strbuf *out) {
    ref r;
    if (ref_build(&r, body, len, TC_REQ_MESH)) {
        tc_test_fail(file, line, "the core could not build the reference");
        ref_free(&r);
        return;
    }
    int nc = tc_mesh_channel_count(r.mesh);
    int32_t nt = tc_mesh_triangle_count(r.mesh);
    cJSON *root = cJSON_ParseWithLength(out->buf, out->len);
    if (!cJSON_IsObject(root)) {
        tc_test_fail(file, line, "response is not a JSON object: %.200s", out->buf);
        ref_free(&r);
        cJSON_Delete(root);
        return;
    }
    const char *method = str_item(root, "method");
    if (!method || strcmp(method, tc_method_name(r.req->opt.method)))
        tc_test_fail(file, line, "method '%s'", method ? method : "(missing)");
    const char *opt[3][2] = {{"cross_boundary", tc_cross_name(r.req->opt.cross_boundary)},
                             {"wedges", tc_wedges_name(r.req->opt.wedges)},
                             {"tangents", tc_tangents_name(r.req->opt.tangents)}};
    for (int i = 0; i < 3; i++) {
        const char *s = str_item(root, opt[i][0]);
        if (!s || strcmp(s, opt[i][1])) tc_test_fail(file, line, "%s is '%s', expected '%s'", opt[i][0], s ? s : "(missing)", opt[i][1]);
    }
    const cJSON *ch = cJSON_GetObjectItemCaseSensitive(root, "channels");
    if (!cJSON_IsNumber(ch) || ch->valuedouble != nc) tc_test_fail(file, line, "channels is not %d", nc);
    const cJSON *lab = cJSON_GetObjectItemCaseSensitive(root, "labels");
    if (!cJSON_IsArray(lab) || cJSON_GetArraySize(lab) != TC_CT_ORDINATES) {
        tc_test_fail(file, line, "labels is not an array of 19");
    } else {
        for (int i = 0; i < TC_CT_ORDINATES; i++) {
            const cJSON *l = cJSON_GetArrayItem(lab, i);
            if (!cJSON_IsString(l) || strcmp(l->valuestring, labels19[i]))
                tc_test_fail(file, line, "labels[%d] is not '%s'", i, labels19[i]);
        }
    }
    const cJSON *ord = cJSON_GetObjectItemCaseSensitive(root, "ordinates");
    int shape_ok = cJSON_IsArray(ord) && cJSON_GetArraySize(ord) == nt;
    for (int t = 0; shape_ok && t < nt; t++) {
        const cJSON *a = cJSON_GetArrayItem(ord, t);
        shape_ok = cJSON_IsArray(a) && cJSON_GetArraySize(a) == nc;
        for (int c = 0; shape_ok && c < nc; c++) {
            const cJSON *b = cJSON_GetArrayItem(a, c);
            shape_ok = cJSON_IsArray(b) && cJSON_GetArraySize(b) == TC_CT_ORDINATES;
            for (int k = 0; shape_ok && k < TC_CT_ORDINATES; k++) shape_ok = cJSON_IsNumber(cJSON_GetArrayItem(b, k));
        }
    }
    if (!shape_ok) tc_test_fail(file, line, "ordinates is not [%d][%d][19] numbers", (int)nt, nc);
    const cJSON *w = cJSON_GetObjectItemCaseSensitive(root, "warnings");
    if (!cJSON_IsArray(w)) tc_test_fail(file, line, "warnings is not an array");

    static numlist nl;
    const double *coef = tc_recon_coefs(r.recon);
    size_t total = (size_t)nt * (size_t)nc * TC_CT_ORDINATES, bad = 0;
    if (scan_member(out->buf, "ordinates", &nl) == 0) {
        if (nl.n != total) tc_test_fail(file, line, "%zu ordinates printed, expected %zu", nl.n, total);
        for (size_t i = 0; i < nl.n && i < total; i++)
            if (nl.null[i] || !same_bits(nl.v[i], coef[i]))
                if (bad++ < 3)
                    tc_test_fail(file, line, "ordinate %zu: printed %.17g, core %.17g", i, nl.v[i], coef[i]);
    }
    cJSON_Delete(root);
    ref_free(&r);
}
#define CHECK_ORDINATES_DOC(body, len, out) check_ordinates_doc(__FILE__, __LINE__, body, len, out)

TEST(api_ordinates_square_light) {
    size_t len = 0;
    char *body = read_example("square-light.json", &len);
    CHECK_MSG(body != NULL, "cannot read api/examples/square-light.json");
    if (!body) return;
    tc_api_result res;
    tc_strbuf out;
    tc_api_result_init(&res);
    tc_strbuf_init(&out);
    int st = tc_api_ordinates(body, len, NULL, &out, &res);
    CHECK(st == 200 && res.status == 200);
    CHECK(res.diags.errors == 0);
    CHECK(out.len > 0 && out.buf[out.len - 1] == '\n');
    CHECK_ORDINATES_DOC(body, len, &out);

    /* The example's own options and an empty warnings list. */
    cJSON *root = cJSON_ParseWithLength(out.buf, out.len);
    CHECK(root != NULL);
    const char *tangents = str_item(root, "tangents");
    CHECK(tangents && !strcmp(tangents, "midpoints"));
    const char *method = str_item(root, "method");
    CHECK(method && !strcmp(method, "clough-tocher"));
    const cJSON *ord = cJSON_GetObjectItemCaseSensitive(root, "ordinates");
    CHECK(cJSON_GetArraySize(ord) == 4);
    CHECK(cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(root, "warnings")) == 0);
    /* uuu of triangle 0 is the value of its first vertex, exactly. */
    const cJSON *uuu = cJSON_GetArrayItem(cJSON_GetArrayItem(cJSON_GetArrayItem(ord, 0), 0), 0);
    CHECK(cJSON_IsNumber(uuu) && uuu->valuedouble == 0.027720037531);
    done(&out, &res, root);
    free(body);
}

TEST(api_ordinates_shadow_edges_and_channels) {
    size_t len = 0;
    char *body = read_example("shadow-edges.json", &len);
    CHECK_MSG(body != NULL, "cannot read api/examples/shadow-edges.json");
    if (body) {
        tc_api_result res;
        tc_strbuf out;
        tc_api_result_init(&res);
        tc_strbuf_init(&out);
        CHECK(tc_api_ordinates(body, len, NULL, &out, &res) == 200);
        CHECK_ORDINATES_DOC(body, len, &out);
        done(&out, &res, NULL);
        free(body);
    }
    /* Three channels, given gradients, another cross-boundary rule. */
    static const char three[] =
        "{\"vertices\": [[0,0],[1,0],[1,1],[0,1],[0.4,0.6]],"
        " \"triangles\": [[0,1,4],[1,2,4],[2,3,4],[3,0,4]],"
        " \"values\": [[0.1,1,-3],[0.2,2,-2],[0.3,3,-1],[0.4,4,0],[0.5,5,1]],"
        " \"gradients\": [[[1,0],[0,1],[1,1]],[[0.5,0.25],[0,0],[-1,2]],[[1,0],[0,1],[1,1]],"
        "[[0.125,-3],[7,0.1],[0.3,0.3]],[[0,0],[1,1],[2,2]]],"
        " \"method\": \"clough-tocher\", \"cross_boundary\": \"affine\", \"tangents\": \"given\"}";
    tc_api_result res;
    tc_strbuf out;
    CHECK(run_ordinates(three, &out, &res) == 200);
    CHECK_ORDINATES_DOC(three, strlen(three), &out);
    cJSON *root = cJSON_ParseWithLength(out.buf, out.len);
    const char *cross = str_item(root, "cross_boundary");
    CHECK(cross && !strcmp(cross, "affine"));
    const cJSON *ch = cJSON_GetObjectItemCaseSensitive(root, "channels");
    CHECK(cJSON_IsNumber(ch) && ch->valueint == 3);
    done(&out, &res, root);
}

/* ---- evaluate ----------------------------------------------------------------- */

#define EVAL_MESH                                                                  \
    "\"vertices\": [[0,0],[1,0],[1,1],[0,1],[0.5,0.5]],"                           \
    " \"triangles\": [[0,1,4],[1,2,4],[2,3,4],[3,0,4]],"                           \
    " \"gradients\": [[1,0.5],[0.25,-1],[0,0],[-0.5,2],[0.1,0.2]],"                \
    " \"tangents\": \"given\""
#define EVAL_POINTS                                                                \
    "\"points\": [[0.5,0.5],[0.25,0.3],[0.9,0.1],[1,1],[1.5,0.5],[0.3,0.7],"       \
    "[-0.2,-0.2],[0,0.5],[0.123456789,0.987654321]]"
#define EVAL_NPOINTS 9

/* Evaluates body (+ optional points doc) through the API and checks values,
 * gradients (when want_grads) and outside against tc_eval_points bit for bit,
 * and the JSON shapes: plain numbers when plain, else arrays of nc. */
static void check_eval_doc(const char *file, int line, const char *body, const char *points, int plain,
                           int want_grads) {
    tc_api_result res;
    tc_strbuf out;
    int st = run_evaluate(body, points, &out, &res);
    if (st != 200) {
        tc_test_fail(file, line, "status %d (%s: %s)", st, res.diags.count ? res.diags.items[0].path : "",
                     res.diags.count ? res.diags.items[0].message : "");
        done(&out, &res, NULL);
        return;
    }
    ref r, rp = {0};
    const tc_request *preq = NULL;
    if (ref_build(&r, body, strlen(body), points ? TC_REQ_MESH : TC_REQ_MESH | TC_REQ_POINTS)) {
        tc_test_fail(file, line, "reference build failed");
        goto out;
    }
    preq = r.req;
    if (points) {
        if (tc_request_parse(points, strlen(points), TC_REQ_POINTS, &rp.req, NULL) != TC_REQ_OK) {
            tc_test_fail(file, line, "reference points parse failed");
            goto out;
        }
        preq = rp.req;
    }
    size_t n = preq->npoints;
    int nc = tc_mesh_channel_count(r.mesh);
    double *val = calloc(n * (size_t)nc + 1, sizeof *val), *grad = calloc(2 * n * (size_t)nc + 1, sizeof *grad);
    int32_t *tri = calloc(n + 1, sizeof *tri);
    tc_eval_points(r.recon, r.L, n, preq->points, val, grad, tri);

    cJSON *root = cJSON_ParseWithLength(out.buf, out.len);
    if (!cJSON_IsObject(root)) tc_test_fail(file, line, "response is not a JSON object: %.200s", out.buf);
    const cJSON *jv = cJSON_GetObjectItemCaseSensitive(root, "values");
    const cJSON *jg = cJSON_GetObjectItemCaseSensitive(root, "gradients");
    const cJSON *jo = cJSON_GetObjectItemCaseSensitive(root, "outside");
    if (!cJSON_IsArray(cJSON_GetObjectItemCaseSensitive(root, "warnings")))
        tc_test_fail(file, line, "warnings is not an array");
    if (!cJSON_IsArray(jv) || (size_t)cJSON_GetArraySize(jv) != n) tc_test_fail(file, line, "values is not an array of %zu", n);
    if (want_grads && (!cJSON_IsArray(jg) || (size_t)cJSON_GetArraySize(jg) != n))
        tc_test_fail(file, line, "gradients is not an array of %zu", n);
    if (!want_grads && jg) tc_test_fail(file, line, "gradients present without with_gradients");
    for (size_t i = 0; cJSON_IsArray(jv) && i < n; i++) {
        const cJSON *v = cJSON_GetArrayItem(jv, (int)i);
        const cJSON *g = want_grads ? cJSON_GetArrayItem(jg, (int)i) : NULL;
        if (tri[i] < 0) {
            if (!cJSON_IsNull(v)) tc_test_fail(file, line, "values[%zu] (outside) is not null", i);
            if (want_grads && !cJSON_IsNull(g)) tc_test_fail(file, line, "gradients[%zu] (outside) is not null", i);
            continue;
        }
        if (plain) {
            if (!cJSON_IsNumber(v)) tc_test_fail(file, line, "values[%zu] is not a plain number", i);
            if (want_grads && !(cJSON_IsArray(g) && cJSON_GetArraySize(g) == 2 &&
                                cJSON_IsNumber(cJSON_GetArrayItem(g, 0))))
                tc_test_fail(file, line, "gradients[%zu] is not [gx, gy]", i);
        } else {
            if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != nc || !cJSON_IsNumber(cJSON_GetArrayItem(v, 0)))
                tc_test_fail(file, line, "values[%zu] is not an array of %d numbers", i, nc);
            if (want_grads) {
                int ok = cJSON_IsArray(g) && cJSON_GetArraySize(g) == nc;
                for (int c = 0; ok && c < nc; c++) {
                    const cJSON *gc = cJSON_GetArrayItem(g, c);
                    ok = cJSON_IsArray(gc) && cJSON_GetArraySize(gc) == 2 && cJSON_IsNumber(cJSON_GetArrayItem(gc, 1));
                }
                if (!ok) tc_test_fail(file, line, "gradients[%zu] is not [%d][2]", i, nc);
            }
        }
    }
    /* outside: exactly the indices with tri < 0, ascending. */
    int k = 0, nout = 0;
    for (size_t i = 0; i < n; i++) nout += tri[i] < 0;
    if (!cJSON_IsArray(jo) || cJSON_GetArraySize(jo) != nout) tc_test_fail(file, line, "outside does not list %d points", nout);
    for (size_t i = 0; cJSON_IsArray(jo) && i < n; i++)
        if (tri[i] < 0) {
            const cJSON *o = cJSON_GetArrayItem(jo, k++);
            if (!cJSON_IsNumber(o) || o->valuedouble != (double)i) tc_test_fail(file, line, "outside[%d] is not %zu", k - 1, i);
        }
    static numlist nl;
    if (scan_member(out.buf, "values", &nl) == 0) check_points_bits(file, line, &nl, n, nc, 1, val, tri);
    if (want_grads && scan_member(out.buf, "gradients", &nl) == 0) check_points_bits(file, line, &nl, n, nc, 2, grad, tri);
    cJSON_Delete(root);
    free(val), free(grad), free(tri);
out:
    ref_free(&r);
    tc_request_free(rp.req);
    done(&out, &res, NULL);
}
#define CHECK_EVAL_DOC(body, points, plain, grads) check_eval_doc(__FILE__, __LINE__, body, points, plain, grads)

TEST(api_evaluate_plain_values) {
    CHECK_EVAL_DOC("{" EVAL_MESH ", \"values\": [0.1,0.7,1.3,0.4,2.0], " EVAL_POINTS ", \"with_gradients\": true}",
                   NULL, 1, 1);
    CHECK_EVAL_DOC("{" EVAL_MESH ", \"values\": [0.1,0.7,1.3,0.4,2.0], " EVAL_POINTS ", \"with_gradients\": false}",
                   NULL, 1, 0);
    CHECK_EVAL_DOC("{" EVAL_MESH ", \"values\": [0.1,0.7,1.3,0.4,2.0], " EVAL_POINTS "}", NULL, 1, 0);
    /* The example pair: shadow edges with their points document. */
    size_t l1 = 0, l2 = 0;
    char *mesh = read_example("shadow-edges.json", &l1), *pts = read_example("points.json", &l2);
    CHECK(mesh && pts);
    if (mesh && pts) CHECK_EVAL_DOC(mesh, pts, 1, 1);
    free(mesh), free(pts);
}

TEST(api_evaluate_channel_arrays) {
    static const char *v2 = "\"values\": [[0.1,-1],[0.7,-2],[1.3,3],[0.4,4.5],[2.0,1e-3]]";
    char body[1024];
    /* Gradients must now be per channel: give none and estimate. */
    snprintf(body, sizeof body,
             "{\"vertices\": [[0,0],[1,0],[1,1],[0,1],[0.5,0.5]], \"triangles\": [[0,1,4],[1,2,4],[2,3,4],[3,0,4]],"
             " %s, %s, \"with_gradients\": true}", v2, EVAL_POINTS);
    CHECK_EVAL_DOC(body, NULL, 0, 1);
    snprintf(body, sizeof body,
             "{\"vertices\": [[0,0],[1,0],[1,1],[0,1],[0.5,0.5]], \"triangles\": [[0,1,4],[1,2,4],[2,3,4],[3,0,4]],"
             " %s, %s}", v2, EVAL_POINTS);
    CHECK_EVAL_DOC(body, NULL, 0, 0);
    /* One channel given as one-element arrays: the response keeps arrays. */
    CHECK_EVAL_DOC("{" EVAL_MESH ", \"values\": [[0.1],[0.7],[1.3],[0.4],[2.0]], " EVAL_POINTS
                   ", \"with_gradients\": true}", NULL, 0, 1);
}

TEST(api_evaluate_outside_points_are_null) {
    tc_api_result res;
    tc_strbuf out;
    int st = run_evaluate("{" EVAL_MESH ", \"values\": [0.1,0.7,1.3,0.4,2.0],"
                          " \"points\": [[2,2],[0.5,0.25],[-1e-9,0.5],[1.0000001,0],[0.5,0.5]], \"with_gradients\": true}",
                          NULL, &out, &res);
    CHECK(st == 200);
    cJSON *root = cJSON_ParseWithLength(out.buf, out.len);
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(root, "values");
    const cJSON *g = cJSON_GetObjectItemCaseSensitive(root, "gradients");
    const cJSON *o = cJSON_GetObjectItemCaseSensitive(root, "outside");
    CHECK(cJSON_GetArraySize(v) == 5 && cJSON_GetArraySize(g) == 5);
    int nulls[5] = {1, 0, 1, 1, 0};
    for (int i = 0; i < 5; i++) {
        CHECK_MSG(cJSON_IsNull(cJSON_GetArrayItem(v, i)) == nulls[i], "values[%d]", i);
        CHECK_MSG(cJSON_IsNull(cJSON_GetArrayItem(g, i)) == nulls[i], "gradients[%d]", i);
    }
    CHECK(cJSON_GetArraySize(o) == 3);
    CHECK(cJSON_GetArrayItem(o, 0) && cJSON_GetArrayItem(o, 0)->valueint == 0);
    CHECK(cJSON_GetArrayItem(o, 1) && cJSON_GetArrayItem(o, 1)->valueint == 2);
    CHECK(cJSON_GetArrayItem(o, 2) && cJSON_GetArrayItem(o, 2)->valueint == 3);
    done(&out, &res, root);

    /* No points inside at all, and no points at all. */
    st = run_evaluate("{" EVAL_MESH ", \"values\": [0.1,0.7,1.3,0.4,2.0], \"points\": [[5,5]]}", NULL, &out, &res);
    CHECK(st == 200);
    CHECK_STR_CONTAINS(out.buf, "\"values\":[null]");
    CHECK_STR_CONTAINS(out.buf, "\"outside\":[0]");
    done(&out, &res, NULL);
    st = run_evaluate("{" EVAL_MESH ", \"values\": [0.1,0.7,1.3,0.4,2.0], \"points\": []}", NULL, &out, &res);
    CHECK(st == 200);
    root = cJSON_ParseWithLength(out.buf, out.len);
    CHECK(cJSON_IsArray(cJSON_GetObjectItemCaseSensitive(root, "values")));
    CHECK(cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(root, "values")) == 0);
    CHECK(cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(root, "outside")) == 0);
    done(&out, &res, root);
}

/* The path of the first error (warnings about the mesh may come before it). */
static int first_error_path_is(const tc_diags *d, const char *path) {
    for (int i = 0; i < d->count; i++)
        if (d->items[i].severity == TC_SEV_ERROR) return !strcmp(d->items[i].path, path);
    return 0;
}

TEST(api_evaluate_points_document) {
    static const char mesh_only[] = "{" EVAL_MESH ", \"values\": [0.1,0.7,1.3,0.4,2.0]}";
    static const char mesh_with_points[] =
        "{" EVAL_MESH ", \"values\": [0.1,0.7,1.3,0.4,2.0], \"points\": [[0.5,0.5],[0.1,0.1]], \"with_gradients\": false}";
    static const char pts3[] = "{\"points\": [[0.9,0.2],[3,3],[0.25,0.75]], \"with_gradients\": true}";
    /* The second document provides the points ... */
    CHECK_EVAL_DOC(mesh_only, pts3, 1, 1);
    /* ... and overrides those (and with_gradients) of the mesh body. */
    CHECK_EVAL_DOC(mesh_with_points, pts3, 1, 1);
    tc_api_result res;
    tc_strbuf out;
    CHECK(run_evaluate(mesh_with_points, pts3, &out, &res) == 200);
    cJSON *root = cJSON_ParseWithLength(out.buf, out.len);
    CHECK(cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(root, "values")) == 3);
    CHECK(cJSON_GetObjectItemCaseSensitive(root, "gradients") != NULL);
    done(&out, &res, root);
    /* Same answer as one document holding the same points. */
    tc_strbuf one;
    tc_api_result r1;
    CHECK(run_evaluate(mesh_with_points, "{\"points\": [[0.5,0.5],[0.1,0.1]]}", &out, &res) == 200);
    CHECK(run_evaluate(mesh_with_points, NULL, &one, &r1) == 200);
    CHECK(out.len == one.len && out.buf && one.buf && !memcmp(out.buf, one.buf, out.len));
    done(&one, &r1, NULL);
    done(&out, &res, NULL);

    /* Without points anywhere: 400 naming "points". */
    int st = run_evaluate(mesh_only, NULL, &out, &res);
    CHECK(st == 400 && res.status == 400);
    CHECK(out.len == 0);
    int found = 0;
    for (int i = 0; i < res.diags.count; i++)
        found |= res.diags.items[i].severity == TC_SEV_ERROR && !strcmp(res.diags.items[i].path, "points") &&
                 strstr(res.diags.items[i].message, "points") != NULL;
    CHECK_MSG(found, "no error at path 'points'");
    tc_strbuf pb;
    tc_strbuf_init(&pb);
    tc_api_problem(&pb, &res);
    root = cJSON_ParseWithLength(pb.buf, pb.len);
    const char *path = str_item(root, "path");
    CHECK(path && !strcmp(path, "points"));
    CHECK_STR_CONTAINS(str_item(root, "detail"), "points");
    cJSON_Delete(root);
    tc_strbuf_free(&pb);
    done(&out, &res, NULL);

    /* A points document without points is malformed too, as is a broken one. */
    CHECK(run_evaluate(mesh_only, "{\"with_gradients\": true}", &out, &res) == 400);
    CHECK(res.diags.errors > 0 && first_error_path_is(&res.diags, "points"));
    done(&out, &res, NULL);
    CHECK(run_evaluate(mesh_only, "{\"points\": [[0,0]", &out, &res) == 400);
    done(&out, &res, NULL);
    CHECK(run_evaluate(mesh_only, "{\"points\": [[0,0,1]]}", &out, &res) == 400);
    done(&out, &res, NULL);
}

/* ---- errors and warnings ------------------------------------------------------ */

/* Renders res as a problem document and checks its members. */
static void check_problem(const char *file, int line, const tc_api_result *res, const char *type, int status,
                          const char *path_prefix) {
    tc_strbuf pb;
    tc_strbuf_init(&pb);
    tc_api_problem(&pb, res);
    cJSON *root = cJSON_ParseWithLength(pb.buf, pb.len);
    if (!cJSON_IsObject(root)) {
        tc_test_fail(file, line, "problem is not a JSON object: %.200s", pb.buf);
        tc_strbuf_free(&pb);
        return;
    }
    const char *t = str_item(root, "type"), *title = str_item(root, "title"), *detail = str_item(root, "detail"),
               *path = str_item(root, "path");
    const cJSON *st = cJSON_GetObjectItemCaseSensitive(root, "status");
    const cJSON *ec = cJSON_GetObjectItemCaseSensitive(root, "error_count");
    const cJSON *errs = cJSON_GetObjectItemCaseSensitive(root, "errors");
    if (!t || strcmp(t, type)) tc_test_fail(file, line, "type '%s', expected '%s'", t ? t : "(missing)", type);
    if (!title || !*title) tc_test_fail(file, line, "no title");
    if (!cJSON_IsNumber(st) || st->valueint != status) tc_test_fail(file, line, "status is not %d", status);
    if (!detail || !*detail) tc_test_fail(file, line, "no detail");
    if (!path || strncmp(path, path_prefix, strlen(path_prefix)))
        tc_test_fail(file, line, "path '%s' does not start with '%s'", path ? path : "(missing)", path_prefix);
    if (!cJSON_IsNumber(ec) || ec->valueint < 1 || ec->valueint != res->diags.errors)
        tc_test_fail(file, line, "error_count is not %d", res->diags.errors);
    if (!cJSON_IsArray(errs) || cJSON_GetArraySize(errs) < 1) {
        tc_test_fail(file, line, "errors is not a non-empty array");
    } else {
        const cJSON *e;
        cJSON_ArrayForEach(e, errs) {
            const char *ep = str_item(e, "path"), *em = str_item(e, "message");
            if (!ep || !em || !*em) tc_test_fail(file, line, "an errors[] entry lacks path or message");
        }
        const char *m0 = str_item(cJSON_GetArrayItem(errs, 0), "message");
        const char *p0 = str_item(cJSON_GetArrayItem(errs, 0), "path");
        if (!m0 || !detail || strcmp(m0, detail)) tc_test_fail(file, line, "detail is not errors[0].message");
        if (!p0 || !path || strcmp(p0, path)) tc_test_fail(file, line, "path is not errors[0].path");
    }
    cJSON_Delete(root);
    tc_strbuf_free(&pb);
}
#define CHECK_PROBLEM(res, type, status, path) check_problem(__FILE__, __LINE__, res, type, status, path)

TEST(api_errors_malformed_request) {
    static const char *bad[] = {
        "{\"vertices\": [[0,0],[1,0]",                        /* truncated */
        "not json",                                           /* not JSON */
        "[1, 2, 3]",                                          /* not an object */
        "{\"vertices\": [[0,0],[1,0],[0,1]], \"triangles\": [[0,1,2]]}", /* values missing */
        "{\"vertices\": \"many\", \"triangles\": [[0,1,2]], \"values\": [1,2,3]}",
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        tc_api_result res;
        tc_strbuf out;
        tc_api_result_init(&res);
        tc_strbuf_init(&out);
        tc_strbuf_puts(&out, "keep");
        int st = tc_api_ordinates(bad[i], strlen(bad[i]), NULL, &out, &res);
        CHECK_MSG(st == 400 && res.status == 400, "case %zu: status %d", i, st);
        CHECK_MSG(out.len == 4 && !strcmp(out.buf, "keep"), "case %zu: out was touched", i);
        CHECK_PROBLEM(&res, "/problems/malformed-request", 400, "");
        done(&out, &res, NULL);
        /* evaluate agrees */
        st = run_evaluate(bad[i], "{\"points\": [[0,0]]}", &out, &res);
        CHECK_MSG(st == 400, "case %zu: evaluate status %d", i, st);
        CHECK_PROBLEM(&res, "/problems/malformed-request", 400, "");
        done(&out, &res, NULL);
    }
    /* The path of a shape error is that of the element at fault. */
    tc_api_result res;
    tc_strbuf out;
    CHECK(run_ordinates("{\"vertices\": [[0,0],[1,\"x\"],[0,1]], \"triangles\": [[0,1,2]], \"values\": [1,2,3]}",
                        &out, &res) == 400);
    CHECK_PROBLEM(&res, "/problems/malformed-request", 400, "vertices[1][1]");
    done(&out, &res, NULL);
}

TEST(api_errors_invalid_mesh) {
    /* Triangle 1's corners are collinear. */
    static const char zero_area[] =
        "{\"vertices\": [[0,0],[1,0],[2,0],[0,1]], \"triangles\": [[0,1,3],[0,1,2]], \"values\": [1,2,3,4]}";
    tc_api_result res;
    tc_strbuf out;
    CHECK(run_ordinates(zero_area, &out, &res) == 422);
    CHECK(res.status == 422 && out.len == 0);
    CHECK_PROBLEM(&res, "/problems/invalid-mesh", 422, "triangles[1]");
    CHECK(res.diags.count > 0 && !strcmp(res.diags.items[0].path, "triangles[1]"));
    done(&out, &res, NULL);
    CHECK(run_evaluate(zero_area, "{\"points\": [[0.1,0.1]]}", &out, &res) == 422);
    CHECK_PROBLEM(&res, "/problems/invalid-mesh", 422, "triangles[1]");
    done(&out, &res, NULL);
    /* Index out of range: the element itself. */
    CHECK(run_ordinates("{\"vertices\": [[0,0],[1,0],[0,1]], \"triangles\": [[0,1,7]], \"values\": [1,2,3]}", &out,
                        &res) == 422);
    CHECK_PROBLEM(&res, "/problems/invalid-mesh", 422, "triangles[0][2]");
    done(&out, &res, NULL);
    /* An unknown method name is a value error as well. */
    CHECK(run_ordinates("{\"vertices\": [[0,0],[1,0],[0,1]], \"triangles\": [[0,1,2]], \"values\": [1,2,3],"
                        " \"method\": \"bicubic\"}", &out, &res) == 422);
    CHECK_PROBLEM(&res, "/problems/invalid-mesh", 422, "method");
    done(&out, &res, NULL);
}

TEST(api_warnings_in_response) {
    static const char body[] = "{\"vertices\": [[0,0],[1,0],[0,1]], \"triangles\": [[0,1,2]], \"values\": [1,2,3],"
                               " \"colour\": \"red\", \"method\": \"linear\", \"point\": [[0.1,0.1]],"
                               " \"points\": [[0.2,0.2]]}";
    for (int endpoint = 0; endpoint < 2; endpoint++) {
        tc_api_result res;
        tc_strbuf out;
        int st = endpoint ? run_evaluate(body, NULL, &out, &res) : run_ordinates(body, &out, &res);
        CHECK(st == 200);
        CHECK(res.diags.warnings == 2);
        cJSON *root = cJSON_ParseWithLength(out.buf, out.len);
        const cJSON *w = cJSON_GetObjectItemCaseSensitive(root, "warnings");
        CHECK_MSG(cJSON_IsArray(w) && cJSON_GetArraySize(w) == 2, "endpoint %d: warnings", endpoint);
        const cJSON *w0 = cJSON_GetArrayItem(w, 0), *w1 = cJSON_GetArrayItem(w, 1);
        const char *p0 = str_item(w0, "path"), *p1 = str_item(w1, "path");
        CHECK(p0 && !strcmp(p0, "colour"));
        CHECK(p1 && !strcmp(p1, "point"));
        CHECK_STR_CONTAINS(str_item(w0, "message"), "unknown field 'colour'");
        CHECK_STR_CONTAINS(str_item(w1, "message"), "did you mean 'points'");
        done(&out, &res, root);
    }
    /* A warning of a points document arrives too. */
    tc_api_result res;
    tc_strbuf out;
    CHECK(run_evaluate("{\"vertices\": [[0,0],[1,0],[0,1]], \"triangles\": [[0,1,2]], \"values\": [1,2,3]}",
                       "{\"points\": [[0.2,0.2]], \"with_gradient\": true}", &out, &res) == 200);
    CHECK_STR_CONTAINS(out.buf, "\"warnings\":[{\"path\":\"with_gradient\",\"message\":");
    done(&out, &res, NULL);
    /* A clean request has an empty warnings array. */
    CHECK(run_ordinates("{\"vertices\": [[0,0],[1,0],[0,1]], \"triangles\": [[0,1,2]], \"values\": [1,2,3]}", &out,
                        &res) == 200);
    CHECK_STR_CONTAINS(out.buf, "\"warnings\":[]}");
    done(&out, &res, NULL);
}

/* ---- determinism ---------------------------------------------------------------- */

TEST(api_output_deterministic) {
    static const char *files[] = {"square-light.json", "shadow-edges.json"};
    for (int f = 0; f < 2; f++) {
        size_t len = 0;
        char *body = read_example(files[f], &len);
        CHECK_MSG(body != NULL, "cannot read %s", files[f]);
        if (!body) continue;
        tc_strbuf a, b;
        tc_api_result ra, rb;
        tc_api_result_init(&ra), tc_api_result_init(&rb);
        tc_strbuf_init(&a), tc_strbuf_init(&b);
        CHECK(tc_api_ordinates(body, len, NULL, &a, &ra) == 200);
        /* Something else in between must not matter. */
        tc_strbuf junk;
        tc_api_result rj;
        CHECK(run_evaluate("{" EVAL_MESH ", \"values\": [9,8,7,6,5], " EVAL_POINTS "}", NULL, &junk, &rj) == 200);
        done(&junk, &rj, NULL);
        CHECK(tc_api_ordinates(body, len, NULL, &b, &rb) == 200);
        CHECK_MSG(a.len > 0 && a.len == b.len && !memcmp(a.buf, b.buf, a.len), "%s: outputs differ", files[f]);
        done(&a, &ra, NULL);
        done(&b, &rb, NULL);
        free(body);
    }
    /* evaluate too */
    static const char body[] = "{" EVAL_MESH ", \"values\": [0.1,0.7,1.3,0.4,2.0], " EVAL_POINTS ", \"with_gradients\": true}";
    tc_strbuf a, b;
    tc_api_result ra, rb;
    CHECK(run_evaluate(body, NULL, &a, &ra) == 200);
    CHECK(run_evaluate(body, NULL, &b, &rb) == 200);
    CHECK(a.len > 0 && a.len == b.len && !memcmp(a.buf, b.buf, a.len));
    done(&a, &ra, NULL);
    done(&b, &rb, NULL);
}

/* ---- exact numbers -------------------------------------------------------------- */

/* Values on a 3x3 grid of vertices (8 triangles), printed into the request
 * as text that reads back exactly. */
#define AWK_N 9
static const char *const awk_text[AWK_N] = {"0.1", "0.3333333333333333", "1e-300", "5e-324", "-0.0",
                                            "1e300", "-2.5", "0.7", "1e-7"};
static double awk_value(int i) {
    static const double v[AWK_N] = {0.1, 1.0 / 3, 1e-300, 5e-324, -0.0, 1e300, -2.5, 0.7, 1e-7};
    return v[i];
}

static void awk_request(char *buf, size_t cap, const char *method, int nchan, int eval) {
    size_t n = (size_t)snprintf(buf, cap,
                                "{\"vertices\": [[0,0],[1,0],[2,0],[0,1],[1,1],[2,1],[0,2],[1,2],[2,2]],"
                                " \"triangles\": [[0,1,4],[0,4,3],[1,2,5],[1,5,4],[3,4,7],[3,7,6],[4,5,8],[4,8,7]],"
                                " \"method\": \"%s\", \"values\": [",
                                method);
    for (int i = 0; i < AWK_N; i++) {
        if (nchan == 1)
            n += (size_t)snprintf(buf + n, cap - n, "%s%s", i ? "," : "", awk_text[i]);
        else /* channel 1 is the list rotated */
            n += (size_t)snprintf(buf + n, cap - n, "%s[%s,%s]", i ? "," : "", awk_text[i], awk_text[(i + 4) % AWK_N]);
    }
    n += (size_t)snprintf(buf + n, cap - n, "]");
    if (eval)
        n += (size_t)snprintf(buf + n, cap - n,
                              ", \"points\": [[0,0],[1,0],[2,0],[0,1],[1,1],[2,1],[0,2],[1,2],[2,2]], \"with_gradients\": true");
    snprintf(buf + n, cap - n, "}");
}

/* Evaluates the awkward mesh at its vertices through the API and checks each
 * printed value reads back to the input value bit for bit (a zero of either
 * sign may come back as +0: -0.0 + 0.0 is +0.0 in any weighted sum). */
static void check_vertex_values(const char *file, int line, const char *method, int nchan) {
    static numlist nl;
    char body[2048];
    awk_request(body, sizeof body, method, nchan, 1);
    tc_api_result res;
    tc_strbuf out;
    int st = run_evaluate(body, NULL, &out, &res);
    if (st != 200) tc_test_fail(file, line, "%s/%d: status %d", method, nchan, st);
    if (st == 200 && scan_member(out.buf, "values", &nl) == 0) {
        if (nl.n != (size_t)AWK_N * (size_t)nchan) tc_test_fail(file, line, "%s/%d: %zu values", method, nchan, nl.n);
        for (size_t k = 0; k < nl.n && k < (size_t)AWK_N * (size_t)nchan; k++) {
            int i = (int)(nchan == 1 ? k : k / 2), c = nchan == 1 ? 0 : (int)(k % 2);
            double want = awk_value(c ? (i + 4) % AWK_N : i);
            int ok = !nl.null[k] && (want == 0 ? nl.v[k] == 0 : same_bits(nl.v[k], want));
            if (!ok)
                tc_test_fail(file, line, "%s/%d: vertex %d channel %d: evaluates to %.17g, input %.17g", method, nchan,
                             i, c, nl.v[k], want);
        }
    }
    done(&out, &res, NULL);
}

TEST(api_numbers_round_trip) {
    for (int i = 0; i < AWK_N; i++) CHECK_MSG(same_bits(strtod(awk_text[i], NULL), awk_value(i)), "literal %d", i);
    static const char *methods[] = {"clough-tocher", "clough-tocher-c1", "linear"};
    char body[2048];
    static numlist nl;
    for (size_t m = 0; m < sizeof methods / sizeof methods[0]; m++)
        for (int nchan = 1; nchan <= 2; nchan++) {
            /* The printed values and gradients are the core's bits, finite. */
            awk_request(body, sizeof body, methods[m], nchan, 1);
            CHECK_EVAL_DOC(body, NULL, nchan == 1, 1);
            /* Linear interpolation is exact at the vertices. */
            if (!strcmp(methods[m], "linear")) check_vertex_values(__FILE__, __LINE__, methods[m], nchan);

            /* The corner ordinates are the input values, -0.0 and 5e-324 included. */
            tc_api_result res;
            tc_strbuf out;
            awk_request(body, sizeof body, methods[m], nchan, 0);
            int st = run_ordinates(body, &out, &res);
            CHECK_MSG(st == 200, "%s/%d: ordinates status %d", methods[m], nchan, st);
            if (st == 200 && scan_member(out.buf, "ordinates", &nl) == 0) {
                static const int32_t tris[8][3] = {{0, 1, 4}, {0, 4, 3}, {1, 2, 5}, {1, 5, 4},
                                                   {3, 4, 7}, {3, 7, 6}, {4, 5, 8}, {4, 8, 7}};
                int nk = m < 2 ? TC_CT_ORDINATES : 3; /* linear: u v w */
                CHECK_MSG(nl.n == (size_t)8 * (size_t)nchan * (size_t)nk, "%s/%d: %zu ordinates", methods[m], nchan, nl.n);
                for (int t = 0; t < 8 && nl.n == (size_t)8 * (size_t)nchan * (size_t)nk; t++)
                    for (int c = 0; c < nchan; c++)
                        for (int k = 0; k < 3; k++) {
                            double want = awk_value(c ? (tris[t][k] + 4) % AWK_N : tris[t][k]);
                            double got = nl.v[((size_t)t * (size_t)nchan + (size_t)c) * (size_t)nk + (size_t)k];
                            CHECK_MSG(same_bits(got, want), "%s/%d: triangle %d corner %d: got %.17g, input %.17g",
                                      methods[m], nchan, t, k, got, want);
                        }
                if (m < 2) CHECK_ORDINATES_DOC(body, strlen(body), &out);
                for (size_t k = 0; k < nl.n; k++) CHECK_MSG(isfinite(nl.v[k]), "ordinate %zu not finite", k);
            }
            /* The text itself: the shortest round trips "-0", 5e-324, 1e300 and 1/3
             * (5e-324 was "4.94065645841247e-324" before Schubfach, issue 17). */
            if (st == 200) {
                CHECK_STR_CONTAINS(out.buf, ",-0,");
                CHECK_STR_CONTAINS(out.buf, "5e-324");
                CHECK(!strstr(out.buf, "4.94065645841247e-324"));
                CHECK_STR_CONTAINS(out.buf, "1e+300");
                CHECK_STR_CONTAINS(out.buf, "0.3333333333333333,");
            }
            done(&out, &res, NULL);
        }
}

/* The cubic pieces interpolate exactly too: the value at a corner of the
 * piece that owns it is that corner's uuu ordinate, which is the input. */
TEST(api_eval_cubic_exact_at_vertices) {
    static const char *methods[] = {"clough-tocher", "clough-tocher-c1"};
    for (int m = 0; m < 2; m++)
        for (int nchan = 1; nchan <= 2; nchan++) check_vertex_values(__FILE__, __LINE__, methods[m], nchan);
    /* The smallest case: one triangle, given values 0.1 and 0.7. */
    tc_api_result res;
    tc_strbuf out;
    CHECK(run_evaluate("{\"vertices\": [[0,0],[1,0],[0,1]], \"triangles\": [[0,1,2]], \"values\": [0.25, 0.1, 0.7],"
                       " \"points\": [[0,0],[1,0],[0,1]]}", NULL, &out, &res) == 200);
    CHECK_STR_CONTAINS(out.buf, "\"values\":[0.25,0.1,0.7]");
    done(&out, &res, NULL);
}

/* ---- tiles of values beyond what a format's samples hold ---- */

/* Values near 1e300 (valid: the ordinates stay within 1e300) render to float
 * tiles as +-FLT_MAX, never infinities, with a warning (issue 14: 87 of 6 000
 * extreme meshes gave raw/EXR/TIFF tiles with infinities, and said nothing).
 * The formats OpenImageIO writes (exr-half: 65504) are checked through the
 * daemon (tests/endpoint), so this process never loads the plugin. */
static const char *const HUGE_TILE =
    "{\"vertices\": [[0,0],[1,0],[1,1],[0,1]], \"triangles\": [[0,1,2],[0,2,3]], \"values\": [%s, %s, %s, %s],"
    " \"method\": \"linear\", \"format\": \"%s\","
    " \"viewport\": {\"x0\": 0, \"y0\": 0, \"x1\": 1, \"y1\": 1, \"width\": 8, \"height\": 8}}";

static int render_huge(const char *a, const char *b, const char *fmt, tc_strbuf *out, tc_api_result *res) {
    char body[512];
    snprintf(body, sizeof body, HUGE_TILE, a, b, a, b, fmt);
    tc_strbuf_init(out);
    tc_api_result_init(res);
    return tc_api_render_as(body, strlen(body), -1, NULL, out, res);
}

static int warnings_with(const tc_api_result *res, const char *needle) {
    int n = 0;
    for (int i = 0; i < res->diags.count; i++)
        n += res->diags.items[i].severity == TC_SEV_WARNING && strstr(res->diags.items[i].message, needle) != NULL;
    return n;
}

TEST(api_render_saturates_to_the_format_with_a_warning) {
    tc_strbuf out;
    tc_api_result res;
    CHECK(render_huge("1e300", "-1e300", "raw", &out, &res) == 200 && out.len == 64 * sizeof(float));
    int inf = 0, at_max = 0;
    for (size_t i = 0; i + sizeof(float) <= out.len; i += sizeof(float)) {
        float f;
        memcpy(&f, out.buf + i, sizeof f);
        inf += isinf(f) || isnan(f), at_max += fabsf(f) == FLT_MAX;
    }
    CHECK_MSG(inf == 0 && at_max > 0, "%d infinite samples, %d at FLT_MAX", inf, at_max);
    CHECK_MSG(warnings_with(&res, "largest value raw holds") == 1, "%d warnings", res.diags.count);
    tc_strbuf_free(&out);
    tc_api_result_free(&res);
    /* Within range: no warning. */
    CHECK(render_huge("1e30", "-1e30", "raw", &out, &res) == 200 && warnings_with(&res, "largest value") == 0);
    tc_strbuf_free(&out);
    tc_api_result_free(&res);
}

/* The samples limit counts channels: a one-triangle, 16-channel request for a
 * 4096^2 raw tile asked for a 1 GiB answer under the pixels limit alone (issue
 * 14: 367 bytes in, +3.2 GB). Refused with 413 naming the viewport before any
 * tile is allocated; within the limit, or with fewer channels, it renders. */
TEST(api_render_samples_limit_counts_channels) {
    char body[1024];
    char vals[512] = "";
    for (int v = 0; v < 3; v++) {
        strcat(vals, v ? ",[" : "[");
        for (int ch = 0; ch < 16; ch++) strcat(vals, ch ? ",0.5" : "0.5");
        strcat(vals, "]");
    }
    snprintf(body, sizeof body,
             "{\"vertices\": [[0,0],[1,0],[0,1]], \"triangles\": [[0,1,2]], \"values\": [%s], \"method\": \"linear\","
             " \"format\": \"raw\", \"viewport\": {\"x0\": 0, \"y0\": 0, \"x1\": 1, \"y1\": 1, \"width\": 64, \"height\": 64}}",
             vals);
    tc_api_limits lim = {.max_pixels = 64 * 64, .max_samples = 64 * 64 * 4, .render_threads = 1};
    tc_strbuf out;
    tc_api_result res;
    tc_strbuf_init(&out);
    tc_api_result_init(&res);
    CHECK(tc_api_render_as(body, strlen(body), -1, &lim, &out, &res) == 413 && out.len == 0);
    CHECK_MSG(res.diags.count && !strcmp(res.diags.items[0].path, "viewport") &&
                  strstr(res.diags.items[0].message, "65536 samples (pixels x channels)"),
              "%s", res.diags.count ? res.diags.items[0].message : "-");
    tc_strbuf_free(&out);
    tc_api_result_free(&res);
    lim.max_samples = 64 * 64 * 16;
    tc_strbuf_init(&out);
    tc_api_result_init(&res);
    CHECK(tc_api_render_as(body, strlen(body), -1, &lim, &out, &res) == 200 && out.len == 64 * 64 * 16 * sizeof(float));
    tc_strbuf_free(&out);
    tc_api_result_free(&res);
}

/* One render under a memory budget: it fits (the answer's share stays reserved
 * until released, the rest is given back at once), it does not fit beside what
 * others hold (503, retry_after, nothing allocated), it could never fit (413
 * naming the viewport). tc_budget itself: a take past the limit changes nothing. */
TEST(api_render_memory_budget) {
    const char *body = "{\"vertices\": [[0,0],[1,0],[0,1]], \"triangles\": [[0,1,2]], \"values\": [1,2,3],"
                       " \"format\": \"raw\", \"viewport\": {\"x0\": 0, \"y0\": 0, \"x1\": 1, \"y1\": 1,"
                       " \"width\": 512, \"height\": 512}}"; /* 1 MiB of answer */
    tc_budget b;
    tc_budget_init(&b, 4 << 20);
    CHECK(tc_budget_take(&b, 3 << 20) == 1 && tc_budget_take(&b, 2 << 20) == 0 && tc_budget_used(&b) == 3 << 20);
    tc_budget_give(&b, 3 << 20);
    CHECK(tc_budget_used(&b) == 0 && tc_budget_take(NULL, 1) == 1);
    tc_api_limits lim = {.render_threads = 1, .memory = &b};
    tc_strbuf out;
    tc_api_result res;
    tc_strbuf_init(&out);
    tc_api_result_init(&res);
    CHECK(tc_api_render_as(body, strlen(body), -1, &lim, &out, &res) == 200 && out.len == 512 * 512 * 4);
    CHECK_MSG(res.held >= (int64_t)out.len && tc_budget_used(&b) == res.held, "held %lld, used %lld",
              (long long)res.held, (long long)tc_budget_used(&b));
    tc_api_result_release(&res);
    CHECK(tc_budget_used(&b) == 0 && res.held == 0);
    tc_strbuf_free(&out);
    tc_api_result_free(&res);
    CHECK(tc_budget_take(&b, 3 << 20) == 1); /* others hold 3 of 4 MiB */
    tc_api_result_init(&res);
    CHECK(tc_api_render_as(body, strlen(body), -1, &lim, &out, &res) == 503 && out.len == 0 && res.retry_after == 1);
    CHECK(tc_budget_used(&b) == 3 << 20 && res.diags.count && strstr(res.diags.items[0].message, "retry"));
    tc_api_result_free(&res);
    tc_budget_give(&b, 3 << 20);
    tc_budget_init(&b, 128 << 10); /* less than the answer alone */
    tc_api_result_init(&res);
    CHECK(tc_api_render_as(body, strlen(body), -1, &lim, &out, &res) == 413 && out.len == 0);
    CHECK(res.diags.count && !strcmp(res.diags.items[0].path, "viewport") && tc_budget_used(&b) == 0);
    tc_api_result_free(&res);
    tc_strbuf_free(&out);
}

/* The same raw render at 1 and at 16 threads under a budget of budget_mib: both fit; then,
 * without a budget, both give the same want_len bytes. */
static void raw_at_1_and_16_threads(const char *body, int budget_mib, size_t want_len) {
    tc_budget b;
    tc_budget_init(&b, (int64_t)budget_mib << 20);
    tc_strbuf out[2];
    tc_api_result res;
    for (int k = 0; k < 2; k++) {
        tc_api_limits lim = {.render_threads = k ? 16 : 1, .memory = &b};
        tc_strbuf_init(&out[k]);
        tc_api_result_init(&res);
        int st = tc_api_render_as(body, strlen(body), -1, &lim, &out[k], &res);
        CHECK_MSG(st == 200, "%d threads: status %d", lim.render_threads, st);
        tc_api_result_release(&res);
        tc_api_result_free(&res);
        tc_strbuf_free(&out[k]);
    }
    for (int k = 0; k < 2; k++) {
        tc_api_limits lim = {.render_threads = k ? 16 : 1};
        tc_strbuf_init(&out[k]);
        tc_api_result_init(&res);
        CHECK(tc_api_render_as(body, strlen(body), -1, &lim, &out[k], &res) == 200 && out[k].len == want_len);
        tc_api_result_free(&res);
    }
    CHECK_MSG(out[0].len == out[1].len && !memcmp(out[0].buf, out[1].buf, out[0].len), "16 threads render other bytes");
    tc_strbuf_free(&out[0]), tc_strbuf_free(&out[1]);
}

#define SQUARE_4096x300 "{\"vertices\": [[0,0],[1,0],[0,1],[1,1]], \"triangles\": [[0,1,2],[1,3,2]], \"values\": [1,2,3,5]," \
                        " \"viewport\": {\"x0\": 0, \"y0\": 0, \"x1\": 1, \"y1\": 1, \"width\": 4096, \"height\": 300}, "

/* A render on many threads takes bands of ROWS_PER_THREAD rows per thread where 8 MiB
 * holds fewer (api.c band_rows): a 4096 x 300 grey EXR render reserves its answer (~9.4 MiB
 * with alpha) and a band of 96 rows on one thread (a peak of ~17 MiB), of 256 on sixteen
 * (~30 MiB). Under a 24 MiB budget of which others hold 12, the first is told to retry
 * (503: it could fit) and the second is refused as never fitting (413, naming the viewport).
 * Neither encodes (the image plugin stays unloaded for test_image). */
TEST(api_render_band_rows_follow_threads) {
    const char *body = SQUARE_4096x300 "\"format\": \"exr\"}";
    tc_budget b;
    tc_budget_init(&b, 24 << 20);
    CHECK(tc_budget_take(&b, 12 << 20) == 1);
    for (int k = 0; k < 2; k++) {
        tc_api_limits lim = {.render_threads = k ? 16 : 1, .memory = &b};
        tc_strbuf out;
        tc_api_result res;
        tc_strbuf_init(&out);
        tc_api_result_init(&res);
        int st = tc_api_render_as(body, strlen(body), -1, &lim, &out, &res);
        CHECK_MSG(st == (k ? 413 : 503), "%d threads: status %d", lim.render_threads, st);
        CHECK(res.diags.count && !strcmp(res.diags.items[0].path, k ? "viewport" : "") && tc_budget_used(&b) == 12 << 20);
        tc_api_result_free(&res);
        tc_strbuf_free(&out);
    }
    CHECK(!tc_img_loaded());
}

/* A raw render goes straight into its answer, in one band: it reserves its answer (~4.7 MiB)
 * and tc_render's owners (32 rows a thread: 8 MiB on sixteen), no band, so sixteen threads
 * fit a 16 MiB budget (with a band of 256 rows, ~25 MiB, they did not). */
TEST(api_render_raw_reserves_no_band) {
    raw_at_1_and_16_threads(SQUARE_4096x300 "\"format\": \"raw\"}", 16, (size_t)4096 * 300 * 4);
}
