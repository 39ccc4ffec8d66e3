/* numfmt.h — exact text of a double as a JSON number: the shortest decimal that reads back
 * (strtod) to the same bits (Schubfach), laid out as %g would. Used by every number writer. */
#ifndef TC_IO_NUMFMT_H
#define TC_IO_NUMFMT_H

#include <stddef.h>

/* Bytes tc_fmt_double may write, NUL included (the text needs at most 25; bytes after
 * the NUL may be overwritten too, up to this size). */
#define TC_FMT_DOUBLE_SIZE 32

/* Writes x into out as a NUL-terminated JSON number and returns its length.
 * The digits are the fewest significant digits that strtod reads back as x and,
 * among those, the nearest to x (ties to an even last digit): Ryu's and
 * Schubfach's "shortest", Python's repr. They are laid out as snprintf("%.*g", P)
 * would with P = max(15, number of digits), in the "C" locale: -0.0 gives "-0",
 * 0.1 gives "0.1", 1e15 gives "1e+15", 1e300 gives "1e+300", 5e-324 gives "5e-324".
 * For every normal double but a few at the bottom of a binade this is the text of
 * the first of %.15g, %.16g, %.17g that round-trips (what this function printed
 * before issue 17). Never writes "inf", "nan", ".5" or "5.": a non-finite x (which
 * callers should not pass) gives "null". Thread-safe; allocates nothing. */
size_t tc_fmt_double(char out[TC_FMT_DOUBLE_SIZE], double x);

#endif
