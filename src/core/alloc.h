/* alloc.h — the core's allocation helpers: never NULL for a zero count (so NULL
 * always means out of memory), and no silent overflow of n * size; and the
 * index of an element of a row-major array. */
#ifndef TC_CORE_ALLOC_H
#define TC_CORE_ALLOC_H

#include <stdint.h>
#include <stdlib.h>

/* From this size on an array is allocated to be backed by huge pages
 * (alloc.c): tc__malloc_huge / tc__calloc_huge, free()d as any other. A
 * build can move it (-DTC__HUGE_MIN=SIZE_MAX: never) to compare. */
#ifndef TC__HUGE_MIN
#define TC__HUGE_MIN ((size_t)4 << 20)
#endif
void *tc__malloc_huge(size_t bytes);
void *tc__calloc_huge(size_t bytes);
/* The advice alone, for a block allocated elsewhere (io/hugemem.c's buffers): the whole
 * huge pages inside [p, p + bytes) are to be backed by huge pages. Changes no byte. */
void tc__advise_huge(void *p, size_t bytes);

/* free(p), for every block the core allocates: one of TC__SPARE_MIN bytes or more is kept as a
 * spare (core/spare.h) for the next big array, so that a daemon's next request does not fault
 * in and zero its pages again (they are lazily free meanwhile: the kernel may take them back). */
void tc__free(void *p);

/* n zeroed elements of size sz; NULL when n * sz overflows. */
static inline void *tc__calloc(size_t n, size_t sz) {
    if (sz && n > (size_t)-1 / sz) return NULL;
    if (n * sz >= TC__HUGE_MIN) return tc__calloc_huge(n * sz);
    return n ? calloc(n, sz) : calloc(1, 1);
}

/* n elements of size sz, uninitialized; NULL when n * sz overflows. */
static inline void *tc__malloc(size_t n, size_t sz) {
    if (sz && n > (size_t)-1 / sz) return NULL;
    size_t bytes = n * sz;
    if (bytes >= TC__HUGE_MIN) return tc__malloc_huge(bytes);
    return malloc(bytes ? bytes : 1);
}

/* Element (i, j) of an [..][n] array: i * n + j in size_t. The core's indices and
 * counts are int / int32_t (-1 marks "none"); an index used here is never negative. */
static inline size_t tc__ix(long i, long n, long j) {
    return (size_t)i * (size_t)n + (size_t)j;
}

#endif
