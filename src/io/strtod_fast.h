/* strtod_fast.h — decimal text to double, equal to the C library's strtod bit for bit, fast on
 * the common cases (Clinger 1990, Eisel–Lemire as in Lemire 2021), libc strtod where undecided. */
#ifndef TC_IO_STRTOD_FAST_H
#define TC_IO_STRTOD_FAST_H

#include <stddef.h>

/* Reads one number in JSON's strict grammar, -?(0|[1-9][0-9]*)(\.[0-9]+)?([eE][+-]?[0-9]+)?,
 * at the start of s[0..len) (s need not be NUL-terminated) into *out, exactly what strtod
 * gives for that text (an infinity on overflow, zero or a subnormal on underflow, -0.0 for
 * "-0"). Returns the number's length in bytes, or 0 when s does not start with such a
 * number (or, for a number of over 127 characters, memory for strtod's copy ran out).
 * The bytes after the number are not looked at: "12x" reads 12 (length 2). */
size_t tc_strtod_fast(const char *s, size_t len, double *out);

/* Test hook: how many calls of this thread have gone to libc strtod (the cases the fast
 * algorithms cannot decide). */
unsigned long tc__strtod_fallbacks(void);

#endif
