/* textpar.h — an answer's big array printed in parts on several threads and joined
 * in order: the ordinates' JSON numbers and base64 text at more than one core's speed. */
#ifndef TC_IO_TEXTPAR_H
#define TC_IO_TEXTPAR_H

#include <stddef.h>
#include <stdint.h>

#include "io/strbuf.h"

/* Appends to b the text of items [lo, hi) of ctx's array. The text of [0, n) must be
 * the texts of any split of it into contiguous ranges, concatenated in order: an item's
 * text depends on the item alone (and on whether it is item 0, for a separator). */
typedef void (*tc__text_fn)(tc_strbuf *b, void *ctx, int32_t lo, int32_t hi);

/* Appends fn's text of items [0, n) to b, printed in parts on up to `threads` threads
 * (parts of at least min_part items; threads <= 1: on the caller's, as fn(b, ctx, 0, n)).
 * per_item bounds one item's text, so a part reserves its room once. The bytes are the
 * same for any number of threads; an allocation failure sets b->oom. */
void tc__text_parallel(tc_strbuf *b, int32_t n, int threads, int32_t min_part, size_t per_item,
                       tc__text_fn fn, void *ctx);

/* tc_base64_append(b, in, bytes), the encoding done in parts on up to `threads` threads
 * (each part a whole number of 3-byte groups, written straight to its place in b). */
void tc__base64_append_parallel(tc_strbuf *b, const void *in, size_t bytes, int threads);

#endif
