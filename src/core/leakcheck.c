/* leakcheck.c — LeakSanitizer's check for the sanitizer builds of the programs (tocherd, tocher,
 * the unit tests), run where its tracer cannot crash; a no-op in any other build. */
#include "core/leakcheck.h"

#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/lsan_interface.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

/* Copies the file at fd (from its start) to stderr, each line indented. */
static void copy_indented(int fd) {
    FILE *f = fdopen(fd, "r");
    char line[512];
    if (!f) return;
    rewind(f);
    while (fgets(line, sizeof line, f)) fprintf(stderr, "  | %s", line);
    fclose(f);
}

/* LeakSanitizer's tracer stops and reads every thread; in CI it crashed ("Tracer caught
 * signal 11", google/sanitizers#1353) both at exit and with every thread idle, while the image
 * libraries' pools (OpenEXR's, OpenImageIO's, log4cplus's: as many threads as CPUs) were alive.
 * So the check runs first in a forked child, where the only thread is the one that forked. Its
 * roots are a subset of the whole process's (the other threads' stacks and TLS are not scanned),
 * so no leak there means none here: done. (The child's own thread is not in LeakSanitizer's
 * registry, so its roots are the globals.) A leak there may be held by another thread: its
 * report is shown, and the whole process is checked, which decides; a child that crashed is
 * tried once more first. */
int tc__leak_check(void) {
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

int tc__leak_checked_exit(int status) {
    int leaked = tc__leak_check();
    fflush(stdout);
    fflush(stderr);
    _exit(leaked ? 23 : status);
}

#else

int tc__leak_check(void) {
    return 0;
}

int tc__leak_checked_exit(int status) {
    return status;
}

#endif
