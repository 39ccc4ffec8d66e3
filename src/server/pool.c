/* pool.c — the compute workers: pthreads over a bounded ring of jobs. A job
 * is always called once, run or cancelled, so a suspended connection it
 * carries is always resumed. */
#include <pthread.h>
#include <stdlib.h>

#include "server/pool.h"

typedef struct {
    tc_pool_fn run;
    void *arg;
} job;

struct tc_pool {
    pthread_mutex_t mu;
    pthread_cond_t ready; /* a job was queued, or the pool is stopping */
    job *ring;
    int cap, head, count; /* the waiting jobs: ring[head .. head + count) mod cap */
    int running;
    int stopping;
    int joined; /* tc_pool_stop has run (only its caller's thread reads it) */
    int nthreads;
    pthread_t *threads;
};

/* The next job, or 0 when the pool stops (waiting jobs are left to tc_pool_free). */
static int take(tc_pool *p, job *out) {
    pthread_mutex_lock(&p->mu);
    while (!p->count && !p->stopping) pthread_cond_wait(&p->ready, &p->mu);
    int got = !p->stopping;
    if (got) {
        *out = p->ring[p->head];
        p->head = (p->head + 1) % p->cap;
        p->count--;
        p->running++;
    }
    pthread_mutex_unlock(&p->mu);
    return got;
}

static void *worker(void *arg) {
    tc_pool *p = arg;
    job j;
    while (take(p, &j)) {
        j.run(j.arg, 0);
        pthread_mutex_lock(&p->mu);
        p->running--;
        pthread_mutex_unlock(&p->mu);
    }
    return NULL;
}

static void pool_destroy(tc_pool *p) {
    pthread_cond_destroy(&p->ready);
    pthread_mutex_destroy(&p->mu);
    free(p->threads);
    free(p->ring);
    free(p);
}

/* Stops and joins the first n workers. */
static void stop_workers(tc_pool *p, int n) {
    pthread_mutex_lock(&p->mu);
    p->stopping = 1;
    pthread_cond_broadcast(&p->ready);
    pthread_mutex_unlock(&p->mu);
    for (int i = 0; i < n; i++) pthread_join(p->threads[i], NULL);
}

tc_pool *tc_pool_new(int nthreads, int max_queue) {
    tc_pool *p = calloc(1, sizeof *p);
    if (!p) return NULL;
    p->cap = max_queue > 0 ? max_queue : 1;
    p->ring = calloc((size_t)p->cap, sizeof *p->ring);
    p->threads = calloc((size_t)nthreads, sizeof *p->threads);
    pthread_mutex_init(&p->mu, NULL);
    pthread_cond_init(&p->ready, NULL);
    if (!p->ring || !p->threads) return pool_destroy(p), NULL;
    for (p->nthreads = 0; p->nthreads < nthreads; p->nthreads++)
        if (pthread_create(&p->threads[p->nthreads], NULL, worker, p)) {
            stop_workers(p, p->nthreads);
            return pool_destroy(p), NULL;
        }
    return p;
}

int tc_pool_submit(tc_pool *p, tc_pool_fn run, void *arg) {
    pthread_mutex_lock(&p->mu);
    int ok = !p->stopping && p->count < p->cap;
    if (ok) {
        p->ring[(p->head + p->count) % p->cap] = (job){run, arg};
        p->count++;
        pthread_cond_signal(&p->ready);
    }
    pthread_mutex_unlock(&p->mu);
    return ok ? 0 : -1;
}

void tc_pool_counts(tc_pool *p, int *waiting, int *running) {
    pthread_mutex_lock(&p->mu);
    *waiting = p->count;
    *running = p->running;
    pthread_mutex_unlock(&p->mu);
}

void tc_pool_stop(tc_pool *p) {
    if (!p || p->joined) return;
    stop_workers(p, p->nthreads);
    p->joined = 1;
    /* The workers are gone and submit refuses: what is still queued is
     * cancelled here, outside the lock (a job may take its time to answer). */
    for (;;) {
        pthread_mutex_lock(&p->mu);
        job j = p->ring[p->head];
        int any = p->count > 0;
        if (any) p->head = (p->head + 1) % p->cap, p->count--;
        pthread_mutex_unlock(&p->mu);
        if (!any) break;
        j.run(j.arg, 1);
    }
}

void tc_pool_free(tc_pool *p) {
    if (!p) return;
    tc_pool_stop(p);
    pool_destroy(p);
}
