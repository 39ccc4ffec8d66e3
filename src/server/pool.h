/* pool.h — the compute workers: a fixed set of threads taking jobs from a
 * bounded FIFO queue, so that libmicrohttpd's I/O threads only move bytes. */
#ifndef TC_SERVER_POOL_H
#define TC_SERVER_POOL_H

#include <stddef.h>

typedef struct tc_pool tc_pool;

/* A job: run(arg, 0) on a worker, or run(arg, 1) ("cancelled": answer that
 * the server could not start it) when the pool stops before a worker took it.
 * Either way it is called exactly once. */
typedef void (*tc_pool_fn)(void *arg, int cancelled);

/* nthreads workers, at most max_queue jobs waiting. NULL if out of memory or
 * a thread cannot start. */
tc_pool *tc_pool_new(int nthreads, int max_queue);

/* 0: queued; -1: the queue is full or the pool is stopping (the caller answers). */
int tc_pool_submit(tc_pool *p, tc_pool_fn run, void *arg);

/* Jobs waiting for a worker, and jobs running. */
void tc_pool_counts(tc_pool *p, int *waiting, int *running);

/* Refuses new jobs, waits for the running ones, then cancels every job still
 * waiting (each gets run(arg, 1), on this thread). Once is enough; NULL: no-op. */
void tc_pool_stop(tc_pool *p);

/* tc_pool_stop, then frees p. NULL: no-op. */
void tc_pool_free(tc_pool *p);

#endif
