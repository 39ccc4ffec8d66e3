/* alloc.c — large arrays on huge pages where the kernel offers them: alloc.h's
 * tc__malloc and tc__calloc send allocations of TC__HUGE_MIN bytes and up here. */
#define _DEFAULT_SOURCE /* madvise */
#include <stdint.h>
#include <stdlib.h>
#include <sys/mman.h>

#include "core/alloc.h"

#include <string.h>

#include "core/spare.h"

/* The huge page size of x86-64 and arm64 (4 KiB base pages); elsewhere the
 * advice covers fewer whole huge pages, or none: only slower, never wrong. */
#define HUGE_PAGE ((size_t)2 << 20)

/* Asks for huge pages on the whole huge pages inside [p, p + bytes). A build
 * writes some 100 MB of fresh arrays (524k triangles); with 4 KiB pages their
 * page faults cost as much as the work, and the gathers through them miss the
 * TLB. Advice only: a kernel without transparent huge pages (or with them
 * "never") refuses it and the pages stay small. Memory not yet touched is what
 * gets huge pages: the advice comes before the array's first write. */
void tc__advise_huge(void *p, size_t bytes) {
#ifdef MADV_HUGEPAGE
    uintptr_t lo = ((uintptr_t)p + HUGE_PAGE - 1) & ~(uintptr_t)(HUGE_PAGE - 1);
    uintptr_t hi = ((uintptr_t)p + bytes) & ~(uintptr_t)(HUGE_PAGE - 1);
    if (hi > lo) (void)madvise((void *)lo, hi - lo, MADV_HUGEPAGE);
#else
    (void)p, (void)bytes;
#endif
}

/* A big array is first the smallest spare that holds it (core/spare.c: the last request's
 * arrays, given back by tc__free): its pages are there already, advised when first made. */
void *tc__malloc_huge(size_t bytes) {
    void *s = tc__spare_take(TC__SPARE_ARRAYS, bytes, 0);
    if (s) return s;
    size_t rounded = (bytes + HUGE_PAGE - 1) & ~(HUGE_PAGE - 1); /* aligned_alloc: a multiple of the alignment */
    void *p = rounded >= bytes ? aligned_alloc(HUGE_PAGE, rounded) : NULL;
    if (!p) p = malloc(bytes);
    else tc__advise_huge(p, rounded);
    return p;
}

void *tc__calloc_huge(size_t bytes) {
    void *s = tc__spare_take(TC__SPARE_ARRAYS, bytes, 0);
    if (s) return memset(s, 0, bytes); /* a spare holds old bytes, or zeros where the kernel took pages back */
    void *p = calloc(1, bytes); /* calloc, not an aligned block cleared here: fresh pages come zeroed */
    if (p) tc__advise_huge(p, bytes); /* (the whole huge pages inside it; calloc has not touched them when fresh) */
    return p;
}

void tc__free(void *p) {
    tc__spare_keep(TC__SPARE_ARRAYS, p, TC__SPARE_MIN);
}
