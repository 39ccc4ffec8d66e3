/* hugemem.c — madvise(MADV_HUGEPAGE) for the big buffers of the io layer. The advice is
 * only a hint: its failure (no THP, an old kernel) changes nothing but speed. */
#define _DEFAULT_SOURCE
#include "io/hugemem.h"

#include <stdint.h>
#include <stdlib.h>
#include <sys/mman.h>
#include <unistd.h>

static _Thread_local long advised;

long tc__huge_advised(void) { return advised; }

void tc__huge_advise(void *p, size_t n) {
    if (!p || n < TC_HUGE_MIN) return;
    advised++;
#ifdef MADV_HUGEPAGE
    /* Whole pages from the one holding p: madvise wants a page-aligned start. The block's
     * own allocator header shares the first page; advice on it is harmless. */
    uintptr_t page = 4096, a = (uintptr_t)p & ~(page - 1);
    (void)madvise((void *)a, (uintptr_t)p + n - a, MADV_HUGEPAGE);
#endif
}

void *tc__huge_realloc(void *p, size_t n) {
    void *q = realloc(p, n);
    tc__huge_advise(q, n);
    return q;
}
