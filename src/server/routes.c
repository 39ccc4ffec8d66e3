/* routes.c — the route table and its handlers. The handlers only move bytes
 * between the request and tc_api_*; the server knows nothing of the mathematics. */
#include <string.h>

#include "io/api.h"
#include "server/metrics.h"
#include "server/routes.h"
#include "server/viewer.h"
#include "tocher.h"

/* Every JSON answer carries a "timings" object, these (all phases 0) too. */
static void put_json(tc_reply *out, const char *text) {
    out->status = 200;
    out->content_type = TC_JSON_TYPE;
    tc_strbuf_puts(&out->body, text);
    tc_api_add_timings(&out->body, &out->res);
}

static void healthz(const tc_route_input *in, tc_reply *out) {
    (void)in;
    put_json(out, "{\"status\":\"ok\"}\n");
}

static void version(const tc_route_input *in, tc_reply *out) {
    (void)in;
    put_json(out, "{\"version\":\"" TC_VERSION "\",\"api\":\"v1\"}\n");
}

static void metrics(const tc_route_input *in, tc_reply *out) {
    (void)in;
    out->status = 200;
    out->content_type = TC_METRICS_CONTENT_TYPE;
    tc_metrics_write(&out->body);
}

/* The API's status and body into the reply: timings added to JSON answers,
 * a problem document (tc_api_problem) for failures. */
static void api_reply(int status, int json, tc_reply *out) {
    out->status = status;
    if (status == 200) {
        if (json) tc_api_add_timings(&out->body, &out->res);
        out->content_type = out->res.content_type ? out->res.content_type : "application/octet-stream";
        return;
    }
    tc_strbuf_reset(&out->body);
    tc_api_problem(&out->body, &out->res);
    out->content_type = TC_PROBLEM_TYPE;
}

static void ordinates(const tc_route_input *in, tc_reply *out) {
    int rc = tc_api_ordinates(in->body, in->len, &in->lim, &out->body, &out->res);
    api_reply(rc, 1, out);
}

static void evaluate(const tc_route_input *in, tc_reply *out) {
    int rc = tc_api_evaluate(in->body, in->len, NULL, 0, &in->lim, &out->body, &out->res);
    api_reply(rc, 1, out);
}

static void render(const tc_route_input *in, tc_reply *out) {
    int rc = tc_api_render(in->body, in->len, in->accept, &in->lim, &out->body, &out->res);
    api_reply(rc, 0, out);
}

static void compare(const tc_route_input *in, tc_reply *out) {
    int rc = tc_api_compare(in->body, in->len, &in->lim, &out->body, &out->res);
    api_reply(rc, 1, out);
}

static const tc_route routes[] = {
    {"/v1/ordinates", "POST", "POST", ordinates},
    {"/v1/evaluate", "POST", "POST", evaluate},
    {"/v1/render", "POST", "POST", render},
    {"/v1/compare", "POST", "POST", compare},
    {"/healthz", "GET", "GET, HEAD", healthz},
    {"/metrics", "GET", "GET, HEAD", metrics},
    {"/v1/version", "GET", "GET, HEAD", version},
    {"/viewer", "GET", "GET, HEAD", tc_viewer},
};
enum { NROUTES = sizeof routes / sizeof routes[0] };

const tc_route *tc_route_find(const char *path, int *index) {
    for (int i = 0; i < NROUTES; i++)
        if (!strcmp(path, routes[i].path)) {
            if (index) *index = i;
            return &routes[i];
        }
    if (index) *index = -1;
    return NULL;
}

int tc_route_allows(const tc_route *r, const char *method) {
    if (!strcmp(method, r->method)) return 1;
    return !strcmp(r->method, "GET") && !strcmp(method, "HEAD");
}

int tc_route_takes_body(const tc_route *r) { return !strcmp(r->method, "POST"); }

int tc_route_count(void) { return NROUTES; }

const char *tc_route_path(int i) { return i >= 0 && i < NROUTES ? routes[i].path : NULL; }
