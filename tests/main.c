/* main.c — runs every registered unit test (optionally only those whose name
 * contains argv[1]) and ends with the line "N passed, N failed". */
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "core/leakcheck.h"
#include "core/parallel.h"

typedef struct { const char *name; tc_test_fn fn; const char *file; int order; } entry;

static entry *tests;
static int ntests, cap;
static int current_failures;
static const char *current_name;

void tc_test_register(const char *name, tc_test_fn fn, const char *file) {
    if (ntests == cap) {
        cap = cap ? 2 * cap : 64;
        tests = realloc(tests, (size_t)cap * sizeof *tests);
        if (!tests) abort();
    }
    tests[ntests] = (entry){name, fn, file, ntests};
    ntests++;
}

void tc_test_fail(const char *file, int line, const char *fmt, ...) {
    /* Report the first few failures of a test in full; count the rest. */
    if (++current_failures <= 5) {
        va_list ap;
        fprintf(stderr, "  FAIL %s (%s:%d): ", current_name, file, line);
        va_start(ap, fmt);
        vfprintf(stderr, fmt, ap);
        va_end(ap);
        fputc('\n', stderr);
    }
}

unsigned long tc_test_seed(void) {
    const char *s = getenv("TC_TEST_SEED");
    return s ? strtoul(s, NULL, 10) : 20261122UL;
}

static int by_file_then_order(const void *a, const void *b) {
    const entry *x = a, *y = b;
    int c = strcmp(x->file, y->file);
    return c ? c : x->order - y->order;
}

int main(int argc, char **argv) {
    const char *filter = argc > 1 ? argv[1] : NULL;
    int passed = 0, failed = 0;
    qsort(tests, (size_t)ntests, sizeof *tests, by_file_then_order);
    for (int i = 0; i < ntests; i++) {
        if (filter && !strstr(tests[i].name, filter)) continue;
        current_name = tests[i].name;
        current_failures = 0;
        tests[i].fn();
        if (current_failures) {
            if (current_failures > 5)
                fprintf(stderr, "  ... %s: %d more failures\n", current_name, current_failures - 5);
            fprintf(stderr, "FAIL %s\n", current_name);
            failed++;
        } else {
            passed++;
        }
    }
    tc__parallel_stop(); /* no thread of the pool left for LeakSanitizer's scan */
    free(tests);
    if (tc__leak_check()) { /* a sanitizer build's (core/leakcheck.c); 0 in any other */
        fprintf(stderr, "FAIL leak check\n");
        failed++;
    }
    printf("%d passed, %d failed\n", passed, failed);
    fflush(stdout); /* _exit: LeakSanitizer's own check at exit, the unsafe one, is not run */
    _exit(failed ? 1 : 0);
}
