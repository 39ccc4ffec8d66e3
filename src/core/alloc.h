/* alloc.h — the core's allocation helpers: never NULL for a zero count (so NULL
 * always means out of memory), and no silent overflow of n * size; and the
 * index of an element of a row-major array. */
#ifndef TC_CORE_ALLOC_H
#define TC_CORE_ALLOC_H

#include <stdlib.h>

/* n zeroed elements of size sz (calloc checks n * sz itself). */
static inline void *tc__calloc(size_t n, size_t sz) {
    return n ? calloc(n, sz) : calloc(1, 1);
}
/* n elements of size sz, uninitialized; NULL when n * sz overflows. */
static inline void *tc__malloc(size_t n, size_t sz) {
    if (sz && n > (size_t)-1 / sz) return NULL;
    size_t bytes = n * sz;
    return malloc(bytes ? bytes : 1);
}

/* Element (i, j) of an [..][n] array: i * n + j in size_t. The core's indices and
 * counts are int / int32_t (-1 marks "none"); an index used here is never negative. */
static inline size_t tc__ix(long i, long n, long j) {
    return (size_t)i * (size_t)n + (size_t)j;
}

#endif
