/* clockprobe.c — how fast one core computes, and writes memory, when 1..N of them do at once:
 * the same dependent chain of multiply-adds (registers only) on each of N threads together.
 *
 *     build/bench_clockprobe [--write MIB] [THREADS,...]   (default "1,2"; one JSON object per count)
 *
 * --write: instead, each thread fills its own buffer of MIB MiB (touched first) again and again
 * with plain stores, and the rate of bytes written, per thread and together, is printed: a tile writes
 * 4 bytes a pixel, so at N threads it can go no faster than that rate allows.
 *
 * A chain of multiply-adds runs at one per their latency, so its rate per thread follows
 * the core's clock alone. Where the rate per thread at N threads falls below one thread's, a
 * tile's speed-up at N threads falls with it, whatever the tile's code does: the cores run at
 * a lower clock when all are busy (turbo), or share their physical cores with other work. */
#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

enum { STEPS = 100000000, MAXT = 256, WRITES = 8 };

typedef struct {
    pthread_barrier_t *start;
    double seconds, sink;
    size_t bytes; /* --write: the buffer's size; 0: the chain */
} probe;

static double now_s(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Four independent chains would measure throughput; one measures latency, i.e. the clock. */
static void *fill(probe *p) {
    char *buf = malloc(p->bytes);
    if (!buf) abort();
    memset(buf, 1, p->bytes);
    pthread_barrier_wait(p->start);
    double t0 = now_s();
    /* plain stores, as the tile's (memset may use stores that bypass the cache) */
    typedef uint64_t v2u __attribute__((vector_size(16)));
    v2u *w = (v2u *)buf;
    for (int r = 0; r < WRITES; r++) {
        v2u x = {(uint64_t)r, (uint64_t)r + 1}, step = {2, 2};
        for (size_t i = 0; i < p->bytes / sizeof *w; i++) w[i] = x, x += step;
    }
    p->seconds = now_s() - t0;
    p->sink = buf[p->bytes / 2];
    free(buf);
    return NULL;
}

static void *chain(void *arg) {
    probe *p = arg;
    if (p->bytes) return fill(p);
    volatile double a0 = 0.999999, b0 = 1e-7;
    double x = 1, a = a0, b = b0;
    pthread_barrier_wait(p->start);
    double t0 = now_s();
    for (int i = 0; i < STEPS; i++) x = x * a + b; /* c11: not contracted, a multiply then an add */
    p->seconds = now_s() - t0;
    p->sink = x;
    return NULL;
}

static void run(int n, size_t bytes) {
    pthread_t th[MAXT];
    probe pr[MAXT];
    pthread_barrier_t start;
    pthread_barrier_init(&start, NULL, (unsigned)n);
    for (int k = 0; k < n; k++) {
        pr[k] = (probe){&start, 0, 0, bytes};
        if (k) pthread_create(&th[k], NULL, chain, &pr[k]);
    }
    chain(&pr[0]);
    double worst = 0, sum = 0, sink = 0;
    for (int k = 0; k < n; k++) {
        if (k) pthread_join(th[k], NULL);
        worst = fmax(worst, pr[k].seconds), sum += pr[k].seconds, sink += pr[k].sink;
    }
    pthread_barrier_destroy(&start);
    if (bytes) {
        printf("{\"threads\": %d, \"mib\": %zu, \"gb_s_per_thread_mean\": %.2f, \"gb_s_together\": %.2f}\n", n,
               bytes >> 20, (double)WRITES * (double)bytes / (sum / n) / 1e9, (double)WRITES * (double)bytes * n / worst / 1e9);
        fflush(stdout);
        return;
    }
    printf("{\"threads\": %d, \"msteps_s_per_thread_mean\": %.1f, \"msteps_s_per_thread_slowest\": %.1f, \"sink\": %.3g}\n", n,
           STEPS / (sum / n) / 1e6, STEPS / worst / 1e6, sink);
    fflush(stdout);
}

int main(int argc, char **argv) {
    size_t bytes = 0;
    if (argc > 2 && !strcmp(argv[1], "--write")) {
        bytes = (size_t)atoi(argv[2]) << 20;
        argc -= 2, argv += 2;
    }
    char *list = strdup(argc > 1 ? argv[1] : "1,2"), *save = NULL;
    for (char *tok = strtok_r(list, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
        int n = atoi(tok);
        if (n >= 1 && n <= MAXT) run(n, bytes);
    }
    free(list);
    return 0;
}
