/* reader.h — the JSON reader under the request parser (request*.c): JSON paths built
 * while descending, findings counted as shape (HTTP 400) or value (422) errors, typed reads. */
#ifndef TC_IO_READER_H
#define TC_IO_READER_H

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cJSON.h>

#include "io/request.h"

#if defined(__GNUC__)
#define PRINTF_LIKE(f, a) __attribute__((format(printf, f, a)))
#else
#define PRINTF_LIKE(f, a)
#endif

/* ---- JSON paths ---- */

/* A JSON path built on the stack while descending. It is rendered only when a
 * finding is reported, so reading a clean request formats no strings. */
typedef struct tc__jpath {
    const struct tc__jpath *up; /* NULL at the top level */
    const char *key;        /* member name, or NULL for an array index */
    size_t index;
} tc__jpath;

static inline tc__jpath tc__jpath_key(const tc__jpath *up, const char *key) { return (tc__jpath){up, key, 0}; }
static inline tc__jpath tc__jpath_index(const tc__jpath *up, size_t i) { return (tc__jpath){up, NULL, i}; }

/* ---- the reader and its findings ---- */

/* A big top-level array read by the fast path (request_fast.c) instead of cJSON. */
typedef struct {
    const char *key;    /* the member's name (one of request_fast.c's fast_keys) */
    const cJSON *node;  /* its placeholder (an empty array) in the tree */
    size_t start, end;  /* its text: the original body's bytes [start, end) */
    size_t n;           /* entries */
    int d1, d2;         /* entry shape: a number (0, 0); [d1] numbers (d1, 0); d1 arrays of d2 (d1, d2) */
    double *data;       /* n * max(d1, 1) * max(d2, 1) numbers in text order (malloc'd) */
} tc__fast;

enum { TC__FAST_MAX = 8 };

/* A "data" string member of a top-level object value ({"dtype", "shape", "data"}: a typed
 * array), seen by the fast path's walk in text order. A taken one (plain bytes: no
 * backslash, no NUL) is "" in the skeleton and read from the body's bytes instead, so cJSON
 * neither scans nor copies the base64 (most of a typed body). */
typedef struct {
    size_t start, end;  /* the string's text with its quotes: the body's bytes [start, end) */
    const cJSON *node;  /* its member in the tree */
    int taken;
} tc__span;

enum { TC__SPAN_MAX = 16 };

/* The state of one tc_request_parse: the request being filled and what was found. */
typedef struct {
    tc_request *r;
    tc_diags *diags;     /* may be NULL: findings are then only counted */
    unsigned expect;     /* TC_REQ_MESH | TC_REQ_POINTS */
    long malformed;      /* shape errors (-> TC_REQ_MALFORMED) */
    long invalid;        /* value errors (-> TC_REQ_INVALID) */
    int nomem;           /* an allocation failed: stop reading */
    int nchan;           /* channels fixed by values[0]; 0 while unknown */
    int nverts_known;    /* vertices was an array: desc.nverts is its length */
    int quads;           /* the mesh is given as "quads": per-corner entries name quads */
    const char *json;    /* the body as given */
    tc__fast fast[TC__FAST_MAX]; /* the arrays the fast path read, nfast of them */
    int nfast;
    tc__span spans[TC__SPAN_MAX]; /* the "data" strings it saw, nspans of them */
    int nspans;
    tc_req_limits *limits; /* tc_request_parse_limited's, or NULL */
} tc__reader;

/* What a finding is, which decides the answer's status. */
typedef enum {
    TC__RD_SHAPE,  /* wrong JSON type or shape, missing field, bad syntax: HTTP 400 */
    TC__RD_VALUE,  /* well-formed but unacceptable value (count, channels, name, infinity): HTTP 422 */
    TC__RD_WARNING /* accepted, with a word about it */
} tc__rd_kind;

/* Records a finding at path p (counted in rd->malformed / rd->invalid for the errors). */
PRINTF_LIKE(4, 5) void tc__rd_report(tc__reader *rd, tc__rd_kind kind, const tc__jpath *p, const char *fmt, ...);
#define tc__rd_shape_error(rd, p, ...) tc__rd_report(rd, TC__RD_SHAPE, p, __VA_ARGS__)
#define tc__rd_value_error(rd, p, ...) tc__rd_report(rd, TC__RD_VALUE, p, __VA_ARGS__)
#define tc__rd_warning(rd, p, ...) tc__rd_report(rd, TC__RD_WARNING, p, __VA_ARGS__)

/* n zeroed elements owned by the request; NULL for n == 0 (absent arrays are NULL
 * in tc_mesh_desc). On failure sets rd->nomem and returns NULL. */
void *tc__rd_alloc(tc__reader *rd, size_t n, size_t size);
/* The test hook of tc_request__fail_alloc_after: 1 when this allocation must fail. */
int tc__rd_injected_failure(void);

/* ---- JSON values ---- */

int tc__json_is(const cJSON *v, int type);
/* "a number", "an array", ... for messages. */
const char *tc__json_kind(const cJSON *v);
size_t tc__json_count(const cJSON *a);
/* "a string", or "an array of 3" for arrays, whose length is usually the point. */
const char *tc__json_describe(const cJSON *v, char *buf, size_t cap);
/* Shortest of %.15g / %.17g that reads back as d, for messages. */
const char *tc__number_text(double d, char *buf, size_t cap);

/* Each reads v at path p into out: 0, or -1 after reporting (out untouched or partly set). */
int tc__rd_number(tc__reader *rd, const cJSON *v, const tc__jpath *p, double *out);
/* An index: a JSON number that is an integer within int32 (range against the mesh is
 * the core's check). */
int tc__rd_int(tc__reader *rd, const cJSON *v, const tc__jpath *p, int32_t *out);
/* An array of exactly n numbers (n indices), e.g. [x, y]; what names its parts for messages. */
int tc__rd_numbers(tc__reader *rd, const cJSON *v, const tc__jpath *p, int n, double *out, const char *what);
int tc__rd_ints(tc__reader *rd, const cJSON *v, const tc__jpath *p, int n, int32_t *out, const char *what);
int tc__rd_bool(tc__reader *rd, const cJSON *v, const tc__jpath *p, int *out);
/* v must be an array of at most max entries; its length goes to *n. */
int tc__rd_array(tc__reader *rd, const cJSON *v, const tc__jpath *p, const char *what, size_t max, size_t *n);
/* Per-vertex arrays must have one entry per vertex (when the vertices were readable). */
void tc__rd_per_vertex(tc__reader *rd, const tc__jpath *p, size_t n);

/* ---- channel data ---- */

/* One sample of C channels: a plain number (C == 1) or [z1..zC], into out[C]. */
int tc__rd_channels(tc__reader *rd, const cJSON *v, const tc__jpath *p, double *out);
/* A tangent datum with dim numbers per channel (what = "[gx, gy]"): either one
 * vector (only when C == 1) or an array of C vectors, into out[C][dim]. */
int tc__rd_channel_vectors(tc__reader *rd, const cJSON *v, const tc__jpath *p, int dim, const char *what,
                           double *out);

/* ---- the fast path for big arrays (request_fast.c) ---- */

/* Scans the top level of json for fast arrays into rd->fast. Returns the skeleton, the body
 * with each of their texts replaced by "[]" (*skel_len bytes), for cJSON to parse instead
 * (the caller frees it), or NULL when none was taken (parse json itself). */
char *tc__rd_fast_scan(tc__reader *rd, const char *json, size_t len, size_t *skel_len);
/* The body's offset of the skeleton's offset pos (pos never falls inside a "[]" or a taken
 * string's ""). */
size_t tc__rd_fast_origin(const tc__reader *rd, size_t pos);
/* f's numbers, handed to the request as one of its arrays (f keeps none), or NULL with
 * rd->nomem set (counted by tc_request__fail_alloc_after as an allocation). */
void *tc__rd_fast_take(tc__reader *rd, tc__fast *f);
/* Binds the scanned arrays and "data" strings to their members of root: 0, or -1 when the
 * tree does not hold the strings the walk saw (then parse the body itself). */
int tc__rd_fast_bind(tc__reader *rd, const cJSON *root);
/* The body's text of the "data" string v when it was taken (*len bytes, no quotes), else NULL:
 * read v->valuestring as usual. */
const char *tc__rd_fast_data(const tc__reader *rd, const cJSON *v, size_t *len);
void tc__rd_fast_free(tc__reader *rd);
/* The fast array whose placeholder is v, or NULL when v is read from the tree as usual. */
tc__fast *tc__rd_fast(tc__reader *rd, const cJSON *v);
/* The original text of f parsed by cJSON, for a reader that does not take f's shape: the
 * tree (cJSON_Delete it), or NULL with rd->nomem set. */
cJSON *tc__rd_fast_json(tc__reader *rd, const tc__fast *f);
/* tc__rd_array's limit for a fast array: 0, or -1 after the same "too many entries". */
int tc__rd_fast_entries(tc__reader *rd, const tc__fast *f, const tc__jpath *p, size_t max);

/* ---- objects ---- */

typedef void (*tc__field_fn)(tc__reader *rd, const cJSON *v, const tc__jpath *p);

typedef struct {
    const char *name;
    tc__field_fn parse;     /* NULL: accepted, read elsewhere (or by the caller) */
    unsigned role;
    const char *shape;  /* what is expected, for messages */
} tc__field;

int tc__field_index(const tc__field *fields, int nf, const char *name);
/* Sorts the members of obj into found[nf] by fields[] (and, with_opts, the
 * options into found[nf .. nf + tc_opt_count())): unknown names warn (with a "did you
 * mean"), a name given twice is a shape error. what describes obj for a type error. */
int tc__rd_sort_members(tc__reader *rd, const cJSON *obj, const tc__jpath *p, const tc__field *fields, int nf,
                        int with_opts, const cJSON **found, const char *what);
/* The same without the options. */
int tc__rd_members(tc__reader *rd, const cJSON *obj, const tc__jpath *p, const tc__field *fields, int nf,
                   const cJSON **found, const char *what);
/* A required integer member of an object entry (e.g. corner_values[2].triangle). */
void tc__rd_member_int(tc__reader *rd, const cJSON *v, const tc__jpath *obj, const char *name, int32_t *out);
/* The element an entry names: "triangle" on a mesh of triangles, "quad" on
 * one of quads (found[0] and found[1] hold the two members); the other name is
 * refused, since its index would mean something else. */
void tc__rd_member_elem(tc__reader *rd, const cJSON *const found[2], const tc__jpath *obj, int required,
                        int32_t *out);

#endif
