/* benchio.h — what every program of bench/perf/ needs: a clock in seconds, a whole file in
 * memory, the scattered points. Header-only: each benchmark is one .c file linked with libtocher.a. */
#ifndef BENCH_PERF_BENCHIO_H
#define BENCH_PERF_BENCHIO_H

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

/* Seconds on clock c (CLOCK_MONOTONIC for wall time, CLOCK_THREAD_CPUTIME_ID or
 * CLOCK_PROCESS_CPUTIME_ID for the CPU time a busy shared machine disturbs least). */
static inline double bench_clock_s(clockid_t c) {
    struct timespec ts;
    clock_gettime(c, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* The whole file, NUL-terminated, its length in *len; NULL if it cannot be read. */
static inline char *bench_slurp(const char *path, size_t *len) {
    *len = 0;
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *buf = n >= 0 ? malloc((size_t)n + 1) : NULL;
    if (buf && fread(buf, 1, (size_t)n, f) != (size_t)n) free(buf), buf = NULL;
    fclose(f);
    if (buf) buf[n] = 0, *len = (size_t)n;
    return buf;
}

/* DIR/points.f64 (bench/perf/meshes.py's scattered points: x, y doubles) holding at least
 * n points; NULL, said on stderr as prog's complaint, if it is missing or short. free() it. */
static inline double *bench_points(const char *dir, size_t n, const char *prog) {
    char path[1024];
    size_t len;
    snprintf(path, sizeof path, "%s/points.f64", dir);
    char *raw = bench_slurp(path, &len);
    if (raw && len >= n * 2 * sizeof(double)) return (double *)(void *)raw;
    fprintf(stderr, "%s: %s: missing or short\n", prog, path);
    free(raw);
    return NULL;
}

#endif
