/* test_options.c — the options table (src/io/options.c) as the reader, the echo
 * and the request writer use it: every row, every value, at the top level and
 * in /v1/compare's "methods"; bad values with their JSON paths. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cJSON.h>

#include "check.h"
#include "io/api.h"
#include "io/jsonout.h"
#include "io/options.h"
#include "io/request.h"
#include "io/request_write.h"

#define MESH1 "\"vertices\": [[0,0],[1,0],[1,1],[0,1]], \"triangles\": [[0,1,2],[0,2,3]], \"values\": [0, 1, 2, 3]"

static tc_request *parse_ok(const char *json) {
    tc_request *r = NULL;
    tc_diags d;
    tc_diags_init(&d);
    int st = tc_request_parse(json, strlen(json), TC_REQ_MESH, &r, &d);
    CHECK_MSG(st == TC_REQ_OK && d.count == 0, "%s: status %d, %s: %s", json, st, d.count ? d.items[0].path : "",
              d.count ? d.items[0].message : "");
    tc_diags_free(&d);
    return r;
}

/* A value of the row other than v (enums: the next name; numbers: in range). */
static void member_text(const tc_opt *row, int v, char *buf, size_t cap) {
    if (row->kind == TC_OPT_ENUM) snprintf(buf, cap, "\"%s\": \"%s\"", row->name, tc_opt_value_name(row, v));
    else snprintf(buf, cap, "\"%s\": %.17g", row->name, row->min + (row->max - row->min) * v / 8.0);
}

static int holds(const tc_opt *row, const tc_request *r, const tc_options *o, int v) {
    const void *obj = row->target == TC_OPT_RECON ? (const void *)o : (const void *)&r->desc;
    if (row->kind == TC_OPT_ENUM) return tc_opt_get_enum(row, obj) == v;
    return tc_opt_get_number(row, obj) == row->min + (row->max - row->min) * v / 8.0;
}

/* The request's rows: the method, every core option (tc_option_*), the two mesh options. */
TEST(options_rows_cover_the_core_table) {
    CHECK(tc_opt_count() == 1 + tc_option_count() + 2 && tc_opt_count() <= TC_OPT_MAX);
    for (int i = 0; i < tc_option_count(); i++)
        CHECK(tc_opt_find(tc_option_name(i)) == tc_opt_at(1 + i) && tc_opt_at(1 + i)->reads == tc_option_bit(i));
}

/* Every value of every row parses at the top level; a reconstruction option
 * also inside an entry of "methods" (which starts from the request's own). */
TEST(options_every_value_parses) {
    for (int i = 0; i < tc_opt_count(); i++) {
        const tc_opt *row = tc_opt_at(i);
        int nv = row->kind == TC_OPT_ENUM ? 0 : 9;
        while (row->kind == TC_OPT_ENUM && tc_opt_value_name(row, nv)) nv++;
        CHECK_MSG(nv >= 2, "%s has %d values", row->name, nv);
        for (int v = 0; v < nv; v++) {
            char member[128], json[512];
            member_text(row, v, member, sizeof member);
            snprintf(json, sizeof json, "{" MESH1 ", %s}", member);
            tc_request *r = parse_ok(json);
            CHECK_MSG(r && holds(row, r, &r->opt, v), "%s", json);
            tc_request_free(r);
            if (row->target != TC_OPT_RECON || !strcmp(row->name, "method")) continue;
            snprintf(json, sizeof json, "{" MESH1 ", %s, \"methods\": [\"linear\", {%s}]}", member, member);
            r = parse_ok(json);
            CHECK_MSG(r && r->nmethods == 2 && holds(row, r, &r->methods[0], v) && holds(row, r, &r->methods[1], v) &&
                          r->methods[0].method == TC_METHOD_LINEAR,
                      "%s", json);
            tc_request_free(r);
        }
    }
}

/* The echo of an answer and the writer print "method" and exactly the
 * options the method reads; what the writer prints reads back the same. */
TEST(options_echo_and_write_what_the_method_reads) {
    for (int m = 0; m < tc_method_count(); m++) {
        tc_options o;
        tc_options_default(&o);
        o.method = (tc_method)m;
        o.range = TC_RANGE_FREE, o.twist = TC_TWIST_ZERO, o.tangents = TC_TANGENTS_ESTIMATE;
        tc_strbuf b;
        tc_strbuf_init(&b);
        tc_strbuf_putc(&b, '{');
        tc_json_options(&b, &o);
        tc_strbuf_putc(&b, '}');
        cJSON *echo = cJSON_ParseWithLength(b.buf, b.len);
        CHECK(cJSON_IsObject(echo));
        for (int i = 0; echo && i < tc_opt_count(); i++) {
            const tc_opt *row = tc_opt_at(i);
            const cJSON *e = cJSON_GetObjectItemCaseSensitive(echo, row->name);
            int want = tc_opt_read_by(row, o.method);
            CHECK_MSG(!e == !want, "%s: '%s' %s", tc_method_name(o.method), row->name, e ? "echoed" : "missing");
            if (e && row->kind == TC_OPT_ENUM)
                CHECK(cJSON_IsString(e) && !strcmp(e->valuestring, tc_opt_value_name(row, tc_opt_get_enum(row, &o))));
        }
        cJSON_Delete(echo);
        tc_strbuf_free(&b);
        const double xy[] = {0, 0, 1, 0, 0, 1}, z[] = {1, 2, 3};
        const int32_t tri[] = {0, 1, 2};
        tc_mesh_desc d = {0};
        d.nverts = 3, d.xy = xy, d.ntris = 1, d.tris = tri, d.nchan = 1, d.values = z;
        tc_strbuf_init(&b);
        tc_json_request(&b, &d, &o);
        tc_request *r = parse_ok(b.buf ? b.buf : "");
        if (r) CHECK(r->desc.value_tolerance == 0); /* a zero-filled description's, written out */
        for (int i = 0; r && i < tc_opt_count(); i++) {
            const tc_opt *row = tc_opt_at(i);
            if (row->target != TC_OPT_RECON || row->kind != TC_OPT_ENUM) continue;
            int want = tc_opt_read_by(row, o.method) ? tc_opt_get_enum(row, &o) : 0; /* else the default */
            CHECK_MSG(tc_opt_get_enum(row, &r->opt) == want, "%s: %s written and read back", tc_method_name(o.method),
                      row->name);
        }
        tc_request_free(r);
        tc_strbuf_free(&b);
    }
}

/* Bad values: 400 for a wrong JSON type, 422 for an unknown name or a number
 * out of range, each at its JSON path (also inside "methods"). */
TEST(options_bad_values_name_their_path) {
    static const struct { const char *json, *path, *msg; int status; } bad[] = {
        {"\"range\": \"wide\"", "range", "unknown range 'wide'; expected one of: local, positive, free",
         TC_REQ_INVALID},
        {"\"range\": 1", "range", "expected a string (one of: local, positive, free)", TC_REQ_MALFORMED},
        {"\"methods\": [{\"method\": \"linear\", \"range\": \"Free\"}]", "methods[0].range", "unknown range 'Free'",
         TC_REQ_INVALID},
        {"\"methods\": [\"spline\"]", "methods[0]", "unknown method 'spline'", TC_REQ_INVALID},
        {"\"methods\": [{\"twist\": [1]}]", "methods[0].twist", "expected a string", TC_REQ_MALFORMED},
        {"\"value_tolerance\": 2", "value_tolerance", "value_tolerance must be a number from 0 to 1, got 2",
         TC_REQ_INVALID},
        {"\"value_tolerance\": -1e-9", "value_tolerance", "got -1e-09", TC_REQ_INVALID},
        {"\"value_tolerance\": \"1e-4\"", "value_tolerance", "expected a number", TC_REQ_MALFORMED},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char json[512];
        snprintf(json, sizeof json, "{" MESH1 ", %s}", bad[i].json);
        tc_request *r = NULL;
        tc_diags d;
        tc_diags_init(&d);
        int st = tc_request_parse(json, strlen(json), TC_REQ_MESH, &r, &d);
        CHECK_MSG(st == bad[i].status && !r, "%s: status %d", bad[i].json, st);
        CHECK_MSG(d.count >= 1 && !strcmp(d.items[0].path, bad[i].path), "%s: path '%s', want '%s'", bad[i].json,
                  d.count ? d.items[0].path : "", bad[i].path);
        if (d.count) CHECK_STR_CONTAINS(d.items[0].message, bad[i].msg);
        tc_request_free(r);
        tc_diags_free(&d);
    }
}

/* A misspelt option is suggested from the table like any other field. */
TEST(options_misspelt_option_suggested) {
    tc_request *r = NULL;
    tc_diags d;
    tc_diags_init(&d);
    const char *json = "{" MESH1 ", \"methods\": [{\"rnage\": \"free\"}], \"rang\": \"free\"}";
    CHECK(tc_request_parse(json, strlen(json), TC_REQ_MESH, &r, &d) == TC_REQ_OK);
    CHECK(d.warnings == 2);
    for (int i = 0; i < d.count; i++) CHECK_STR_CONTAINS(d.items[i].message, "did you mean 'range'?");
    if (r) CHECK(r->opt.range == TC_RANGE_LOCAL && r->methods[0].range == TC_RANGE_LOCAL);
    tc_request_free(r);
    tc_diags_free(&d);
}

/* A mesh option inside an entry of "methods" cannot apply to one method only:
 * it is ignored with a warning at its path. Requests default to
 * tc_mesh_desc_init's values. */
TEST(options_mesh_option_in_methods_warns) {
    tc_request *r = NULL;
    tc_diags d;
    tc_diags_init(&d);
    const char *json = "{" MESH1 ", \"methods\": [{\"method\": \"linear\", \"value_tolerance\": 0.5}]}";
    CHECK(tc_request_parse(json, strlen(json), TC_REQ_MESH, &r, &d) == TC_REQ_OK);
    CHECK(d.warnings == 1 && d.count == 1);
    if (d.count) {
        CHECK(!strcmp(d.items[0].path, "methods[0].value_tolerance"));
        CHECK_STR_CONTAINS(d.items[0].message, "applies to the mesh");
    }
    if (r) CHECK(r->desc.value_tolerance == TC_VALUE_TOLERANCE_DEFAULT && r->methods[0].method == TC_METHOD_LINEAR);
    tc_request_free(r);
    tc_diags_free(&d);
}
