/* budget.h — memory promised to requests in flight (--max-memory): a render
 * reserves what it may hold at its peak before it allocates, keeps what its
 * answer holds until the answer is freed, and gives the rest back at once. */
#ifndef TC_IO_BUDGET_H
#define TC_IO_BUDGET_H

#include <stdatomic.h>
#include <stdint.h>

/* Invariant: 0 <= used, and used <= limit after every successful take (a take
 * that would pass the limit changes nothing). limit 0: no limit, used is still
 * counted (the metrics show it). */
typedef struct {
    _Atomic int64_t used;
    int64_t limit;
} tc_budget;

void tc_budget_init(tc_budget *b, int64_t limit);
/* 1 if n bytes were reserved, 0 if they do not fit now (b NULL: always 1). */
int tc_budget_take(tc_budget *b, int64_t n);
/* Returns n bytes taken before (b NULL or n <= 0: nothing). */
void tc_budget_give(tc_budget *b, int64_t n);
int64_t tc_budget_used(const tc_budget *b);

#endif
