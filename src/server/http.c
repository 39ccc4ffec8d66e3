/* http.c — one request's life in libmicrohttpd: the first call checks the
 * headers (and refuses bad framing, 404/405/415/413 before any body byte is read), data calls
 * collect the body under --max-body, the last call hands a POST route to the
 * worker pool with the connection suspended (GET routes run inline), and the
 * call after the worker resumes it queues the reply; the completion callback
 * logs it and counts it. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "io/api.h"
#include "io/hugemem.h"
#include "server/body.h"
#include "server/conns.h"
#include "server/framing.h"
#include "server/http.h"
#include "server/log.h"
#include "server/metrics.h"
#include "server/reply.h"
#include "server/routes.h"

/* One HTTP exchange in flight: what the server knows about a request and its
 * answer between libmicrohttpd's callbacks (the JSON request itself is io's tc_request). */
typedef struct {
    double t0; /* tc_now_ms() at the first call */
    const tc_route *route;
    int route_index;
    tc_path_params params; /* the {name} segments of a pattern route */
    tc_query query;        /* GET arguments, copied at the first call */
    char method[16];
    char *path;
    tc_body body;
    int keep_body;   /* a POST route: collect the bytes (else count and drop them) */
    size_t received; /* body bytes seen */
    int pending;     /* a problem is decided; answer it at the first chance */
    tc_problem problem;
    char detail[256];
    int close;  /* framing that cannot be trusted: close the connection after the answer */
    int queued; /* a response is queued: what follows is for the log and metrics */
    int status;
    size_t bytes;
    /* The route on a worker: job goes JOB_NONE -> JOB_QUEUED (connection
     * suspended) -> JOB_DONE (reply filled, then the worker resumes the
     * connection; MHD's resume lock orders the two threads). */
    int job;
    struct MHD_Connection *conn;
    const tc_http_state *srv;
    const char *accept; /* the Accept header (the connection's memory, kept while the request lives) */
    const char *if_none_match; /* the If-None-Match header (the same) */
    tc_reply reply;
} exchange;

enum { JOB_NONE, JOB_QUEUED, JOB_DONE };

/* libmicrohttpd 0.9.75 cannot queue a response in the middle of an upload, so
 * a body refused mid-way (a chunked one past the limit) is read and dropped
 * to its end, then answered; but past this many bytes beyond the limit, or
 * well past the deadline, the connection is just closed. */
#define DISCARD_MIN ((size_t)64 << 20)

static const char oom_problem[] =
    "{\"type\":\"/problems/internal\",\"title\":\"Internal error\",\"status\":500,"
    "\"detail\":\"out of memory\",\"path\":\"\",\"error_count\":1,"
    "\"errors\":[{\"path\":\"\",\"message\":\"out of memory\"}],\"warnings\":[]}\n";

static exchange *exchange_new(const tc_http_state *srv, const char *url, const char *method) {
    exchange *ex = calloc(1, sizeof *ex);
    if (!ex) return NULL;
    ex->path = strdup(url ? url : "");
    if (!ex->path) return free(ex), NULL;
    ex->t0 = tc_now_ms();
    snprintf(ex->method, sizeof ex->method, "%s", method ? method : "");
    ex->route = tc_route_find(ex->path, &ex->route_index, &ex->params);
    tc_body_init(&ex->body, (size_t)srv->cfg->max_body);
    return ex;
}

static void exchange_free(exchange *ex) {
    if (ex->job != JOB_NONE) tc_reply_free(&ex->reply);
    tc_body_free(&ex->body);
    tc_query_free(&ex->query);
    free(ex->path);
    free(ex);
}

/* Copies one GET argument (MHD_get_connection_values' iterator). */
static enum MHD_Result take_argument(void *cls, enum MHD_ValueKind kind, const char *key, const char *value) {
    (void)kind;
    tc_query *q = cls;
    if (q->n == TC_QUERY_MAX) return q->overflow = 1, MHD_NO;
    q->key[q->n] = strdup(key ? key : "");
    q->value[q->n] = strdup(value ? value : "");
    if (!q->key[q->n] || !q->value[q->n]) {
        free(q->key[q->n]), free(q->value[q->n]);
        return q->overflow = 1, MHD_NO; /* refused as too many: the answer is a 400 either way */
    }
    q->n++;
    return MHD_YES;
}

static void refuse(exchange *ex, tc_problem p, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static void refuse(exchange *ex, tc_problem p, const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(ex->detail, sizeof ex->detail, fmt, ap);
    va_end(ap);
    ex->pending = 1;
    ex->problem = p;
    tc_body_free(&ex->body);
}

static const char *header(struct MHD_Connection *c, const char *name) {
    return MHD_lookup_connection_value(c, MHD_HEADER_KIND, name);
}

static int has_body(struct MHD_Connection *c) {
    return tc_content_length(header(c, MHD_HTTP_HEADER_CONTENT_LENGTH)) > 0 ||
           header(c, MHD_HTTP_HEADER_TRANSFER_ENCODING) != NULL;
}

/* The body checks of a POST route, from the headers alone. */
static void check_body_headers(const tc_http_state *srv, struct MHD_Connection *c, exchange *ex) {
    const char *ct = header(c, MHD_HTTP_HEADER_CONTENT_TYPE);
    const char *ce = header(c, MHD_HTTP_HEADER_CONTENT_ENCODING);
    long long len = tc_content_length(header(c, MHD_HTTP_HEADER_CONTENT_LENGTH));
    if (!tc_media_is_json(ct))
        return refuse(ex, TC_PROBLEM_MEDIA_TYPE, "%s takes application/json (UTF-8), not %s", ex->path,
                      ct ? ct : "a body without Content-Type");
    if (ce && strcasecmp(ce, "identity"))
        return refuse(ex, TC_PROBLEM_MEDIA_TYPE, "Content-Encoding %.64s is not supported; send the body as is", ce);
    if (len > srv->cfg->max_body)
        return refuse(ex, TC_PROBLEM_TOO_LARGE, "the body has %lld bytes; this server accepts at most %lld", len,
                      srv->cfg->max_body);
    ex->keep_body = 1;
    if (len > 0 && tc_body_reserve(&ex->body, (size_t)len))
        refuse(ex, TC_PROBLEM_BUSY, "no memory for a body of %lld bytes now; retry later", len);
}

static void check_headers(const tc_http_state *srv, struct MHD_Connection *c, exchange *ex) {
    if (!ex->route) return refuse(ex, TC_PROBLEM_NOT_FOUND, "there is no resource at %.200s", ex->path);
    if (!tc_route_allows(ex->route, ex->method))
        return refuse(ex, TC_PROBLEM_METHOD, "%s answers %s, not %.16s", ex->route->path, ex->route->allow, ex->method);
    if (atomic_load(&srv->draining))
        return refuse(ex, TC_PROBLEM_BUSY, "the server is shutting down; retry on another connection");
    MHD_get_connection_values(c, MHD_GET_ARGUMENT_KIND, take_argument, &ex->query);
    if (tc_route_takes_body(ex->route, ex->method)) check_body_headers(srv, c, ex);
}

/* "parse;dur=0.120, ..., encode;dur=0.050, total;dur=1.270" (milliseconds). */
static void server_timing(const exchange *ex, const tc_api_result *res, char *out, size_t n) {
    size_t k = 0;
    for (int i = 0; i < TC_NPHASES && k < n; i++)
        k += (size_t)snprintf(out + k, n - k, "%s;dur=%.3f, ", tc_phase_names[i], res->ms[i]);
    if (k < n) snprintf(out + k, n - k, "total;dur=%.3f", tc_now_ms() - ex->t0);
}

/* An image carries no JSON "warnings", so a 200 that is not JSON repeats them
 * as headers: "Tocher-Warnings: N" (all of them) and up to TC_WARNING_HEADERS
 * "Tocher-Warning: <path>: <message>" lines, in the order the core found them.
 * The messages are the core's own printable ASCII; anything else becomes '?'. */
enum { TC_WARNING_HEADERS = 8 };

static void warning_headers(const tc_reply *r, struct MHD_Response *resp) {
    const tc_diags *d = &r->res.diags;
    if (r->status != 200 || !d->warnings || !strcmp(r->content_type, TC_JSON_TYPE)) return;
    char line[sizeof d->items->path + sizeof d->items->message + 4];
    snprintf(line, sizeof line, "%d", d->warnings);
    MHD_add_response_header(resp, "Tocher-Warnings", line);
    for (int i = 0, n = 0; i < d->count && n < TC_WARNING_HEADERS; i++) {
        if (d->items[i].severity != TC_SEV_WARNING) continue;
        snprintf(line, sizeof line, "%s%s%s", d->items[i].path, *d->items[i].path ? ": " : "", d->items[i].message);
        for (char *c = line; *c; c++)
            if (*c < 0x20 || *c > 0x7e) *c = '?';
        MHD_add_response_header(resp, "Tocher-Warning", line);
        n++;
    }
}

static void add_headers(const tc_http_state *srv, const exchange *ex, const tc_reply *r, struct MHD_Response *resp,
                        const char *ctype) {
    char timing[256], retry[16];
    server_timing(ex, &r->res, timing, sizeof timing);
    if (ctype) MHD_add_response_header(resp, MHD_HTTP_HEADER_CONTENT_TYPE, ctype); /* none on a 204 or 304 */
    MHD_add_response_header(resp, "Server-Timing", timing);
    if (r->allow) MHD_add_response_header(resp, MHD_HTTP_HEADER_ALLOW, r->allow);
    if (r->etag[0]) MHD_add_response_header(resp, MHD_HTTP_HEADER_ETAG, r->etag);
    if (r->cache_control) MHD_add_response_header(resp, MHD_HTTP_HEADER_CACHE_CONTROL, r->cache_control);
    if (r->vary) MHD_add_response_header(resp, MHD_HTTP_HEADER_VARY, r->vary);
    if (r->location[0]) MHD_add_response_header(resp, MHD_HTTP_HEADER_LOCATION, r->location);
    warning_headers(r, resp);
    if (r->retry_after > 0) {
        snprintf(retry, sizeof retry, "%d", r->retry_after);
        MHD_add_response_header(resp, MHD_HTTP_HEADER_RETRY_AFTER, retry);
    }
    if (atomic_load(&srv->draining) || ex->close) MHD_add_response_header(resp, MHD_HTTP_HEADER_CONNECTION, "close");
}

/* A body handed to libmicrohttpd, and the share of the memory budget it
 * holds: both let go when libmicrohttpd is done with it. */
typedef struct {
    char *buf;
    tc_budget *budget;
    int64_t held;
} sent_body;

static void sent_body_free(void *cls) {
    sent_body *sb = cls;
    tc__huge_free(sb->buf); /* a big answer's pages serve the next one (io/hugemem.h) */
    tc_budget_give(sb->budget, sb->held);
    free(sb);
}

/* The response for the reply's body, which it takes over (no copy), with the
 * budget share it holds; NULL (everything freed) if out of memory. */
static struct MHD_Response *body_response(tc_reply *r, char *buf, size_t len) {
    sent_body *sb = malloc(sizeof *sb);
    struct MHD_Response *resp =
        sb ? MHD_create_response_from_buffer_with_free_callback_cls(len, buf, sent_body_free, sb) : NULL;
    if (!resp) {
        free(sb), free(buf);
        return NULL;
    }
    *sb = (sent_body){buf, r->res.budget, r->res.held};
    r->res.held = 0; /* the response gives it back */
    return resp;
}

/* Queues r (and frees it). Out of memory for the body degrades to a fixed 500. */
static enum MHD_Result send_reply(const tc_http_state *srv, struct MHD_Connection *c, exchange *ex, tc_reply *r) {
    size_t len = 0;
    char *buf = tc_strbuf_detach(&r->body, &len);
    struct MHD_Response *resp = buf ? body_response(r, buf, len) : NULL;
    int status = resp ? r->status : 500;
    const char *ctype = resp ? r->content_type : TC_PROBLEM_TYPE;
    if (!resp) {
        len = sizeof oom_problem - 1;
        resp = MHD_create_response_from_buffer(len, (void *)oom_problem, MHD_RESPMEM_PERSISTENT);
    }
    enum MHD_Result ok = MHD_NO;
    if (resp) {
        add_headers(srv, ex, r, resp, ctype);
        ok = MHD_queue_response(c, (unsigned)status, resp);
        MHD_destroy_response(resp);
    }
    if (ok == MHD_YES) {
        ex->queued = 1, ex->status = status, ex->bytes = len;
        tc_metrics_answered(ex->route_index, status, (tc_now_ms() - ex->t0) * 1e-3, r->res.triangles,
                            r->res.pixels);
    }
    tc_reply_free(r);
    return ok;
}

/* Queues the pending problem. Before the body (first call) libmicrohttpd then
 * reads none of it and closes the connection after the answer. */
static enum MHD_Result answer_pending(const tc_http_state *srv, struct MHD_Connection *c, exchange *ex) {
    tc_reply r;
    tc_reply_init(&r);
    tc_reply_problem(&r, ex->problem, ex->detail);
    if (ex->problem == TC_PROBLEM_METHOD) r.allow = ex->route->allow;
    if (ex->problem == TC_PROBLEM_BUSY) r.retry_after = 1;
    return send_reply(srv, c, ex, &r);
}

static enum MHD_Result first_call(tc_http_state *srv, struct MHD_Connection *c, const char *url, const char *method,
                                  const char *version, void **req_cls) {
    exchange *ex = exchange_new(srv, url, method);
    if (!ex) return MHD_NO; /* no memory even for the bookkeeping: drop the connection */
    *req_cls = ex;
    tc_metrics_begin();
    tc_conns_phase(c, TC_CONN_BODY);
    char why[sizeof ex->detail];
    if (tc_framing_error(c, version, why, sizeof why)) {
        refuse(ex, TC_PROBLEM_MALFORMED, "%s", why);
        return ex->close = 1, answer_pending(srv, c, ex);
    }
    check_headers(srv, c, ex);
    if (ex->pending && has_body(c)) return answer_pending(srv, c, ex);
    return MHD_YES;
}

static int past_deadline(const tc_srv_config *cfg, const exchange *ex) {
    return cfg->request_timeout > 0 && tc_now_ms() - ex->t0 > cfg->request_timeout * 1e3;
}

static int may_discard(const tc_srv_config *cfg, const exchange *ex) {
    size_t slack = ex->body.limit > DISCARD_MIN ? ex->body.limit : DISCARD_MIN;
    if (ex->received > ex->body.limit + slack) return 0;
    double late_ms = (cfg->request_timeout + (double)cfg->connection_timeout) * 1e3;
    return cfg->request_timeout <= 0 || tc_now_ms() - ex->t0 <= late_ms;
}

/* Collects (or, for a route without a body, counts) upload data. Past the
 * limit (or the deadline) the body is dropped and the problem answered as soon
 * as libmicrohttpd allows. */
static enum MHD_Result take_data(const tc_http_state *srv, struct MHD_Connection *c, exchange *ex, const char *data,
                                 size_t *size) {
    size_t n = *size;
    *size = 0;
    ex->received += n;
    if (ex->queued) return MHD_YES;
    if (ex->pending) return may_discard(srv->cfg, ex) ? MHD_YES : MHD_NO;
    int r = ex->keep_body ? tc_body_append(&ex->body, data, n) : ex->received > ex->body.limit;
    if (r == 0 && !past_deadline(srv->cfg, ex)) return MHD_YES;
    if (r > 0)
        refuse(ex, TC_PROBLEM_TOO_LARGE, "the body is larger than %lld bytes, the most this server accepts",
               srv->cfg->max_body);
    else if (r < 0) refuse(ex, TC_PROBLEM_BUSY, "no memory for a body of %zu bytes now; retry later", ex->received);
    else refuse(ex, TC_PROBLEM_TIMEOUT, "the body took longer than %g s to arrive", srv->cfg->request_timeout);
    answer_pending(srv, c, ex); /* may be refused mid-upload: then the last call answers */
    return MHD_YES;
}

static tc_api_limits limits(const tc_srv_config *cfg, tc_budget *memory, double t0) {
    tc_api_limits lim = {.max_vertices = cfg->max_vertices, .max_triangles = cfg->max_triangles,
                         .max_points = cfg->max_points, .max_pixels = cfg->max_pixels,
                         .max_samples = cfg->max_samples, .render_threads = (int)cfg->render_threads,
                         .memory = memory};
    if (cfg->request_timeout > 0) lim.deadline_ms = t0 + cfg->request_timeout * 1e3;
    return lim;
}

/* Runs the route (on a worker for POST routes: it touches no connection state). */
static void run(const tc_http_state *srv, exchange *ex, tc_reply *r) {
    tc_route_input in = {ex->body.buf ? ex->body.buf : "", ex->body.len, ex->accept,
                         limits(srv->cfg, (tc_budget *)&srv->memory, ex->t0), &ex->params, &ex->query,
                         ex->if_none_match, srv->meshes};
    long long bad;
    if (past_deadline(srv->cfg, ex))
        return tc_reply_problem(r, TC_PROBLEM_TIMEOUT, "the request took too long to arrive");
    if ((bad = tc_utf8_error(in.body, in.len)) >= 0) {
        char detail[96];
        snprintf(detail, sizeof detail, "the body is not UTF-8 (byte %lld)", bad);
        return tc_reply_problem(r, TC_PROBLEM_MALFORMED, detail);
    }
    tc_route_handler(ex->route, ex->method)(&in, r);
    /* Not every phase of the API watches the deadline; the answer keeps the promise. */
    if (r->status < 500 && past_deadline(srv->cfg, ex)) {
        char detail[128];
        snprintf(detail, sizeof detail, "the request ran past its time limit: it took %.1f s; this server allows %g s",
                 (tc_now_ms() - ex->t0) * 1e-3, srv->cfg->request_timeout);
        tc_reply_problem(r, TC_PROBLEM_TIMEOUT, detail);
    }
}

/* A worker's job: the route, or (cancelled at shutdown) a 503 saying it could
 * not start. Resuming the connection is the last touch of ex. */
static void job_run(void *arg, int cancelled) {
    exchange *ex = arg;
    if (cancelled) {
        tc_metrics_workers(-1, 0);
        tc_reply_problem(&ex->reply, TC_PROBLEM_BUSY, "the server shut down before this request could start; retry");
        ex->reply.retry_after = 1;
    } else {
        tc_metrics_workers(-1, 1);
        run(ex->srv, ex, &ex->reply);
        tc_metrics_workers(0, -1);
    }
    ex->job = JOB_DONE;
    MHD_resume_connection(ex->conn);
}

/* Suspends the connection and queues the route on the pool. The idle timeout
 * is off meanwhile (restored in reply_job): the work is bounded by the request
 * deadline, and a wait longer than the idle timeout must not cost the answer.
 * A full queue is answered 503 at once. */
static enum MHD_Result submit_job(const tc_http_state *srv, struct MHD_Connection *c, exchange *ex) {
    ex->conn = c, ex->srv = srv;
    ex->accept = header(c, MHD_HTTP_HEADER_ACCEPT);
    ex->if_none_match = header(c, MHD_HTTP_HEADER_IF_NONE_MATCH);
    tc_reply_init(&ex->reply);
    ex->job = JOB_QUEUED;
    MHD_set_connection_option(c, MHD_CONNECTION_OPTION_TIMEOUT, 0u);
    MHD_suspend_connection(c); /* before submit: a worker may resume it at once */
    tc_metrics_workers(1, 0);
    if (tc_pool_submit(srv->pool, job_run, ex) == 0) return MHD_YES;
    tc_metrics_workers(-1, 0);
    /* Refused: answered like a finished job, by the call the resume brings. */
    char detail[160];
    snprintf(detail, sizeof detail, "all %lld workers are busy and %lld requests wait for one; retry later",
             srv->cfg->workers, srv->cfg->max_queue);
    tc_reply_problem(&ex->reply, TC_PROBLEM_BUSY, detail);
    ex->reply.retry_after = 1;
    ex->job = JOB_DONE;
    MHD_resume_connection(c);
    return MHD_YES;
}

/* After the worker resumed the connection: restore the idle timeout, send. */
static enum MHD_Result reply_job(const tc_http_state *srv, struct MHD_Connection *c, exchange *ex) {
    MHD_set_connection_option(c, MHD_CONNECTION_OPTION_TIMEOUT, (unsigned)srv->cfg->connection_timeout);
    ex->job = JOB_NONE;
    tc_reply r = ex->reply;
    tc_reply_init(&ex->reply);
    return send_reply(srv, c, ex, &r);
}

static enum MHD_Result last_call(const tc_http_state *srv, struct MHD_Connection *c, exchange *ex) {
    if (ex->queued) return MHD_YES;
    if (ex->job == JOB_DONE) return reply_job(srv, c, ex);
    if (ex->job == JOB_QUEUED) return MHD_YES; /* not expected while suspended; the worker resumes it */
    if (ex->pending) return answer_pending(srv, c, ex);
    if (tc_route_on_pool(ex->route, ex->method)) return submit_job(srv, c, ex);
    tc_reply r; /* the other GET routes answer from memory: inline */
    tc_reply_init(&r);
    ex->accept = header(c, MHD_HTTP_HEADER_ACCEPT);
    ex->if_none_match = header(c, MHD_HTTP_HEADER_IF_NONE_MATCH);
    run(srv, ex, &r);
    return send_reply(srv, c, ex, &r);
}

enum MHD_Result tc_http_access(void *cls, struct MHD_Connection *c, const char *url, const char *method,
                               const char *version, const char *upload_data, size_t *upload_data_size,
                               void **req_cls) {
    exchange *ex = *req_cls;
    if (!ex) return first_call(cls, c, url, method, version, req_cls);
    if (*upload_data_size) return take_data(cls, c, ex, upload_data, upload_data_size);
    tc_conns_phase(c, TC_CONN_WORK);
    return last_call(cls, c, ex);
}

static const char *ending(enum MHD_RequestTerminationCode toe) {
    switch (toe) {
    case MHD_REQUEST_TERMINATED_COMPLETED_OK: return NULL;
    case MHD_REQUEST_TERMINATED_TIMEOUT_REACHED: return "idle timeout";
    case MHD_REQUEST_TERMINATED_DAEMON_SHUTDOWN: return "shutdown";
    case MHD_REQUEST_TERMINATED_CLIENT_ABORT: return "client closed";
    case MHD_REQUEST_TERMINATED_READ_ERROR: return "read error";
    default: return "connection error";
    }
}

void tc_http_completed(void *cls, struct MHD_Connection *c, void **req_cls, enum MHD_RequestTerminationCode toe) {
    (void)cls;
    exchange *ex = *req_cls;
    if (!ex) return;
    *req_cls = NULL;
    double ms = tc_now_ms() - ex->t0;
    tc_log_request(ex->method, ex->path, ex->status, ex->bytes, ms, ending(toe));
    tc_metrics_end(ex->route_index, ex->queued);
    tc_conns_phase(c, TC_CONN_IDLE);
    exchange_free(ex);
}
