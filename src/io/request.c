/* request.c — the JSON request reader: cJSON tree -> tc_mesh_desc, tc_options, points.
 * Walks every array once (->child / ->next) and reports each finding with its JSON path. */
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cJSON.h>

#include "image/image.h"
#include "io/options.h"
#include "io/request.h"

#if defined(__GNUC__)
#define PRINTF_LIKE(f, a) __attribute__((format(printf, f, a)))
#else
#define PRINTF_LIKE(f, a)
#endif

/* ---- JSON paths -------------------------------------------------------------- */

/* A JSON path built on the stack while descending. It is rendered only when a
 * finding is reported, so reading a clean request formats no strings. */
typedef struct jpath {
    const struct jpath *up; /* NULL at the top level */
    const char *key;        /* member name, or NULL for an array index */
    size_t index;
} jpath;

static jpath key_path(const jpath *up, const char *key) { return (jpath){up, key, 0}; }
static jpath index_path(const jpath *up, size_t i) { return (jpath){up, NULL, i}; }

/* Writes "a.b[3][1]" into buf (truncated to cap); returns the length written. */
static size_t render_path(const jpath *p, char *buf, size_t cap) {
    if (!p) {
        buf[0] = '\0';
        return 0;
    }
    size_t n = render_path(p->up, buf, cap);
    if (n + 1 >= cap) return n;
    int w = p->key ? snprintf(buf + n, cap - n, "%s%s", p->up ? "." : "", p->key)
                   : snprintf(buf + n, cap - n, "[%zu]", p->index);
    if (w < 0) return n;
    n += (size_t)w;
    return n < cap ? n : cap - 1;
}

/* ---- the reader and its findings ---------------------------------------------- */

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
} reader;

static void vreport(reader *rd, tc_severity sev, const jpath *p, const char *fmt, va_list ap) {
    if (!rd->diags) return;
    if (rd->diags->count >= TC_DIAGS_KEEP) { /* only counted from here on: skip the formatting */
        tc_diags_add(rd->diags, sev, NULL, "%s", "");
        return;
    }
    char path[sizeof ((tc_diag *)0)->path];
    char msg[sizeof ((tc_diag *)0)->message];
    render_path(p, path, sizeof path);
    vsnprintf(msg, sizeof msg, fmt, ap);
    tc_diags_add(rd->diags, sev, path, "%s", msg);
}

/* Wrong JSON type or shape, missing field, bad syntax: HTTP 400. */
PRINTF_LIKE(3, 4) static void shape_error(reader *rd, const jpath *p, const char *fmt, ...) {
    va_list ap;
    rd->malformed++;
    va_start(ap, fmt);
    vreport(rd, TC_SEV_ERROR, p, fmt, ap);
    va_end(ap);
}

/* Well-formed but unacceptable value (count, channels, name, infinity): HTTP 422. */
PRINTF_LIKE(3, 4) static void value_error(reader *rd, const jpath *p, const char *fmt, ...) {
    va_list ap;
    rd->invalid++;
    va_start(ap, fmt);
    vreport(rd, TC_SEV_ERROR, p, fmt, ap);
    va_end(ap);
}

PRINTF_LIKE(3, 4) static void warning(reader *rd, const jpath *p, const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    vreport(rd, TC_SEV_WARNING, p, fmt, ap);
    va_end(ap);
}

/* ---- allocation: every array belongs to the request --------------------------- */

static _Thread_local long alloc_countdown; /* test hook; 0 = never fail */

void tc_request__fail_alloc_after(long n) { alloc_countdown = n; }

static int injected_failure(void) {
    return alloc_countdown > 0 && --alloc_countdown == 0;
}

/* n zeroed elements owned by the request; NULL for n == 0 (absent arrays are NULL
 * in tc_mesh_desc). On failure sets rd->nomem and returns NULL. */
static void *own_alloc(reader *rd, size_t n, size_t size) {
    tc_request *r = rd->r;
    if (n == 0) return NULL;
    void *p = NULL;
    if (r->nowned_ < TC_REQ_OWNED_MAX && !injected_failure()) p = calloc(n, size);
    if (!p) {
        rd->nomem = 1;
        return NULL;
    }
    r->owned_[r->nowned_++] = p;
    return p;
}

/* ---- JSON values ------------------------------------------------------------- */

static int is_type(const cJSON *v, int type) { return (v->type & 0xFF) == type; }

static const char *kind_of(const cJSON *v) {
    switch (v->type & 0xFF) {
    case cJSON_False:
    case cJSON_True: return "a boolean";
    case cJSON_NULL: return "null";
    case cJSON_Number: return "a number";
    case cJSON_String: return "a string";
    case cJSON_Array: return "an array";
    case cJSON_Object: return "an object";
    default: return "an unknown value";
    }
}

static size_t count_items(const cJSON *a) {
    size_t n = 0;
    for (const cJSON *e = a->child; e; e = e->next) n++;
    return n;
}

/* "a string", or "an array of 3" for arrays, whose length is usually the point. */
static const char *describe(const cJSON *v, char *buf, size_t cap) {
    if (!is_type(v, cJSON_Array)) return kind_of(v);
    snprintf(buf, cap, "an array of %zu", count_items(v));
    return buf;
}

/* Shortest of %.15g / %.17g that reads back as d, for messages. */
static const char *format_number(double d, char *buf, size_t cap) {
    snprintf(buf, cap, "%.15g", d);
    if (strtod(buf, NULL) != d) snprintf(buf, cap, "%.17g", d);
    return buf;
}

static int read_number(reader *rd, const cJSON *v, const jpath *p, double *out) {
    if (!is_type(v, cJSON_Number)) {
        shape_error(rd, p, "expected a number, got %s", kind_of(v));
        return -1;
    }
    if (!isfinite(v->valuedouble)) { /* cJSON reads 1e999 as inf */
        value_error(rd, p, "number is not finite (beyond the range of a double)");
        return -1;
    }
    *out = v->valuedouble;
    return 0;
}

/* An index: a JSON number that is an integer within int32. Range against the
 * mesh is the core's check (tc_mesh_new), not repeated here. */
static int read_int(reader *rd, const cJSON *v, const jpath *p, int32_t *out) {
    double d;
    char num[32];
    if (read_number(rd, v, p, &d)) return -1;
    if (d != floor(d) || d < INT32_MIN || d > INT32_MAX) {
        shape_error(rd, p, "must be an integer (a 32-bit index), got %s",
                    format_number(d, num, sizeof num));
        return -1;
    }
    *out = (int32_t)d;
    return 0;
}

/* An array of exactly n numbers, e.g. [x, y]; what names its parts for messages. */
static int read_numbers(reader *rd, const cJSON *v, const jpath *p, int n, double *out,
                        const char *what) {
    char buf[48];
    if (!is_type(v, cJSON_Array) || count_items(v) != (size_t)n) {
        shape_error(rd, p, "expected an array of %d numbers %s, got %s", n, what,
                    describe(v, buf, sizeof buf));
        return -1;
    }
    int bad = 0, k = 0;
    for (const cJSON *e = v->child; e; e = e->next, k++) {
        jpath pk = index_path(p, (size_t)k);
        bad |= read_number(rd, e, &pk, &out[k]) != 0;
    }
    return bad ? -1 : 0;
}

/* An array of exactly n indices, e.g. [i, j, k]. */
static int read_ints(reader *rd, const cJSON *v, const jpath *p, int n, int32_t *out,
                     const char *what) {
    char buf[48];
    if (!is_type(v, cJSON_Array) || count_items(v) != (size_t)n) {
        shape_error(rd, p, "expected an array of %d vertex indices %s, got %s", n, what,
                    describe(v, buf, sizeof buf));
        return -1;
    }
    int bad = 0, k = 0;
    for (const cJSON *e = v->child; e; e = e->next, k++) {
        jpath pk = index_path(p, (size_t)k);
        bad |= read_int(rd, e, &pk, &out[k]) != 0;
    }
    return bad ? -1 : 0;
}

/* v must be an array of at most max entries; its length goes to *n. */
static int open_array(reader *rd, const cJSON *v, const jpath *p, const char *what, size_t max,
                      size_t *n) {
    if (!is_type(v, cJSON_Array)) {
        shape_error(rd, p, "expected %s, got %s", what, kind_of(v));
        return -1;
    }
    *n = count_items(v);
    if (*n > max) {
        value_error(rd, p, "too many entries (%zu, at most %zu)", *n, max);
        return -1;
    }
    return 0;
}

/* Per-vertex arrays must have one entry per vertex (when the vertices were readable). */
static void check_per_vertex(reader *rd, const jpath *p, size_t n) {
    if (rd->nverts_known && n != (size_t)rd->r->desc.nverts)
        value_error(rd, p, "%s has %zu entries, expected %d (one per vertex)", p->key, n,
                    (int)rd->r->desc.nverts);
}

/* ---- channel data --------------------------------------------------------------- */

/* One sample of C channels: a plain number (C == 1) or [z1..zC], into out[C]. */
static int read_channels(reader *rd, const cJSON *v, const jpath *p, double *out) {
    int C = rd->nchan;
    if (is_type(v, cJSON_Number)) {
        if (C != 1) {
            value_error(rd, p, "1 channel, expected %d (as values[0])", C);
            return -1;
        }
        return read_number(rd, v, p, out);
    }
    if (!is_type(v, cJSON_Array)) {
        shape_error(rd, p, "expected a number or an array of %d channel values, got %s", C,
                    kind_of(v));
        return -1;
    }
    size_t k = count_items(v);
    if (k != (size_t)C) {
        value_error(rd, p, "%zu channel%s, expected %d (as values[0])", k, k == 1 ? "" : "s", C);
        return -1;
    }
    int bad = 0;
    size_t j = 0;
    for (const cJSON *e = v->child; e; e = e->next, j++) {
        jpath pj = index_path(p, j);
        bad |= read_number(rd, e, &pj, &out[j]) != 0;
    }
    return bad ? -1 : 0;
}

/* A tangent datum with dim numbers per channel (what = "[gx, gy]"): either one
 * vector (only when C == 1) or an array of C vectors, into out[C][dim]. */
static int read_channel_vectors(reader *rd, const cJSON *v, const jpath *p, int dim,
                                const char *what, double *out) {
    int C = rd->nchan;
    if (!is_type(v, cJSON_Array) || !v->child) {
        shape_error(rd, p, "expected %s or an array of %d of them (one per channel), got %s",
                    what, C, is_type(v, cJSON_Array) ? "an empty array" : kind_of(v));
        return -1;
    }
    if (!is_type(v->child, cJSON_Array)) { /* the single-vector form */
        if (C != 1 && is_type(v->child, cJSON_Number)) {
            value_error(rd, p, "a single %s is 1 channel, expected %d (as values[0])", what, C);
            return -1;
        }
        return read_numbers(rd, v, p, dim, out, what);
    }
    size_t k = count_items(v);
    if (k != (size_t)C) {
        value_error(rd, p, "%zu channel%s, expected %d (as values[0])", k, k == 1 ? "" : "s", C);
        return -1;
    }
    int bad = 0;
    size_t j = 0;
    for (const cJSON *e = v->child; e; e = e->next, j++) {
        jpath pj = index_path(p, j);
        bad |= read_numbers(rd, e, &pj, dim, out + j * (size_t)dim, what) != 0;
    }
    return bad ? -1 : 0;
}

/* ---- objects ------------------------------------------------------------------- */

typedef void (*field_fn)(reader *rd, const cJSON *v, const jpath *p);

/* Roles of top-level fields, for the presence rules. */
enum {
    ROLE_MESH = 1,      /* vertices, triangles, values: all or none */
    ROLE_MESH_DATA = 2, /* meaningless without a mesh: makes the mesh required */
    ROLE_POINTS = 4,    /* required when TC_REQ_POINTS is expected */
    ROLE_VIEWPORT = 8,  /* required when TC_REQ_VIEWPORT is expected */
    ROLE_REFERENCE = 16 /* required when TC_REQ_REFERENCE is expected */
};

typedef struct {
    const char *name;
    field_fn parse;     /* NULL: accepted, read elsewhere (or by the caller) */
    unsigned role;
    const char *shape;  /* what is expected, for messages */
} field;

static int field_index(const field *fields, int nf, const char *name) {
    for (int i = 0; i < nf; i++)
        if (strcmp(fields[i].name, name) == 0) return i;
    return -1;
}

/* Levenshtein distance, case-insensitive, for "did you mean"; large for long names. */
static int edit_distance(const char *a, const char *b) {
    enum { MAXLEN = 32 };
    size_t la = strlen(a), lb = strlen(b);
    int row[MAXLEN + 1];
    if (la > MAXLEN || lb > MAXLEN) return MAXLEN;
    for (size_t j = 0; j <= lb; j++) row[j] = (int)j;
    for (size_t i = 1; i <= la; i++) {
        int diag = row[0];
        row[0] = (int)i;
        for (size_t j = 1; j <= lb; j++) {
            int up = row[j];
            int ca = a[i - 1] | 0x20, cb = b[j - 1] | 0x20; /* ASCII case fold is enough here */
            int best = diag + (ca != cb);
            if (up + 1 < best) best = up + 1;
            if (row[j - 1] + 1 < best) best = row[j - 1] + 1;
            row[j] = best;
            diag = up;
        }
    }
    return row[lb];
}

/* Objects that take the options (the request, each of /v1/compare's
 * "methods") know the names of fields[nf] and then of every row of the
 * options table: slot nf + j is row j (io/options.c). */
static int member_slot(const field *fields, int nf, int with_opts, const char *name) {
    int i = field_index(fields, nf, name);
    const tc_opt *o = with_opts && i < 0 ? tc_opt_find(name) : NULL;
    return o ? nf + (int)(o - tc_opts) : i;
}

static const char *slot_name(const field *fields, int nf, int slot) {
    return slot < nf ? fields[slot].name : tc_opts[slot - nf].name;
}

static void warn_unknown(reader *rd, const jpath *p, const char *name, const field *fields, int nf, int with_opts) {
    int best = -1, best_d = 3; /* suggest only names within 2 edits */
    for (int i = 0; i < nf + (with_opts ? tc_nopts : 0); i++) {
        const char *known = slot_name(fields, nf, i);
        int d = edit_distance(name, known);
        if (d < best_d && d < (int)strlen(known)) best = i, best_d = d;
    }
    if (best >= 0)
        warning(rd, p, "unknown field '%.60s' ignored (did you mean '%s'?)", name, slot_name(fields, nf, best));
    else
        warning(rd, p, "unknown field '%.60s' ignored", name);
}

/* Sorts the members of obj into found[nf] by fields[] (and, with_opts, the
 * options into found[nf .. nf + tc_nopts)): unknown names warn, a name given
 * twice is a shape error. what describes obj for a type error. */
static int sort_members(reader *rd, const cJSON *obj, const jpath *p, const field *fields, int nf, int with_opts,
                        const cJSON **found, const char *what) {
    if (!is_type(obj, cJSON_Object)) {
        shape_error(rd, p, "expected %s, got %s", what, kind_of(obj));
        return -1;
    }
    for (int i = 0; i < nf + (with_opts ? tc_nopts : 0); i++) found[i] = NULL;
    for (const cJSON *m = obj->child; m; m = m->next) {
        const char *name = m->string ? m->string : "";
        jpath pm = key_path(p, name);
        int i = member_slot(fields, nf, with_opts, name);
        if (i < 0)
            warn_unknown(rd, &pm, name, fields, nf, with_opts);
        else if (found[i])
            shape_error(rd, &pm, "field '%s' given more than once", name);
        else
            found[i] = m;
    }
    return 0;
}

static int read_members(reader *rd, const cJSON *obj, const jpath *p, const field *fields, int nf,
                        const cJSON **found, const char *what) {
    return sort_members(rd, obj, p, fields, nf, 0, found, what);
}

/* A required integer member of an object entry (e.g. corner_values[2].triangle). */
static void read_member_int(reader *rd, const cJSON *v, const jpath *obj, const char *name,
                            int32_t *out) {
    jpath p = key_path(obj, name);
    if (!v)
        shape_error(rd, &p, "missing required field '%s' (a %s index)", name, name);
    else
        read_int(rd, v, &p, out);
}

/* The element an entry names: "triangle" on a mesh of triangles, "quad" on
 * one of quads (found[0] and found[1] hold the two members); the other name is
 * refused, since its index would mean something else. Corner counts follow. */
static void read_member_elem(reader *rd, const cJSON *const found[2], const jpath *obj, int required,
                             int32_t *out) {
    const char *want = rd->quads ? "quad" : "triangle", *other = rd->quads ? "triangle" : "quad";
    const cJSON *v = found[rd->quads], *bad = found[!rd->quads];
    if (bad) {
        jpath p = key_path(obj, other);
        value_error(rd, &p, "this mesh is given as %ss: name the %s ('%s': index)", want, want, want);
        return;
    }
    if (v || required) read_member_int(rd, v, obj, want, out);
}

/* ---- fields: geometry ------------------------------------------------------------- */

/* [[x, y], ...] into a new [n][2] array (vertices, points). */
static int read_xy_list(reader *rd, const cJSON *v, const jpath *p, size_t max, size_t *n_out,
                        double **xy_out) {
    size_t n;
    if (open_array(rd, v, p, "an array of points [[x, y], ...]", max, &n)) return -1;
    double *xy = own_alloc(rd, n, 2 * sizeof *xy);
    if (n && !xy) return -1;
    size_t i = 0;
    for (const cJSON *e = v->child; e; e = e->next, i++) {
        jpath pi = index_path(p, i);
        read_numbers(rd, e, &pi, 2, xy + 2 * i, "[x, y]");
    }
    *n_out = n;
    *xy_out = xy;
    return 0;
}

static void parse_vertices(reader *rd, const cJSON *v, const jpath *p) {
    size_t n;
    double *xy;
    if (read_xy_list(rd, v, p, INT32_MAX, &n, &xy)) return;
    rd->r->desc.nverts = (int32_t)n;
    rd->r->desc.xy = xy;
    rd->nverts_known = 1;
}

static void parse_quads(reader *rd, const cJSON *v, const jpath *p) {
    size_t n, i = 0;
    if (open_array(rd, v, p, "an array of quads [[a, b, c, d], ...]", INT32_MAX / 2, &n)) return;
    int32_t *quads = own_alloc(rd, n, 4 * sizeof *quads);
    if (n && !quads) return;
    for (const cJSON *e = v->child; e; e = e->next, i++) {
        jpath pi = index_path(p, i);
        read_ints(rd, e, &pi, 4, quads + 4 * i, "[a, b, c, d]");
    }
    rd->r->desc.nquads = (int32_t)n;
    rd->r->desc.quads = quads;
}

static void parse_triangles(reader *rd, const cJSON *v, const jpath *p) {
    size_t n, i = 0;
    if (open_array(rd, v, p, "an array of triangles [[i, j, k], ...]", INT32_MAX, &n)) return;
    int32_t *tris = own_alloc(rd, n, 3 * sizeof *tris);
    if (n && !tris) return;
    for (const cJSON *e = v->child; e; e = e->next, i++) {
        jpath pi = index_path(p, i);
        read_ints(rd, e, &pi, 3, tris + 3 * i, "[i, j, k]");
    }
    rd->r->desc.ntris = (int32_t)n;
    rd->r->desc.tris = tris;
}

static void parse_points(reader *rd, const cJSON *v, const jpath *p) {
    size_t n;
    double *xy;
    if (read_xy_list(rd, v, p, SIZE_MAX / 2 / sizeof(double), &n, &xy)) return;
    rd->r->npoints = n;
    rd->r->points = xy;
}

/* ---- fields: samples ------------------------------------------------------------- */

/* values[0] fixes the channel count C (and whether responses use plain numbers). */
static int channels_from_first(reader *rd, const cJSON *first, const jpath *p) {
    jpath p0 = index_path(p, 0);
    if (!first || is_type(first, cJSON_Number)) { /* no entries: nothing to disagree with */
        rd->nchan = 1;
        rd->r->values_plain = 1;
        return 0;
    }
    if (!is_type(first, cJSON_Array)) {
        shape_error(rd, &p0, "expected a number or an array of channel values [z1, ..., zC], got %s",
                    kind_of(first));
        return -1;
    }
    size_t k = count_items(first);
    if (k < 1 || k > TC_MAX_CHANNELS) {
        value_error(rd, &p0, "%zu channels, expected 1 to %d", k, TC_MAX_CHANNELS);
        return -1;
    }
    rd->nchan = (int)k;
    return 0;
}

static void parse_values(reader *rd, const cJSON *v, const jpath *p) {
    size_t n, i = 0;
    if (open_array(rd, v, p, "an array of per-vertex values [z, ...] or [[z1, ..., zC], ...]",
                   INT32_MAX, &n))
        return;
    if (channels_from_first(rd, v->child, p)) return;
    check_per_vertex(rd, p, n);
    size_t C = (size_t)rd->nchan;
    double *z = own_alloc(rd, n, C * sizeof *z);
    if (n && !z) return;
    for (const cJSON *e = v->child; e; e = e->next, i++) {
        jpath pi = index_path(p, i);
        read_channels(rd, e, &pi, z + i * C);
    }
    rd->r->desc.nchan = rd->nchan;
    rd->r->desc.values = z;
}

static const field corner_value_fields[] = {
    {"triangle", NULL, 0, "t"},
    {"quad", NULL, 0, "q"},
    {"values", NULL, 0, "[za, zb, zc]"},
};
enum { CV_TRIANGLE, CV_QUAD, CV_VALUES, CV_NFIELDS };

/* Corners per entry, and how their list is shown in messages. */
static int entry_corners(const reader *rd) { return rd->quads ? 4 : 3; }

/* {"triangle": t, "values": [za, zb, zc]} into *tri and z[3][C]; on a quad
 * mesh {"quad": q, "values": [za, zb, zc, zd]} into *tri and z[4][C]. */
static void read_corner_value(reader *rd, const cJSON *e, const jpath *p, int32_t *tri, double *z) {
    const cJSON *f[CV_NFIELDS];
    char buf[48];
    int nk = entry_corners(rd);
    const char *list = rd->quads ? "[za, zb, zc, zd]" : "[za, zb, zc]";
    if (read_members(rd, e, p, corner_value_fields, CV_NFIELDS, f,
                     rd->quads ? "an object {\"quad\": q, \"values\": [za, zb, zc, zd]}"
                               : "an object {\"triangle\": t, \"values\": [za, zb, zc]}"))
        return;
    read_member_elem(rd, f + CV_TRIANGLE, p, 1, tri);
    jpath pv = key_path(p, "values");
    const cJSON *vals = f[CV_VALUES];
    if (!vals) {
        shape_error(rd, &pv, "missing required field 'values' (the %d corner values %s)", nk, list);
        return;
    }
    if (!is_type(vals, cJSON_Array) || count_items(vals) != (size_t)nk) {
        shape_error(rd, &pv, "expected an array of %d corner values %s, got %s", nk, list,
                    describe(vals, buf, sizeof buf));
        return;
    }
    size_t k = 0, C = (size_t)rd->nchan;
    for (const cJSON *c = vals->child; c; c = c->next, k++) {
        jpath pk = index_path(&pv, k);
        read_channels(rd, c, &pk, z + k * C);
    }
}

static void parse_corner_values(reader *rd, const cJSON *v, const jpath *p) {
    size_t n, i = 0;
    if (!rd->nchan) return; /* values unreadable: already reported, C unknown */
    if (open_array(rd, v, p, "an array of {\"triangle\": t, \"values\": [za, zb, zc]}", INT32_MAX, &n))
        return;
    size_t C = (size_t)rd->nchan, nk = (size_t)entry_corners(rd);
    int32_t *tri = own_alloc(rd, n, sizeof *tri);
    double *z = own_alloc(rd, n, nk * C * sizeof *z);
    if (n && (!tri || !z)) return;
    for (const cJSON *e = v->child; e; e = e->next, i++) {
        jpath pi = index_path(p, i);
        read_corner_value(rd, e, &pi, &tri[i], z + i * nk * C);
    }
    rd->r->desc.ncorner_values = (int32_t)n;
    rd->r->desc.corner_values_tri = tri;
    rd->r->desc.corner_values = z;
}

static const field midpoint_fields[] = {
    {"edge", NULL, 0, "[i, j]"},
    {"value", NULL, 0, "z or [z1, ..., zC]"},
    {"triangle", NULL, 0, "t"},
    {"quad", NULL, 0, "q"},
};
enum { MP_EDGE, MP_VALUE, MP_TRIANGLE, MP_QUAD, MP_NFIELDS };

/* {"edge": [i, j], "value": z, "triangle": t (optional)} into edge[2], *tri, z[C]. */
static void read_midpoint(reader *rd, const cJSON *e, const jpath *p, int32_t *edge, int32_t *tri,
                          double *z) {
    const cJSON *f[MP_NFIELDS];
    if (read_members(rd, e, p, midpoint_fields, MP_NFIELDS, f,
                     "an object {\"edge\": [i, j], \"value\": z}"))
        return;
    jpath pe = key_path(p, "edge"), pv = key_path(p, "value");
    if (!f[MP_EDGE])
        shape_error(rd, &pe, "missing required field 'edge' (the edge's vertex indices [i, j])");
    else
        read_ints(rd, f[MP_EDGE], &pe, 2, edge, "[i, j]");
    if (!f[MP_VALUE])
        shape_error(rd, &pv, "missing required field 'value' (the sample at the edge midpoint)");
    else
        read_channels(rd, f[MP_VALUE], &pv, z);
    *tri = -1; /* both sides, unless it names one */
    read_member_elem(rd, f + MP_TRIANGLE, p, 0, tri);
}

static void parse_midpoints(reader *rd, const cJSON *v, const jpath *p) {
    size_t n, i = 0;
    if (!rd->nchan) return;
    if (open_array(rd, v, p, "an array of {\"edge\": [i, j], \"value\": z}", INT32_MAX, &n)) return;
    size_t C = (size_t)rd->nchan;
    int32_t *edge = own_alloc(rd, n, 2 * sizeof *edge);
    int32_t *tri = own_alloc(rd, n, sizeof *tri);
    double *z = own_alloc(rd, n, C * sizeof *z);
    if (n && (!edge || !tri || !z)) return;
    for (const cJSON *e = v->child; e; e = e->next, i++) {
        jpath pi = index_path(p, i);
        read_midpoint(rd, e, &pi, edge + 2 * i, &tri[i], z + i * C);
    }
    rd->r->desc.nmidpoints = (int32_t)n;
    rd->r->desc.midpoint_edge = edge;
    rd->r->desc.midpoint_tri = tri;
    rd->r->desc.midpoint_values = z;
}

/* ---- fields: tangent planes --------------------------------------------------------- */

/* Per-vertex vectors (gradients, normals), null where a vertex has none: data
 * [n][C][dim], mask [n] (left NULL when every vertex has one). */
static void read_vertex_vectors(reader *rd, const cJSON *v, const jpath *p, int dim,
                                const char *what, const double **data, const uint8_t **mask) {
    char shape[96];
    size_t n, i = 0;
    if (!rd->nchan) return;
    snprintf(shape, sizeof shape, "an array of per-vertex %s (null where not given)", what);
    if (open_array(rd, v, p, shape, INT32_MAX, &n)) return;
    check_per_vertex(rd, p, n);
    size_t stride = (size_t)rd->nchan * (size_t)dim;
    double *g = own_alloc(rd, n, stride * sizeof *g);
    uint8_t *m = own_alloc(rd, n, 1);
    if (n && (!g || !m)) return;
    int all = 1;
    for (const cJSON *e = v->child; e; e = e->next, i++) {
        jpath pi = index_path(p, i);
        if (is_type(e, cJSON_NULL)) {
            all = 0; /* m[i] stays 0, g zero-filled */
            continue;
        }
        m[i] = 1;
        read_channel_vectors(rd, e, &pi, dim, what, g + i * stride);
    }
    *data = g;
    *mask = all ? NULL : m;
}

static void parse_gradients(reader *rd, const cJSON *v, const jpath *p) {
    read_vertex_vectors(rd, v, p, 2, "[gx, gy]", &rd->r->desc.gradients,
                        &rd->r->desc.gradients_mask);
}

static void parse_normals(reader *rd, const cJSON *v, const jpath *p) {
    read_vertex_vectors(rd, v, p, 3, "[nx, ny, nz]", &rd->r->desc.normals,
                        &rd->r->desc.normals_mask);
}

static void parse_hessians(reader *rd, const cJSON *v, const jpath *p) {
    read_vertex_vectors(rd, v, p, 3, "[fxx, fxy, fyy]", &rd->r->desc.hessians,
                        &rd->r->desc.hessians_mask);
}

static const field corner_gradient_fields[] = {
    {"triangle", NULL, 0, "t"},
    {"quad", NULL, 0, "q"},
    {"gradients", NULL, 0, "[g_a, g_b, g_c]"},
};
enum { CG_TRIANGLE, CG_QUAD, CG_GRADIENTS, CG_NFIELDS };

/* {"triangle": t, "gradients": [g_a, g_b, g_c]} into *tri, g[3][C][2], mask[3]
 * (on a quad mesh {"quad": q, "gradients": [g_a, g_b, g_c, g_d]}, 4 corners);
 * returns 0 if some corner is null (not given). */
static int read_corner_gradient(reader *rd, const cJSON *e, const jpath *p, int32_t *tri,
                                double *g, uint8_t *mask) {
    const cJSON *f[CG_NFIELDS];
    char buf[48];
    int nk = entry_corners(rd);
    const char *list = rd->quads ? "[g_a, g_b, g_c, g_d]" : "[g_a, g_b, g_c]";
    if (read_members(rd, e, p, corner_gradient_fields, CG_NFIELDS, f,
                     rd->quads ? "an object {\"quad\": q, \"gradients\": [g_a, g_b, g_c, g_d]}"
                               : "an object {\"triangle\": t, \"gradients\": [g_a, g_b, g_c]}"))
        return 1;
    read_member_elem(rd, f + CG_TRIANGLE, p, 1, tri);
    jpath pg = key_path(p, "gradients");
    const cJSON *gs = f[CG_GRADIENTS];
    if (!gs) {
        shape_error(rd, &pg, "missing required field 'gradients' (one per corner: %s)", list);
        return 1;
    }
    if (!is_type(gs, cJSON_Array) || count_items(gs) != (size_t)nk) {
        shape_error(rd, &pg, "expected an array of %d corner gradients %s, got %s", nk, list,
                    describe(gs, buf, sizeof buf));
        return 1;
    }
    int all = 1;
    size_t k = 0, stride = 2 * (size_t)rd->nchan;
    for (const cJSON *c = gs->child; c; c = c->next, k++) {
        jpath pk = index_path(&pg, k);
        if (is_type(c, cJSON_NULL)) {
            all = 0;
            continue;
        }
        mask[k] = 1;
        read_channel_vectors(rd, c, &pk, 2, "[gx, gy]", g + k * stride);
    }
    return all;
}

static void parse_corner_gradients(reader *rd, const cJSON *v, const jpath *p) {
    size_t n, i = 0;
    if (!rd->nchan) return;
    if (open_array(rd, v, p, "an array of {\"triangle\": t, \"gradients\": [g_a, g_b, g_c]}",
                   INT32_MAX, &n))
        return;
    size_t nk = (size_t)entry_corners(rd), stride = nk * 2 * (size_t)rd->nchan;
    int32_t *tri = own_alloc(rd, n, sizeof *tri);
    double *g = own_alloc(rd, n, stride * sizeof *g);
    uint8_t *mask = own_alloc(rd, n, nk);
    if (n && (!tri || !g || !mask)) return;
    int all = 1;
    for (const cJSON *e = v->child; e; e = e->next, i++) {
        jpath pi = index_path(p, i);
        all &= read_corner_gradient(rd, e, &pi, &tri[i], g + i * stride, mask + nk * i);
    }
    rd->r->desc.ncorner_gradients = (int32_t)n;
    rd->r->desc.corner_gradients_tri = tri;
    rd->r->desc.corner_gradients = g;
    rd->r->desc.corner_gradients_mask = all ? NULL : mask;
}

/* ---- fields: discontinuities --------------------------------------------------------- */

/* Shapes of the polylines and their total length, so verts is allocated once. */
static size_t polyline_total(reader *rd, const cJSON *v, const jpath *p) {
    size_t total = 0, i = 0;
    for (const cJSON *e = v->child; e; e = e->next, i++) {
        jpath pi = index_path(p, i);
        if (!is_type(e, cJSON_Array)) {
            shape_error(rd, &pi, "expected a polyline: an array of at least 2 vertex indices, got %s",
                        kind_of(e));
            continue;
        }
        size_t k = count_items(e);
        if (k < 2) shape_error(rd, &pi, "a polyline needs at least 2 vertices, got %zu", k);
        total += k;
    }
    return total;
}

/* [[i, j, ...], ...] into a tc_polylines (start[count + 1] offsets into verts). */
static void read_polylines(reader *rd, const cJSON *v, const jpath *p, tc_polylines *out) {
    size_t n, i = 0, off = 0;
    if (open_array(rd, v, p, "an array of polylines [[i, j, ...], ...]", INT32_MAX - 1, &n)) return;
    size_t total = polyline_total(rd, v, p);
    if (total > INT32_MAX) {
        value_error(rd, p, "too many polyline vertices (%zu, at most %d)", total, INT32_MAX);
        return;
    }
    int32_t *start = own_alloc(rd, n + 1, sizeof *start);
    int32_t *verts = own_alloc(rd, total, sizeof *verts);
    if (!start || (total && !verts)) return;
    for (const cJSON *e = v->child; e; e = e->next, i++) {
        start[i] = (int32_t)off;
        if (!is_type(e, cJSON_Array)) continue; /* reported by polyline_total */
        jpath pi = index_path(p, i);
        size_t k = 0;
        for (const cJSON *c = e->child; c; c = c->next, k++, off++) {
            jpath pk = index_path(&pi, k);
            read_int(rd, c, &pk, &verts[off]);
        }
    }
    start[n] = (int32_t)off;
    out->count = (int32_t)n;
    out->start = start;
    out->verts = verts;
}

static const field discontinuity_fields[] = {
    {"c0", NULL, 0, "[[i, j, ...], ...]"},
    {"c-1", NULL, 0, "[[i, j, ...], ...]"},
};
enum { DC_C0, DC_CM1, DC_NFIELDS };

static void parse_discontinuities(reader *rd, const cJSON *v, const jpath *p) {
    const cJSON *f[DC_NFIELDS];
    if (read_members(rd, v, p, discontinuity_fields, DC_NFIELDS, f,
                     "an object {\"c0\": [[i, j, ...], ...], \"c-1\": [[i, j, ...], ...]}"))
        return;
    if (f[DC_C0]) {
        jpath pc = key_path(p, "c0");
        read_polylines(rd, f[DC_C0], &pc, &rd->r->desc.c0);
    }
    if (f[DC_CM1]) {
        jpath pc = key_path(p, "c-1");
        read_polylines(rd, f[DC_CM1], &pc, &rd->r->desc.cm1);
    }
}

/* ---- fields: options (the table in io/options.c) ------------------------------------ */

/* One option's value into its field: o's for a reconstruction option, the
 * request's mesh description for a mesh option. */
static void read_option(reader *rd, const tc_opt *row, const cJSON *v, const jpath *p, tc_options *o) {
    void *obj = tc_opt_object(row, o, &rd->r->desc);
    char accepts[160], num[32];
    tc_opt_accepts(row, accepts, sizeof accepts);
    if (row->kind == TC_OPT_NUMBER) {
        double x;
        if (read_number(rd, v, p, &x)) return;
        if (!(x >= row->min && x <= row->max))
            value_error(rd, p, "%s must be %s, got %s", row->name, accepts, format_number(x, num, sizeof num));
        else
            tc_opt_set_number(row, obj, x);
        return;
    }
    if (!is_type(v, cJSON_String) || !v->valuestring) {
        shape_error(rd, p, "expected a string (one of: %s), got %s", accepts, kind_of(v));
        return;
    }
    int x = tc_opt_parse_name(row, v->valuestring);
    if (x < 0) value_error(rd, p, "unknown %s '%.40s'; expected one of: %s", row->name, v->valuestring, accepts);
    else tc_opt_set_enum(row, obj, x);
}

/* The options found at the top level (found[j] for row j): the request's own,
 * and the defaults of each entry of "methods". */
static void read_options(reader *rd, const cJSON *const *found) {
    for (int j = 0; j < tc_nopts; j++) {
        if (!found[j]) continue;
        jpath p = key_path(NULL, tc_opts[j].name);
        read_option(rd, &tc_opts[j], found[j], &p, &rd->r->opt);
    }
}

static int read_bool(reader *rd, const cJSON *v, const jpath *p, int *out) {
    if (!is_type(v, cJSON_True) && !is_type(v, cJSON_False)) {
        shape_error(rd, p, "expected true or false, got %s", kind_of(v));
        return -1;
    }
    *out = is_type(v, cJSON_True);
    return 0;
}

static void parse_with_gradients(reader *rd, const cJSON *v, const jpath *p) {
    read_bool(rd, v, p, &rd->r->with_gradients);
}

/* ---- fields: rendering ------------------------------------------------------------- */

static const field viewport_fields[] = {
    {"x0", NULL, 0, "x"}, {"y0", NULL, 0, "y"}, {"x1", NULL, 0, "x"},
    {"y1", NULL, 0, "y"}, {"width", NULL, 0, "pixels"}, {"height", NULL, 0, "pixels"},
};
#define NVIEWPORT ((int)(sizeof viewport_fields / sizeof viewport_fields[0]))

/* One required member of the viewport: a number, or a pixel count 1 .. 2^20. */
static int viewport_member(reader *rd, const cJSON *v, const jpath *obj, int i, double *num, int32_t *count) {
    jpath p = key_path(obj, viewport_fields[i].name);
    if (!v) {
        shape_error(rd, &p, "missing required field '%s'", viewport_fields[i].name);
        return -1;
    }
    if (!count) return read_number(rd, v, &p, num);
    if (read_int(rd, v, &p, count)) return -1;
    if (*count < 1 || *count > (1 << 20)) {
        value_error(rd, &p, "%s must be 1 to %d pixels, got %d", viewport_fields[i].name, 1 << 20, (int)*count);
        return -1;
    }
    return 0;
}

static void parse_viewport(reader *rd, const cJSON *v, const jpath *p) {
    const cJSON *found[NVIEWPORT];
    if (read_members(rd, v, p, viewport_fields, NVIEWPORT, found, "an object {x0, y0, x1, y1, width, height}"))
        return;
    tc_viewport *vp = &rd->r->viewport;
    double *num[4] = {&vp->x0, &vp->y0, &vp->x1, &vp->y1};
    int bad = 0;
    for (int i = 0; i < 4; i++) bad |= viewport_member(rd, found[i], p, i, num[i], NULL) != 0;
    bad |= viewport_member(rd, found[4], p, 4, NULL, &vp->width) != 0;
    bad |= viewport_member(rd, found[5], p, 5, NULL, &vp->height) != 0;
    if (bad) return;
    for (int axis = 0; axis < 2; axis++) {
        double lo = axis ? vp->y0 : vp->x0, hi = axis ? vp->y1 : vp->x1;
        jpath ph = key_path(p, axis ? "y1" : "x1");
        if (!(hi > lo)) {
            value_error(rd, &ph, "%s = %g must be greater than %s = %g", axis ? "y1" : "x1", hi, axis ? "y0" : "x0", lo);
            bad = 1;
        }
    }
    rd->r->has_viewport = !bad;
}

static void parse_format(reader *rd, const cJSON *v, const jpath *p) {
    tc_img_format f;
    if (!is_type(v, cJSON_String) || !v->valuestring) {
        shape_error(rd, p, "expected a string (png, png16, exr, exr-half, tiff, raw), got %s", kind_of(v));
        return;
    }
    if (tc_img_format_parse(v->valuestring, &f)) {
        value_error(rd, p, "unknown format '%.40s'; expected one of: png, png16, exr, exr-half, tiff, raw",
                    v->valuestring);
        return;
    }
    rd->r->format = (int)f;
}

static void parse_exposure(reader *rd, const cJSON *v, const jpath *p) {
    double e;
    if (read_number(rd, v, p, &e)) return;
    if (fabs(e) > 64) {
        value_error(rd, p, "exposure %g stops is out of range (-64 to 64)", e);
        return;
    }
    rd->r->exposure = e;
}

static void parse_overlay(reader *rd, const cJSON *v, const jpath *p) { read_bool(rd, v, p, &rd->r->overlay); }
static void parse_linear(reader *rd, const cJSON *v, const jpath *p) { read_bool(rd, v, p, &rd->r->linear); }

/* ---- fields: comparison ------------------------------------------------------------ */

static const field reference_fields[] = {
    {"points", NULL, 0, "[[x, y], ...]"},
    {"values", NULL, 0, "[z, ...] or [[z1, ..., zC], ...]"},
    {"scale", NULL, 0, "the full-scale value"},
};
enum { REF_POINTS, REF_VALUES, REF_SCALE, REF_NFIELDS };

/* The reference values: one per point, C channels each. */
static void read_reference_values(reader *rd, const cJSON *v, const jpath *p, size_t n) {
    size_t m, i = 0;
    if (open_array(rd, v, p, "an array of reference values [z, ...] or [[z1, ..., zC], ...]", SIZE_MAX / 16, &m))
        return;
    if (m != n) {
        value_error(rd, p, "%zu values for %zu points", m, n);
        return;
    }
    double *z = own_alloc(rd, n, (size_t)rd->nchan * sizeof *z);
    if (n && !z) return;
    for (const cJSON *e = v->child; e; e = e->next, i++) {
        jpath pi = index_path(p, i);
        read_channels(rd, e, &pi, z + i * (size_t)rd->nchan);
    }
    rd->r->reference_values = z;
}

static void parse_reference(reader *rd, const cJSON *v, const jpath *p) {
    const cJSON *found[REF_NFIELDS];
    if (!rd->nchan || read_members(rd, v, p, reference_fields, REF_NFIELDS, found, "an object {points, values}"))
        return;
    jpath pp = key_path(p, "points"), pv = key_path(p, "values"), ps = key_path(p, "scale");
    if (!found[REF_POINTS] || !found[REF_VALUES]) {
        shape_error(rd, found[REF_POINTS] ? &pv : &pp, "missing required field '%s'",
                    found[REF_POINTS] ? "values" : "points");
        return;
    }
    size_t n;
    double *xy;
    if (read_xy_list(rd, found[REF_POINTS], &pp, SIZE_MAX / 2 / sizeof(double), &n, &xy)) return;
    rd->r->nreference = n;
    rd->r->reference_points = xy;
    read_reference_values(rd, found[REF_VALUES], &pv, n);
    if (found[REF_SCALE] && !read_number(rd, found[REF_SCALE], &ps, &rd->r->reference_scale) &&
        !(rd->r->reference_scale > 0))
        value_error(rd, &ps, "scale must be positive, got %g", rd->r->reference_scale);
}

/* One entry of "methods": a method name, or an object of options (the
 * request's own options are the defaults for the fields it leaves out). A
 * mesh option there would mean another mesh: it is ignored with a warning. */
static void read_method(reader *rd, const cJSON *e, const jpath *p, tc_options *o) {
    *o = rd->r->opt;
    if (is_type(e, cJSON_String)) {
        read_option(rd, tc_opt_find("method"), e, p, o);
        return;
    }
    const cJSON *found[TC_OPT_MAX];
    if (sort_members(rd, e, p, NULL, 0, 1, found, "a method name or an object {method, ...}")) return;
    for (int j = 0; j < tc_nopts; j++) {
        if (!found[j]) continue;
        jpath pj = key_path(p, tc_opts[j].name);
        if (tc_opts[j].target == TC_OPT_MESH)
            warning(rd, &pj, "'%s' applies to the mesh, which every method shares: give it at the top level (ignored "
                    "here)", tc_opts[j].name);
        else
            read_option(rd, &tc_opts[j], found[j], &pj, o);
    }
}

static void parse_methods(reader *rd, const cJSON *v, const jpath *p) {
    size_t n, i = 0;
    if (open_array(rd, v, p, "an array of methods", TC_REQ_MAX_METHODS, &n)) return;
    for (const cJSON *e = v->child; e; e = e->next, i++) {
        jpath pi = index_path(p, i);
        read_method(rd, e, &pi, &rd->r->methods[i]);
    }
    rd->r->nmethods = (int)n;
}

/* A number (every channel) or one number per channel. */
static void parse_background(reader *rd, const cJSON *v, const jpath *p) {
    if (!rd->nchan) return; /* values unreadable: already reported */
    if (!is_type(v, cJSON_Array)) {
        double z;
        if (read_number(rd, v, p, &z)) return;
        for (int ch = 0; ch < rd->nchan; ch++) rd->r->background[ch] = z;
    } else if (read_numbers(rd, v, p, rd->nchan, rd->r->background, "(one per channel)")) {
        return;
    }
    rd->r->has_background = 1;
}

/* ---- the request ------------------------------------------------------------------- */

/* Every top-level field the service knows but the options (io/options.c). To
 * add one, add a row (and its parser).
 * Invariant: rows are parsed in this order, so a field comes after those it
 * depends on (vertices before per-vertex data; values, which fix the channel
 * count, before every other per-channel field). */
static const field top_fields[] = {
    {"vertices", parse_vertices, ROLE_MESH, "[[x, y], ...]"},
    {"triangles", parse_triangles, ROLE_MESH, "[[i, j, k], ...] (or \"quads\": [[a, b, c, d], ...])"},
    {"quads", parse_quads, ROLE_MESH_DATA, ""}, /* instead of triangles */
    {"values", parse_values, ROLE_MESH, "[z, ...] or [[z1, ..., zC], ...]"},
    {"corner_values", parse_corner_values, ROLE_MESH_DATA, ""},
    {"gradients", parse_gradients, ROLE_MESH_DATA, ""},
    {"normals", parse_normals, ROLE_MESH_DATA, ""},
    {"hessians", parse_hessians, ROLE_MESH_DATA, ""},
    {"corner_gradients", parse_corner_gradients, ROLE_MESH_DATA, ""},
    {"midpoints", parse_midpoints, ROLE_MESH_DATA, ""},
    {"discontinuities", parse_discontinuities, ROLE_MESH_DATA, ""},
    {"points", parse_points, ROLE_POINTS, "[[x, y], ...]"},
    {"with_gradients", parse_with_gradients, 0, ""},
    {"viewport", parse_viewport, ROLE_VIEWPORT, "{x0, y0, x1, y1, width, height}"},
    {"format", parse_format, 0, ""},
    {"exposure", parse_exposure, 0, ""},
    {"overlay", parse_overlay, 0, ""},
    {"linear", parse_linear, 0, ""},
    {"background", parse_background, 0, ""},
    {"reference", parse_reference, ROLE_REFERENCE, "{points, values}"},
    {"methods", NULL, 0, ""}, /* after the options, which its entries start from */
};
#define NTOP ((int)(sizeof top_fields / sizeof top_fields[0]))

/* The mesh is all-or-nothing: required when the caller expects it or when any
 * mesh field is present. Points are required when expected. */
static void check_required(reader *rd, const cJSON *const *found) {
    int want_mesh = (rd->expect & TC_REQ_MESH) != 0;
    for (int i = 0; i < NTOP; i++)
        if (found[i] && (top_fields[i].role & (ROLE_MESH | ROLE_MESH_DATA))) want_mesh = 1;
    for (int i = 0; i < NTOP; i++) {
        unsigned role = top_fields[i].role;
        int quads_instead = !strcmp(top_fields[i].name, "triangles") && found[field_index(top_fields, NTOP, "quads")];
        int required = ((role & ROLE_MESH) && want_mesh && !quads_instead) ||
                       ((role & ROLE_POINTS) && (rd->expect & TC_REQ_POINTS)) ||
                       ((role & ROLE_VIEWPORT) && (rd->expect & TC_REQ_VIEWPORT)) ||
                       ((role & ROLE_REFERENCE) && (rd->expect & TC_REQ_REFERENCE));
        if (required && !found[i]) {
            jpath p = key_path(NULL, top_fields[i].name);
            shape_error(rd, &p, "missing required field '%s': expected %s", top_fields[i].name,
                        top_fields[i].shape);
        }
    }
    rd->r->has_mesh = want_mesh;
}

static void check_exclusive(reader *rd, const cJSON *const *found) {
    if (found[field_index(top_fields, NTOP, "gradients")] &&
        found[field_index(top_fields, NTOP, "normals")]) {
        jpath p = key_path(NULL, "normals");
        value_error(rd, &p, "give either gradients or normals, not both");
    }
    if (found[field_index(top_fields, NTOP, "triangles")] && found[field_index(top_fields, NTOP, "quads")]) {
        jpath p = key_path(NULL, "quads");
        value_error(rd, &p, "give either triangles or quads, not both");
    }
}

static void read_request(reader *rd, const cJSON *root) {
    const cJSON *found[NTOP + TC_OPT_MAX];
    if (sort_members(rd, root, NULL, top_fields, NTOP, 1, found, "a JSON object (the request)")) return;
    check_required(rd, found);
    rd->quads = found[field_index(top_fields, NTOP, "quads")] && !found[field_index(top_fields, NTOP, "triangles")];
    for (int i = 0; i < NTOP && !rd->nomem; i++) {
        if (!found[i] || !top_fields[i].parse) continue;
        jpath p = key_path(NULL, top_fields[i].name);
        top_fields[i].parse(rd, found[i], &p);
    }
    read_options(rd, found + NTOP);
    int methods = field_index(top_fields, NTOP, "methods");
    if (found[methods] && !rd->nomem) {
        jpath p = key_path(NULL, "methods");
        parse_methods(rd, found[methods], &p);
    }
    check_exclusive(rd, found);
}

/* ---- JSON syntax ------------------------------------------------------------------- */

/* Reports a syntax problem at byte pos as "line L, column C" (columns count
 * UTF-8 characters), with a short printable excerpt of the text there. */
static void syntax_error(reader *rd, const char *json, size_t len, size_t pos, const char *what) {
    size_t line = 1, col = 1;
    char near[32];
    for (size_t i = 0; i < pos && i < len; i++) {
        unsigned char b = (unsigned char)json[i];
        if (b == '\n') line++, col = 1;
        else if ((b & 0xC0) != 0x80) col++;
    }
    size_t k = 0;
    for (size_t i = pos; i < len && k < 16 && json[i] != '\n' && json[i] != '\r'; i++) {
        unsigned char b = (unsigned char)json[i];
        near[k++] = b >= 0x20 && b < 0x7F ? (char)b : '?';
    }
    near[k] = '\0';
    if (pos >= len)
        shape_error(rd, NULL, "%s at line %zu, column %zu (end of input)", what, line, col);
    else
        shape_error(rd, NULL, "%s at line %zu, column %zu, near '%s'", what, line, col, near);
}

/* Parses the text, requiring only whitespace (or NULs) after the value. Returns
 * the tree or NULL after reporting. */
static cJSON *parse_json(reader *rd, const char *json, size_t len) {
    if (!json || len == 0) {
        shape_error(rd, NULL, "empty request: expected a JSON object");
        return NULL;
    }
    const char *end = json;
    /* require_null_terminated = 0: the buffer need not end in NUL; end marks
     * where parsing stopped (the error position on failure). A failed
     * allocation inside cJSON is indistinguishable from a syntax error here.
     * (cJSON also records the position in a global it never synchronizes; we
     * read only our own `end`, so concurrent parses do not mix positions.) */
    cJSON *root = cJSON_ParseWithLengthOpts(json, len, &end, 0);
    size_t pos = (size_t)(end - json);
    if (!root) {
        syntax_error(rd, json, len, pos, "not valid JSON");
        return NULL;
    }
    while (pos < len && (json[pos] == ' ' || json[pos] == '\t' || json[pos] == '\n' ||
                         json[pos] == '\r' || json[pos] == '\0'))
        pos++;
    if (pos < len) {
        syntax_error(rd, json, len, pos, "unexpected text after the JSON value");
        cJSON_Delete(root);
        return NULL;
    }
    return root;
}

int tc_request_parse(const char *json, size_t len, unsigned expect, tc_request **out,
                     tc_diags *diags) {
    reader rd = {.diags = diags, .expect = expect};
    *out = NULL;
    tc_request *r = injected_failure() ? NULL : calloc(1, sizeof *r);
    if (!r) {
        tc_diags_add(diags, TC_SEV_ERROR, "", "out of memory reading the request");
        return TC_REQ_NOMEM;
    }
    tc_options_default(&r->opt);
    tc_mesh_desc_init(&r->desc);
    r->format = -1;
    rd.r = r;
    cJSON *root = parse_json(&rd, json, len);
    if (root) {
        read_request(&rd, root);
        cJSON_Delete(root); /* the request keeps only its own arrays */
    }
    int status = rd.nomem ? TC_REQ_NOMEM
                 : rd.malformed ? TC_REQ_MALFORMED
                 : rd.invalid ? TC_REQ_INVALID
                              : TC_REQ_OK;
    if (status != TC_REQ_OK) {
        if (rd.nomem) tc_diags_add(diags, TC_SEV_ERROR, "", "out of memory reading the request");
        tc_request_free(r);
        return status;
    }
    *out = r;
    return TC_REQ_OK;
}

void tc_request_free(tc_request *r) {
    if (!r) return;
    for (int i = 0; i < r->nowned_; i++) free(r->owned_[i]);
    free(r);
}
