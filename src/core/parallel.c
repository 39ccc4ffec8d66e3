/* parallel.c — tc__parallel_for: a loop split into contiguous parts, a few
 * per thread, that the threads take in turn as they finish one (the caller's
 * thread among them): a thread slowed by anything (another process on its
 * CPU, a page fault, a costlier stretch of the mesh) delays its part, not the
 * loop by a whole thread's share. The threads are a process-wide pool,
 * started on first use and kept until tc__parallel_stop (a build runs some thirty loops: starting
 * threads for each would cost more than a small loop); a loop that finds the
 * pool busy with another caller's loop starts its own threads. */
#include <pthread.h>
#include <stdatomic.h>
#include <stdint.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "core/cpu.h"
#include "core/parallel.h"

typedef struct {
    tc__part_fn fn;
    void *ctx;
    int32_t lo, hi;
    int part;
} part_job;

/* One loop in hand: its parts, and the next one not yet taken. */
typedef struct {
    const part_job *jobs;
    int parts;
    atomic_int next;
} loop_parts;

/* Runs parts of the loop until none is left to take. */
static void *take_parts(void *arg) {
    loop_parts *lp = arg;
    for (int p; (p = atomic_fetch_add(&lp->next, 1)) < lp->parts;) {
        const part_job *j = &lp->jobs[p];
        j->fn(j->ctx, j->lo, j->hi, j->part);
    }
    return NULL;
}

/* Parts per thread: enough that a slow thread's part is a fraction of its
 * share, few enough that a part's own set-up (scratch, merging) stays small. */
#define PARTS_PER_THREAD 4

/* Parts of n items for `per` parts per thread, each of at least min_part items. */
static int parts_of(int threads, int32_t n, int32_t min_part, int per) {
    if (threads <= 1 || n <= 0) return 1;
    int want = threads > TC_PARALLEL_MAX / per ? TC_PARALLEL_MAX : per * threads;
    if (min_part < 1) min_part = 1;
    int32_t most = n / min_part;
    return most < 1 ? 1 : most < want ? (int)most : want;
}

int tc__parallel_parts(int threads, int32_t n, int32_t min_part) {
    return parts_of(threads, n, min_part, PARTS_PER_THREAD);
}

int tc__parallel_thread_parts(int threads, int32_t n, int32_t min_part) {
    return parts_of(threads, n, min_part, 1);
}

/* The pool: workers 1 .. nthreads - 1 take parts of the loop in hand with the
 * caller. `busy` is held by the one caller using it; the rest is guarded by
 * `mu` (gen and pending are also read without it, while spinning). Invariant:
 * pending counts the workers in the loop that have not run out of parts; a
 * new loop (gen + 1) starts only when it is 0, so no worker misses the loop it
 * is in. */
static struct {
    pthread_mutex_t busy, mu;
    pthread_cond_t go, done;
    int nworkers, nthreads;
    atomic_int pending;
    int stopping; /* tc__parallel_stop: the workers are to end at the next gen */
    atomic_int spin; /* the workers and the caller fit on the CPUs: spinning takes no CPU a thread needs */
    atomic_ulong gen;
    loop_parts *loop;
    pthread_t tid[TC_PARALLEL_MAX];
} pool = {PTHREAD_MUTEX_INITIALIZER, PTHREAD_MUTEX_INITIALIZER, PTHREAD_COND_INITIALIZER, PTHREAD_COND_INITIALIZER,
          0, 0, 0, 0, 0, 0, NULL, {0}};

/* A build runs some thirty loops back to back, with little serial work
 * between them: a worker that went to sleep after its part, and a caller
 * asleep until the last part ends, each cost a futex wake-up per loop (tens to
 * hundreds of microseconds, more in a virtual machine), which at 16 threads
 * added up to a good part of the build. So both first spin this long on the
 * word they wait for, and only then sleep on the condition variable; unless
 * there are more threads than CPUs, where a spinning thread would hold a CPU
 * that a thread with work needs. */
#define SPIN_NS 200000L

static void cpu_relax(void) {
#if TC__X86
    __builtin_ia32_pause();
#elif defined(__aarch64__)
    __asm__ __volatile__("yield");
#endif
}

static long now_ns(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (long)ts.tv_sec * 1000000000L + ts.tv_nsec;
}

/* Spins up to SPIN_NS while gen == seen (workers) or pending > 0 (the caller). */
static void spin_gen(unsigned long seen) {
    if (!atomic_load_explicit(&pool.spin, memory_order_relaxed)) return;
    long until = now_ns() + SPIN_NS;
    for (int i = 1; atomic_load_explicit(&pool.gen, memory_order_relaxed) == seen; i++) {
        cpu_relax();
        if (i % 16 == 0 && now_ns() > until) return;
    }
}

static void spin_pending(void) {
    if (!atomic_load_explicit(&pool.spin, memory_order_relaxed)) return;
    long until = now_ns() + SPIN_NS;
    for (int i = 1; atomic_load_explicit(&pool.pending, memory_order_acquire) > 0; i++) {
        cpu_relax();
        if (i % 16 == 0 && now_ns() > until) return;
    }
}

static void *pool_worker(void *arg) {
    int k = (int)(intptr_t)arg;
    unsigned long seen = 0;
    for (;;) {
        spin_gen(seen);
        pthread_mutex_lock(&pool.mu);
        while (atomic_load(&pool.gen) == seen) pthread_cond_wait(&pool.go, &pool.mu);
        seen = atomic_load(&pool.gen);
        if (pool.stopping) {
            pthread_mutex_unlock(&pool.mu);
            return NULL;
        }
        if (k >= pool.nthreads) {
            pthread_mutex_unlock(&pool.mu);
            continue;
        }
        loop_parts *lp = pool.loop;
        pthread_mutex_unlock(&pool.mu);
        take_parts(lp);
        if (atomic_fetch_sub(&pool.pending, 1) == 1) { /* the last part: the caller may sleep (under mu) */
            pthread_mutex_lock(&pool.mu);
            pthread_cond_signal(&pool.done);
            pthread_mutex_unlock(&pool.mu);
        }
    }
    return NULL;
}

/* Runs the loop on the pool with nthreads threads, the caller's one of them
 * (the caller holds pool.busy): 0, or -1 if it has too few workers and cannot
 * start more (nothing was run). */
static int pool_run(loop_parts *lp, int nthreads) {
    while (pool.nworkers < nthreads - 1) { /* workers only ever join: each keeps its index */
        int k = pool.nworkers + 1;
        if (pthread_create(&pool.tid[k], NULL, pool_worker, (void *)(intptr_t)k) != 0) return -1;
        pool.nworkers++;
        atomic_store(&pool.spin, pool.nworkers + 1 <= sysconf(_SC_NPROCESSORS_ONLN));
    }
    pthread_mutex_lock(&pool.mu);
    pool.loop = lp, pool.nthreads = nthreads;
    atomic_store(&pool.pending, nthreads - 1);
    atomic_fetch_add(&pool.gen, 1);
    pthread_cond_broadcast(&pool.go);
    pthread_mutex_unlock(&pool.mu);
    take_parts(lp);
    spin_pending();
    pthread_mutex_lock(&pool.mu);
    while (atomic_load(&pool.pending) > 0) pthread_cond_wait(&pool.done, &pool.mu);
    pool.nthreads = 0, pool.loop = NULL;
    pthread_mutex_unlock(&pool.mu);
    return 0;
}

void tc__parallel_stop(void) {
    pthread_mutex_lock(&pool.busy); /* no loop is in hand, and none starts */
    pthread_mutex_lock(&pool.mu);
    pool.stopping = 1;
    atomic_fetch_add(&pool.gen, 1);
    pthread_cond_broadcast(&pool.go);
    pthread_mutex_unlock(&pool.mu);
    for (int k = 1; k <= pool.nworkers; k++) pthread_join(pool.tid[k], NULL);
    pool.nworkers = 0, pool.stopping = 0;
    atomic_store(&pool.spin, 0);
    pthread_mutex_unlock(&pool.busy);
}

/* Without the pool: threads of its own for this loop (any not started leaves
 * its parts to the others). */
static void own_threads(loop_parts *lp, int nthreads) {
    pthread_t tid[TC_PARALLEL_MAX];
    int started[TC_PARALLEL_MAX] = {0};
    for (int k = 1; k < nthreads; k++) started[k] = pthread_create(&tid[k], NULL, take_parts, lp) == 0;
    take_parts(lp);
    for (int k = 1; k < nthreads; k++)
        if (started[k]) pthread_join(tid[k], NULL);
}

static void run_loop(int threads, int32_t n, int parts, tc__part_fn fn, void *ctx);

/* ---- tracing (tc__parallel_trace) ---- */

static struct {
    _Atomic(tc__loop_record *) rec;
    int cap;
    atomic_int count; /* loops started while recording */
} trace;

/* A traced loop: its parts run through traced_part, which adds up their clocks. */
typedef struct {
    tc__part_fn fn;
    void *ctx;
    atomic_llong cpu_ns, slowest_ns;
} traced_loop;

static long long clock_ns(clockid_t c) {
    struct timespec ts;
    clock_gettime(c, &ts);
    return (long long)ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

static void traced_part(void *ctx, int32_t lo, int32_t hi, int part) {
    traced_loop *tl = ctx;
    long long c0 = clock_ns(CLOCK_THREAD_CPUTIME_ID), w0 = clock_ns(CLOCK_MONOTONIC);
    tl->fn(tl->ctx, lo, hi, part);
    long long wall = clock_ns(CLOCK_MONOTONIC) - w0, seen = atomic_load(&tl->slowest_ns);
    atomic_fetch_add(&tl->cpu_ns, clock_ns(CLOCK_THREAD_CPUTIME_ID) - c0);
    while (wall > seen && !atomic_compare_exchange_weak(&tl->slowest_ns, &seen, wall)) continue;
}

static void traced_run(tc__loop_record *rec, int threads, int32_t n, int parts, tc__part_fn fn, void *ctx) {
    int i = atomic_fetch_add(&trace.count, 1);
    traced_loop tl = {fn, ctx, 0, 0};
    double t0 = 1e-9 * (double)clock_ns(CLOCK_MONOTONIC);
    run_loop(threads, n, parts, traced_part, &tl);
    if (i >= trace.cap) return;
    rec[i] = (tc__loop_record){(const void *)fn, n, n > 0 ? parts : 0, t0,
                               1e-9 * (double)clock_ns(CLOCK_MONOTONIC), 1e-9 * (double)atomic_load(&tl.cpu_ns),
                               1e-9 * (double)atomic_load(&tl.slowest_ns)};
}

int tc__parallel_trace(tc__loop_record *rec, int cap) {
    int had = atomic_load(&trace.count);
    atomic_store(&trace.rec, NULL);
    trace.cap = rec ? cap : 0;
    atomic_store(&trace.count, 0);
    atomic_store(&trace.rec, rec);
    return had;
}

/* The loop in `parts` parts, traced while tc__parallel_trace records. */
static void dispatch(int threads, int32_t n, int parts, tc__part_fn fn, void *ctx) {
    tc__loop_record *rec = atomic_load_explicit(&trace.rec, memory_order_relaxed);
    if (rec) traced_run(rec, threads, n, parts, fn, ctx);
    else run_loop(threads, n, parts, fn, ctx);
}

void tc__parallel_for(int threads, int32_t n, int32_t min_part, tc__part_fn fn, void *ctx) {
    dispatch(threads, n, tc__parallel_parts(threads, n, min_part), fn, ctx);
}

void tc__parallel_for_threads(int threads, int32_t n, int32_t min_part, tc__part_fn fn, void *ctx) {
    dispatch(threads, n, tc__parallel_thread_parts(threads, n, min_part), fn, ctx);
}

static void run_loop(int threads, int32_t n, int parts, tc__part_fn fn, void *ctx) {
    if (n <= 0) return;
    if (parts == 1) {
        fn(ctx, 0, n, 0);
        return;
    }
    part_job jobs[TC_PARALLEL_MAX];
    for (int p = 0; p < parts; p++) /* the split is a function of (n, parts) only */
        jobs[p] = (part_job){fn, ctx, (int32_t)((int64_t)n * p / parts), (int32_t)((int64_t)n * (p + 1) / parts), p};
    loop_parts lp = {jobs, parts, 0};
    int nthreads = threads < parts ? threads : parts; /* parts <= TC_PARALLEL_MAX */
    if (pthread_mutex_trylock(&pool.busy) == 0) {
        int ran = pool_run(&lp, nthreads) == 0;
        pthread_mutex_unlock(&pool.busy);
        if (ran) return;
    }
    own_threads(&lp, nthreads);
}

typedef struct {
    char *dst;
    const char *src;
    size_t bytes;
} copy_job;

enum { COPY_BLOCK = 1 << 16 }; /* bytes per index of the loop */

static void copy_part(void *ctx, int32_t lo, int32_t hi, int part) {
    const copy_job *cj = ctx;
    size_t from = (size_t)lo * COPY_BLOCK, to = (size_t)hi * COPY_BLOCK;
    (void)part;
    if (to > cj->bytes) to = cj->bytes;
    if (cj->src) memcpy(cj->dst + from, cj->src + from, to - from);
    else memset(cj->dst + from, 0, to - from);
}

/* memcpy, or memset to 0 without src. */
static void copy_or_zero(int threads, void *dst, const void *src, size_t bytes) {
    size_t blocks = (bytes + COPY_BLOCK - 1) / COPY_BLOCK;
    copy_job cj = {dst, src, bytes};
    if (blocks <= 1 || blocks > INT32_MAX || threads <= 1) { /* beyond INT32_MAX blocks: beyond any mesh */
        if (src) memcpy(dst, src, bytes);
        else memset(dst, 0, bytes);
        return;
    }
    tc__parallel_for(threads, (int32_t)blocks, 16, copy_part, &cj);
}

void tc__parallel_copy(int threads, void *dst, const void *src, size_t bytes) {
    copy_or_zero(threads, dst, src, bytes);
}

void tc__parallel_zero(int threads, void *dst, size_t bytes) {
    copy_or_zero(threads, dst, NULL, bytes);
}
