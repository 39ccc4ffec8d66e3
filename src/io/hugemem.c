/* hugemem.c — which buffers of the io layer get the core's huge-page advice (from TC_HUGE_MIN
 * on). The advice is only a hint: its failure (no THP, an old kernel) changes nothing but speed. */
#include "io/hugemem.h"

#include "core/alloc.h"

#include <stdint.h>
#include <stdlib.h>

static _Thread_local long advised;

long tc__huge_advised(void) { return advised; }

void tc__huge_advise(void *p, size_t n) {
    if (!p || n < TC_HUGE_MIN) return;
    advised++;
    tc__advise_huge(p, n); /* the core's madvise: one place knows the huge page and the call */
}

void *tc__huge_realloc(void *p, size_t n) {
    void *q = realloc(p, n);
    tc__huge_advise(q, n);
    return q;
}
