/* typed.h — typed arrays in requests: {"dtype", "shape", "data": base64} objects read,
 * checked against the shape a field expects, and converted to the request's doubles and indices. */
#ifndef TC_IO_TYPED_H
#define TC_IO_TYPED_H

#include <stddef.h>
#include <stdint.h>

#include "io/reader.h"

enum { TC_TYPED_MAXDIM = 4 };

typedef enum { TC_DT_FLOAT64, TC_DT_FLOAT32, TC_DT_INT32, TC_DT_UINT32 } tc_dtype;

/* "float64", ... ; the element size in bytes. */
const char *tc_dtype_name(tc_dtype d);
size_t tc_dtype_size(tc_dtype d);

/* A typed array whose header was read: the data is still base64 text (in the cJSON
 * tree), decoded only by the conversions, straight into the request's array when
 * the dtype is the destination's (float64 -> doubles, int32 -> indices).
 * The conversions check tc_base64_decoded_len(data, data_len) == count * size first. */
typedef struct {
    tc_dtype dtype;
    int ndim;
    size_t shape[TC_TYPED_MAXDIM];
    size_t count;     /* the product of shape */
    const char *data; /* base64 text */
    size_t data_len;
} tc__typed;

/* v is an object with a "dtype", "shape" or "data" member: meant as a typed array. */
int tc__is_typed(const cJSON *v);
/* Reads the header of the typed array v at path p: dtype (index fields, want_index,
 * take int32 or uint32; others every dtype), shape (1 to 4 dimensions) and data (a
 * string; its length is checked by the conversions, after the field's shape checks).
 * 0, or -1 after reporting at p (HTTP 400). */
int tc__rd_typed(tc__reader *rd, const cJSON *v, const tc__jpath *p, int want_index, tc__typed *t);
/* The shape must be [dims[0], ..., dims[ndim-1]] where a 0 in dims matches any length;
 * otherwise reports "shape [4, 3]: expected <expected>" at p and returns -1. */
int tc__typed_dims(tc__reader *rd, const tc__typed *t, const tc__jpath *p, int ndim, const size_t *dims,
                   const char *expected);
/* Writes "[4, 3]" (t's shape) to buf. */
const char *tc__typed_shape_text(const tc__typed *t, char *buf, size_t cap);

/* Decodes the count elements into out as doubles (exactly: every dtype converts
 * exactly); out may be NULL when count is 0. A data length that is not count
 * elements, or bad base64, is refused at p (400); NaN and infinities are refused (HTTP 422) at the element's path,
 * p[i][j]..., and bad base64 at p (400). 0, or -1 after reporting. */
int tc__typed_doubles(tc__reader *rd, const tc__typed *t, const tc__jpath *p, double *out);
/* The same into 32-bit indices (the dtype is int32 or uint32): a uint32 above
 * INT32_MAX is refused at its path, as the JSON form refuses it. Range against
 * the mesh stays the core's check. */
int tc__typed_indices(tc__reader *rd, const tc__typed *t, const tc__jpath *p, int32_t *out);

/* Replaces every typed array inside the small per-entry fields (corner_values,
 * corner_gradients, midpoints, discontinuities) of the request root by the
 * equivalent JSON array, so their readers (and messages) stay those of the JSON
 * form; "edge" and discontinuity polylines take indices. The big arrays are
 * decoded by their own readers without a tree. */
void tc__rd_expand_nested(tc__reader *rd, cJSON *root);

#endif
