/* perf.c — tocher's side of `make bench`: times every phase of the core on the meshes and
 * points bench/perf/meshes.py wrote, and prints one JSON object (bench/perf/report.py reads it).
 *
 *     build/bench_perf DIR NAME...      (DIR/NAME.json, DIR/NAME.noderiv.json, DIR/points.f64)
 *
 * Each figure is the best of a few runs (the machines are noisy; the minimum is the
 * least disturbed), taken in the same process, so ratios between phases are fair. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

#include "io/api.h"
#include "io/request.h"
#include "io/strbuf.h"
#include "tocher.h"
#include "benchio.h"

#define TILE 1024
#define NSCATTER 1000000

static double now_s(void) {
    return bench_clock_s(CLOCK_MONOTONIC);
}

static long peak_rss_kb(void) {
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return ru.ru_maxrss;
}

/* Repetitions for a phase that took `first` seconds once: enough for ~1 s in all, 1..5. */
static int reps_for(double first) {
    int n = first > 0 ? (int)(1.0 / first) : 5;
    return n < 1 ? 1 : n > 5 ? 5 : n;
}

typedef struct {
    tc_request *req;
    tc_mesh *m;
    tc_recon *r;
    tc_locator *L;
} built;

static void unbuild(built *b) {
    tc_locator_free(b->L);
    tc_recon_free(b->r);
    tc_mesh_free(b->m);
    tc_request_free(b->req);
    memset(b, 0, sizeof *b);
}

/* parse -> mesh (validation, topology) -> ordinates -> locator, each timed. */
static int build(const char *json, size_t len, const tc_options *opt, built *b, double t[4]) {
    memset(b, 0, sizeof *b);
    double t0 = now_s();
    if (tc_request_parse(json, len, TC_REQ_MESH, &b->req, NULL) != TC_REQ_OK) return -1;
    double t1 = now_s();
    if (tc_mesh_new(&b->req->desc, &b->m, NULL) != TC_OK) return -1;
    double t2 = now_s();
    if (tc_recon_new(b->m, opt ? opt : &b->req->opt, &b->r, NULL) != TC_OK) return -1;
    double t3 = now_s();
    if (tc_locator_new(b->m, &b->L) != TC_OK) return -1;
    double t4 = now_s();
    t[0] = t1 - t0, t[1] = t2 - t1, t[2] = t3 - t2, t[3] = t4 - t3;
    return 0;
}

/* Best of a few full builds; b keeps the last. */
static int build_best(const char *json, size_t len, const tc_options *opt, built *b, double best[4]) {
    double t[4];
    if (build(json, len, opt, b, best)) return -1;
    int n = reps_for(best[0] + best[1] + best[2] + best[3]);
    for (int i = 1; i < n; i++) {
        unbuild(b);
        if (build(json, len, opt, b, t)) return -1;
        for (int k = 0; k < 4; k++) best[k] = fmin(best[k], t[k]);
    }
    return 0;
}

/* Seconds for the parse alone, the best of `reps` in this process (the heap warm, as in a
 * daemon that has parsed a request before: build_best's first parse of a big mesh is the
 * process's first, and pays every page fault of a fresh heap). fast 0: every array through
 * cJSON (tc_request__fast_arrays(0)), the parser before the fast path for big arrays
 * (io/request_fast.c), for the before/after of issue 17's "numbers in". At least `reps`
 * parses, more when they are quick (reps_for). NaN if refused. */
static double parse_best(const char *json, size_t len, int fast, int reps) {
    double best = INFINITY;
    tc_request__fast_arrays(fast);
    for (int i = 0, n = reps; i < n; i++) {
        tc_request *r = NULL;
        double t0 = now_s();
        int st = tc_request_parse(json, len, TC_REQ_MESH, &r, NULL);
        double dt = now_s() - t0;
        tc_request_free(r);
        if (st != TC_REQ_OK) {
            best = NAN;
            break;
        }
        best = fmin(best, dt);
        if (i == 0 && reps_for(dt) > n) n = reps_for(dt);
    }
    tc_request__fast_arrays(1);
    return best;
}

/* Seconds for the ordinates alone (tc_recon_new) on an existing mesh. */
static double recon_best(const tc_mesh *m, const tc_options *o) {
    double best = INFINITY;
    for (int i = 0, n = 1; i < n; i++) {
        tc_recon *r = NULL;
        double t0 = now_s();
        if (tc_recon_new(m, o, &r, NULL) != TC_OK) return NAN;
        double dt = now_s() - t0;
        tc_recon_free(r);
        best = fmin(best, dt);
        if (i == 0) n = reps_for(dt);
    }
    return best;
}

static double eval_best(const built *b, size_t n, const double *xy, double *v, double *g) {
    double best = INFINITY;
    for (int i = 0, reps = 1; i < reps; i++) {
        double t0 = now_s();
        tc_eval_points(b->r, b->L, n, xy, v, g, NULL);
        double dt = now_s() - t0;
        best = fmin(best, dt);
        if (i == 0) reps = reps_for(dt);
    }
    return best;
}

static double render_vp(const built *b, const tc_viewport *vp, int threads, float *px) {
    tc_render_options o = {.threads = threads};
    double best = INFINITY;
    for (int i = 0, reps = 1; i < reps; i++) {
        double t0 = now_s();
        if (tc_render(b->r, b->L, vp, &o, px, NULL) != TC_OK) return NAN;
        double dt = now_s() - t0;
        best = fmin(best, dt);
        if (i == 0) reps = reps_for(dt) + 1;
    }
    return best;
}

/* Mesh + ordinates of DIR/NAME.flags.json (the mesh with C0 rows and a C-1
 * column), best of a few; NAN when there is no such file. */
static double flagged_build(const char *dir, const char *name, double *mesh_s) {
    char path[1024];
    size_t len;
    snprintf(path, sizeof path, "%s/%s.flags.json", dir, name);
    char *json = bench_slurp(path, &len);
    if (!json) return NAN;
    built b;
    double t[4];
    double r = build_best(json, len, NULL, &b, t) ? NAN : t[2];
    *mesh_s = t[1];
    unbuild(&b);
    free(json);
    return r;
}

static double render_best(const built *b, int threads, float *px, double *checksum) {
    tc_viewport vp = {0, 0, 1, 1, TILE, TILE};
    tc_render_options o = {.threads = threads};
    double best = INFINITY;
    for (int i = 0, reps = 1; i < reps; i++) {
        double t0 = now_s();
        if (tc_render(b->r, b->L, &vp, &o, px, NULL) != TC_OK) return NAN;
        double dt = now_s() - t0;
        best = fmin(best, dt);
        if (i == 0) reps = reps_for(dt) + 1;
    }
    double s = 0;
    for (size_t p = 0; p < (size_t)TILE * TILE; p++) s += px[p];
    *checksum = s;
    return best;
}

/* One tc_api_* call as tocherd makes it; ctx carries what differs. */
typedef int (*api_call)(const char *body, size_t len, const void *ctx, tc_strbuf *out, tc_api_result *res);

static int call_render(const char *body, size_t len, const void *ctx, tc_strbuf *out, tc_api_result *res) {
    return tc_api_render(body, len, NULL, ctx, out, res);
}

static int call_ordinates(const char *body, size_t len, const void *ctx, tc_strbuf *out, tc_api_result *res) {
    (void)ctx;
    return tc_api_ordinates(body, len, NULL, out, res);
}

/* Best of a few whole calls; the phase times and response size of the best
 * into ms[] and *bytes. NAN when the call fails. */
static double api_best(api_call fn, const char *body, size_t len, const void *ctx, double ms[TC_NPHASES],
                       size_t *bytes) {
    double best = INFINITY;
    for (int i = 0, reps = 1; i < reps; i++) {
        tc_strbuf out;
        tc_api_result res;
        tc_strbuf_init(&out);
        tc_api_result_init(&res);
        double t0 = now_s();
        int st = fn(body, len, ctx, &out, &res);
        double dt = now_s() - t0;
        if (st != 200) {
            fprintf(stderr, "bench_perf: status %d: %s\n", st, res.diags.count ? res.diags.items[0].message : "");
            dt = NAN;
        } else if (dt < best) {
            best = dt;
            memcpy(ms, res.ms, sizeof res.ms);
            *bytes = out.len;
        }
        tc_api_result_free(&res);
        tc_strbuf_free(&out);
        if (i == 0) reps = isnan(dt) ? 0 : reps_for(dt);
    }
    return best;
}

/* The whole POST /v1/render (parse + validate + build + render + encode): the
 * mesh with a viewport and format spliced in before its last '}'. */
static double whole_render(const char *json, size_t len, const char *format, int threads, double ms[TC_NPHASES],
                           size_t *bytes) {
    tc_strbuf body;
    tc_strbuf_init(&body);
    size_t cut = len;
    while (cut > 0 && json[cut - 1] != '}') cut--;
    tc_strbuf_append(&body, json, cut - 1);
    tc_strbuf_printf(&body, ",\"viewport\":{\"x0\":0,\"y0\":0,\"x1\":1,\"y1\":1,\"width\":%d,\"height\":%d},"
                            "\"format\":\"%s\"}",
                     TILE, TILE, format);
    tc_api_limits lim = {.render_threads = threads};
    double best = api_best(call_render, body.buf, body.len, &lim, ms, bytes);
    tc_strbuf_free(&body);
    return best;
}

/* POST /v1/ordinates as a whole and its output phase (writing the JSON). */
static double whole_ordinates(const char *json, size_t len, double *encode_s, size_t *bytes) {
    double ms[TC_NPHASES] = {0};
    double best = api_best(call_ordinates, json, len, NULL, ms, bytes);
    *encode_s = ms[TC_PHASE_ENCODE] * 1e-3;
    return best;
}

static void tile_points(double *xy) {
    for (int j = 0; j < TILE; j++)
        for (int i = 0; i < TILE; i++) {
            xy[2 * ((size_t)j * TILE + (size_t)i)] = (i + 0.5) / TILE;
            xy[2 * ((size_t)j * TILE + (size_t)i) + 1] = (j + 0.5) / TILE;
        }
}

/* Largest |tocher - scipy| over the first points, scipy's values from NAME.scipy_vals.f64. */
static double agree_scipy(const char *dir, const char *name, const built *b, const double *xy) {
    char path[1024];
    size_t len;
    snprintf(path, sizeof path, "%s/%s.scipy_vals.f64", dir, name);
    char *raw = bench_slurp(path, &len);
    if (!raw) return NAN;
    size_t n = len / sizeof(double);
    double *v = malloc(n * sizeof *v), worst = 0;
    tc_eval_points(b->r, b->L, n, xy, v, NULL, NULL);
    for (size_t i = 0; i < n; i++) {
        double s;
        memcpy(&s, raw + i * sizeof s, sizeof s);
        worst = fmax(worst, fabs(v[i] - s));
    }
    free(v);
    free(raw);
    return worst;
}

static void bench_mesh(const char *dir, const char *name, const double *scatter, const double *tile, int first) {
    char path[1024];
    size_t len, len_nd;
    snprintf(path, sizeof path, "%s/%s.json", dir, name);
    char *json = bench_slurp(path, &len);
    snprintf(path, sizeof path, "%s/%s.noderiv.json", dir, name);
    char *json_nd = bench_slurp(path, &len_nd);
    if (!json || !json_nd) {
        fprintf(stderr, "bench_perf: cannot read %s\n", path);
        exit(1);
    }
    fprintf(stderr, "bench_perf: %s\n", name);
    built b, bn;
    double t[4], tn[4];
    if (build_best(json, len, NULL, &b, t) || build_best(json_nd, len_nd, NULL, &bn, tn)) {
        fprintf(stderr, "bench_perf: %s does not build\n", name);
        exit(1);
    }
    int32_t nt = tc_mesh_triangle_count(b.m);
    double t_parse = parse_best(json, len, 1, 5), t_parse_cjson = parse_best(json, len, 0, 1);
    tc_options lin;
    tc_options_default(&lin);
    lin.method = TC_METHOD_LINEAR;
    double t_lin = recon_best(b.m, &lin);

    size_t most = (size_t)TILE * TILE > NSCATTER ? (size_t)TILE * TILE : NSCATTER;
    double *v = malloc(most * sizeof *v), *g = malloc(2 * most * sizeof *g);
    float *px = malloc((size_t)TILE * TILE * sizeof *px);
    double e_val = eval_best(&b, NSCATTER, scatter, v, NULL);
    double e_grad = eval_best(&b, NSCATTER, scatter, v, g);
    double e_tile = eval_best(&b, (size_t)TILE * TILE, tile, v, NULL);
    double sum1, sum2;
    double r1 = render_best(&b, 1, px, &sum1), r2 = render_best(&b, 2, px, &sum2);
    double agree = agree_scipy(dir, name, &b, scatter);
    /* A tile visits only the triangles that overlap it: 256^2 pixels over 1/256 of the
     * mesh against the same pixels over all of it. */
    tc_viewport part = {0.25, 0.25, 0.3125, 0.3125, 256, 256}, whole = {0, 0, 1, 1, 256, 256};
    double r_part = render_vp(&b, &part, 1, px), r_whole = render_vp(&b, &whole, 1, px);
    double fl_mesh = NAN, fl_ord = flagged_build(dir, name, &fl_mesh);
    double ms_raw[TC_NPHASES] = {0}, ms_exr[TC_NPHASES] = {0}, enc_s = 0;
    size_t raw_bytes = 0, exr_bytes = 0, ord_bytes = 0;
    double w_raw = whole_render(json, len, "raw", 2, ms_raw, &raw_bytes);
    double w_exr = whole_render(json, len, "exr", 2, ms_exr, &exr_bytes);
    double w_ord = whole_ordinates(json, len, &enc_s, &ord_bytes);
    size_t coef_bytes = (size_t)nt * (size_t)tc_mesh_channel_count(b.m) * (size_t)tc_recon_coef_count(b.r) * sizeof(double);

    printf("%s\n  \"%s\": {\"triangles\": %d, \"vertices\": %d, \"json_bytes\": %zu", first ? "" : ",", name,
           (int)nt, (int)tc_mesh_vertex_count(b.m), len);
    const struct {
        const char *name;
        double v;
    } f[] = {{"parse_s", t_parse}, {"parse_first_s", t[0]}, {"parse_cjson_s", t_parse_cjson}, {"mesh_s", t[1]}, {"ordinates_s", t[2]}, {"locator_s", t[3]},
             {"parse_noderiv_s", tn[0]}, {"mesh_noderiv_s", tn[1]}, {"ordinates_noderiv_s", tn[2]},
             {"linear_s", t_lin}, {"eval_scattered_s", e_val}, {"eval_scattered_grad_s", e_grad},
             {"eval_tile_points_s", e_tile}, {"render_1t_s", r1}, {"render_2t_s", r2}, {"tile_checksum", sum1},
             {"threads_agree", sum1 == sum2}, {"max_diff_scipy", agree}, {"render_256_part_s", r_part},
             {"render_256_whole_s", r_whole}, {"flags_mesh_s", fl_mesh}, {"flags_ordinates_s", fl_ord},
             {"whole_render_raw_s", w_raw}, {"whole_render_exr_s", w_exr}, {"exr_bytes", (double)exr_bytes},
             {"raw_bytes", (double)raw_bytes}, {"whole_ordinates_s", w_ord}, {"ordinates_output_s", enc_s},
             {"ordinates_json_bytes", (double)ord_bytes}, {"coef_bytes", (double)coef_bytes},
             {"peak_rss_kb", (double)peak_rss_kb()}};
    for (size_t i = 0; i < sizeof f / sizeof f[0]; i++) /* JSON has no NaN: null */
        printf(isfinite(f[i].v) ? ",\n    \"%s\": %.17g" : ",\n    \"%s\": null", f[i].name, f[i].v);
    printf(",\n    \"render_raw_phases_ms\": [%.3f, %.3f, %.3f, %.3f, %.3f]", ms_raw[0], ms_raw[1], ms_raw[2],
           ms_raw[3], ms_raw[4]);
    printf(",\n    \"render_exr_phases_ms\": [%.3f, %.3f, %.3f, %.3f, %.3f]}", ms_exr[0], ms_exr[1], ms_exr[2],
           ms_exr[3], ms_exr[4]);
    fflush(stdout);
    free(v), free(g), free(px);
    unbuild(&b), unbuild(&bn);
    free(json), free(json_nd);
}

/* The first image encoded in a process loads OpenImageIO (~0.4 s, docs/performance.md
 * shows it separately): load it before anything is timed. */
static void warm_image_stack(void) {
    static const char tiny[] = "{\"vertices\":[[0,0],[1,0],[0,1]],\"triangles\":[[0,1,2]],\"values\":[0,1,2],"
                               "\"viewport\":{\"x0\":0,\"y0\":0,\"x1\":1,\"y1\":1,\"width\":4,\"height\":4},"
                               "\"format\":\"exr\"}";
    tc_strbuf out;
    tc_api_result res;
    tc_strbuf_init(&out);
    tc_api_result_init(&res);
    tc_api_render(tiny, sizeof tiny - 1, NULL, NULL, &out, &res);
    tc_api_result_free(&res);
    tc_strbuf_free(&out);
}

int main(int argc, char **argv) {
    if (argc < 3) {
        fprintf(stderr, "usage: bench_perf DIR NAME...\n");
        return 2;
    }
    double *scatter = bench_points(argv[1], NSCATTER, "bench_perf"), *tile = malloc((size_t)TILE * TILE * 2 * sizeof *tile);
    if (!scatter) return 1;
    tile_points(tile);
    warm_image_stack();
    printf("{\"tile\": %d, \"scattered\": %d, \"meshes\": {", TILE, NSCATTER);
    for (int i = 2; i < argc; i++) bench_mesh(argv[1], argv[i], scatter, tile, i == 2);
    printf("\n}}\n");
    free(tile);
    free(scatter);
    return 0;
}
