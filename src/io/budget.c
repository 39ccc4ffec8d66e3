/* budget.c — tc_budget: a counter of reserved bytes with a ceiling, lock-free
 * (a compare-and-swap loop, so two takes can never both pass the limit). */
#include "io/budget.h"

void tc_budget_init(tc_budget *b, int64_t limit) {
    atomic_init(&b->used, 0);
    b->limit = limit > 0 ? limit : 0;
}

int tc_budget_take(tc_budget *b, int64_t n) {
    if (!b || n <= 0) return 1;
    int64_t used = atomic_load(&b->used);
    do {
        if (b->limit > 0 && (n > b->limit || used > b->limit - n)) return 0;
    } while (!atomic_compare_exchange_weak(&b->used, &used, used + n));
    return 1;
}

void tc_budget_give(tc_budget *b, int64_t n) {
    if (b && n > 0) atomic_fetch_sub(&b->used, n);
}

int64_t tc_budget_used(const tc_budget *b) { return b ? atomic_load(&b->used) : 0; }
