/* api.c — request bytes -> io -> core -> response bytes, one function per
 * endpoint. The CLI and the daemon both call these, so their output is one. */
#include <stdlib.h>
#include <time.h>

#include "io/api.h"
#include "io/request.h"
#include "io/response.h"

const char *const tc_phase_names[TC_NPHASES] = {"parse", "validate", "build", "evaluate", "encode"};

void tc_api_result_init(tc_api_result *res) {
    res->status = 200;
    res->second_doc = TC_DIAGS_KEEP;
    tc_diags_init(&res->diags);
    for (int i = 0; i < TC_NPHASES; i++) res->ms[i] = 0;
}

void tc_api_result_free(tc_api_result *res) { tc_diags_free(&res->diags); }

static double now_ms(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

/* Adds the time since *t0 to phase p and restarts the clock. */
static void lap(tc_api_result *res, int p, double *t0) {
    double t = now_ms();
    res->ms[p] += t - *t0;
    *t0 = t;
}

static int status_of_request(int rs) {
    return rs == TC_REQ_MALFORMED ? 400 : rs == TC_REQ_INVALID ? 422 : 500;
}

static int status_of_core(int st) { return st == TC_EINVAL ? 422 : st == TC_ELIMIT ? 413 : 500; }

/* Everything a request needs up to a built reconstruction. */
typedef struct {
    tc_request *req;
    tc_mesh *mesh;
    tc_recon *recon;
} job;

static void job_free(job *j) {
    tc_recon_free(j->recon);
    tc_mesh_free(j->mesh);
    tc_request_free(j->req);
}

static int job_build(job *j, const char *body, size_t len, unsigned expect, tc_api_result *res, double *t0) {
    int rs = tc_request_parse(body, len, expect, &j->req, &res->diags);
    lap(res, TC_PHASE_PARSE, t0);
    if (rs != TC_REQ_OK) return res->status = status_of_request(rs);
    int st = tc_mesh_new(&j->req->desc, &j->mesh, &res->diags);
    lap(res, TC_PHASE_VALIDATE, t0);
    if (st != TC_OK) return res->status = status_of_core(st);
    st = tc_recon_new(j->mesh, &j->req->opt, &j->recon, &res->diags);
    lap(res, TC_PHASE_BUILD, t0);
    if (st != TC_OK) return res->status = status_of_core(st);
    return res->status = 200;
}

static int finish(tc_strbuf *out, tc_strbuf *body, tc_api_result *res) {
    tc_json_diags(body, "warnings", &res->diags, TC_SEV_WARNING);
    tc_strbuf_puts(body, "}\n");
    if (body->oom) {
        tc_strbuf_free(body);
        tc_diags_add(&res->diags, TC_SEV_ERROR, "", "out of memory writing the response");
        return res->status = 500;
    }
    tc_strbuf_append(out, body->buf, body->len);
    tc_strbuf_free(body);
    return res->status = out->oom ? 500 : 200;
}

int tc_api_ordinates(const char *body, size_t len, tc_strbuf *out, tc_api_result *res) {
    double t0 = now_ms();
    job j = {0};
    if (job_build(&j, body, len, TC_REQ_MESH, res, &t0) != 200) {
        job_free(&j);
        return res->status;
    }
    tc_strbuf b;
    tc_strbuf_init(&b);
    tc_strbuf_putc(&b, '{');
    tc_json_ordinates(&b, j.recon);
    job_free(&j);
    int st = finish(out, &b, res);
    lap(res, TC_PHASE_ENCODE, &t0);
    return st;
}

/* Locates and evaluates the points; writes the response members. */
static int evaluate(const job *j, const tc_request *pts, tc_strbuf *b) {
    int nc = tc_mesh_channel_count(j->mesh);
    size_t n = pts->npoints;
    tc_locator *L = NULL;
    double *val = malloc((n ? n : 1) * nc * sizeof *val);
    double *grad = pts->with_gradients ? malloc((n ? n : 1) * 2 * nc * sizeof *grad) : NULL;
    int32_t *tri = malloc((n ? n : 1) * sizeof *tri);
    int st = !val || !tri || (pts->with_gradients && !grad) ? TC_ENOMEM : tc_locator_new(j->mesh, &L);
    if (st == TC_OK) {
        tc_eval_points(j->recon, L, n, pts->points, val, grad, tri);
        tc_strbuf_putc(b, '{');
        tc_json_points(b, nc, n, val, grad, tri, j->req->values_plain);
    }
    tc_locator_free(L);
    free(val), free(grad), free(tri);
    return st;
}

int tc_api_evaluate(const char *body, size_t len, const char *points, size_t plen, tc_strbuf *out,
                    tc_api_result *res) {
    double t0 = now_ms();
    job j = {0};
    tc_request *pts = NULL;
    unsigned expect = points ? TC_REQ_MESH : TC_REQ_MESH | TC_REQ_POINTS;
    if (job_build(&j, body, len, expect, res, &t0) == 200 && points) {
        res->second_doc = res->diags.count;
        int rs = tc_request_parse(points, plen, TC_REQ_POINTS, &pts, &res->diags);
        lap(res, TC_PHASE_PARSE, &t0);
        if (rs != TC_REQ_OK) res->status = status_of_request(rs);
    }
    tc_strbuf b;
    tc_strbuf_init(&b);
    if (res->status == 200) {
        if (evaluate(&j, pts ? pts : j.req, &b) != TC_OK) res->status = 500;
        lap(res, TC_PHASE_EVALUATE, &t0);
    }
    tc_request_free(pts);
    job_free(&j);
    if (res->status != 200) {
        tc_strbuf_free(&b);
        return res->status;
    }
    int st = finish(out, &b, res);
    lap(res, TC_PHASE_ENCODE, &t0);
    return st;
}

void tc_api_problem(tc_strbuf *out, const tc_api_result *res) {
    const char *type = "internal", *title = "Internal error";
    if (res->status == 400) type = "malformed-request", title = "Malformed request";
    if (res->status == 413) type = "too-large", title = "Request too large";
    if (res->status == 422) type = "invalid-mesh", title = "Invalid mesh";
    const tc_diag *first = NULL;
    for (int i = 0; i < res->diags.count && !first; i++)
        if (res->diags.items[i].severity == TC_SEV_ERROR) first = &res->diags.items[i];
    tc_strbuf_puts(out, "{\"type\":\"/problems/");
    tc_strbuf_puts(out, type);
    tc_strbuf_puts(out, "\",\"title\":");
    tc_strbuf_json_string(out, title);
    tc_strbuf_printf(out, ",\"status\":%d,\"detail\":", res->status);
    tc_strbuf_json_string(out, first ? first->message : title);
    tc_strbuf_puts(out, ",\"path\":");
    tc_strbuf_json_string(out, first ? first->path : "");
    tc_strbuf_printf(out, ",\"error_count\":%d", res->diags.errors); /* errors[] keeps the first few */
    tc_json_diags(out, "errors", &res->diags, TC_SEV_ERROR);
    tc_json_diags(out, "warnings", &res->diags, TC_SEV_WARNING);
    tc_strbuf_puts(out, "}\n");
}
