/* parallel.h — runs a loop over [0, n) in contiguous parts on up to `threads`
 * threads, a few parts per thread (parallel.c), for the per-vertex /
 * per-triangle steps of a build. */
#ifndef TC_CORE_PARALLEL_H
#define TC_CORE_PARALLEL_H

#include <stddef.h>
#include <stdint.h>

/* At most this many parts (and so threads) for one loop. */
#define TC_PARALLEL_MAX 64

/* One part: fn(ctx, lo, hi, part) for [lo, hi). Parts are contiguous, in
 * order (part p covers lower indices than part p + 1), and each runs wholly
 * on one thread, the threads (the caller's among them) taking the next part
 * as they finish one. A caller keeps whatever a part finds in a
 * slot of its own (indexed by part) and merges the slots in part order, so
 * its result does not depend on how many parts there were: counts, the first
 * or the largest in index order, never a floating-point sum across parts. */
typedef void (*tc__part_fn)(void *ctx, int32_t lo, int32_t hi, int part);

/* How many parts tc__parallel_for makes of n items on `threads` threads:
 * threads <= 1: one; else a few per thread (up to TC_PARALLEL_MAX), fewer
 * for small loops: a part has at least min_part items. */
int tc__parallel_parts(int threads, int32_t n, int32_t min_part);

/* Runs fn over every part and returns when all are done. A thread that
 * cannot be started leaves its part to the caller's thread: never a
 * failure, only less parallel. */
void tc__parallel_for(int threads, int32_t n, int32_t min_part, tc__part_fn fn, void *ctx);

/* The same with one part per thread (at most `threads` parts, of at least min_part
 * items; tc__parallel_thread_parts says how many), for loops whose parts each pay a
 * set-up of their own that more parts would repeat: a buffer of fresh memory for
 * its text (io/textpar.c), a render worker's scratch (raster.c). */
int tc__parallel_thread_parts(int threads, int32_t n, int32_t min_part);
void tc__parallel_for_threads(int threads, int32_t n, int32_t min_part, tc__part_fn fn, void *ctx);

/* Ends the pool's threads and waits for them (a loop in hand ends first; the
 * next loop starts them again). For a process that must leave no thread
 * behind when it exits: the tests, whose exit under LeakSanitizer scans every
 * live thread from a tracer that is known to crash now and then on a process
 * with many (google/sanitizers#1353; 63 idle workers here). */
void tc__parallel_stop(void);

/* One loop as tc__parallel_trace records it (bench/perf/phases.c: where a
 * build's time goes on each thread count, and what runs between its loops). */
typedef struct {
    const void *fn;           /* the part function: which loop it was */
    int32_t n;                /* its items */
    int parts;                /* the parts it ran in */
    double start_s, end_s;    /* CLOCK_MONOTONIC at its call and its return */
    double cpu_s;             /* CPU time of all its parts (each thread's clock) */
    double slowest_s;         /* wall time of its slowest part */
} tc__loop_record;

/* Starts recording every tc__parallel_for of the process into rec[0 .. cap)
 * (rec NULL: stops) and returns how many loops the recording it ends had
 * started (beyond cap: not kept). For benchmarks: while on, each part reads
 * two clocks; while off, a loop pays one relaxed load. Not for concurrent use
 * with its own calls. */
int tc__parallel_trace(tc__loop_record *rec, int cap);

/* memcpy(dst, src, bytes) in parts (a large copy runs at more than one core's bandwidth). */
void tc__parallel_copy(int threads, void *dst, const void *src, size_t bytes);

/* memset(dst, 0, bytes) in parts: a fresh array zeroed this way has its pages
 * faulted in by several threads (calloc's clearing of a reused block, or the
 * first writes to a fresh one, fault them in on one). */
void tc__parallel_zero(int threads, void *dst, size_t bytes);

#endif
