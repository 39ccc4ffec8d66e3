/* hugemem.c — which buffers of the io layer get the core's huge-page advice (from TC_HUGE_MIN
 * on), and the spare big blocks that a sent answer's buffers go back to for the next answer's.
 * The advice is only a hint: its failure (no THP, an old kernel) changes nothing but speed. */
#define _DEFAULT_SOURCE /* madvise, MADV_FREE */
#include "io/hugemem.h"

#include "core/alloc.h"

#include <malloc.h>
#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

static _Thread_local long advised;

long tc__huge_advised(void) { return advised; }

void tc__huge_advise(void *p, size_t n) {
    if (!p || n < TC_HUGE_MIN) return;
    advised++;
    tc__advise_huge(p, n); /* the core's madvise: one place knows the huge page and the call */
}

/* The spares: up to SPARES blocks, TC_HUGE_SPARE_MAX bytes in all, under spare_mu (an empty
 * slot has n == 0). Several: a JSON answer printed on T threads is the answer and T - 1 part
 * buffers (textpar.c), all big, all fresh otherwise. */
#define SPARES 8
static pthread_mutex_t spare_mu = PTHREAD_MUTEX_INITIALIZER;
static struct {
    void *p;
    size_t n;
} spare[SPARES];
static size_t spare_total;

static void *unslot(int k) {
    void *p = spare[k].p;
    spare_total -= spare[k].n;
    spare[k].p = NULL, spare[k].n = 0;
    return p;
}

void *tc__huge_take(size_t n) {
    void *s = NULL, *drop = NULL;
    if (n < TC_HUGE_SPARE_MIN) return NULL; /* a block that small: glibc's, not a spare's pages */
    pthread_mutex_lock(&spare_mu);
    int best = -1, under = -1; /* the smallest that holds n; the largest that does not */
    for (int k = 0; k < SPARES; k++) {
        if (!spare[k].n) continue;
        if (spare[k].n >= n && (best < 0 || spare[k].n < spare[best].n)) best = k;
        if (spare[k].n < n && (under < 0 || spare[k].n > spare[under].n)) under = k;
    }
    if (best >= 0) s = unslot(best);
    else if (under >= 0) drop = unslot(under); /* too small now: it would sit beside the new block */
    pthread_mutex_unlock(&spare_mu);
    free(drop);
    return s;
}

void *tc__huge_realloc(void *p, size_t n) {
    size_t had = p ? malloc_usable_size(p) : 0;
    if (n >= TC_HUGE_MIN && had < TC_HUGE_MIN) { /* a fresh big block; a small p is cheap to copy */
        char *s = tc__huge_take(n);
        if (s) {
            if (p) memcpy(s, p, had < n ? had : n);
            free(p);
            return s; /* advised when it was first made */
        }
    }
    void *q = realloc(p, n);
    tc__huge_advise(q, n);
    return q;
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

/* free(p), or p kept as a spare when its usable size is in [from, TC_HUGE_SPARE_MAX]. */
static void keep_from(void *p, size_t from) {
    size_t n = p ? malloc_usable_size(p) : 0;
    if (n < from || n > TC_HUGE_SPARE_MAX) {
        free(p);
        return;
    }
    lazy_free(p, n);
    void *drop[SPARES + 1];
    int ndrop = 0, slot = -1;
    pthread_mutex_lock(&spare_mu);
    for (;;) { /* room for n: an empty slot, the total within bounds; else the smallest goes */
        int empty = -1, least = -1;
        for (int k = 0; k < SPARES; k++) {
            if (!spare[k].n) empty = k;
            else if (least < 0 || spare[k].n < spare[least].n) least = k;
        }
        if (empty >= 0 && spare_total + n <= TC_HUGE_SPARE_MAX) {
            slot = empty;
            break;
        }
        if (least < 0 || spare[least].n > n) break; /* only bigger ones held: p is the one to go */
        drop[ndrop++] = unslot(least);
    }
    if (slot >= 0) spare[slot].p = p, spare[slot].n = n, spare_total += n;
    pthread_mutex_unlock(&spare_mu);
    if (slot < 0) drop[ndrop++] = p;
    for (int k = 0; k < ndrop; k++) free(drop[k]);
}

void tc__huge_free(void *p) {
    keep_from(p, TC_HUGE_MIN);
}

void tc__huge_keep(void *p) {
    keep_from(p, TC_HUGE_SPARE_MIN);
}

size_t tc__huge_spare(void) {
    pthread_mutex_lock(&spare_mu);
    size_t n = spare_total;
    pthread_mutex_unlock(&spare_mu);
    return n;
}
