/* numfmt.h — exact text of a double as a JSON number: the first of %.15g, %.16g,
 * %.17g that reads back (strtod) to the same bits. Used by every number writer. */
#ifndef TC_IO_NUMFMT_H
#define TC_IO_NUMFMT_H

#include <stddef.h>

/* Bytes tc_fmt_double may write, NUL included (it needs at most 25). */
#define TC_FMT_DOUBLE_SIZE 32

/* Writes x into out as a NUL-terminated JSON number and returns its length.
 * The text is byte for byte what the cascade
 *     for p in 15, 16, 17: snprintf("%.*g", p, x); keep it if strtod gives x back
 * produces in the "C" locale, so -0.0 gives "-0", 0.1 gives "0.1", 1e300 gives
 * "1e+300". Never writes "inf", "nan", ".5" or "5.": a non-finite x (which
 * callers should not pass) gives "null". Thread-safe; allocates nothing. */
size_t tc_fmt_double(char out[TC_FMT_DOUBLE_SIZE], double x);

#endif
