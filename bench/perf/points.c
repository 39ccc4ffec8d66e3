/* points.c — scattered-point evaluation (issue 17 §3): where tc_eval_points spends its time
 * and how it compares with the path it replaced, on the meshes bench/perf/meshes.py writes.
 *
 *     build/bench_points DIR NAME...     (DIR/NAME.json, DIR/points.f64; JSON on stdout)
 *
 * Per mesh: locator_new_s (the tree), grid_s (its grid of cells, built here at once; tc_eval_points
 * builds it once enough points were asked for), then each figure the best of 5 runs over the 1e6
 * points, one thread, in CPU time:
 *   locate_tree_s   tc__locate_tree per point (the bounding-volume tree alone: the old tc_locate)
 *   locate_s        tc_locate per point (the locator's grid of cells, then the tree's rule)
 *   eval_known_s    tc_eval_triangle per point, the owners already known (evaluation alone)
 *   ref_s, ref_grad_s       tc__eval_points_ref: the old batch path (tree, Z order, per-point frame)
 *   points_s, points_grad_s tc_eval_points: the new batch path
 *   points_2t_s     tc_eval_points_mt with 2 threads (values; wall time)
 * and whether the new path's owners, values and gradients equal the old one's bit for bit.
 *
 *     build/bench_points --batch DIR NAME...
 *
 * only times tc_eval_points (values, one thread), its best of 3 runs in wall time as a client
 * would see it: sidebyside.py's tocher half of a round against scipy on the same points. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/eval.h"
#include "core/locate.h"
#include "io/request.h"
#include "tocher.h"
#include "benchio.h"
#include "benchmesh.h"

#define NPTS 1000000
#define REPS 5

/* CPU time of this thread (what a busy shared machine disturbs least), or wall time
 * for the multi-threaded figure. */
static int wall;

static double now_s(void) {
    return bench_clock_s(wall ? CLOCK_MONOTONIC : CLOCK_THREAD_CPUTIME_ID);
}

typedef struct {
    const tc_recon *r;
    const tc_locator *L;
    const double *xy;
    double *v, *g;
    int32_t *tri;
    int threads;
} ctx;

static volatile int32_t sink;

static void run_locate_tree(const ctx *c) {
    int32_t s = 0;
    for (size_t i = 0; i < NPTS; i++) s += tc__locate_tree(c->L, c->xy[2 * i], c->xy[2 * i + 1]);
    sink = s;
}

static void run_locate(const ctx *c) {
    int32_t s = 0;
    for (size_t i = 0; i < NPTS; i++) s += tc_locate(c->L, c->xy[2 * i], c->xy[2 * i + 1]);
    sink = s;
}

static void run_known(const ctx *c) {
    for (size_t i = 0; i < NPTS; i++)
        if (c->tri[i] >= 0) tc_eval_triangle(c->r, c->tri[i], c->xy[2 * i], c->xy[2 * i + 1], c->v + i, NULL);
}

static void run_ref(const ctx *c) { tc__eval_points_ref(c->r, c->L, NPTS, c->xy, c->v, c->g, c->tri); }
static void run_points(const ctx *c) { tc_eval_points(c->r, c->L, NPTS, c->xy, c->v, c->g, c->tri); }
static void run_points_mt(const ctx *c) { tc_eval_points_mt(c->r, c->L, NPTS, c->xy, c->v, c->g, c->tri, c->threads); }

static double best_of(int reps, void (*fn)(const ctx *), const ctx *c) {
    double b = INFINITY;
    for (int i = 0; i < reps; i++) {
        double t0 = now_s();
        fn(c);
        b = fmin(b, now_s() - t0);
    }
    return b;
}

static double best(void (*fn)(const ctx *), const ctx *c) { return best_of(REPS, fn, c); }

/* The mesh DIR/NAME.json built and located (benchmesh.h); exits when it does not build. */
static void load_mesh(const char *dir, const char *name, bench_mesh *b) {
    char path[1024];
    snprintf(path, sizeof path, "%s/%s.json", dir, name);
    if (bench_mesh_load(path, b) != 0) exit(1);
}

/* --batch: tc_eval_points alone, values only, best of 3 in wall time. */
static void bench_batch(const char *dir, const char *name, const double *xy, int first) {
    bench_mesh ld;
    load_mesh(dir, name, &ld);
    double *v = malloc(NPTS * sizeof *v);
    int32_t *t = malloc(NPTS * sizeof *t);
    if (!v || !t) exit(1);
    ctx c = {ld.r, ld.L, xy, v, NULL, t, 1};
    wall = 1;
    double b = best_of(3, run_points, &c); /* 3, not REPS: sidebyside.py calls this once a round */
    printf("%s\n  \"%s\": {\"triangles\": %d, \"points_s\": %.6g}", first ? "" : ",", name,
           (int)tc_mesh_triangle_count(ld.m), b);
    fflush(stdout);
    free(v), free(t);
    bench_mesh_free(&ld);
}

static void time_mesh(const char *dir, const char *name, const double *xy, int first) {
    bench_mesh ld;
    load_mesh(dir, name, &ld);
    tc_recon *r = ld.r;
    const tc_locator *L = ld.L; /* its grid not built yet: timed below */
    tc_locator *L2; /* a second locator, for the time one takes to make */
    double t0 = now_s();
    if (tc_locator_new(ld.m, &L2) != TC_OK) exit(1);
    double t_loc = now_s() - t0;
    tc_locator_free(L2);
    t0 = now_s();
    tc__locator_grid_now(L); /* what the first large batch would do */
    double t_grid = now_s() - t0;
    double *v0 = malloc(NPTS * sizeof *v0), *g0 = malloc(2 * NPTS * sizeof *g0);
    double *v1 = malloc(NPTS * sizeof *v1), *g1 = malloc(2 * NPTS * sizeof *g1);
    int32_t *t0i = malloc(NPTS * sizeof *t0i), *t1i = malloc(NPTS * sizeof *t1i);
    ctx c0 = {r, L, xy, v0, NULL, t0i, 1}, c1 = {r, L, xy, v1, NULL, t1i, 1};
    double f_tree = best(run_locate_tree, &c0), f_loc = best(run_locate, &c0);
    double f_ref = best(run_ref, &c0), f_pts = best(run_points, &c1);
    double f_known = best(run_known, &c0);
    c1.threads = 2, wall = 1;
    double f_mt = best(run_points_mt, &c1);
    wall = 0;
    c0.g = g0, c1.g = g1, c1.threads = 1;
    double f_ref_g = best(run_ref, &c0), f_pts_g = best(run_points, &c1);
    int same = memcmp(v0, v1, NPTS * sizeof *v0) == 0 && memcmp(g0, g1, 2 * NPTS * sizeof *g0) == 0 &&
               memcmp(t0i, t1i, NPTS * sizeof *t0i) == 0;
    c1.threads = 2;
    run_points_mt(&c1);
    same = same && memcmp(v0, v1, NPTS * sizeof *v0) == 0 && memcmp(g0, g1, 2 * NPTS * sizeof *g0) == 0;
    printf("%s\n  \"%s\": {\"triangles\": %d, \"locator_new_s\": %.6g, \"grid_s\": %.6g, \"locate_tree_s\": %.6g, \"locate_s\": %.6g, "
           "\"eval_known_s\": %.6g, \"ref_s\": %.6g, \"points_s\": %.6g, \"points_2t_s\": %.6g, "
           "\"ref_grad_s\": %.6g, \"points_grad_s\": %.6g, \"identical\": %s}",
           first ? "" : ",", name, (int)tc_mesh_triangle_count(ld.m), t_loc, t_grid, f_tree, f_loc, f_known, f_ref, f_pts, f_mt,
           f_ref_g, f_pts_g, same ? "true" : "false");
    fflush(stdout);
    free(v0), free(g0), free(v1), free(g1), free(t0i), free(t1i);
    bench_mesh_free(&ld);
}

int main(int argc, char **argv) {
    int batch = argc > 1 && strcmp(argv[1], "--batch") == 0;
    if (argc < 3 + batch) {
        fprintf(stderr, "usage: bench_points [--batch] DIR NAME...\n");
        return 2;
    }
    argv += batch, argc -= batch;
    double *raw = bench_points(argv[1], NPTS, "bench_points");
    if (!raw) return 1;
    printf("{\"points\": %d, \"meshes\": {", NPTS);
    for (int i = 2; i < argc; i++) (batch ? bench_batch : time_mesh)(argv[1], argv[i], raw, i == 2);
    printf("\n}}\n");
    free(raw);
    return 0;
}
