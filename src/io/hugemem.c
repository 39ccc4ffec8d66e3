/* hugemem.c — which buffers of the io layer get the core's huge-page advice (from TC_HUGE_MIN
 * on), and the one spare big block that an answer's pages go back to for the next answer.
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

/* The spare: one big block (or none), under spare_mu. */
static pthread_mutex_t spare_mu = PTHREAD_MUTEX_INITIALIZER;
static void *spare;
static size_t spare_size;

/* The spare if it holds n bytes; NULL otherwise, and a spare too small for n is freed (it
 * would only add to the memory that the block about to be made takes). */
static void *take_spare(size_t n) {
    pthread_mutex_lock(&spare_mu);
    void *s = spare, *drop = NULL;
    if (s && spare_size < n) drop = s, s = NULL;
    if (spare && (s || drop)) spare = NULL, spare_size = 0;
    pthread_mutex_unlock(&spare_mu);
    free(drop);
    return s;
}

void *tc__huge_realloc(void *p, size_t n) {
    size_t had = p ? malloc_usable_size(p) : 0;
    if (n >= TC_HUGE_MIN && had < TC_HUGE_MIN) { /* a fresh big block; a small p is cheap to copy */
        char *s = take_spare(n);
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

void tc__huge_free(void *p) {
    size_t n = p ? malloc_usable_size(p) : 0;
    if (n < TC_HUGE_MIN || n > TC_HUGE_SPARE_MAX) {
        free(p);
        return;
    }
    lazy_free(p, n);
    pthread_mutex_lock(&spare_mu);
    void *old = spare;
    spare = p, spare_size = n;
    pthread_mutex_unlock(&spare_mu);
    free(old);
}

size_t tc__huge_spare(void) {
    pthread_mutex_lock(&spare_mu);
    size_t n = spare ? spare_size : 0;
    pthread_mutex_unlock(&spare_mu);
    return n;
}
