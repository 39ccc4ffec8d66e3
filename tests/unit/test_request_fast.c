/* test_request_fast.c — the fast path for big arrays (io/request_fast.c) against the cJSON path
 * (tc_request__fast_arrays(0)): same status, same findings (paths, messages, line and column),
 * same request (canonical text of io/request_write.c, points bit for bit) on random and bad input. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "io/request.h"
#include "io/request_write.h"
#include "io/strbuf.h"

static uint64_t xs(uint64_t *s) {
    *s ^= *s << 13, *s ^= *s >> 7, *s ^= *s << 17;
    return *s;
}

/* One parse: status, every finding as text, the canonical request and its points. */
typedef struct {
    int status, taken;
    char *findings, *canon;
} outcome;

static outcome parse(const char *json, size_t len, unsigned expect, int fast) {
    outcome o = {0};
    tc_request *r = NULL;
    tc_diags d;
    tc_strbuf b;
    tc_diags_init(&d);
    tc_strbuf_init(&b);
    tc_request__fast_arrays(fast);
    o.status = tc_request_parse(json, len, expect, &r, &d);
    o.taken = tc_request__fast_taken();
    tc_request__fast_arrays(1);
    for (int k = 0; k < d.count; k++)
        tc_strbuf_printf(&b, "%d %s: %s\n", (int)d.items[k].severity, d.items[k].path, d.items[k].message);
    tc_strbuf_printf(&b, "errors %d warnings %d\n", d.errors, d.warnings);
    o.findings = tc_strbuf_detach(&b, NULL);
    tc_strbuf_init(&b);
    if (r) {
        if (r->has_mesh) tc_json_request(&b, &r->desc, &r->opt);
        tc_strbuf_printf(&b, "plain %d points %zu:", r->values_plain, r->npoints);
        for (size_t k = 0; k < 2 * r->npoints; k++) tc_strbuf_printf(&b, " %a", r->points[k]);
    }
    o.canon = tc_strbuf_detach(&b, NULL);
    tc_request_free(r);
    tc_diags_free(&d);
    return o;
}

static int last_ok; /* agree's last request was accepted (so its arrays were compared) */

/* The fast and the cJSON path agree on json; returns how many arrays the fast path took. */
static int agree(const char *json, unsigned expect) {
    outcome a = parse(json, strlen(json), expect, 1), b = parse(json, strlen(json), expect, 0);
    CHECK_MSG(b.taken == 0, "the cJSON path took %d arrays fast", b.taken);
    CHECK_MSG(a.status == b.status, "status %d vs %d for %.200s", a.status, b.status, json);
    CHECK_MSG(!strcmp(a.findings, b.findings), "findings differ for %.200s:\nfast:\n%s\ncJSON:\n%s", json,
              a.findings, b.findings);
    CHECK_MSG(a.canon && b.canon && !strcmp(a.canon, b.canon), "requests differ for %.200s", json);
    int taken = a.taken;
    last_ok = a.status == TC_REQ_OK;
    free(a.findings), free(a.canon), free(b.findings), free(b.canon);
    return taken;
}

/* A random number's text: mostly forms the fast path takes (shortest, 17 digits, 25-digit
 * mantissas, exponents, -0, integers, leading zeros), and with `odd` now and then one it
 * leaves to cJSON (70 digits, 1e999, "01", "+1", ".5", a string, null, true). */
static void number(tc_strbuf *b, uint64_t *st, int odd) {
    uint64_t r = xs(st);
    double x = ((double)(r >> 11) / 9007199254740992.0 - 0.5) * pow(10, (int)(xs(st) % 40) - 20);
    switch (odd && xs(st) % 300 == 0 ? 10 + xs(st) % 6 : xs(st) % 10) {
    case 0: tc_strbuf_double(b, x); break;
    case 1: tc_strbuf_printf(b, "%.17g", x); break;
    case 2: tc_strbuf_printf(b, "%.24e", x); break;
    case 3: tc_strbuf_printf(b, "%.3E", x * 1e280); break;
    case 4: tc_strbuf_puts(b, xs(st) & 1 ? "-0" : "0.0"); break;
    case 5: tc_strbuf_printf(b, "%d", (int)(xs(st) % 2000) - 1000); break;
    case 6: tc_strbuf_printf(b, "0.000%llu", (unsigned long long)(xs(st) % 100000)); break;
    case 7: tc_strbuf_printf(b, "%llu.%llue-3%02d", (unsigned long long)(r % 1000), (unsigned long long)(r >> 20), (int)(r % 30)); break;
    case 8: tc_strbuf_printf(b, "%.40f", x); break; /* 42+ characters, under cJSON's 63 */
    case 9: tc_strbuf_printf(b, "%.5g", x); break;
    case 10: tc_strbuf_printf(b, "%.70f", x); break; /* over 63 characters */
    case 11: tc_strbuf_puts(b, xs(st) & 1 ? "1e999" : "-2e400"); break;
    case 12: tc_strbuf_puts(b, xs(st) & 1 ? "01" : "+1"); break;
    case 13: tc_strbuf_puts(b, xs(st) & 1 ? ".5" : "1."); break;
    case 14: tc_strbuf_puts(b, xs(st) & 1 ? "\"7\"" : "null"); break;
    default: tc_strbuf_puts(b, "1e-400"); break;
    }
}

/* Whitespace JSON allows, mostly none. */
static void sp(tc_strbuf *b, uint64_t *st) {
    uint64_t r = xs(st) % 16;
    if (r < 12) return;
    tc_strbuf_puts(b, r == 12 ? " " : r == 13 ? "\n" : r == 14 ? "\r\n\t" : "  ");
}

static void list(tc_strbuf *b, uint64_t *st, int n, int odd, int as_int, int nv) {
    tc_strbuf_putc(b, '[');
    for (int k = 0; k < n; k++) {
        if (k) tc_strbuf_putc(b, ','), sp(b, st);
        if (as_int && !(odd && xs(st) % 50 == 0)) tc_strbuf_printf(b, "%d", (int)(xs(st) % (uint64_t)nv));
        else number(b, st, odd);
    }
    tc_strbuf_putc(b, ']');
}

/* A random request: nv vertices, triangles, C channels (plain numbers or arrays), gradients
 * in one of their forms, points; odd: rare entries the fast path refuses. */
static char *random_request(uint64_t *st, int nv, int odd) {
    tc_strbuf b;
    tc_strbuf_init(&b);
    int C = 1 + (int)(xs(st) % 3), plain = C == 1 && (xs(st) & 1), single = C == 1 && (xs(st) & 1);
    tc_strbuf_puts(&b, "{");
    sp(&b, st);
    tc_strbuf_puts(&b, "\"vertices\":");
    sp(&b, st);
    tc_strbuf_putc(&b, '[');
    for (int i = 0; i < nv; i++) tc_strbuf_puts(&b, i ? "," : ""), sp(&b, st), list(&b, st, 2, odd, 0, nv);
    tc_strbuf_puts(&b, "],\"triangles\":[");
    for (int i = 0; i < nv; i++) tc_strbuf_puts(&b, i ? "," : ""), list(&b, st, 3, odd, 1, nv);
    tc_strbuf_puts(&b, "],\n\"with_gradients\": true, \"values\":[");
    for (int i = 0; i < nv; i++) {
        tc_strbuf_puts(&b, i ? "," : "");
        if (plain) number(&b, st, odd);
        else list(&b, st, C, odd, 0, nv);
    }
    tc_strbuf_puts(&b, "],\"gradients\":[");
    for (int i = 0; i < nv; i++) {
        tc_strbuf_puts(&b, i ? "," : "");
        if (single) {
            list(&b, st, 2, odd, 0, nv);
            continue;
        }
        tc_strbuf_putc(&b, '[');
        for (int c = 0; c < C; c++) tc_strbuf_puts(&b, c ? "," : ""), list(&b, st, 2, odd, 0, nv);
        tc_strbuf_putc(&b, ']');
    }
    tc_strbuf_puts(&b, "],\"points\":");
    sp(&b, st);
    tc_strbuf_putc(&b, '[');
    for (int i = 0; i < nv; i++) tc_strbuf_puts(&b, i ? "," : ""), list(&b, st, 2, odd, 0, nv);
    tc_strbuf_puts(&b, "]");
    sp(&b, st);
    tc_strbuf_puts(&b, "}");
    return tc_strbuf_detach(&b, NULL);
}

TEST(request_fast_random_meshes_same_request) {
    uint64_t st = 0x1234567 ^ tc_test_seed();
    int taken = 0, ok = 0;
    for (int k = 0; k < 300; k++) {
        char *json = random_request(&st, 1 + (int)(xs(&st) % 60), 0);
        int t = agree(json, TC_REQ_MESH | TC_REQ_POINTS);
        taken += t == 5 && last_ok;
        ok += last_ok;
        free(json);
    }
    CHECK_MSG(ok == 300, "only %d of 300 random requests accepted", ok);
    /* the %.40f form of big numbers passes 63 characters: most requests are all fast anyway */
    CHECK_MSG(taken > 100, "only %d of 300 requests had all five arrays read fast", taken);
}

TEST(request_fast_random_odd_entries_same_findings) {
    uint64_t st = 0x7654321 ^ tc_test_seed();
    int ok = 0;
    for (int k = 0; k < 300; k++) {
        char *json = random_request(&st, 1 + (int)(xs(&st) % 40), 1);
        agree(json, TC_REQ_MESH | TC_REQ_POINTS);
        ok += last_ok;
        free(json);
    }
    CHECK_MSG(ok > 10 && ok < 290, "%d of 300 odd requests accepted: both outcomes should be common", ok);
}

TEST(request_fast_bad_input_same_findings) {
    static const char *const bodies[] = {
        /* accepted fast, then judged by the readers */
        "{\"vertices\":[[0,0],[1,0],[0,1]],\"triangles\":[[0,1,2]],\"values\":[1,2,3]}",
        "{\"vertices\":[[0,0],[1,0],[0,1]],\"triangles\":[[0,1,2]],\"values\":[[1,2],[2,3],[3,4]],"
        "\"gradients\":[[1,2],[3,4],[5,6]]}", /* single vectors with 2 channels */
        "{\"vertices\":[[0,0],[1,0],[0,1]],\"triangles\":[[0,1,2]],\"values\":[[1,2],[2,3],[3,4]],"
        "\"gradients\":[[[1,2],[3,4],[5,6]],[[1,2],[3,4],[5,6]],[[1,2],[3,4],[5,6]]]}", /* 3 vectors for 2 */
        "{\"vertices\":[[0,0],[1,0],[0,1]],\"triangles\":[[0,1.5,2]],\"values\":[1,2,3]}",
        "{\"vertices\":[[0,0],[1,0],[0,1]],\"triangles\":[[0,1,3e9]],\"values\":[1,2,3]}",
        "{\"vertices\":[[0,0],[1,0],[0,1]],\"triangles\":[[0,1,2,3]],\"values\":[1,2,3]}",
        "{\"vertices\":[[0,0,0],[1,0,0],[0,1,0]],\"triangles\":[[0,1,2]],\"values\":[1,2,3]}",
        "{\"vertices\":[[0,0],[1,0]],\"triangles\":[[0,1,2]],\"values\":[1,2,3]}",
        "{\"vertices\":[[0,0],[1,0],[0,1]],\"triangles\":[[0,1,2]],\"values\":[[1,2,3,4,5,6,7,8,9,10,11,12,13,14,"
        "15,16,17],[1],[2]]}",
        "{\"vertices\":[0,0,1,0,0,1],\"triangles\":[0,1,2],\"values\":[[[1]],[[2]],[[3]]]}",
        "{\"vertices\":[[0,0],[1,0],[0,1]],\"triangles\":[[0,1,2]],\"values\":[1,2,3],\"points\":[[0.5,0.5]]}",
        "{\"points\":[[0.5,0.5],[1,2]]}",
        "{\"points\":[[0.5,0.5],[1,2]],\"reference\":{\"points\":[[1,2]],\"values\":[1]}}",
        /* left to cJSON */
        "{\"vertices\":[[0,0],[1,\"0\"],[0,1]],\"triangles\":[[0,1,2]],\"values\":[1,2,3]}",
        "{\"vertices\":[[0,0],[1,0],[0,1]],\"triangles\":[[0,1,2]],\"values\":[1,1e999,3]}",
        "{\"vertices\":[[0,0],[1,0],[0,1]],\"triangles\":[[0,1,2]],\"values\":[1,2,3],\"gradients\":[null,[1,2],[3,4]]}",
        "{\"vertices\":[[0,0],[1,0],[0,1]],\"triangles\":[[0,1,2]],\"values\":[1,[2],3]}",
        "{\"vertices\":[[0,0],[1,0],[0,1]],\"triangles\":[[0,1,2]],\"values\":[01,2,3]}",
        "{\"vertices\":[[0,0],[1,0],[0,1]],\"triangles\":[[0,1,2]],\"values\":[-0,2,1e-400]}",
        "{\"vertices\":[[0,0],[1,0],[0,1]],\"triangles\":[[0,1,2]],\"values\":[1,2,3],\"values\":[4,5,6]}",
        "{\"vertices\":[[0,0],[1,0],[0,1]],\"vert\\u0069ces\":[[0,0]],\"triangles\":[[0,1,2]],\"values\":[1,2,3]}",
        "{\"vertices\":[[0,0],[1,0],[0,1]],\"triangles\":[[0,1,2]],\"values\":[1,2,3],\"points\":[]}",
        "{\"vertices\":[[0,0],[1,0],[0,1]],\"triangles\":[[0,1,2]],\"values\":[1,2,3]\x01}",
        "{\"vertices\":[[0,0],\x01[1,0],[0,1]],\"triangles\":[[0,1,2]],\"values\":[1,2,3]}",
        "{\"vertices\":[[0,0],[1,0],[0,1]],\"triangles\":[[0,1,2]],\"values\":[1,2,3],\"points\":[[1,2],]}",
        "{\"vertices\":[[0,0],[1,0],[0,1]],\n\"triangles\":[[0,1,2]],\n\"values\":[1,2,3],\n\"format\":tru}",
        "{\"vertices\":[[0,0],[1,0],[0,1]],\n\"triangles\":[[0,1,2]],\n\"values\":[1,2,3]}\n{}",
        "{\"vertices\":[[0,0],[1,0],[0,1]],\"triangles\":[[0,1,2]],\"values\":[1,2,3],\"exposure\":\"x\"}",
        "{\"vertices\":[[0,0],[1,0],[0,1]],\"triangles\":[[0,1,2]],\"values\":[1,2,3],\"viewport\":{\"x0\":[1,2]",
        "{\"vertices\":[[0,0],[1,0],[0,1]],\"triangles\":[[0,1,2]],\"values\":[1,2,3],\"format\":\"a\\\"b\"}",
        "[[0,0],[1,0]]",
        /* a syntax error after arrays with lines in them: its line and column are the body's */
        "{\"vertices\":[[0,0],\n[1,0],\n  [0,1]],\n\"values\":[1,\r\n2,3],\"triangles\":[[0,1,2]],\n  \"x\": tru}",
        "{\"vertices\":[[0,0],\n[1,0],\n  [0,1]],\n\"values\":[1,\r\n2,3],\"triangles\":[[0,1,2]]\n\n,",
        "{\"vertices\":[[0,0],[1,0],[0,1]],\"triangles\":[[0,1,2]],\"values\":[1,2,3],\"points\":[[1.00000000000000"
        "0000000000000000000000000000000000000000000000000000000001,2]]}",
    };
    int taken = 0, ok = 0;
    for (size_t k = 0; k < sizeof bodies / sizeof bodies[0]; k++)
        taken += agree(bodies[k], k < 12 ? TC_REQ_MESH : TC_REQ_POINTS) > 0, ok += last_ok;
    CHECK_MSG(ok >= 5 && ok <= 25, "%d of the bodies accepted", ok);
    CHECK_MSG(taken >= 15, "the fast path took arrays in only %d bodies", taken);
}

/* Typed arrays' "data" strings read from the body (not copied by cJSON) give what cJSON's
 * strings give: the same request, the same findings (bad base64 at the same character, wrong
 * length, syntax errors after them at the same line and column), and strings with an escape
 * or a \u0000 are left to cJSON. */
TEST(fast_typed_data_strings_agree) {
    static const char *const V = "{\"dtype\":\"float64\",\"shape\":[3,2],\"data\":\"AAAAAAAAAAAAAAAAAADwPwAAAAAAAAAAAAAAAAAAAAAAAAAAAADwPw==\"}";
    static const char *const T = "{\"dtype\":\"int32\",\"shape\":[1,3],\"data\":\"AAAAAAEAAAACAAAA\"}";
    static const struct {
        const char *vertices, *values, *tail;
        int spans; /* strings the fast path reads from the body */
    } cases[] = {
        {NULL, "[1,2,3]", "", 2},
        {NULL, "{\"dtype\":\"float64\",\"shape\":[3],\"data\":\"AAAAAAAA8D8AAAAAAAAAQAAAAAAAAAhA\"}", "", 3},
        {NULL, "{\"dtype\":\"float64\",\"shape\":[3],\"data\":\"AAAAAAAA8D8AAAAA*AAAAQAAAAAAAAAhA\"}", "", 3},
        {NULL, "{\"dtype\":\"float64\",\"shape\":[3],\"data\":\"AAAAAAAA8D8AAAAAAAAAQA==\"}", "", 3},
        {NULL, "{\"dtype\":\"float64\",\"shape\":[3],\"data\":\"AAAAAAAA8D8AAAAAAAAAQAAAAAAAAAhA\"}", ",\"x\":[1,}", 0},
        {NULL, "{\"dtype\":\"float64\",\"shape\":[3],\"data\":\"AAAAAAAA8D8AAAAAAAAAQAAAAAAAAAhA\"}",
         ",\n  \"method\": \"nope\"", 3},
        {NULL, "{\"dtype\":\"float64\",\"shape\":[3],\"data\":\"AAAAAAAA8D8AAAAAAAAAQAAAAAAAAAh\\/\"}", "", 2},
        {NULL, "{\"dtype\":\"float64\",\"shape\":[3],\"data\":\"AAAAAAAA8D8AAAAAAAAAQAAA\\u0000AAAAAhA\"}", "", 2},
        {NULL, "{\"dtype\":\"float64\",\"data\":\"AAAAAAAA8D8AAAAAAAAAQAAAAAAAAAhA\",\"shape\":[3],\"data\":\"AAAA\"}", "", 4},
        {NULL, "{\"dtype\":\"float64\",\"shape\":[3],\"data\":7}", "", 2},
        {"{\"dtype\":\"float64\",\"shape\":[3,2],\"data\":\"\"}", "[1,2,3]", "", 2},
        {NULL, "{\"dtype\":\"float64\",\"shape\":[3],\"data\":\"AAAAAAAA8D8AAAAAAAAAQAAAAAAAAAhA\"}",
         ",\n \"x\": tru", 0}, /* the skeleton's syntax error, mapped back past the cuts */
        {NULL, "[1,2,3]", ",\"reference\":{\"points\":{\"dtype\":\"float64\",\"shape\":[1,2],\"data\":\"AAAAAAAAAAAAAAAAAAAAAA==\"}}", 2},
    };
    char body[1024];
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        snprintf(body, sizeof body, "{\"vertices\":%s,\n\"triangles\":%s,\"values\":%s%s}",
                 cases[i].vertices ? cases[i].vertices : V, T, cases[i].values, cases[i].tail);
        agree(body, TC_REQ_MESH);
        outcome o = parse(body, strlen(body), TC_REQ_MESH, 1);
        CHECK_MSG(tc_request__fast_spans() == cases[i].spans, "case %zu: %d strings read from the body, expected %d",
                  i, tc_request__fast_spans(), cases[i].spans);
        free(o.findings), free(o.canon);
    }
}

/* The limits checked in the fast path's walk (tc_request_parse_limited) refuse exactly what
 * tc_prescan on the whole body refuses: the same first array over, the same full count, and
 * the same request otherwise. Random requests (with odd entries the fast path leaves to the
 * prescan), random limits, and typed or JSON arrays over them in either order. */
TEST(request_fast_limits_equal_prescan) {
    uint64_t st = 0x51ab5eedULL ^ tc_test_seed();
    for (int it = 0; it < 300; it++) {
        int nv = 1 + (int)(xs(&st) % 40);
        char *json = random_request(&st, nv, (int)(it & 1));
        tc_scan_limit L[] = {{"vertices", (int64_t)(xs(&st) % 50)}, {"triangles", (int64_t)(xs(&st) % 80)},
                             {"quads", 0}, {"points", (int64_t)(xs(&st) % 30)}, {"reference.points", 3}};
        int64_t n_pre = -1;
        int k_pre = tc_prescan(json, strlen(json), L, 5, &n_pre);
        tc_req_limits rl = {L, 5, -2, -2};
        tc_request *r = NULL;
        tc_diags d;
        tc_diags_init(&d);
        int rs = tc_request_parse_limited(json, strlen(json), TC_REQ_MESH, &rl, &r, &d);
        CHECK_MSG(rl.over == k_pre && (k_pre < 0 || rl.count == n_pre), "limit %d (%lld) vs prescan %d (%lld): %.200s",
                  rl.over, (long long)rl.count, k_pre, (long long)n_pre, json);
        CHECK((rs == TC_REQ_OVER_LIMIT) == (k_pre >= 0) && (rs != TC_REQ_OVER_LIMIT || (!r && d.count == 0)));
        if (k_pre < 0) { /* within the limits: the request of tc_request_parse */
            outcome o = parse(json, strlen(json), TC_REQ_MESH, 1);
            CHECK(o.status == rs);
            free(o.findings), free(o.canon);
        }
        tc_request_free(r);
        tc_diags_free(&d);
        free(json);
    }
    static const char *const bodies[] = {
        "{\"vertices\":[[0,0],[1,0],[0,1]],\"triangles\":[[0,1,2],[0,1,2]],\"values\":[1,2,3]}",
        "{\"triangles\":[[0,1,2],[0,1,2]],\"vertices\":[[0,0],[1,0],[0,1]],\"values\":[1,2,3]}",
        "{\"triangles\":{\"dtype\":\"int32\",\"shape\":[2,3],\"data\":\"AAAAAAEAAAACAAAAAAAAAAEAAAACAAAA\"},"
        "\"vertices\":[[0,0],[1,0],[0,1]],\"values\":[1,2,3]}",
        "{\"vertices\":[[0,0],[1,0],[0,1]],\"triangles\":{\"dtype\":\"int32\",\"shape\":[2,3],"
        "\"data\":\"AAAAAAEAAAACAAAAAAAAAAEAAAACAAAA\"},\"values\":[1,2,3]}",
        "{\"vertices\":[[0,0],[1,0],[0,1],[\"x\"]],\"triangles\":[[0,1,2],[0,1,2]],\"values\":[1,2,3]}",
    };
    const tc_scan_limit L2[] = {{"vertices", 2}, {"triangles", 1}};
    for (size_t i = 0; i < sizeof bodies / sizeof bodies[0]; i++) {
        int64_t n_pre = -1;
        int k_pre = tc_prescan(bodies[i], strlen(bodies[i]), L2, 2, &n_pre);
        tc_req_limits rl = {L2, 2, -2, -2};
        tc_request *r = NULL;
        CHECK(tc_request_parse_limited(bodies[i], strlen(bodies[i]), TC_REQ_MESH, &rl, &r, NULL) == TC_REQ_OVER_LIMIT);
        CHECK_MSG(k_pre >= 0 && rl.over == k_pre && rl.count == n_pre, "body %zu: %d (%lld) vs prescan %d (%lld)", i,
                  rl.over, (long long)rl.count, k_pre, (long long)n_pre);
        CHECK_MSG(tc_request__fast_taken() == 0, "body %zu: an array over its limit was read", i);
        tc_request_free(r);
    }
}
