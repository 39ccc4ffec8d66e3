/* numfmt_cascade.h — the pre-Schubfach tc_fmt_double (bench/perf/numfmt_cascade.c), the
 * baseline `make bench` times the new one against; the library does not use it. */
#ifndef TC_BENCH_NUMFMT_CASCADE_H
#define TC_BENCH_NUMFMT_CASCADE_H

#include "io/numfmt.h"

/* Same contract as tc_fmt_double had: the first of %.15g, %.16g, %.17g that round-trips. */
size_t tc_fmt_double_cascade(char out[TC_FMT_DOUBLE_SIZE], double x);

#endif
