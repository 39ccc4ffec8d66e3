/* parallel.c — tc__parallel_for: a loop split into contiguous parts, one
 * pthread per part (the caller's thread runs part 0). Threads live for one loop. */
#include <pthread.h>

#include "core/parallel.h"

typedef struct {
    tc__part_fn fn;
    void *ctx;
    int32_t lo, hi;
    int part;
} part_job;

static void *run_part(void *arg) {
    part_job *j = arg;
    j->fn(j->ctx, j->lo, j->hi, j->part);
    return NULL;
}

int tc__parallel_parts(int threads, int32_t n, int32_t min_part) {
    if (threads <= 1 || n <= 0) return 1;
    if (threads > TC_PARALLEL_MAX) threads = TC_PARALLEL_MAX;
    if (min_part < 1) min_part = 1;
    int32_t most = n / min_part;
    return most < 1 ? 1 : most < threads ? (int)most : threads;
}

void tc__parallel_for(int threads, int32_t n, int32_t min_part, tc__part_fn fn, void *ctx) {
    int parts = tc__parallel_parts(threads, n, min_part);
    if (n <= 0) return;
    if (parts == 1) {
        fn(ctx, 0, n, 0);
        return;
    }
    part_job jobs[TC_PARALLEL_MAX];
    pthread_t tid[TC_PARALLEL_MAX];
    int started[TC_PARALLEL_MAX] = {0};
    for (int p = 0; p < parts; p++) /* the split is a function of (n, parts) only */
        jobs[p] = (part_job){fn, ctx, (int32_t)((int64_t)n * p / parts), (int32_t)((int64_t)n * (p + 1) / parts), p};
    for (int p = 1; p < parts; p++) started[p] = pthread_create(&tid[p], NULL, run_part, &jobs[p]) == 0;
    run_part(&jobs[0]);
    for (int p = 1; p < parts; p++) {
        if (started[p]) pthread_join(tid[p], NULL);
        else run_part(&jobs[p]);
    }
}
