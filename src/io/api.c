/* api.c — request bytes -> io -> core -> response bytes, one function per
 * endpoint. The CLI and the daemon both call these, so their output is one. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "image/image.h"
#include "io/accept.h"
#include "io/api.h"
#include "io/jsonout.h"
#include "io/prescan.h"
#include "io/request.h"
#include "io/request_write.h"
#include "io/response.h"

const char *const tc_phase_names[TC_NPHASES] = {"parse", "validate", "build", "evaluate", "encode"};

void tc_api_result_init(tc_api_result *res) {
    res->status = 200;
    res->second_doc = TC_DIAGS_KEEP;
    res->triangles = res->pixels = 0;
    res->content_type = "application/json";
    res->budget = NULL;
    res->held = 0;
    res->retry_after = 0;
    tc_diags_init(&res->diags);
    for (int i = 0; i < TC_NPHASES; i++) res->ms[i] = 0;
}

void tc_api_result_free(tc_api_result *res) {
    tc_api_result_release(res);
    tc_diags_free(&res->diags);
}

void tc_api_result_release(tc_api_result *res) {
    tc_budget_give(res->budget, res->held);
    res->held = 0;
}

/* Adds the time since *t0 to phase p and restarts the clock. */
static void lap(tc_api_result *res, int p, double *t0) {
    double t = tc_now_ms();
    res->ms[p] += t - *t0;
    *t0 = t;
}

/* parse_within's answer for a body whose arrays are over a limit. */
enum { REQ_OVER_LIMIT = -1 };

/* Past the request's deadline (lim->deadline_ms): a 503 whose problem says in
 * which phase. One clock read, so it may run between phases and every chunk. */
static int late(const tc_api_limits *lim, tc_api_result *res, const char *doing) {
    if (!lim || lim->deadline_ms <= 0 || tc_now_ms() <= lim->deadline_ms) return 0;
    tc_diags_add(&res->diags, TC_SEV_ERROR, "", "the request ran past its time limit while %s", doing);
    res->status = 503;
    return 1;
}

/* late() as a callback of the printer. */
typedef struct {
    const tc_api_limits *lim;
    tc_api_result *res;
} late_ctx;

static int late_printing(void *ctx) {
    late_ctx *lc = ctx;
    return late(lc->lim, lc->res, "writing the answer");
}

/* Points evaluated between two deadline checks (each point is independent:
 * chunks change nothing but the checks), and points compared between two
 * checks (pooling chunks rounds differently: a request of fewer points is
 * one tc_compare, as before). */
enum { EVAL_CHUNK = 8192, COMPARE_CHUNK = 65536 };

static int status_of_request(int rs) {
    return rs == TC_REQ_MALFORMED ? 400 : rs == TC_REQ_INVALID ? 422 : rs == REQ_OVER_LIMIT ? 413 : 500;
}

static int status_of_core(int rc) { return rc == TC_EINVAL ? 422 : rc == TC_ELIMIT ? 413 : 500; }

/* Everything a request needs up to a built reconstruction. */
typedef struct {
    tc_request *req;
    tc_mesh *mesh;
    tc_recon *recon;
    tc_locator *locator; /* built once for a stored mesh (tc_api_job); NULL: each use makes its own */
} job;

static void job_free(job *j) {
    tc_locator_free(j->locator);
    tc_recon_free(j->recon);
    tc_mesh_free(j->mesh);
    tc_request_free(j->req);
}

/* A count over its limit: 413 naming the field. */
static int over(tc_api_result *res, const char *field, int64_t n, int64_t max, const char *what) {
    if (max <= 0 || n <= max) return 0;
    tc_diags_add(&res->diags, TC_SEV_ERROR, field, "%lld %s; this server accepts at most %lld", (long long)n, what,
                 (long long)max);
    res->status = 413;
    return 1;
}

/* The triangles a request's mesh becomes: a quad counts as the two it is split into. */
static int64_t triangle_count(const tc_request *req) {
    return req->desc.ntris > 0 ? req->desc.ntris : 2 * (int64_t)req->desc.nquads;
}

static int within_limits(const tc_request *req, const tc_api_limits *lim, tc_api_result *res) {
    if (!lim) return 1;
    int quads = req->desc.ntris <= 0 && req->desc.nquads > 0;
    return !over(res, "vertices", req->desc.nverts, lim->max_vertices, "vertices") &&
           !over(res, quads ? "quads" : "triangles", triangle_count(req), lim->max_triangles,
                 quads ? "triangles (2 per quad)" : "triangles") &&
           !over(res, "points", (int64_t)req->npoints, lim->max_points, "points") &&
           !over(res, "reference.points", (int64_t)req->nreference, lim->max_points, "reference points");
}

/* Parses the request, counting its limited arrays in the bytes first (io/prescan.h, in
 * tc_request_parse_limited's one walk with the fast path): a body over a limit gets its 413
 * without a cJSON tree, which costs ~40 bytes per byte of input. The messages are
 * within_limits' own. */
static int parse_within(const char *body, size_t len, unsigned expect, const tc_api_limits *lim, tc_request **req,
                        tc_api_result *res) {
    *req = NULL;
    if (!lim) return tc_request_parse(body, len, expect, req, &res->diags);
    int64_t t = lim->max_triangles;
    const tc_scan_limit L[] = {{"vertices", lim->max_vertices}, {"triangles", t}, {"quads", t > 0 ? t / 2 : 0},
                               {"points", lim->max_points}, {"reference.points", lim->max_points}};
    static const char *const what[] = {"vertices", "triangles", "triangles (2 per quad)", "points",
                                       "reference points"};
    tc_req_limits rl = {L, (int)(sizeof L / sizeof L[0]), -1, 0};
    int rs = tc_request_parse_limited(body, len, expect, &rl, req, &res->diags);
    if (rs != TC_REQ_OVER_LIMIT) return rs;
    int k = rl.over;
    int64_t n = rl.count;
    /* as within_limits counts; a typed array's shape may say up to INT64_MAX quads (fuzz_api) */
    if (k == 2) return over(res, "quads", n > INT64_MAX / 2 ? INT64_MAX : 2 * n, t, what[k]), REQ_OVER_LIMIT;
    return over(res, L[k].path, n, L[k].max, what[k]), REQ_OVER_LIMIT;
}

/* The threads one request may use (the daemon's --render-threads): at least 1. */
static int threads_of(const tc_api_limits *lim) { return lim && lim->render_threads > 1 ? lim->render_threads : 1; }

/* What the validation and the builds take from the limits: the threads, the
 * render's (the daemon's worker count; they change the time only, never a number
 * or a finding), and the request's deadline, checked between a build's stages. */
static void pass_limits(tc_request *req, const tc_api_limits *lim) {
    int n = threads_of(lim);
    double deadline = lim ? lim->deadline_ms : 0;
    req->desc.threads = n;
    req->opt.threads = n, req->opt.deadline_ms = deadline;
    for (int i = 0; i < req->nmethods; i++) req->methods[i].threads = n, req->methods[i].deadline_ms = deadline;
}

/* Parses a request into j->req under the limits: 200, or the status (res says why). */
static int job_parse(job *j, const char *body, size_t len, unsigned expect, const tc_api_limits *lim,
                     tc_api_result *res, double *t0) {
    int rs = parse_within(body, len, expect, lim, &j->req, res);
    lap(res, TC_PHASE_PARSE, t0);
    if (rs != TC_REQ_OK) return res->status = status_of_request(rs);
    pass_limits(j->req, lim);
    if (!within_limits(j->req, lim, res) || late(lim, res, "parsing")) return res->status;
    return 200;
}

/* Validates j->req's mesh and builds its reconstruction: 200, or the status. */
static int job_make(job *j, const tc_api_limits *lim, tc_api_result *res, double *t0) {
    int rc = tc_mesh_new(&j->req->desc, &j->mesh, &res->diags);
    lap(res, TC_PHASE_VALIDATE, t0);
    if (rc != TC_OK) return res->status = status_of_core(rc);
    if (late(lim, res, "checking the mesh")) return res->status;
    rc = tc_recon_new(j->mesh, &j->req->opt, &j->recon, &res->diags);
    lap(res, TC_PHASE_BUILD, t0);
    /* TC_ETIMEOUT: the build stopped between two stages, past the deadline late() reads */
    if ((rc == TC_OK || rc == TC_ETIMEOUT) && late(lim, res, "building the reconstruction")) return res->status;
    if (rc != TC_OK) return res->status = status_of_core(rc);
    res->triangles = triangle_count(j->req);
    return res->status = 200;
}

/* Parse, validate, build: the one path from request bytes to a built job. */
static int job_build(job *j, const char *body, size_t len, unsigned expect, const tc_api_limits *lim,
                     tc_api_result *res, double *t0) {
    if (job_parse(j, body, len, expect, lim, res, t0) != 200) return res->status;
    return job_make(j, lim, res, t0);
}

/* Ends the answer in body and puts it in out: appended to out's content, or, when out is
 * empty, handed over (a big answer is not copied; its pages were faulted in once). */
static int finish(tc_strbuf *out, tc_strbuf *body, tc_api_result *res) {
    tc_json_diags(body, "warnings", &res->diags, TC_SEV_WARNING);
    tc_strbuf_puts(body, "}\n");
    if (body->oom) {
        tc_strbuf_free(body);
        tc_diags_add(&res->diags, TC_SEV_ERROR, "", "out of memory writing the response");
        return res->status = 500;
    }
    if (!out->len && !out->oom) { /* the usual case: out becomes the body, no copy */
        size_t len = 0, cap = body->cap;
        char *buf = tc_strbuf_detach(body, &len);
        tc_strbuf_adopt(out, buf, len, cap);
    } else {
        tc_strbuf_append(out, body->buf, body->len);
        tc_strbuf_free(body);
    }
    return res->status = out->oom ? 500 : 200;
}

int tc_api_ordinates(const char *body, size_t len, const tc_api_limits *lim, tc_strbuf *out, tc_api_result *res) {
    double t0 = tc_now_ms();
    job j = {0};
    if (job_build(&j, body, len, TC_REQ_MESH, lim, res, &t0) != 200) {
        job_free(&j);
        return res->status;
    }
    tc_strbuf b;
    tc_strbuf_init(&b);
    tc_strbuf_putc(&b, '{');
    tc_json_ordinates_enc(&b, j.recon, j.req->encoding_base64);
    job_free(&j);
    int rc = finish(out, &b, res);
    lap(res, TC_PHASE_ENCODE, &t0);
    return rc;
}

/* Evaluates the points in chunks, checking the deadline between them: 0, or
 * 503 (res says why) if it passed. */
static int eval_chunked(const job *j, const tc_locator *L, const tc_request *pts, int nc, double *val,
                        double *grad, int32_t *tri, const tc_api_limits *lim, tc_api_result *res) {
    size_t n = pts->npoints, ncs = (size_t)nc;
    for (size_t i = 0; i < n; i += EVAL_CHUNK) {
        if (late(lim, res, "evaluating the points")) return res->status;
        size_t k = n - i < EVAL_CHUNK ? n - i : EVAL_CHUNK;
        tc_eval_points(j->recon, L, k, pts->points + 2 * i, val + i * ncs, grad ? grad + 2 * i * ncs : NULL, tri + i);
    }
    return late(lim, res, "evaluating the points") ? res->status : 0; /* before the encoding */
}

/* Locates and evaluates the points; writes the response members. TC_OK,
 * TC_ENOMEM, or TC_ETIMEOUT (res holds the 503). */
static int evaluate(const job *j, const tc_request *pts, tc_strbuf *b, const tc_api_limits *lim,
                    tc_api_result *res) {
    int nc = tc_mesh_channel_count(j->mesh);
    size_t n = pts->npoints;
    tc_locator *L = NULL;
    double *val = malloc((n ? n : 1) * (size_t)nc * sizeof *val);
    double *grad = pts->with_gradients ? malloc((n ? n : 1) * 2 * (size_t)nc * sizeof *grad) : NULL;
    int32_t *tri = malloc((n ? n : 1) * sizeof *tri);
    int rc = !val || !tri || (pts->with_gradients && !grad) ? TC_ENOMEM
             : j->locator                                   ? TC_OK
                                                            : tc_locator_new(j->mesh, &L);
    if (rc == TC_OK && eval_chunked(j, L ? L : j->locator, pts, nc, val, grad, tri, lim, res)) rc = TC_ETIMEOUT;
    if (rc == TC_OK) { /* printing is most of a large answer now: the deadline is checked in it too */
        tc_strbuf_putc(b, '{');
        late_ctx lc = {lim, res};
        if (tc_json_points_enc_until(b, nc, n, val, grad, tri, j->req->values_plain,
                                     pts->encoding_base64 || j->req->encoding_base64, late_printing, &lc))
            rc = TC_ETIMEOUT;
    }
    tc_locator_free(L);
    free(val), free(grad), free(tri);
    return rc;
}

int tc_api_evaluate(const char *body, size_t len, const char *points, size_t plen, const tc_api_limits *lim,
                    tc_strbuf *out, tc_api_result *res) {
    double t0 = tc_now_ms();
    job j = {0};
    tc_request *pts = NULL;
    unsigned expect = points ? TC_REQ_MESH : TC_REQ_MESH | TC_REQ_POINTS;
    if (job_build(&j, body, len, expect, lim, res, &t0) == 200 && points) {
        res->second_doc = res->diags.count;
        int rs = parse_within(points, plen, TC_REQ_POINTS, lim, &pts, res);
        lap(res, TC_PHASE_PARSE, &t0);
        if (rs != TC_REQ_OK) res->status = status_of_request(rs);
        else if (!within_limits(pts, lim, res)) res->status = 413;
    }
    tc_strbuf b;
    tc_strbuf_init(&b);
    if (res->status == 200) {
        int rc = evaluate(&j, pts ? pts : j.req, &b, lim, res);
        if (rc != TC_OK) res->status = rc == TC_ETIMEOUT ? 503 : 500;
        lap(res, TC_PHASE_EVALUATE, &t0);
    }
    tc_request_free(pts);
    job_free(&j);
    if (res->status != 200) {
        tc_strbuf_free(&b);
        return res->status;
    }
    int rc = finish(out, &b, res);
    lap(res, TC_PHASE_ENCODE, &t0);
    return rc;
}

void tc_api_problem_write(tc_strbuf *out, int status, const char *type, const char *title, const tc_diags *d) {
    const tc_diag *first = NULL;
    for (int i = 0; i < d->count && !first; i++)
        if (d->items[i].severity == TC_SEV_ERROR) first = &d->items[i];
    tc_strbuf_puts(out, "{\"type\":\"/problems/");
    tc_strbuf_puts(out, type);
    tc_strbuf_puts(out, "\",\"title\":");
    tc_strbuf_json_string(out, title);
    tc_strbuf_printf(out, ",\"status\":%d,\"detail\":", status);
    tc_strbuf_json_string(out, first ? first->message : title);
    tc_strbuf_puts(out, ",\"path\":");
    tc_strbuf_json_string(out, first ? first->path : "");
    tc_strbuf_printf(out, ",\"error_count\":%d", d->errors); /* errors[] keeps the first few */
    tc_json_diags(out, "errors", d, TC_SEV_ERROR);
    tc_json_diags(out, "warnings", d, TC_SEV_WARNING);
    tc_strbuf_puts(out, "}\n");
}

void tc_api_problem(tc_strbuf *out, const tc_api_result *res) {
    const char *type = "internal", *title = "Internal error";
    if (res->status == 400) type = "malformed-request", title = "Malformed request";
    if (res->status == 413) type = "too-large", title = "Request too large";
    if (res->status == 422) type = "invalid-mesh", title = "Invalid mesh";
    if (res->status == 503) type = "timeout", title = "Request took too long";
    if (res->status == 503 && res->retry_after) type = "busy", title = "Server busy";
    tc_api_problem_write(out, res->status, type, title, &res->diags);
}

void tc_api_add_timings(tc_strbuf *out, const tc_api_result *res) {
    if (out->len < 2 || out->buf[out->len - 1] != '\n' || out->buf[out->len - 2] != '}') return;
    out->len -= 2;
    double total = 0;
    tc_strbuf_puts(out, ",\"timings\":{");
    for (int i = 0; i < TC_NPHASES; i++) {
        tc_strbuf_printf(out, "\"%s\":%.3f,", tc_phase_names[i], res->ms[i]);
        total += res->ms[i];
    }
    tc_strbuf_printf(out, "\"total\":%.3f}}\n", total);
}

/* A render is rasterized and encoded a band of rows at a time, so that it
 * holds at most its encoded answer (grown in place, handed to the response
 * without a copy) and one band: ~8 MiB of working floats, a multiple of
 * tc_render's unit of work for its threads; or, on many threads, ROWS_PER_THREAD
 * rows per thread (at most BAND_MAX_BYTES). A band of 96 rows (8 MiB of a
 * 4096-wide grey tile) kept 16 threads to 12 bands of 8 rows per call: such a
 * tile rendered at 1461 Mpixel/s in 96-row calls, 2075 in 256-row ones and 2834
 * whole (lent Xeon, 16 threads, bench/perf/device/rows_per_call.txt). */
enum { BAND_BYTES = 8 << 20, BAND_MAX_BYTES = 64 << 20, BAND_MIN_ROWS = TC_RENDER_BAND_ROWS, ROWS_PER_THREAD = 16 };

/* One band's pixels: values, and for a format with alpha its coverage and owners (else
 * NULL: tc_render then keeps a band's owners in its own cache-sized scratch), freed
 * together. The big ones come from and go back to the core's spare blocks (tc__free), so a
 * render does not fault in and zero fresh pages for every band buffer. */
typedef struct {
    float *values, *alpha;
    int32_t *owner;
    int32_t rows; /* rows allocated */
} band;

static void band_free(band *b) { tc__free(b->values), tc__free(b->alpha), tc__free(b->owner); }

/* Working bytes of one pixel of a band: values, alpha, owner, and the
 * encoder's converted copy of the samples (plus alpha). */
static int64_t band_pixel_bytes(int nc) { return (int64_t)(2 * nc + 3) * 4; }

/* threads: threads_of(lim), at least 1. A render into its answer (tc_img_places) is one
 * band, the whole tile: it holds no band of its own, and one tc_render call keeps every
 * thread busy to the end (a 4096² tile rendered 1.37x faster whole than in 256-row calls on
 * 16 threads of the lent Xeon, rows_per_call.txt). */
static int32_t band_rows(const tc_viewport *vp, int nc, int threads, int in_place) {
    if (in_place) return vp->height;
    int64_t row_bytes = (int64_t)vp->width * band_pixel_bytes(nc), rows = BAND_BYTES / row_bytes;
    int64_t wide = (int64_t)threads * ROWS_PER_THREAD, most = BAND_MAX_BYTES / row_bytes;
    if (wide > most) wide = most;
    if (rows < wide) rows = wide;
    rows = rows < BAND_MIN_ROWS ? BAND_MIN_ROWS : rows / BAND_MIN_ROWS * BAND_MIN_ROWS;
    return rows > vp->height ? vp->height : (int32_t)rows;
}

/* The most a render may hold at once: its answer at most (every stored
 * sample uncompressed, plus 1/64 and 64 KiB for headers and a compressor's
 * worst case) and one band, or rendered into its answer, tc_render's owners
 * (TC_RENDER_BAND_ROWS rows per thread). What --max-memory reserves before it starts. */
static int64_t render_peak(const tc_viewport *vp, int nc, int fmt, int threads) {
    const tc_img_traits *t = tc_img_traits_of((tc_img_format)fmt);
    int64_t np = (int64_t)vp->width * vp->height;
    int64_t stored = np * (nc + (tc_img_has_alpha((tc_img_format)fmt, nc) ? 1 : 0)) * t->sample_bytes;
    int64_t working = tc_img_places((tc_img_format)fmt, nc)
                          ? (int64_t)threads * TC_RENDER_BAND_ROWS * vp->width * (int64_t)sizeof(int32_t)
                          : (int64_t)vp->width * band_rows(vp, nc, threads, 0) * band_pixel_bytes(nc);
    return stored + stored / 64 + (64 << 10) + working;
}

/* in_place: the writer takes the samples where they are rendered (raw), so the band has no
 * values of its own. */
static int band_alloc(band *b, const tc_viewport *vp, int nc, int threads, int in_place, int alpha) {
    int values = !in_place;
    b->rows = band_rows(vp, nc, threads, in_place);
    size_t np = (size_t)vp->width * (size_t)b->rows;
    b->values = values ? tc__malloc(np * (size_t)nc, sizeof *b->values) : NULL;
    b->alpha = alpha ? tc__malloc(np, sizeof *b->alpha) : NULL;
    b->owner = alpha ? tc__malloc(np, sizeof *b->owner) : NULL;
    return (!values || b->values) && (!alpha || (b->alpha && b->owner)) ? TC_OK : TC_ENOMEM;
}

/* The request's "format", else the caller's (an Accept header, a file's extension), else the default. */
static int format_of(const tc_request *req, int fallback) {
    int f = req->format >= 0 ? req->format : fallback;
    return f >= 0 ? f : TC_IMG_DEFAULT;
}

/* Rasterizes rows [row0, row0 + rows) of the viewport into values (b's, or the
 * answer's own bytes) and b's owners and alpha (overlay included): each pixel as
 * the whole tile's. A linear format's samples hold values up to its max_sample (float:
 * FLT_MAX, half: 65504; display formats 0, none): tc_render writes a sample beyond it
 * as that bound and adds it to *saturated (the warning says so: the encoders would
 * otherwise write infinities that /v1/evaluate does not give). The overlay, drawn after,
 * is at most 1 in a linear format. Returns a core status. */
static int rasterize(const job *j, const tc_api_limits *lim, int fmt, const tc_locator *L, int32_t row0,
                     int32_t rows, band *b, float *values, int64_t *saturated) {
    const tc_request *req = j->req;
    const tc_viewport *vp = &req->viewport;
    tc_render_options ropt = {.background = req->has_background ? req->background : NULL,
                              .threads = threads_of(lim),
                              .deadline_ms = lim ? lim->deadline_ms : 0,
                              .row0 = row0,
                              .rows = rows,
                              .limit = tc_img_traits_of((tc_img_format)fmt)->max_sample,
                              .limited = saturated};
    int rc = tc_render(j->recon, L, vp, &ropt, values, b->owner);
    if (rc != TC_OK) return rc;
    if (b->alpha)
        for (size_t p = 0; p < (size_t)vp->width * (size_t)rows; p++) b->alpha[p] = b->owner[p] >= 0 ? 1.0f : 0.0f;
    if (req->overlay) /* a display-referred format shows v * 2^exposure: scale the overlay so it shows as drawn */
        tc_render_overlay_rows(j->recon, vp, tc_img_traits_of((tc_img_format)fmt)->display ? pow(2, -req->exposure) : 1,
                               row0, rows, values);
    return TC_OK;
}

static void saturate_warning(int fmt, int64_t count, tc_api_result *res) {
    if (count)
        tc_diags_add(&res->diags, TC_SEV_WARNING, "format",
                     "%lld samples reach or pass the largest value %s holds, %.6g: they are written as that, with "
                     "their sign (/v1/evaluate gives the values in double precision)",
                     (long long)count, tc_img_format_name((tc_img_format)fmt), tc_img_traits_of((tc_img_format)fmt)->max_sample);
}

/* A render's state from the first band to the answer. */
typedef struct {
    const job *j;
    const tc_api_limits *lim;
    int fmt;
    tc_locator *L;
    tc_img_writer *w;
    band b;
    int64_t saturated;
    char err[256];
} render_state;

/* Every band rendered and handed to the writer; a core status (TC_EINVAL:
 * the writer failed, with its message in st->err). */
static int render_bands(render_state *st, tc_api_result *res, double *t0) {
    const tc_viewport *vp = &st->j->req->viewport;
    for (int32_t row0 = 0; row0 < vp->height; row0 += st->b.rows) {
        int32_t rows = vp->height - row0 < st->b.rows ? vp->height - row0 : st->b.rows;
        float *values = st->b.values ? st->b.values : tc_img_writer_place(st->w, rows);
        int rc = rasterize(st->j, st->lim, st->fmt, st->L ? st->L : st->j->locator, row0, rows, &st->b, values,
                           &st->saturated);
        lap(res, TC_PHASE_EVALUATE, t0);
        if (rc != TC_OK) return rc;
        rc = tc_img_writer_rows(st->w, values, st->b.alpha, rows, st->err, sizeof st->err); /* NULL: no alpha */
        lap(res, TC_PHASE_ENCODE, t0);
        if (rc != 0) return TC_EINVAL;
    }
    return TC_OK;
}

/* Renders and encodes into out (empty): a core status, or TC_EINVAL with the
 * image library's message in st->err. */
static int render_encode(render_state *st, tc_strbuf *out, tc_api_result *res, double *t0) {
    const tc_request *req = st->j->req;
    int nc = tc_mesh_channel_count(st->j->mesh);
    tc_img header = {req->viewport.width, req->viewport.height, nc, NULL, NULL, req->exposure, req->linear};
    static const float marks_alpha = 1;
    if (tc_img_has_alpha((tc_img_format)st->fmt, nc)) header.alpha = &marks_alpha;
    if (tc_img_writer_open(&header, (tc_img_format)st->fmt, &st->w, st->err, sizeof st->err) != 0) return TC_EINVAL;
    int in_place = tc_img_places((tc_img_format)st->fmt, nc); /* raw: rendered straight into the answer */
    int rc = band_alloc(&st->b, &req->viewport, nc, threads_of(st->lim), in_place, header.alpha != NULL);
    if (rc == TC_OK && !st->j->locator) rc = tc_locator_new(st->j->mesh, &st->L); /* a stored mesh has its own */
    if (rc != TC_OK) return rc;
    if ((rc = render_bands(st, res, t0)) != TC_OK) return rc;
    unsigned char *bytes;
    size_t len, cap;
    if (tc_img_writer_finish(st->w, &bytes, &len, &cap, st->err, sizeof st->err) != 0) return TC_EINVAL;
    lap(res, TC_PHASE_ENCODE, t0);
    tc_strbuf_adopt(out, (char *)bytes, len, cap);
    return out->oom ? TC_ENOMEM : TC_OK;
}

/* Reserves the render's peak in the memory budget: 413 if it could never fit,
 * 503 (retry) if requests in flight hold too much of it now. */
static int reserve(const job *j, const tc_api_limits *lim, int fmt, int64_t *peak, tc_api_result *res) {
    tc_budget *b = lim ? lim->memory : NULL;
    *peak = render_peak(&j->req->viewport, tc_mesh_channel_count(j->mesh), fmt, threads_of(lim));
    if (!b || tc_budget_take(b, *peak)) return 200;
    int64_t mib = 1 << 20;
    if (*peak > b->limit) {
        tc_diags_add(&res->diags, TC_SEV_ERROR, "viewport",
                     "this render may hold %lld MiB at once (its answer and one band); this server's memory budget "
                     "for requests is %lld MiB",
                     (long long)((*peak + mib - 1) / mib), (long long)(b->limit / mib));
        return res->status = 413;
    }
    tc_diags_add(&res->diags, TC_SEV_ERROR, "",
                 "renders in flight hold %lld of this server's %lld MiB for requests; this one needs %lld MiB: retry",
                 (long long)(tc_budget_used(b) / mib), (long long)(b->limit / mib), (long long)((*peak + mib - 1) / mib));
    res->retry_after = 1;
    return res->status = 503;
}

/* A format that cannot hold the mesh's channel count (PNG: grey or RGB only) is
 * refused before any work. */
static int check_format(const job *j, int fmt, tc_api_result *res) {
    int nc = tc_mesh_channel_count(j->mesh);
    char counts[96], use[96];
    if (!tc_img_holds((tc_img_format)fmt, nc)) {
        tc_img_format f = (tc_img_format)fmt;
        tc_diags_add(&res->diags, TC_SEV_ERROR, "format", "%s holds %s channels; this mesh has %d (use %s)",
                     tc_img_format_name(f), tc_img_list_channels(f, counts, sizeof counts), nc,
                     tc_img_list_holding(nc, 0, use, sizeof use));
        return res->status = 422;
    }
    return 200;
}

int tc_api_render(const char *body, size_t len, const char *accept, const tc_api_limits *lim, tc_strbuf *out,
                  tc_api_result *res) {
    return tc_api_render_as(body, len, tc_accept_format(accept), lim, out, res);
}

/* The render of a built job: j->req holds the viewport and the look (format
 * aside, given as fmt), j->mesh and j->recon the reconstruction. Every render,
 * of a request's own mesh or of a stored one, goes through here: the limits,
 * the format's channels, the memory budget, then bands rasterized and encoded,
 * and only what the answer holds kept in the budget. */
static int render_job(const job *j, int fmt, const tc_api_limits *lim, tc_strbuf *out, tc_api_result *res,
                      double *t0) {
    const tc_viewport *vp = &j->req->viewport;
    int64_t np = (int64_t)vp->width * vp->height, peak;
    if (over(res, "viewport", np, lim ? lim->max_pixels : 0, "pixels") ||
        over(res, "viewport", np * tc_mesh_channel_count(j->mesh), lim ? lim->max_samples : 0,
             "samples (pixels x channels)") ||
        check_format(j, fmt, res) != 200 || reserve(j, lim, fmt, &peak, res) != 200)
        return res->status;
    render_state st = {j, lim, fmt, NULL, NULL, {0}, 0, ""};
    int rc = render_encode(&st, out, res, t0);
    tc_img_writer_free(st.w);
    tc_locator_free(st.L);
    band_free(&st.b);
    res->pixels = rc == TC_OK ? np : 0;
    if (rc == TC_OK) {
        saturate_warning(fmt, st.saturated, res);
        res->content_type = tc_img_mime((tc_img_format)fmt);
        res->budget = lim ? lim->memory : NULL;
        res->held = !res->budget ? 0 : (int64_t)out->cap < peak ? (int64_t)out->cap : peak; /* never more than taken */
        tc_budget_give(res->budget, peak - res->held);
        return res->status = 200;
    }
    tc_budget_give(lim ? lim->memory : NULL, peak);
    tc_strbuf_free(out);
    if (rc == TC_ETIMEOUT)
        tc_diags_add(&res->diags, TC_SEV_ERROR, "", "the request ran past its time limit while rendering");
    else if (*st.err)
        tc_diags_add(&res->diags, TC_SEV_ERROR, "format", "%s", st.err);
    return res->status = rc == TC_ETIMEOUT ? 503 : rc == TC_EINVAL && !*st.err ? 422 : 500;
}


int tc_api_render_as(const char *body, size_t len, int fallback, const tc_api_limits *lim, tc_strbuf *out,
                     tc_api_result *res) {
    double t0 = tc_now_ms();
    job j = {0};
    if (job_build(&j, body, len, TC_REQ_MESH | TC_REQ_VIEWPORT, lim, res, &t0) == 200)
        render_job(&j, format_of(j.req, fallback), lim, out, res, &t0);
    job_free(&j);
    return res->status;
}

/* ---- /v1/compare ---- */

static void compare_member_number(tc_strbuf *b, const char *name, double x) {
    tc_json_key(b, ",", name);
    tc_strbuf_double(b, x);
}

/* Sums of a comparison made in chunks, pooled as one tc_compare would pool them. */
typedef struct {
    double sum2, sum_abs, count;
} pooled;

static void pool_add(pooled *p, tc_error_stats *all, const tc_error_stats *e, int nc) {
    double count = (double)e->n * nc;
    p->sum2 += e->rms * e->rms * count;
    p->sum_abs += e->mean_rel * e->scale * count;
    p->count += count;
    all->max_abs = fmax(all->max_abs, e->max_abs);
    all->n += e->n, all->outside += e->outside;
}

static double max_abs_of(const double *v, size_t n) {
    double m = 0;
    for (size_t i = 0; i < n; i++) m = fmax(m, fabs(v[i]));
    return m;
}

/* tc_compare with the deadline checked between chunks of points (one call,
 * and the same numbers, for fewer than COMPARE_CHUNK): TC_OK or TC_ETIMEOUT. */
static int compare_chunked(const tc_recon *r, const tc_locator *L, const tc_request *req, int nc,
                           const tc_api_limits *lim, tc_api_result *res, tc_error_stats *e) {
    size_t n = req->nreference, ncs = (size_t)nc;
    if (n <= COMPARE_CHUNK)
        return tc_compare(r, L, n, req->reference_points, req->reference_values, req->reference_scale, e);
    double scale = req->reference_scale > 0 ? req->reference_scale : max_abs_of(req->reference_values, n * ncs);
    pooled p = {0, 0, 0};
    *e = (tc_error_stats){0};
    e->scale = scale;
    for (size_t i = 0; i < n; i += COMPARE_CHUNK) {
        if (late(lim, res, "comparing with the reference")) return TC_ETIMEOUT;
        size_t k = n - i < COMPARE_CHUNK ? n - i : COMPARE_CHUNK;
        tc_error_stats c;
        tc_compare(r, L, k, req->reference_points + 2 * i, req->reference_values + i * ncs, scale, &c);
        pool_add(&p, e, &c, nc);
    }
    if (p.count > 0) e->rms = sqrt(p.sum2 / p.count), e->mean_rel = scale > 0 ? p.sum_abs / p.count / scale : 0;
    return TC_OK;
}

/* One method: build it, compare it at the reference points, write its entry.
 * TC_ETIMEOUT (res holds the 503) if the deadline passed, else TC_OK. */
static int compare_one(const job *j, const tc_locator *L, const tc_options *opt, tc_strbuf *b,
                       const tc_api_limits *lim, tc_api_result *res, double *t0) {
    const tc_request *req = j->req;
    tc_recon *r = NULL;
    tc_diags dg;
    tc_diags_init(&dg);
    tc_strbuf_putc(b, '{');
    tc_json_options(b, opt);
    double t_build = tc_now_ms();
    int rc = tc_recon_new(j->mesh, opt, &r, &dg);
    double build_ms = tc_now_ms() - t_build;
    lap(res, TC_PHASE_BUILD, t0);
    if ((rc == TC_OK || rc == TC_ETIMEOUT) && late(lim, res, "building a method")) rc = TC_ETIMEOUT;
    else if (rc != TC_OK) {
        tc_strbuf_puts(b, ",\"error\":{\"path\":");
        tc_strbuf_json_string(b, dg.count ? dg.items[0].path : "");
        tc_strbuf_puts(b, ",\"message\":");
        tc_strbuf_json_string(b, dg.count ? dg.items[0].message : "out of memory");
        tc_strbuf_puts(b, "}}");
    } else {
        tc_error_stats e;
        double t_eval = tc_now_ms();
        rc = compare_chunked(r, L, req, tc_mesh_channel_count(j->mesh), lim, res, &e);
        double eval_ms = tc_now_ms() - t_eval;
        lap(res, TC_PHASE_EVALUATE, t0);
        compare_member_number(b, "build_ms", build_ms);
        compare_member_number(b, "evaluate_ms", eval_ms);
        compare_member_number(b, "max_abs", e.max_abs);
        compare_member_number(b, "rms", e.rms);
        compare_member_number(b, "mean_rel", e.mean_rel);
        compare_member_number(b, "scale", e.scale);
        tc_strbuf_printf(b, ",\"compared\":%lld,\"outside\":%lld}", (long long)e.n, (long long)e.outside);
    }
    tc_recon_free(r);
    tc_diags_free(&dg);
    return rc == TC_ETIMEOUT ? TC_ETIMEOUT : TC_OK;
}

int tc_api_compare(const char *body, size_t len, const tc_api_limits *lim, tc_strbuf *out, tc_api_result *res) {
    double t0 = tc_now_ms();
    job j = {0};
    int rs = parse_within(body, len, TC_REQ_MESH | TC_REQ_REFERENCE, lim, &j.req, res);
    lap(res, TC_PHASE_PARSE, &t0);
    if (rs != TC_REQ_OK) return res->status = status_of_request(rs);
    pass_limits(j.req, lim);
    tc_locator *L = NULL;
    int rc = within_limits(j.req, lim, res) ? tc_mesh_new(&j.req->desc, &j.mesh, &res->diags) : -1;
    if (rc == TC_OK) rc = tc_locator_new(j.mesh, &L);
    lap(res, TC_PHASE_VALIDATE, &t0);
    if (rc == TC_OK) {
        tc_strbuf b;
        tc_strbuf_init(&b);
        tc_strbuf_printf(&b, "{\"channels\":%d,\"reference_points\":%zu,\"results\":[", j.req->desc.nchan,
                         j.req->nreference);
        int n = j.req->nmethods ? j.req->nmethods : tc_method_count(); /* default: every method */
        int timeout = late(lim, res, "checking the mesh");
        for (int i = 0; i < n && !timeout; i++) {
            tc_options opt = j.req->opt;
            if (j.req->nmethods) opt = j.req->methods[i];
            else opt.method = (tc_method)i;
            if (i) tc_strbuf_putc(&b, ',');
            timeout = compare_one(&j, L, &opt, &b, lim, res, &t0) == TC_ETIMEOUT;
        }
        tc_strbuf_putc(&b, ']');
        res->triangles = (int64_t)n * triangle_count(j.req);
        if (timeout) tc_strbuf_free(&b);
        else finish(out, &b, res);
        lap(res, TC_PHASE_ENCODE, &t0);
    } else if (rc > 0) {
        res->status = status_of_core(rc);
    }
    tc_locator_free(L);
    job_free(&j);
    return res->status;
}

/* ---- stored meshes: a job built once, used by many requests ---- */

struct tc_api_job {
    job j;              /* req holds the description and options; locator built */
    tc_diags warnings;  /* of parsing, validating and building: every use repeats them */
    tc_api_mesh_info info;
};

void tc_api_job_free(tc_api_job *J) {
    if (!J) return;
    job_free(&J->j);
    tc_diags_free(&J->warnings);
    free(J);
}

/* Copies the warnings of `from` to the end of `to` (the kept ones). */
static void add_warnings(tc_diags *to, const tc_diags *from) {
    for (int i = 0; i < from->count; i++)
        if (from->items[i].severity == TC_SEV_WARNING)
            tc_diags_add(to, TC_SEV_WARNING, from->items[i].path, "%s", from->items[i].message);
}

/* A stored mesh is the reconstruction only: parts of other requests are
 * refused (400 naming the field) rather than silently dropped. */
static int refuse_extras(const tc_request *r, tc_api_result *res) {
    const char *field = r->npoints ? "points" : r->has_viewport ? "viewport" : r->format >= 0 ? "format"
                        : r->nreference                                  ? "reference"
                        : r->nmethods                                    ? "methods"
                                                                         : NULL;
    if (!field) return 0;
    tc_diags_add(&res->diags, TC_SEV_ERROR, field,
                 "a stored mesh holds the mesh and its options only; send '%s' to the mesh's own routes "
                 "(/v1/meshes/{id}/evaluate, /render, /tiles)", field);
    return res->status = 400;
}

/* The memory a built job holds, estimated from its counts: the ordinates
 * (exact), plus per vertex and per triangle allowances for the mesh, its
 * topology, the request's arrays and the locator. The cache's bound is in these units. */
static size_t job_bytes(const job *j) {
    const tc_mesh_desc *d = &j->req->desc;
    size_t nt = (size_t)triangle_count(j->req), nv = (size_t)d->nverts, nc = (size_t)d->nchan;
    size_t coefs = nt * nc * (size_t)tc_recon_coef_count(j->recon) * sizeof(double);
    return sizeof(tc_api_job) + coefs + nv * (64 + 48 * nc) + nt * (160 + 24 * nc);
}

static void fill_info(tc_api_job *J) {
    const tc_mesh_desc *d = &J->j.req->desc;
    tc_api_mesh_info *in = &J->info;
    in->vertices = d->nverts;
    in->triangles = triangle_count(J->j.req);
    in->channels = d->nchan;
    for (int k = 0; k < 2; k++) in->bbox[k] = in->bbox[2 + k] = d->nverts ? d->xy[k] : 0;
    for (int32_t v = 1; v < d->nverts; v++)
        for (int k = 0; k < 2; k++) {
            double x = d->xy[2 * v + k];
            if (x < in->bbox[k]) in->bbox[k] = x;
            if (x > in->bbox[2 + k]) in->bbox[2 + k] = x;
        }
    in->bytes = job_bytes(&J->j);
}

int tc_api_job_build(const char *body, size_t len, const tc_api_limits *lim, tc_api_job **out, tc_api_result *res) {
    double t0 = tc_now_ms();
    *out = NULL;
    tc_api_job *J = calloc(1, sizeof *J);
    if (!J) {
        tc_diags_add(&res->diags, TC_SEV_ERROR, "", "out of memory");
        return res->status = 500;
    }
    tc_diags_init(&J->warnings);
    if (job_parse(&J->j, body, len, TC_REQ_MESH, lim, res, &t0) == 200 && !refuse_extras(J->j.req, res) &&
        job_make(&J->j, lim, res, &t0) == 200) {
        int rc = tc_locator_new(J->j.mesh, &J->j.locator);
        lap(res, TC_PHASE_BUILD, &t0);
        if (rc != TC_OK) res->status = status_of_core(rc);
    }
    if (res->status != 200) {
        tc_api_job_free(J);
        return res->status;
    }
    /* As a rebuild from the canonical form (plain numbers for one channel) answers. */
    J->j.req->values_plain = J->j.req->desc.nchan == 1;
    J->j.req->encoding_base64 = 0; /* the stored mesh is one resource, whatever encoding its POST asked */
    add_warnings(&J->warnings, &res->diags);
    fill_info(J);
    *out = J;
    return 200;
}

const tc_api_mesh_info *tc_api_job_info(const tc_api_job *J) { return &J->info; }

void tc_api_job_canonical(const tc_api_job *J, tc_strbuf *out) {
    tc_json_request(out, &J->j.req->desc, &J->j.req->opt);
}

void tc_api_job_describe(const tc_api_job *J, const char *id, tc_strbuf *out) {
    const tc_api_mesh_info *in = &J->info;
    tc_strbuf_puts(out, "{\"id\":");
    tc_strbuf_json_string(out, id);
    tc_strbuf_printf(out, ",\"vertices\":%lld,\"triangles\":%lld,\"channels\":%d,\"bbox\":[", (long long)in->vertices,
                     (long long)in->triangles, in->channels);
    for (int k = 0; k < 4; k++) {
        if (k) tc_strbuf_putc(out, ',');
        tc_strbuf_double(out, in->bbox[k]);
    }
    tc_strbuf_putc(out, ']');
    tc_json_options(out, &J->j.req->opt);
    tc_json_diags(out, "warnings", &J->warnings, TC_SEV_WARNING);
    tc_strbuf_puts(out, "}\n");
}

int tc_api_job_ordinates(const tc_api_job *J, const tc_api_limits *lim, tc_strbuf *out, tc_api_result *res) {
    double t0 = tc_now_ms();
    add_warnings(&res->diags, &J->warnings);
    res->triangles = J->info.triangles;
    if (late(lim, res, "waiting for the reconstruction")) return res->status;
    tc_strbuf b;
    tc_strbuf_init(&b);
    tc_strbuf_putc(&b, '{');
    tc_json_ordinates(&b, J->j.recon);
    int rc = finish(out, &b, res);
    lap(res, TC_PHASE_ENCODE, &t0);
    return rc;
}

/* The mesh is stored: a document that brings one is refused, naming it. */
static int refuse_mesh(const tc_request *r, tc_api_result *res) {
    if (!r->has_mesh) return 0;
    tc_diags_add(&res->diags, TC_SEV_ERROR, "vertices",
                 "this route uses the stored mesh; send no vertices, triangles or values (POST a new mesh to "
                 "/v1/meshes)");
    return res->status = 400;
}

int tc_api_job_evaluate(const tc_api_job *J, const char *body, size_t len, const tc_api_limits *lim, tc_strbuf *out,
                        tc_api_result *res) {
    double t0 = tc_now_ms();
    add_warnings(&res->diags, &J->warnings);
    res->second_doc = res->diags.count;
    res->triangles = J->info.triangles;
    tc_request *pts = NULL;
    int rs = parse_within(body, len, TC_REQ_POINTS, lim, &pts, res);
    lap(res, TC_PHASE_PARSE, &t0);
    if (rs != TC_REQ_OK) return res->status = status_of_request(rs);
    tc_strbuf b;
    tc_strbuf_init(&b);
    if (!refuse_mesh(pts, res) && within_limits(pts, lim, res)) {
        int rc = evaluate(&J->j, pts, &b, lim, res);
        if (rc != TC_OK) res->status = rc == TC_ETIMEOUT ? 503 : 500;
        lap(res, TC_PHASE_EVALUATE, &t0);
    }
    tc_request_free(pts);
    if (res->status != 200) {
        tc_strbuf_free(&b);
        return res->status;
    }
    int rc = finish(out, &b, res);
    lap(res, TC_PHASE_ENCODE, &t0);
    return rc;
}

/* Renders the stored reconstruction with the look in `view` (a request with a
 * viewport and no mesh), through the stateless routes' render_job. */
static int render_view(const tc_api_job *J, tc_request *view, int fallback, const tc_api_limits *lim,
                       tc_strbuf *out, tc_api_result *res, double *t0) {
    job v = J->j; /* shares the stored mesh and reconstruction; frees nothing */
    v.req = view;
    return render_job(&v, format_of(view, fallback), lim, out, res, t0);
}

int tc_api_job_render(const tc_api_job *J, const char *body, size_t len, const char *accept,
                      const tc_api_limits *lim, tc_strbuf *out, tc_api_result *res) {
    double t0 = tc_now_ms();
    add_warnings(&res->diags, &J->warnings);
    res->triangles = J->info.triangles;
    tc_request *view = NULL;
    int rs = tc_request_parse_for(body, len, TC_REQ_VIEWPORT, J->info.channels, &view, &res->diags);
    lap(res, TC_PHASE_PARSE, &t0);
    if (rs != TC_REQ_OK) return res->status = status_of_request(rs);
    if (!refuse_mesh(view, res)) render_view(J, view, tc_accept_format(accept), lim, out, res, &t0);
    tc_request_free(view);
    return res->status;
}

int tc_api_job_render_look(const tc_api_job *J, const tc_api_look *look, const tc_api_limits *lim, tc_strbuf *out,
                           tc_api_result *res) {
    double t0 = tc_now_ms();
    add_warnings(&res->diags, &J->warnings);
    res->triangles = J->info.triangles;
    tc_request *view = calloc(1, sizeof *view);
    if (!view) {
        tc_diags_add(&res->diags, TC_SEV_ERROR, "", "out of memory");
        return res->status = 500;
    }
    /* What tc_request_parse makes of {"viewport", "format", "exposure", "overlay", "linear", "background"}. */
    view->has_viewport = 1;
    view->viewport = look->viewport;
    view->format = look->format;
    view->exposure = look->exposure;
    view->overlay = look->overlay;
    view->linear = look->linear;
    view->has_background = look->has_background;
    for (int c = 0; c < TC_MAX_CHANNELS; c++) view->background[c] = look->background[c];
    render_view(J, view, -1, lim, out, res, &t0);
    tc_request_free(view);
    return res->status;
}
