/* spare.c — the spare big blocks (spare.h): per pool a few slots, all under one mutex, best
 * fit on take, the smallest evicted on keep. Invariant: totals[pool] is the sum of its slots'
 * n, at most TC__SPARE_MAX; an empty slot has p == NULL and n == 0. */
#define _DEFAULT_SOURCE /* madvise, MADV_FREE */
#include "core/spare.h"

#include <malloc.h>
#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>
#include <sys/mman.h>
#include <unistd.h>

typedef struct {
    void *p;
    size_t n;
} slot;

static pthread_mutex_t spare_mu = PTHREAD_MUTEX_INITIALIZER;
static slot spares[TC__SPARE_POOLS][TC__SPARES];
static size_t totals[TC__SPARE_POOLS];

static void *unslot(int pool, int k) {
    slot *sl = &spares[pool][k];
    void *p = sl->p;
    totals[pool] -= sl->n;
    sl->p = NULL, sl->n = 0;
    return p;
}

void *tc__spare_take(int pool, size_t n, int drop_smaller) {
    void *s = NULL, *drop = NULL;
    size_t most = n > SIZE_MAX / 2 ? SIZE_MAX : 2 * n;
    pthread_mutex_lock(&spare_mu);
    int best = -1, under = -1; /* the smallest that holds n (and not twice over); the largest that does not */
    const slot *sp = spares[pool];
    for (int k = 0; k < TC__SPARES; k++) {
        if (!sp[k].n) continue;
        if (sp[k].n >= n && sp[k].n <= most && (best < 0 || sp[k].n < sp[best].n)) best = k;
        if (sp[k].n < n && (under < 0 || sp[k].n > sp[under].n)) under = k;
    }
    if (best >= 0) s = unslot(pool, best);
    else if (under >= 0 && drop_smaller) drop = unslot(pool, under);
    pthread_mutex_unlock(&spare_mu);
    free(drop);
    return s;
}

/* Gives the whole base pages inside [p, p + n) to the kernel as lazily free. Only inside:
 * the page holding p's start also holds the allocator's header of the block, which must stay. */
static void lazy_free(void *p, size_t n) {
#ifdef MADV_FREE
    uintptr_t page = (uintptr_t)sysconf(_SC_PAGESIZE);
    uintptr_t lo = ((uintptr_t)p + page - 1) & ~(page - 1), hi = ((uintptr_t)p + n) & ~(page - 1);
    if (hi > lo) (void)madvise((void *)lo, hi - lo, MADV_FREE);
#else
    (void)p, (void)n;
#endif
}

void tc__spare_keep(int pool, void *p, size_t from) {
    size_t n = p ? malloc_usable_size(p) : 0;
    if (n < from || n > TC__SPARE_MAX) {
        free(p);
        return;
    }
    lazy_free(p, n);
    void *drop[TC__SPARES + 1];
    int ndrop = 0, at = -1;
    slot *sp = spares[pool];
    pthread_mutex_lock(&spare_mu);
    for (;;) { /* room for n: an empty slot, the total within bounds; else the smallest goes */
        int empty = -1, least = -1;
        for (int k = 0; k < TC__SPARES; k++) {
            if (!sp[k].n) empty = k;
            else if (least < 0 || sp[k].n < sp[least].n) least = k;
        }
        if (empty >= 0 && totals[pool] + n <= TC__SPARE_MAX) {
            at = empty;
            break;
        }
        if (least < 0 || sp[least].n > n) break; /* only bigger ones held: p is the one to go */
        drop[ndrop++] = unslot(pool, least);
    }
    if (at >= 0) sp[at].p = p, sp[at].n = n, totals[pool] += n;
    pthread_mutex_unlock(&spare_mu);
    if (at < 0) drop[ndrop++] = p;
    for (int k = 0; k < ndrop; k++) free(drop[k]);
}

size_t tc__spare_bytes(int pool) {
    pthread_mutex_lock(&spare_mu);
    size_t n = totals[pool];
    pthread_mutex_unlock(&spare_mu);
    return n;
}

void tc__spare_drop(int pool) {
    void *drop[TC__SPARES];
    pthread_mutex_lock(&spare_mu);
    for (int k = 0; k < TC__SPARES; k++) drop[k] = unslot(pool, k);
    pthread_mutex_unlock(&spare_mu);
    for (int k = 0; k < TC__SPARES; k++) free(drop[k]);
}
