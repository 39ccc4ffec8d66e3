/* check.h — the unit-test harness: TEST() registers a test, CHECK*() record failures.
 * A test passes when none of its checks failed; tests/main.c runs them all. */
#ifndef TC_TEST_CHECK_H
#define TC_TEST_CHECK_H

#include <math.h>
#include <stdio.h>

typedef void (*tc_test_fn)(void);
void tc_test_register(const char *name, tc_test_fn fn, const char *file);
void tc_test_fail(const char *file, int line, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
/* The seed of the randomized tests: fixed unless TC_TEST_SEED is set. */
unsigned long tc_test_seed(void);

#define TEST(name)                                                              \
    static void name(void);                                                     \
    __attribute__((constructor)) static void tc_reg_##name(void) {              \
        tc_test_register(#name, name, __FILE__);                                \
    }                                                                           \
    static void name(void)

#define CHECK(cond)                                                             \
    do {                                                                        \
        if (!(cond)) tc_test_fail(__FILE__, __LINE__, "CHECK(%s)", #cond);      \
    } while (0)

#define CHECK_MSG(cond, ...)                                                    \
    do {                                                                        \
        if (!(cond)) tc_test_fail(__FILE__, __LINE__, __VA_ARGS__);             \
    } while (0)

/* |a - b| <= tol, and both finite. */
#define CHECK_NEAR(a, b, tol)                                                   \
    do {                                                                        \
        double tc_a_ = (a), tc_b_ = (b), tc_t_ = (tol);                         \
        if (!(isfinite(tc_a_) && isfinite(tc_b_) && fabs(tc_a_ - tc_b_) <= tc_t_)) \
            tc_test_fail(__FILE__, __LINE__, "CHECK_NEAR(%s, %s): %.17g vs %.17g, diff %.3g > %.3g", \
                         #a, #b, tc_a_, tc_b_, fabs(tc_a_ - tc_b_), tc_t_);      \
    } while (0)

#define CHECK_STR_CONTAINS(hay, needle)                                         \
    do {                                                                        \
        const char *tc_h_ = (hay), *tc_n_ = (needle);                           \
        if (!tc_h_ || !strstr(tc_h_, tc_n_))                                    \
            tc_test_fail(__FILE__, __LINE__, "'%s' does not contain '%s'",      \
                         tc_h_ ? tc_h_ : "(null)", tc_n_);                      \
    } while (0)

#endif
