/* leakcheck.h — a sanitizer build's leak check at exit, made safe beside other threads (the image
 * libraries' pools): LeakSanitizer's scan run first in a forked child with one thread. */
#ifndef TC_CORE_LEAKCHECK_H
#define TC_CORE_LEAKCHECK_H

/* With AddressSanitizer: checks for leaks now, any report on stderr; nonzero when a leak was
 * found. Without it (no LeakSanitizer to ask): 0. */
int tc__leak_check(void);

/* The end of a program's main. With AddressSanitizer: the check above, then _exit with status,
 * or with 23 (LeakSanitizer's own exit code) on a leak, so that LeakSanitizer's check at exit,
 * the one that stops every thread, never runs. Without it: returns status, for main to return. */
int tc__leak_checked_exit(int status);

#endif
