/* hugemem.c — which buffers of the io layer get the core's huge-page advice (from TC_HUGE_MIN
 * on), and which of them go back to the spare blocks (core/spare.c) for the next answer's.
 * The advice is only a hint: its failure (no THP, an old kernel) changes nothing but speed. */
#include "io/hugemem.h"

#include "core/alloc.h"
#include "core/spare.h"

#include <malloc.h>
#include <stdlib.h>
#include <string.h>

static _Thread_local long advised;

long tc__huge_advised(void) { return advised; }

void tc__huge_advise(void *p, size_t n) {
    if (!p || n < TC_HUGE_MIN) return;
    advised++;
    tc__advise_huge(p, n); /* the core's madvise: one place knows the huge page and the call */
}

void *tc__huge_take(size_t n) {
    return n < TC__SPARE_MIN ? NULL : tc__spare_take(TC__SPARE_ANSWERS, n, 1); /* a block that small: glibc's */
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

void tc__huge_free(void *p) {
    tc__spare_keep(TC__SPARE_ANSWERS, p, TC_HUGE_MIN);
}

void tc__huge_keep(void *p) {
    tc__spare_keep(TC__SPARE_ANSWERS, p, TC__SPARE_MIN);
}

size_t tc__huge_spare(void) { return tc__spare_bytes(TC__SPARE_ANSWERS); }
