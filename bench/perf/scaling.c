/* scaling.c — tile throughput per thread and thread scaling (issue 17 §3): renders one mesh's
 * square tile with 1..N threads, best of a few, and prints one JSON object on stdout; with
 * --build, the validation (tc_mesh_new) and build (tc_recon_new) of the mesh instead.
 *
 *     build/bench_scaling [--portable | --no-fma] [--rows N] MESH.json [SIZE [THREADS,...]]  (default 1024, "1,2")
 *     build/bench_scaling --build MESH.json [THREADS,...]
 *
 * --rows N: the tile rendered in calls of N rows (tc_render_options.row0/rows), as the daemon
 * renders a big tile a band of ~8 MiB at a time (96 rows of a 4096-wide one-channel tile).
 * --portable: the row loop's portable build, as on a CPU without AVX2 and FMA (its fused
 * multiply-adds are calls of libm's fma: with GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA, libm's
 * software fma, as such a CPU has it). --no-fma: as tc_render runs on such a CPU (no fast form:
 * the exact path for every triangle).
 *
 * The viewport is the unit square the bench meshes (bench/perf/meshes.py) cover. Each thread
 * count renders the same tile; the checksum of every run must agree (bit-identical output for
 * any thread count), and the program fails if it does not. Built without the daemon or the
 * image plugin, so the one binary can be carried to a machine with more cores. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/ct_fast.h"
#include "core/mesh.h"
#include "core/recon.h"
#include "io/request.h"
#include "tocher.h"
#include "benchio.h"
#include "benchmesh.h"

static double now_s(void) {
    return bench_clock_s(CLOCK_MONOTONIC);
}

static double cpu_s(void) {
    return bench_clock_s(CLOCK_PROCESS_CPUTIME_ID);
}

/* Best wall time of tc_render over at least 3 runs and 0.5 s; *cpu the CPU time (all threads)
 * of the run with the least of it (pixels per CPU second = throughput per thread, the figure a
 * busy machine disturbs least); *sum gets the pixels' sum. */
static int32_t call_rows; /* --rows: rows per tc_render call; 0 = the whole tile in one */

static int render_tile(const tc_recon *r, const tc_locator *L, const tc_viewport *vp, int threads, float *px) {
    int32_t step = call_rows > 0 ? call_rows : vp->height;
    for (int32_t j = 0; j < vp->height; j += step) {
        tc_render_options o = {.threads = threads, .row0 = j, .rows = vp->height - j < step ? vp->height - j : step};
        if (tc_render(r, L, vp, &o, px + (size_t)j * (size_t)vp->width * (size_t)r->m->nc, NULL) != TC_OK) return -1;
    }
    return 0;
}

static double render_best(const tc_recon *r, const tc_locator *L, int32_t size, int threads, float *px,
                          double *sum, double *cpu) {
    tc_viewport vp = {0, 0, 1, 1, size, size};
    double best = INFINITY, spent = 0;
    *cpu = INFINITY;
    for (int i = 0; i < 3 || spent < 0.5; i++) {
        double t0 = now_s(), c0 = cpu_s();
        if (render_tile(r, L, &vp, threads, px)) return NAN;
        double dt = now_s() - t0;
        *cpu = fmin(*cpu, cpu_s() - c0);
        best = fmin(best, dt), spent += dt;
    }
    double s = 0;
    for (size_t p = 0; p < (size_t)size * (size_t)size * (size_t)r->m->nc; p++) s += px[p];
    *sum = s;
    return best;
}

/* Best of at least 3 runs and 1 s of validate + build with `threads`; *sum: the ordinates' sum. */
static void build_best(const tc_request *req, int threads, double *val_s, double *build_s, double *sum) {
    tc_mesh_desc d = req->desc;
    tc_options o = req->opt;
    d.threads = o.threads = threads;
    *val_s = *build_s = INFINITY;
    double spent = 0;
    for (int i = 0; i < 3 || spent < 1; i++) {
        tc_mesh *m = NULL;
        tc_recon *r = NULL;
        double t0 = now_s();
        if (tc_mesh_new(&d, &m, NULL) != TC_OK) exit(1);
        double t1 = now_s();
        if (tc_recon_new(m, &o, &r, NULL) != TC_OK) exit(1);
        double t2 = now_s();
        *val_s = fmin(*val_s, t1 - t0), *build_s = fmin(*build_s, t2 - t1), spent += t2 - t0;
        if (i == 0) {
            double s = 0;
            size_t n = (size_t)tc_mesh_triangle_count(m) * (size_t)m->nc * (size_t)tc_recon_coef_count(r);
            for (size_t k = 0; k < n; k++) s += tc_recon_coefs(r)[k];
            *sum = s;
        }
        tc_recon_free(r), tc_mesh_free(m);
    }
}

static int main_build(const char *path, const char *list) {
    size_t len;
    char *json = bench_slurp(path, &len);
    tc_request *req = NULL;
    if (!json || tc_request_parse(json, len, TC_REQ_MESH, &req, NULL) != TC_REQ_OK) {
        fprintf(stderr, "%s: cannot parse\n", path);
        return 1;
    }
    printf("{\"mesh\": \"%s\", \"triangles\": %d, \"runs\": [", path, (int)req->desc.ntris);
    double first = NAN, sum0 = NAN;
    int bad = 0;
    char *copy = strdup(list), *save = NULL;
    for (char *tok = strtok_r(copy, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
        double v, b, sum = 0;
        build_best(req, atoi(tok), &v, &b, &sum);
        if (isnan(first)) first = v + b, sum0 = sum;
        if (memcmp(&sum, &sum0, sizeof sum)) bad = 1;
        printf("%s{\"threads\": %d, \"validate_s\": %.6f, \"build_s\": %.6f, \"total_s\": %.6f, "
               "\"speedup\": %.2f, \"checksum\": %.17g}",
               tok == copy ? "" : ", ", atoi(tok), v, b, v + b, first / (v + b), sum);
        fflush(stdout);
    }
    printf("], \"identical\": %s}\n", bad ? "false" : "true");
    free(copy), free(json);
    tc_request_free(req);
    return bad;
}

int main(int argc, char **argv) {
    if (argc > 2 && !strcmp(argv[1], "--build")) return main_build(argv[2], argc > 3 ? argv[3] : "1,2");
    if (argc > 2 && (!strcmp(argv[1], "--portable") || !strcmp(argv[1], "--no-fma"))) {
        tc__raster_force_generic(!strcmp(argv[1], "--portable") ? 1 : 2);
        argc -= 1, argv += 1;
    }
    if (argc > 3 && !strcmp(argv[1], "--rows")) {
        call_rows = atoi(argv[2]);
        argc -= 2, argv += 2;
    }
    if (argc < 2) {
        fprintf(stderr, "usage: %s [--portable | --no-fma] [--rows N] MESH.json [SIZE [THREADS,...]] | --build MESH.json [THREADS,...]\n",
                argv[0]);
        return 2;
    }
    int32_t size = argc > 2 ? atoi(argv[2]) : 1024;
    const char *list = argc > 3 ? argv[3] : "1,2";
    double t0 = now_s();
    bench_mesh bm;
    if (bench_mesh_load(argv[1], &bm)) return 1;
    const tc_mesh *m = bm.m;
    const tc_recon *r = bm.r;
    const tc_locator *L = bm.L;
    double built = now_s() - t0;
    float *px = malloc((size_t)size * (size_t)size * (size_t)r->m->nc * sizeof *px);
    if (!px) return 1;
    printf("{\"mesh\": \"%s\", \"triangles\": %d, \"size\": %d, \"rows_per_call\": %d, \"build_s\": %.6f, \"runs\": [",
           argv[1], (int)tc_mesh_triangle_count(m), (int)size, call_rows > 0 ? call_rows : (int)size, built);
    double first = NAN, sum0 = NAN;
    int bad = 0;
    char *copy = strdup(list), *save = NULL;
    for (char *tok = strtok_r(copy, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
        int th = atoi(tok);
        double sum = 0, cpu = 0, s = render_best(r, L, size, th, px, &sum, &cpu);
        if (isnan(first)) first = s, sum0 = sum;
        if (memcmp(&sum, &sum0, sizeof sum)) bad = 1;
        printf("%s{\"threads\": %d, \"seconds\": %.6f, \"mpixel_s\": %.2f, \"mpixel_cpu_s\": %.2f, "
               "\"speedup\": %.2f, \"checksum\": %.17g}",
               tok == copy ? "" : ", ", th, s, (double)size * size / s / 1e6, (double)size * size / cpu / 1e6, first / s,
               sum);
        fflush(stdout);
    }
    printf("], \"identical\": %s}\n", bad ? "false" : "true");
    free(copy), free(px);
    bench_mesh_free(&bm);
    return bad;
}
