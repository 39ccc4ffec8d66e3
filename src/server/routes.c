/* routes.c — the route table, its path matching, and the stateless handlers.
 * The handlers only move bytes between the request and tc_api_*; the server
 * knows nothing of the mathematics. The stored-mesh handlers are in meshes.c. */
#include <stdlib.h>
#include <string.h>

#include "io/api.h"
#include "server/meshes.h"
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

/* Liveness: 200 while the daemon answers, whatever the store's state (a
 * restart would not bring Redis back); the state is there for operators. */
static void healthz(const tc_route_input *in, tc_reply *out) {
    out->status = 200;
    out->content_type = TC_JSON_TYPE;
    tc_strbuf_puts(&out->body, "{\"status\":\"ok\"");
    if (in->meshes) {
        tc_strbuf_puts(&out->body, ",\"store\":");
        tc_meshes_write_store(in->meshes, &out->body);
    }
    tc_strbuf_puts(&out->body, "}\n");
    tc_api_add_timings(&out->body, &out->res);
}

/* Readiness: 200 when the store answers now, else 503 with Retry-After (a
 * balancer or Kubernetes then sends this replica no traffic until it does). */
static void readyz(const tc_route_input *in, tc_reply *out) {
    if (in->meshes && !tc_meshes_ready(in->meshes)) {
        tc_reply_problem(out, TC_PROBLEM_BUSY, "the mesh store is unreachable; not ready");
        out->retry_after = 1;
        return;
    }
    out->status = 200;
    out->content_type = TC_JSON_TYPE;
    tc_strbuf_puts(&out->body, "{\"status\":\"ready\"");
    if (in->meshes) {
        tc_strbuf_puts(&out->body, ",\"store\":");
        tc_meshes_write_store(in->meshes, &out->body);
    }
    tc_strbuf_puts(&out->body, "}\n");
    tc_api_add_timings(&out->body, &out->res);
}

static void version(const tc_route_input *in, tc_reply *out) {
    (void)in;
    put_json(out, "{\"version\":\"" TC_VERSION "\",\"api\":\"v1\"}\n");
}

static void metrics(const tc_route_input *in, tc_reply *out) {
    out->status = 200;
    out->content_type = TC_METRICS_CONTENT_TYPE;
    tc_metrics_write(&out->body);
    if (in->meshes) tc_meshes_write_metrics(in->meshes, &out->body);
}

static void ordinates(const tc_route_input *in, tc_reply *out) {
    int rc = tc_api_ordinates(in->body, in->len, &in->lim, &out->body, &out->res);
    tc_reply_api(out, rc, 1);
}

static void evaluate(const tc_route_input *in, tc_reply *out) {
    int rc = tc_api_evaluate(in->body, in->len, NULL, 0, &in->lim, &out->body, &out->res);
    tc_reply_api(out, rc, 1);
}

static void render(const tc_route_input *in, tc_reply *out) {
    int rc = tc_api_render(in->body, in->len, in->accept, &in->lim, &out->body, &out->res);
    tc_reply_api(out, rc, 0);
    out->vary = "Accept"; /* the format may come from the Accept header */
}

static void compare(const tc_route_input *in, tc_reply *out) {
    int rc = tc_api_compare(in->body, in->len, &in->lim, &out->body, &out->res);
    tc_reply_api(out, rc, 1);
}

#define GET_ONLY "GET, HEAD"
static const tc_route routes[] = {
    {"/v1/ordinates", "POST", NULL, ordinates, NULL, 0},
    {"/v1/evaluate", "POST", NULL, evaluate, NULL, 0},
    {"/v1/render", "POST", NULL, render, NULL, 0},
    {"/v1/compare", "POST", NULL, compare, NULL, 0},
    {"/healthz", GET_ONLY, healthz, NULL, NULL, 0},
    {"/readyz", GET_ONLY, readyz, NULL, NULL, 0},
    {"/metrics", GET_ONLY, metrics, NULL, NULL, 0},
    {"/v1/version", GET_ONLY, version, NULL, NULL, 0},
    /* Stored meshes (meshes.c). */
    {"/v1/meshes", "POST", NULL, tc_meshes_post, NULL, 1},
    {"/v1/meshes/{id}", "GET, HEAD, DELETE", tc_meshes_get, NULL, tc_meshes_delete, 1},
    {"/v1/meshes/{id}/ordinates", GET_ONLY, tc_meshes_ordinates, NULL, NULL, 1},
    {"/v1/meshes/{id}/evaluate", "POST", NULL, tc_meshes_evaluate, NULL, 1},
    {"/v1/meshes/{id}/render", "POST", NULL, tc_meshes_render, NULL, 1},
    {"/v1/meshes/{id}/tiles/{z}/{x}/{tile}", GET_ONLY, tc_meshes_tile, NULL, NULL, 1},
    {"/viewer", GET_ONLY, tc_viewer, NULL, NULL, 0},
};
enum { NROUTES = sizeof routes / sizeof routes[0] };

/* Matches path against pattern segment by segment; a {name} segment takes one
 * non-empty path segment of at most TC_ROUTE_PARAM_MAX bytes into params. */
static int match(const char *pattern, const char *path, tc_path_params *params) {
    tc_path_params p = {0};
    while (*pattern && *path) {
        if (*pattern == '{') {
            const char *pe = strchr(pattern, '}'), *se = strchr(path, '/');
            size_t n = se ? (size_t)(se - path) : strlen(path);
            if (!pe || n == 0 || n > TC_ROUTE_PARAM_MAX || p.n == TC_ROUTE_MAX_PARAMS) return 0;
            memcpy(p.seg[p.n], path, n);
            p.seg[p.n++][n] = '\0';
            pattern = pe + 1, path += n;
        } else if (*pattern++ != *path++) {
            return 0;
        }
    }
    if (*pattern || *path) return 0;
    if (params) *params = p;
    return 1;
}

const tc_route *tc_route_find(const char *path, int *index, tc_path_params *params) {
    for (int i = 0; i < NROUTES; i++)
        if (match(routes[i].path, path, params)) {
            if (index) *index = i;
            return &routes[i];
        }
    if (index) *index = -1;
    return NULL;
}

tc_route_fn tc_route_handler(const tc_route *r, const char *method) {
    if (!strcmp(method, "GET") || !strcmp(method, "HEAD")) return r->get;
    if (!strcmp(method, "POST")) return r->post;
    if (!strcmp(method, "DELETE")) return r->del;
    return NULL;
}

int tc_route_allows(const tc_route *r, const char *method) { return tc_route_handler(r, method) != NULL; }

int tc_route_takes_body(const tc_route *r, const char *method) { return r->post && !strcmp(method, "POST"); }

int tc_route_on_pool(const tc_route *r, const char *method) {
    return tc_route_takes_body(r, method) || (r->compute && tc_route_allows(r, method));
}

int tc_route_count(void) { return NROUTES; }

const char *tc_route_path(int i) { return i >= 0 && i < NROUTES ? routes[i].path : NULL; }

void tc_query_free(tc_query *q) {
    for (int i = 0; i < q->n; i++) free(q->key[i]), free(q->value[i]);
    q->n = 0;
}
