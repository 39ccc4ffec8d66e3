/* main.c — runs every registered unit test (optionally only those whose name
 * contains argv[1]) and ends with the line "N passed, N failed". */
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "check.h"
#include "core/parallel.h"

#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/lsan_interface.h>
#define TC_LEAK_CHECK_HERE 1
#endif

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

#ifdef TC_LEAK_CHECK_HERE
/* Copies the file at fd (from its start) to stderr, each line indented. */
static void copy_indented(int fd) {
    FILE *f = fdopen(fd, "r");
    char line[512];
    if (!f) return;
    rewind(f);
    while (fgets(line, sizeof line, f)) fprintf(stderr, "  | %s", line);
    fclose(f);
}

/* The leak check, run before exit and without exit handlers. LeakSanitizer's tracer
 * stops and reads every thread; in CI it crashed ("Tracer caught signal 11",
 * google/sanitizers#1353) both at exit and with every thread idle, while the image
 * libraries' pools (OpenEXR's, OpenImageIO's, log4cplus's: as many threads as CPUs)
 * were alive. So the check runs first in a forked child, where the only thread is
 * the one that forked. Its roots are a subset of the whole process's (the other
 * threads' stacks and TLS are not scanned), so no leak there means none here: done.
 * (The child's own thread is not in LeakSanitizer's registry, so its roots are the
 * globals.) A leak there may be held by another thread: its report is shown, and the
 * whole process is checked, which decides; a child that crashed is tried once more
 * first. Returns nonzero when a leak was found. */
static int leak_check(void) {
    char path[] = "/tmp/tocher-leaks-XXXXXX";
    int fd = mkstemp(path);
    if (fd >= 0) unlink(path);
    pid_t pid = -1;
    int status = -1;
    for (int attempt = 0; attempt < 2; attempt++) { /* a second try only after a crash */
        fflush(stdout);
        fflush(stderr);
        pid = fork();
        if (pid == 0) {
            if (fd >= 0) dup2(fd, 2);
            _exit(__lsan_do_recoverable_leak_check() ? 3 : 0);
        }
        if (pid < 0 || waitpid(pid, &status, 0) != pid) break;
        if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
            if (fd >= 0) close(fd);
            return 0;
        }
        if (WIFEXITED(status) && WEXITSTATUS(status) == 3) break;
    }
    fprintf(stderr, "leak check: the single-thread check %s; the whole process is checked\n",
            pid < 0 ? "could not fork" : WIFEXITED(status) && WEXITSTATUS(status) == 3 ? "found leaks" : "failed");
    if (fd >= 0) copy_indented(fd);
    int leaked = __lsan_do_recoverable_leak_check();
    if (!leaked) fprintf(stderr, "leak check: the whole process has no leak\n");
    return leaked;
}
#endif

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
#ifdef TC_LEAK_CHECK_HERE
    if (leak_check()) {
        fprintf(stderr, "FAIL leak check\n");
        failed++;
    }
#endif
    printf("%d passed, %d failed\n", passed, failed);
#ifdef TC_LEAK_CHECK_HERE
    fflush(stdout); /* _exit: LeakSanitizer's own check at exit is not run again */
    _exit(failed ? 1 : 0);
#endif
    return failed ? 1 : 0;
}
