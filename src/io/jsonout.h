/* jsonout.h — the primitives every JSON writer of tocher shares: member keys,
 * arrays of exact numbers, and the method with the options it ran with. */
#ifndef TC_IO_JSONOUT_H
#define TC_IO_JSONOUT_H

#include <stdint.h>

#include "io/strbuf.h"
#include "tocher.h"

/* `sep` (e.g. "," or ",\n") unless b is empty or ends with '{', then "name":. */
void tc_json_key(tc_strbuf *b, const char *sep, const char *name);
/* [x0,x1,...] with every double exact. */
void tc_json_numbers(tc_strbuf *b, const double *x, int n);
/* A typed array {"dtype":"float64","shape":[...],"data":"<base64>"} of the
 * doubles x in C order, shape[0..ndim) (the request's typed-array format, io/typed.h). */
void tc_json_typed(tc_strbuf *b, const double *x, const size_t *shape, int ndim);
/* The same in three steps, for data appended in pieces: the frame up to the data's opening
 * quote, then tc_base64_append of each piece (each but the last a multiple of 3 bytes, so
 * that their texts join into the encoding of the whole), then the closing quote and brace. */
void tc_json_typed_open(tc_strbuf *b, const size_t *shape, int ndim);
void tc_json_typed_close(tc_strbuf *b);
void tc_json_ints(tc_strbuf *b, const int32_t *x, int n);
/* "method" and the options it reads (io/options.c, tc_method_reads), as
 * members of the object being written. */
void tc_json_options(tc_strbuf *b, const tc_options *o);

#endif
