/* test_spare.c — the spare big blocks (core/spare.c) and the core's allocator on them
 * (core/alloc.c: tc__malloc / tc__calloc take a spare, tc__free keeps one). */
#include <malloc.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "core/alloc.h"
#include "core/spare.h"

/* A big array freed by tc__free is the next big array of about its size (the same pages, not
 * a fresh mapping); tc__calloc's is zeroed though the spare held old bytes; a small block, or
 * a spare more than twice the size asked, is not used; and the pools do not share blocks. */
TEST(spare_core_arrays_reused) {
    tc__spare_drop(TC__SPARE_ARRAYS);
    size_t n = TC__HUGE_MIN + 3 * 4096;
    unsigned char *a = tc__malloc(n, 1);
    CHECK(a != NULL);
    if (!a) return;
    memset(a, 0xab, n);
    uintptr_t at = (uintptr_t)a; /* compared as a number: a is not used once freed */
    tc__free(a);
    CHECK_MSG(tc__spare_bytes(TC__SPARE_ARRAYS) >= n, "a %zu-byte array was not kept", n);
    CHECK_MSG(tc__spare_take(TC__SPARE_ANSWERS, n, 0) == NULL, "the answers' pool had the array's block");
    double *b = tc__calloc(n / sizeof(double), sizeof(double));
    CHECK_MSG((uintptr_t)b == at, "the next array of its size was not the spare");
    CHECK(tc__spare_bytes(TC__SPARE_ARRAYS) == 0);
    int zero = 1;
    for (size_t i = 0; b && i < n / sizeof(double); i += 511) zero &= b[i] == 0;
    CHECK_MSG(zero, "tc__calloc's array from a spare is not zeroed");
    tc__free(b);
    unsigned char *c = tc__malloc(n / 3, 3); /* about the same size again: the spare */
    CHECK((uintptr_t)c == at);
    tc__free(c);
    void *small = tc__malloc(1000, 1);
    size_t before = tc__spare_bytes(TC__SPARE_ARRAYS);
    tc__free(small);
    CHECK_MSG(tc__spare_bytes(TC__SPARE_ARRAYS) == before, "a 1000-byte block became a spare");
    void *quarter = tc__malloc(n / 4 + 4096, 1); /* TC__HUGE_MIN / 4: glibc's, not the spare */
    CHECK((uintptr_t)quarter != at && tc__spare_bytes(TC__SPARE_ARRAYS) == before);
    tc__free(quarter);
    tc__spare_drop(TC__SPARE_ARRAYS);
    CHECK(tc__spare_bytes(TC__SPARE_ARRAYS) == 0);
}

/* A pool keeps at most TC__SPARES blocks and TC__SPARE_MAX bytes, the smallest going first;
 * a block over TC__SPARE_MAX is freed at once. (Blocks not touched: only address space.) */
TEST(spare_pool_bounds) {
    tc__spare_drop(TC__SPARE_ARRAYS);
    size_t unit = TC__SPARE_MAX / 16;
    for (int i = 0; i < 20; i++) tc__spare_keep(TC__SPARE_ARRAYS, malloc(unit + (size_t)i * 4096), TC__SPARE_MIN);
    size_t held = tc__spare_bytes(TC__SPARE_ARRAYS);
    CHECK_MSG(held <= TC__SPARE_MAX && held >= TC__SPARE_MAX - 2 * unit, "%zu bytes held", held);
    void *big = tc__spare_take(TC__SPARE_ARRAYS, unit + 19 * 4096, 0); /* the largest was kept */
    CHECK(big != NULL && malloc_usable_size(big) >= unit + 19 * 4096);
    free(big);
    void *small = tc__spare_take(TC__SPARE_ARRAYS, unit + 4096, 0); /* smaller ones: the first kept went */
    CHECK(small != NULL && malloc_usable_size(small) < unit + 19 * 4096);
    free(small);
    for (int i = 0; i < TC__SPARES + 4; i++) tc__spare_keep(TC__SPARE_ARRAYS, malloc(TC__SPARE_MIN), TC__SPARE_MIN);
    CHECK(tc__spare_bytes(TC__SPARE_ARRAYS) <= TC__SPARE_MAX);
    size_t before = tc__spare_bytes(TC__SPARE_ARRAYS);
    tc__spare_keep(TC__SPARE_ARRAYS, malloc(TC__SPARE_MAX + 1), TC__SPARE_MIN);
    CHECK(tc__spare_bytes(TC__SPARE_ARRAYS) == before);
    tc__spare_drop(TC__SPARE_ARRAYS);
}
