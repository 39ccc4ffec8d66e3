/* assert.h — TC_ASSERT: the core's invariants and preconditions, checked in the debug
 * build (TC_DEBUG: make check) and compiled out of release builds (nothing evaluated). */
#ifndef TC_CORE_ASSERT_H
#define TC_CORE_ASSERT_H

#include <stddef.h>

/* TC_ASSERT(cond): with TC_DEBUG, a false cond prints "file:line: TC_ASSERT(cond)
 * failed" to stderr and aborts. Without it, cond is not evaluated (sizeof only
 * names it, so the variables it reads still count as used).
 *
 * TC_ASSERT_CHECK(checker, args...): a checker's call checker(args..., why, n)
 * returns 0 when the invariants it knows hold, else nonzero with the first one
 * found broken written to why[n]; with TC_DEBUG a nonzero return prints that
 * and aborts. The checkers themselves are always compiled, so a test can call
 * them in either build; only the builders' calls go away. */
#ifdef TC_DEBUG
#include <stdio.h>
#include <stdlib.h>

_Noreturn static inline void tc__assert_fail(const char *file, int line, const char *what, const char *why) {
    fprintf(stderr, "%s:%d: TC_ASSERT(%s) failed%s%s\n", file, line, what, why ? ": " : "", why ? why : "");
    fflush(stderr);
    abort();
}

#define TC_ASSERT(cond) ((cond) ? (void)0 : tc__assert_fail(__FILE__, __LINE__, #cond, NULL))
#define TC_ASSERT_CHECK(checker, ...)                                                                       \
    do {                                                                                                    \
        char tc_why_[256];                                                                                  \
        if (checker(__VA_ARGS__, tc_why_, sizeof tc_why_))                                                  \
            tc__assert_fail(__FILE__, __LINE__, #checker "(" #__VA_ARGS__ ")", tc_why_);                    \
    } while (0)
#else
#define TC_ASSERT(cond) ((void)sizeof(cond))
#define TC_ASSERT_CHECK(checker, ...) ((void)sizeof(checker(__VA_ARGS__, (char *)NULL, (size_t)0)))
#endif

#endif
