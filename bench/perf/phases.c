/* phases.c — where the validation (tc_mesh_new) and build (tc_recon_new) of one mesh spend
 * their time on each thread count: every parallel loop, and the serial time between loops.
 *
 *     build/bench_phases MESH.json [THREADS,... [REPS]]      (default "1,2", 5)
 *
 * For each thread count, REPS runs; per loop (in call order, the same every run) the least
 * serial time before it, wall time, CPU time of its parts together and wall time of its slowest
 * part, each the minimum over the runs (a shared machine disturbs single runs, rarely all). The
 * serial time is what no thread count shortens (Amdahl's fraction); CPU time that grows with
 * the threads is work the parts add (atomics, page faults, memory traffic); a slowest part well
 * above wall/parts is imbalance. One JSON object per thread count, one line each. Loops are
 * named by their part function where addr2line is installed, else by its offset in this
 * binary (`addr2line -f -e build/bench_phases OFFSET` names it on the machine that built it).
 * Built like bench_scaling (cJSON only), to be carried to a machine with more cores. */
#define _GNU_SOURCE /* dladdr */
#include <dlfcn.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "core/parallel.h"
#include "io/request.h"
#include "tocher.h"
#include "benchio.h"

enum { MAX_LOOPS = 512 };

typedef struct {
    int nloops;
    double total_s, validate_s, build_s;       /* of the fastest run */
    double gap[MAX_LOOPS], wall[MAX_LOOPS], cpu[MAX_LOOPS], slowest[MAX_LOOPS], tail; /* least over runs */
    tc__loop_record loop[MAX_LOOPS];           /* of the first run: fn, n, parts */
} phases;

/* One validate + build with `threads`, its loops folded into *ph. 0, or -1 on failure or
 * when the loops differ from the first run's (then the minima would mix loops). */
static int run_once(const tc_request *req, int threads, int first, phases *ph) {
    static tc__loop_record rec[MAX_LOOPS];
    tc_mesh_desc d = req->desc;
    tc_options o = req->opt;
    d.threads = o.threads = threads;
    tc_mesh *m = NULL;
    tc_recon *r = NULL;
    tc__parallel_trace(rec, MAX_LOOPS);
    double t0 = bench_clock_s(CLOCK_MONOTONIC);
    int ok = tc_mesh_new(&d, &m, NULL) == TC_OK;
    double t1 = bench_clock_s(CLOCK_MONOTONIC);
    ok = ok && tc_recon_new(m, &o, &r, NULL) == TC_OK;
    double t2 = bench_clock_s(CLOCK_MONOTONIC);
    int n = tc__parallel_trace(NULL, 0);
    tc_recon_free(r), tc_mesh_free(m);
    if (!ok || n > MAX_LOOPS || (!first && n != ph->nloops)) return -1;
    if (first) {
        ph->nloops = n, ph->total_s = INFINITY, ph->tail = INFINITY;
        memcpy(ph->loop, rec, (size_t)n * sizeof *rec);
        for (int i = 0; i < n; i++) ph->gap[i] = ph->wall[i] = ph->cpu[i] = ph->slowest[i] = INFINITY;
    }
    if (t2 - t0 < ph->total_s) ph->total_s = t2 - t0, ph->validate_s = t1 - t0, ph->build_s = t2 - t1;
    double prev = t0;
    for (int i = 0; i < n; i++) {
        if (rec[i].fn != ph->loop[i].fn) return -1;
        ph->gap[i] = fmin(ph->gap[i], rec[i].start_s - prev);
        ph->wall[i] = fmin(ph->wall[i], rec[i].end_s - rec[i].start_s);
        ph->cpu[i] = fmin(ph->cpu[i], rec[i].cpu_s);
        ph->slowest[i] = fmin(ph->slowest[i], rec[i].slowest_s);
        prev = rec[i].end_s;
    }
    ph->tail = fmin(ph->tail, t2 - prev);
    return 0;
}

/* The loop's name: its part function's, by addr2line on this binary, else its offset. */
static void loop_name(const void *fn, char *out, size_t size) {
    Dl_info info;
    uintptr_t off = (uintptr_t)fn;
    if (dladdr(fn, &info) && info.dli_fbase) off -= (uintptr_t)info.dli_fbase;
    snprintf(out, size, "0x%lx", (unsigned long)off);
    static char self[4096]; /* this binary: /proc/self/exe would be the shell popen starts */
    if (!self[0]) {
        ssize_t k = readlink("/proc/self/exe", self, sizeof self - 1);
        self[k > 0 ? k : 0] = 0;
    }
    if (!self[0] || strchr(self, '\'')) return;
    char cmd[4200];
    snprintf(cmd, sizeof cmd, "addr2line -f -s -e '%s' 0x%lx 2>/dev/null", self, (unsigned long)off);
    FILE *p = popen(cmd, "r");
    char line[96];
    if (p && fgets(line, sizeof line, p) && line[0] != '?') {
        line[strcspn(line, "\n")] = 0;
        snprintf(out, size, "%s", line);
    }
    if (p) pclose(p);
}

static void print_phases(const char *mesh, int threads, const phases *ph) {
    double loops = 0, serial = ph->tail, cpu = 0;
    for (int i = 0; i < ph->nloops; i++) loops += ph->wall[i], serial += ph->gap[i], cpu += ph->cpu[i];
    printf("{\"mesh\": \"%s\", \"threads\": %d, \"total_ms\": %.3f, \"validate_ms\": %.3f, \"build_ms\": %.3f, "
           "\"loops_ms\": %.3f, \"serial_ms\": %.3f, \"loops_cpu_ms\": %.3f, \"loops\": [",
           mesh, threads, 1e3 * ph->total_s, 1e3 * ph->validate_s, 1e3 * ph->build_s, 1e3 * loops, 1e3 * serial,
           1e3 * cpu);
    for (int i = 0; i < ph->nloops; i++) {
        char name[96];
        loop_name(ph->loop[i].fn, name, sizeof name);
        printf("%s{\"fn\": \"%s\", \"n\": %d, \"parts\": %d, \"serial_before_ms\": %.3f, \"wall_ms\": %.3f, "
               "\"cpu_ms\": %.3f, \"slowest_part_ms\": %.3f}",
               i ? ", " : "", name, (int)ph->loop[i].n, ph->loop[i].parts, 1e3 * ph->gap[i], 1e3 * ph->wall[i],
               1e3 * ph->cpu[i], 1e3 * ph->slowest[i]);
    }
    printf("], \"serial_after_ms\": %.3f}\n", 1e3 * ph->tail);
    fflush(stdout);
}

int main(int argc, char **argv) {
    if (argc < 2) {
        fprintf(stderr, "usage: %s MESH.json [THREADS,... [REPS]]\n", argv[0]);
        return 2;
    }
    const char *list = argc > 2 ? argv[2] : "1,2";
    int reps = argc > 3 ? atoi(argv[3]) : 5;
    size_t len;
    char *json = bench_slurp(argv[1], &len);
    tc_request *req = NULL;
    if (!json || tc_request_parse(json, len, TC_REQ_MESH, &req, NULL) != TC_REQ_OK) {
        fprintf(stderr, "%s: cannot parse\n", argv[1]);
        return 1;
    }
    static phases ph;
    char *copy = strdup(list), *save = NULL;
    int rc = 0;
    for (char *tok = strtok_r(copy, ",", &save); tok && !rc; tok = strtok_r(NULL, ",", &save)) {
        for (int i = 0; i < (reps < 1 ? 1 : reps) && !rc; i++) rc = run_once(req, atoi(tok), i == 0, &ph);
        if (rc) fprintf(stderr, "%s: the build failed, or its loops changed between runs\n", argv[1]);
        else print_phases(argv[1], atoi(tok), &ph);
    }
    free(copy), free(json);
    tc_request_free(req);
    return rc ? 1 : 0;
}
