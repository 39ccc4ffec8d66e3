/* typed.c — the typed arrays of a request ({"dtype", "shape", "data"}): headers checked
 * with the JSON form's paths, data decoded from base64 at memory speed into the request's arrays. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/base64.h"
#include "io/typed.h"

static const char *const dtype_names[] = {"float64", "float32", "int32", "uint32"};
static const size_t dtype_sizes[] = {8, 4, 4, 4};

const char *tc_dtype_name(tc_dtype d) { return dtype_names[d]; }
size_t tc_dtype_size(tc_dtype d) { return dtype_sizes[d]; }

static const tc__field typed_fields[] = {
    {"dtype", NULL, 0, "\"float64\", \"float32\", \"int32\" or \"uint32\""},
    {"shape", NULL, 0, "[n, ...]"},
    {"data", NULL, 0, "base64"},
};
enum { TY_DTYPE, TY_SHAPE, TY_DATA, TY_NFIELDS };

int tc__is_typed(const cJSON *v) {
    if (!tc__json_is(v, cJSON_Object)) return 0;
    for (const cJSON *m = v->child; m; m = m->next)
        if (m->string && (!strcmp(m->string, "dtype") || !strcmp(m->string, "shape") || !strcmp(m->string, "data")))
            return 1;
    return 0;
}

const char *tc__typed_shape_text(const tc__typed *t, char *buf, size_t cap) {
    size_t n = 0;
    buf[0] = '\0';
    for (int k = 0; k < t->ndim && n < cap; k++) {
        int w = snprintf(buf + n, cap - n, "%s%zu", k ? ", " : "[", t->shape[k]);
        if (w > 0) n += (size_t)w;
    }
    if (n < cap) snprintf(buf + n, cap - n, "%s", t->ndim ? "]" : "[]");
    return buf;
}

/* ---- the header ------------------------------------------------------------------ */

static int read_dtype(tc__reader *rd, const cJSON *v, const tc__jpath *p, int want_index, tc__typed *t) {
    if (!v || !tc__json_is(v, cJSON_String) || !v->valuestring) {
        tc__rd_shape_error(rd, p, "dtype: expected \"float64\", \"float32\", \"int32\" or \"uint32\", got %s",
                           v ? tc__json_kind(v) : "nothing (a typed array needs dtype, shape and data)");
        return -1;
    }
    int d = -1;
    for (int k = 0; k < 4; k++)
        if (!strcmp(v->valuestring, dtype_names[k])) d = k;
    if (d < 0) {
        tc__rd_shape_error(rd, p, "dtype '%.40s' unknown: expected float64, float32, int32 or uint32", v->valuestring);
        return -1;
    }
    if (want_index && d != TC_DT_INT32 && d != TC_DT_UINT32) {
        tc__rd_shape_error(rd, p, "dtype %s: expected int32 or uint32 (vertex indices)", dtype_names[d]);
        return -1;
    }
    t->dtype = (tc_dtype)d;
    return 0;
}

/* One length of the shape: an integer 0 .. 2^53. */
static int shape_dim(const cJSON *e, size_t *out) {
    if (!tc__json_is(e, cJSON_Number)) return -1;
    double d = e->valuedouble;
    if (!(d >= 0 && d <= 9007199254740992.0) || d != floor(d)) return -1;
    *out = (size_t)d;
    return 0;
}

static int read_shape(tc__reader *rd, const cJSON *v, const tc__jpath *p, tc__typed *t) {
    size_t n = v && tc__json_is(v, cJSON_Array) ? tc__json_count(v) : 0;
    if (n < 1 || n > TC_TYPED_MAXDIM) {
        tc__rd_shape_error(rd, p, "shape: expected an array of 1 to %d lengths [n, ...], got %s", TC_TYPED_MAXDIM,
                           v ? tc__json_kind(v) : "nothing (a typed array needs dtype, shape and data)");
        return -1;
    }
    t->ndim = (int)n;
    t->count = 1;
    int k = 0, overflow = 0;
    for (const cJSON *e = v->child; e; e = e->next, k++) {
        if (shape_dim(e, &t->shape[k])) {
            tc__rd_shape_error(rd, p, "shape[%d]: expected a length (an integer >= 0), got %s", k, tc__json_kind(e));
            return -1;
        }
        if (t->shape[k] && t->count > SIZE_MAX / 8 / t->shape[k]) overflow = 1;
        else t->count *= t->shape[k];
    }
    if (overflow) {
        tc__rd_value_error(rd, p, "shape: too many elements");
        return -1;
    }
    return 0;
}

static int read_data(tc__reader *rd, const cJSON *v, const tc__jpath *p, tc__typed *t) {
    if (!v || !tc__json_is(v, cJSON_String) || !v->valuestring) {
        tc__rd_shape_error(rd, p, "data: expected a base64 string, got %s",
                           v ? tc__json_kind(v) : "nothing (a typed array needs dtype, shape and data)");
        return -1;
    }
    t->data = tc__rd_fast_data(rd, v, &t->data_len); /* the body's bytes, when the fast path took them */
    if (!t->data) t->data = v->valuestring, t->data_len = strlen(v->valuestring);
    return 0;
}

/* The data must hold count elements: checked after the field's shape checks, whose
 * message says more, and before decoding. 0, or -1 after reporting at p. */
static int check_length(tc__reader *rd, const tc__typed *t, const tc__jpath *p) {
    char shape[96];
    size_t want = t->count * tc_dtype_size(t->dtype), have = tc_base64_decoded_len(t->data, t->data_len);
    if (t->data_len % 4) {
        tc__rd_shape_error(rd, p, "data: bad base64: %zu characters, not a multiple of 4 (padding missing?)",
                           t->data_len);
        return -1;
    }
    if (have != want) {
        tc__rd_shape_error(rd, p, "data: %zu bytes, expected %zu (shape %s of %s, %zu bytes each)", have, want,
                           tc__typed_shape_text(t, shape, sizeof shape), dtype_names[t->dtype],
                           tc_dtype_size(t->dtype));
        return -1;
    }
    return 0;
}

int tc__rd_typed(tc__reader *rd, const cJSON *v, const tc__jpath *p, int want_index, tc__typed *t) {
    const cJSON *f[TY_NFIELDS];
    memset(t, 0, sizeof *t);
    if (tc__rd_members(rd, v, p, typed_fields, TY_NFIELDS, f,
                       "a typed array {\"dtype\": ..., \"shape\": [n, ...], \"data\": base64}"))
        return -1;
    if (read_dtype(rd, f[TY_DTYPE], p, want_index, t) || read_shape(rd, f[TY_SHAPE], p, t)) return -1;
    return read_data(rd, f[TY_DATA], p, t);
}

int tc__typed_dims(tc__reader *rd, const tc__typed *t, const tc__jpath *p, int ndim, const size_t *dims,
                   const char *expected) {
    int ok = t->ndim == ndim;
    for (int k = 0; ok && k < ndim; k++) ok = !dims[k] || dims[k] == t->shape[k];
    if (ok) return 0;
    char shape[96];
    tc__rd_shape_error(rd, p, "shape %s: expected %s", tc__typed_shape_text(t, shape, sizeof shape), expected);
    return -1;
}

/* ---- the data -------------------------------------------------------------------- */

/* Decodes t's data into out (count * size bytes), little-endian to the host's order. */
static int decode(tc__reader *rd, const tc__typed *t, const tc__jpath *p, void *out) {
    size_t bad;
    const char *why;
    if (check_length(rd, t, p)) return -1;
    if (tc_base64_decode(t->data, t->data_len, out, &bad, &why)) {
        tc__rd_shape_error(rd, p, "data: bad base64 at character %zu: %s", bad, why);
        return -1;
    }
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
    size_t size = tc_dtype_size(t->dtype);
    unsigned char *b = out;
    for (size_t i = 0; i < t->count; i++, b += size)
        for (size_t k = 0; k < size / 2; k++) {
            unsigned char c = b[k];
            b[k] = b[size - 1 - k], b[size - 1 - k] = c;
        }
#endif
    return 0;
}

/* Reports at element i's path (p[i0][i1]...) when a conversion refuses it. */
PRINTF_LIKE(6, 7)
static void element_error(tc__reader *rd, tc__rd_kind kind, const tc__typed *t, const tc__jpath *p, size_t i,
                          const char *fmt, ...);

static void element_error(tc__reader *rd, tc__rd_kind kind, const tc__typed *t, const tc__jpath *p, size_t i,
                          const char *fmt, ...) {
    tc__jpath chain[TC_TYPED_MAXDIM];
    size_t idx[TC_TYPED_MAXDIM];
    for (int k = t->ndim - 1; k >= 0; k--) idx[k] = i % t->shape[k], i /= t->shape[k];
    const tc__jpath *up = p;
    for (int k = 0; k < t->ndim; k++) chain[k] = tc__jpath_index(up, idx[k]), up = &chain[k];
    char msg[160];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    tc__rd_report(rd, kind, up, "%s", msg);
}

/* Malloc'd room for t's decoded bytes (rd->nomem on failure). */
static void *scratch(tc__reader *rd, const tc__typed *t) {
    void *b = tc__rd_injected_failure() ? NULL : malloc(t->count ? t->count * tc_dtype_size(t->dtype) : 1);
    if (!b) rd->nomem = 1;
    return b;
}

/* Widens the decoded elements (float32, int32, uint32) to doubles, exactly. */
static void widen(const tc__typed *t, const void *in, double *out) {
    for (size_t i = 0; i < t->count; i++) {
        if (t->dtype == TC_DT_FLOAT32) {
            float f;
            memcpy(&f, (const char *)in + 4 * i, 4);
            out[i] = (double)f;
        } else if (t->dtype == TC_DT_INT32) {
            int32_t k;
            memcpy(&k, (const char *)in + 4 * i, 4);
            out[i] = (double)k;
        } else {
            uint32_t u;
            memcpy(&u, (const char *)in + 4 * i, 4);
            out[i] = (double)u;
        }
    }
}

int tc__typed_doubles(tc__reader *rd, const tc__typed *t, const tc__jpath *p, double *out) {
    if (!t->count) return check_length(rd, t, p); /* out may be NULL */
    if (t->dtype == TC_DT_FLOAT64) {
        if (decode(rd, t, p, out)) return -1;
    } else {
        void *b = scratch(rd, t);
        if (!b) return -1;
        int rc = decode(rd, t, p, b);
        if (!rc) widen(t, b, out);
        free(b);
        if (rc) return -1;
    }
    int bad = 0;
    for (size_t i = 0; i < t->count; i++)
        if (!isfinite(out[i])) {
            element_error(rd, TC__RD_VALUE, t, p, i, "%s in a typed array: numbers must be finite",
                          isnan(out[i]) ? "NaN" : "infinity");
            bad = 1;
        }
    return bad ? -1 : 0;
}

int tc__typed_indices(tc__reader *rd, const tc__typed *t, const tc__jpath *p, int32_t *out) {
    if (!t->count) return check_length(rd, t, p); /* out may be NULL */
    if (decode(rd, t, p, out)) return -1;
    if (t->dtype != TC_DT_UINT32) return 0; /* int32 as is: the core checks the range */
    int bad = 0;
    for (size_t i = 0; i < t->count; i++)
        if (out[i] < 0) { /* the uint32 was above INT32_MAX */
            element_error(rd, TC__RD_SHAPE, t, p, i, "must be an integer (a 32-bit index), got %u (uint32)",
                          (unsigned)(uint32_t)out[i]);
            bad = 1;
        }
    return bad ? -1 : 0;
}

/* ---- typed arrays inside per-entry fields, as JSON ------------------------------- */

/* Nested arrays of x[*k ...] following t's shape from dimension dim; NULL if out of memory. */
static cJSON *nest(const tc__typed *t, const double *x, int dim, size_t *k) {
    cJSON *a = cJSON_CreateArray();
    for (size_t i = 0; a && i < t->shape[dim]; i++) {
        cJSON *e = dim + 1 < t->ndim ? nest(t, x, dim + 1, k) : cJSON_CreateNumber(x[(*k)++]);
        if (!e || !cJSON_AddItemToArray(a, e)) {
            cJSON_Delete(e);
            cJSON_Delete(a);
            return NULL;
        }
    }
    return a;
}

/* The typed array v as JSON numbers, or NULL after reporting. */
static cJSON *as_json(tc__reader *rd, const cJSON *v, const tc__jpath *p, int want_index) {
    tc__typed t;
    if (tc__rd_typed(rd, v, p, want_index, &t)) return NULL;
    double *x = malloc((t.count ? t.count : 1) * sizeof *x);
    int32_t *ix = want_index ? malloc((t.count ? t.count : 1) * sizeof *ix) : NULL;
    cJSON *a = NULL;
    int rc = !x || (want_index && !ix) ? (rd->nomem = 1, -1)
             : want_index              ? tc__typed_indices(rd, &t, p, ix)
                                       : tc__typed_doubles(rd, &t, p, x);
    for (size_t i = 0; !rc && want_index && i < t.count; i++) x[i] = ix[i];
    size_t k = 0;
    if (!rc && !(a = nest(&t, x, 0, &k))) rd->nomem = 1;
    free(x), free(ix);
    return a;
}

/* Walks node (at path p), replacing typed arrays by JSON arrays; index: the
 * numbers below are vertex indices. */
static void expand_in(tc__reader *rd, cJSON *node, const tc__jpath *p, int index) {
    size_t i = 0;
    for (cJSON *c = node->child, *next; c && !rd->nomem; c = next, i++) {
        next = c->next;
        tc__jpath pc = tc__json_is(node, cJSON_Object) ? tc__jpath_key(p, c->string ? c->string : "")
                                                        : tc__jpath_index(p, i);
        int ci = index || (c->string && !strcmp(c->string, "edge"));
        if (!tc__is_typed(c)) {
            if (tc__json_is(c, cJSON_Array) || tc__json_is(c, cJSON_Object)) expand_in(rd, c, &pc, ci);
            continue;
        }
        cJSON *a = as_json(rd, c, &pc, ci);
        if (!a) continue; /* left as is on error: reported above */
        if (c->string) cJSON_ReplaceItemInObjectCaseSensitive(node, c->string, a); /* keeps the key */
        else cJSON_ReplaceItemViaPointer(node, c, a);
    }
}

void tc__rd_expand_nested(tc__reader *rd, cJSON *root) {
    static const char *const nested[] = {"corner_values", "corner_gradients", "midpoints", "discontinuities"};
    if (!tc__json_is(root, cJSON_Object)) return;
    for (cJSON *m = root->child; m; m = m->next)
        for (size_t k = 0; k < sizeof nested / sizeof nested[0]; k++)
            if (m->string && !strcmp(m->string, nested[k]) && !tc__is_typed(m)) {
                tc__jpath p = tc__jpath_key(NULL, m->string);
                expand_in(rd, m, &p, k == 3);
            }
}
