/* reader.c — the JSON reader under the request parser: JSON paths, findings with
 * their paths, the request's own allocations, typed reads of values and objects. */
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/options.h"
#include "io/hugemem.h"
#include "io/reader.h"

/* ---- JSON paths -------------------------------------------------------------- */

/* Writes "a.b[3][1]" into buf (truncated to cap); returns the length written. */
static size_t render_path(const tc__jpath *p, char *buf, size_t cap) {
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

static void vreport(tc__reader *rd, tc_severity sev, const tc__jpath *p, const char *fmt, va_list ap) {
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

void tc__rd_report(tc__reader *rd, tc__rd_kind kind, const tc__jpath *p, const char *fmt, ...) {
    va_list ap;
    if (kind == TC__RD_SHAPE) rd->malformed++;
    if (kind == TC__RD_VALUE) rd->invalid++;
    va_start(ap, fmt);
    vreport(rd, kind == TC__RD_WARNING ? TC_SEV_WARNING : TC_SEV_ERROR, p, fmt, ap);
    va_end(ap);
}

/* ---- allocation: every array belongs to the request --------------------------- */

static _Thread_local long alloc_countdown; /* test hook; 0 = never fail */

void tc_request__fail_alloc_after(long n) { alloc_countdown = n; }

int tc__rd_injected_failure(void) {
    return alloc_countdown > 0 && --alloc_countdown == 0;
}

/* n zeroed elements owned by the request; NULL for n == 0 (absent arrays are NULL
 * in tc_mesh_desc). On failure sets rd->nomem and returns NULL. */
void *tc__rd_alloc(tc__reader *rd, size_t n, size_t size) {
    tc_request *r = rd->r;
    if (n == 0) return NULL;
    void *p = NULL;
    if (r->nowned_ < TC_REQ_OWNED_MAX && !tc__rd_injected_failure()) p = calloc(n, size);
    if (!p) {
        rd->nomem = 1;
        return NULL;
    }
    r->owned_[r->nowned_++] = p;
    tc__huge_advise(p, n * size); /* calloc gave untouched pages: few faults for a big array */
    return p;
}

/* ---- JSON values ------------------------------------------------------------- */

int tc__json_is(const cJSON *v, int type) { return (v->type & 0xFF) == type; }

const char *tc__json_kind(const cJSON *v) {
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

size_t tc__json_count(const cJSON *a) {
    size_t n = 0;
    for (const cJSON *e = a->child; e; e = e->next) n++;
    return n;
}

/* "a string", or "an array of 3" for arrays, whose length is usually the point. */
const char *tc__json_describe(const cJSON *v, char *buf, size_t cap) {
    if (!tc__json_is(v, cJSON_Array)) return tc__json_kind(v);
    snprintf(buf, cap, "an array of %zu", tc__json_count(v));
    return buf;
}

/* Shortest of %.15g / %.17g that reads back as d, for messages. */
const char *tc__number_text(double d, char *buf, size_t cap) {
    snprintf(buf, cap, "%.15g", d);
    if (strtod(buf, NULL) != d) snprintf(buf, cap, "%.17g", d);
    return buf;
}

int tc__rd_number(tc__reader *rd, const cJSON *v, const tc__jpath *p, double *out) {
    if (!tc__json_is(v, cJSON_Number)) {
        tc__rd_shape_error(rd, p, "expected a number, got %s", tc__json_kind(v));
        return -1;
    }
    if (!isfinite(v->valuedouble)) { /* cJSON reads 1e999 as inf */
        tc__rd_value_error(rd, p, "number is not finite (beyond the range of a double)");
        return -1;
    }
    *out = v->valuedouble;
    return 0;
}

/* An index: a JSON number that is an integer within int32. Range against the
 * mesh is the core's check (tc_mesh_new), not repeated here. */
int tc__rd_int(tc__reader *rd, const cJSON *v, const tc__jpath *p, int32_t *out) {
    double d;
    char num[32];
    if (tc__rd_number(rd, v, p, &d)) return -1;
    if (d != floor(d) || d < INT32_MIN || d > INT32_MAX) {
        tc__rd_shape_error(rd, p, "must be an integer (a 32-bit index), got %s",
                           tc__number_text(d, num, sizeof num));
        return -1;
    }
    *out = (int32_t)d;
    return 0;
}

/* An array of exactly n items, each read by `one` into out + k * size;
 * `items` ("numbers", "vertex indices") and `what` ("[x, y]") name them in messages. */
static int read_fixed(tc__reader *rd, const cJSON *v, const tc__jpath *p, int n, const char *items,
                      const char *what, int (*one)(tc__reader *, const cJSON *, const tc__jpath *, void *),
                      void *out, size_t size) {
    char buf[48];
    if (!tc__json_is(v, cJSON_Array) || tc__json_count(v) != (size_t)n) {
        tc__rd_shape_error(rd, p, "expected an array of %d %s %s, got %s", n, items, what,
                           tc__json_describe(v, buf, sizeof buf));
        return -1;
    }
    int bad = 0;
    size_t k = 0;
    for (const cJSON *e = v->child; e; e = e->next, k++) {
        tc__jpath pk = tc__jpath_index(p, k);
        bad |= one(rd, e, &pk, (char *)out + k * size) != 0;
    }
    return bad ? -1 : 0;
}

static int one_number(tc__reader *rd, const cJSON *v, const tc__jpath *p, void *out) {
    return tc__rd_number(rd, v, p, out);
}
static int one_int(tc__reader *rd, const cJSON *v, const tc__jpath *p, void *out) {
    return tc__rd_int(rd, v, p, out);
}

int tc__rd_numbers(tc__reader *rd, const cJSON *v, const tc__jpath *p, int n, double *out, const char *what) {
    return read_fixed(rd, v, p, n, "numbers", what, one_number, out, sizeof *out);
}

int tc__rd_ints(tc__reader *rd, const cJSON *v, const tc__jpath *p, int n, int32_t *out, const char *what) {
    return read_fixed(rd, v, p, n, "vertex indices", what, one_int, out, sizeof *out);
}

/* v must be an array of at most max entries; its length goes to *n. */
int tc__rd_array(tc__reader *rd, const cJSON *v, const tc__jpath *p, const char *what, size_t max,
                 size_t *n) {
    if (!tc__json_is(v, cJSON_Array)) {
        tc__rd_shape_error(rd, p, "expected %s, got %s", what, tc__json_kind(v));
        return -1;
    }
    *n = tc__json_count(v);
    if (*n > max) {
        tc__rd_value_error(rd, p, "too many entries (%zu, at most %zu)", *n, max);
        return -1;
    }
    return 0;
}

/* Per-vertex arrays must have one entry per vertex (when the vertices were readable). */
void tc__rd_per_vertex(tc__reader *rd, const tc__jpath *p, size_t n) {
    if (rd->nverts_known && n != (size_t)rd->r->desc.nverts)
        tc__rd_value_error(rd, p, "%s has %zu entries, expected %d (one per vertex)", p->key, n,
                           (int)rd->r->desc.nverts);
}

/* ---- channel data --------------------------------------------------------------- */

/* An array of per-channel entries whose length is not the channel count (as
 * values[0] fixed it): says so at p. */
static int channel_count_differs(tc__reader *rd, const cJSON *v, const tc__jpath *p) {
    size_t k = tc__json_count(v), C = (size_t)rd->nchan;
    if (k == C) return 0;
    tc__rd_value_error(rd, p, "%zu channel%s, expected %zu (as values[0])", k, k == 1 ? "" : "s", C);
    return 1;
}

/* One sample of C channels: a plain number (C == 1) or [z1..zC], into out[C]. */
int tc__rd_channels(tc__reader *rd, const cJSON *v, const tc__jpath *p, double *out) {
    int C = rd->nchan;
    if (tc__json_is(v, cJSON_Number)) {
        if (C != 1) {
            tc__rd_value_error(rd, p, "1 channel, expected %d (as values[0])", C);
            return -1;
        }
        return tc__rd_number(rd, v, p, out);
    }
    if (!tc__json_is(v, cJSON_Array)) {
        tc__rd_shape_error(rd, p, "expected a number or an array of %d channel values, got %s", C,
                           tc__json_kind(v));
        return -1;
    }
    if (channel_count_differs(rd, v, p)) return -1;
    int bad = 0;
    size_t j = 0;
    for (const cJSON *e = v->child; e; e = e->next, j++) {
        tc__jpath pj = tc__jpath_index(p, j);
        bad |= tc__rd_number(rd, e, &pj, &out[j]) != 0;
    }
    return bad ? -1 : 0;
}

/* A tangent datum with dim numbers per channel (what = "[gx, gy]"): either one
 * vector (only when C == 1) or an array of C vectors, into out[C][dim]. */
int tc__rd_channel_vectors(tc__reader *rd, const cJSON *v, const tc__jpath *p, int dim,
                           const char *what, double *out) {
    int C = rd->nchan;
    if (!tc__json_is(v, cJSON_Array) || !v->child) {
        tc__rd_shape_error(rd, p, "expected %s or an array of %d of them (one per channel), got %s",
                           what, C, tc__json_is(v, cJSON_Array) ? "an empty array" : tc__json_kind(v));
        return -1;
    }
    if (!tc__json_is(v->child, cJSON_Array)) { /* the single-vector form */
        if (C != 1 && tc__json_is(v->child, cJSON_Number)) {
            tc__rd_value_error(rd, p, "a single %s is 1 channel, expected %d (as values[0])", what, C);
            return -1;
        }
        return tc__rd_numbers(rd, v, p, dim, out, what);
    }
    if (channel_count_differs(rd, v, p)) return -1;
    int bad = 0;
    size_t j = 0;
    for (const cJSON *e = v->child; e; e = e->next, j++) {
        tc__jpath pj = tc__jpath_index(p, j);
        bad |= tc__rd_numbers(rd, e, &pj, dim, out + j * (size_t)dim, what) != 0;
    }
    return bad ? -1 : 0;
}

/* ---- objects ------------------------------------------------------------------- */

int tc__field_index(const tc__field *fields, int nf, const char *name) {
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
static int member_slot(const tc__field *fields, int nf, int with_opts, const char *name) {
    int i = tc__field_index(fields, nf, name);
    const tc_opt *row = with_opts && i < 0 ? tc_opt_find(name) : NULL;
    return row ? nf + tc_opt_index(row) : i;
}

static const char *slot_name(const tc__field *fields, int nf, int slot) {
    return slot < nf ? fields[slot].name : tc_opt_at(slot - nf)->name;
}

static void warn_unknown(tc__reader *rd, const tc__jpath *p, const char *name, const tc__field *fields, int nf,
                         int with_opts) {
    int best = -1, best_d = 3; /* suggest only names within 2 edits */
    for (int i = 0; i < nf + (with_opts ? tc_opt_count() : 0); i++) {
        const char *known = slot_name(fields, nf, i);
        int d = edit_distance(name, known);
        if (d < best_d && d < (int)strlen(known)) best = i, best_d = d;
    }
    if (best >= 0)
        tc__rd_warning(rd, p, "unknown field '%.60s' ignored (did you mean '%s'?)", name, slot_name(fields, nf, best));
    else
        tc__rd_warning(rd, p, "unknown field '%.60s' ignored", name);
}

/* Sorts the members of obj into found[nf] by fields[] (and, with_opts, the
 * options into found[nf .. nf + tc_opt_count())): unknown names warn, a name given
 * twice is a shape error. what describes obj for a type error. */
int tc__rd_sort_members(tc__reader *rd, const cJSON *obj, const tc__jpath *p, const tc__field *fields, int nf,
                        int with_opts, const cJSON **found, const char *what) {
    if (!tc__json_is(obj, cJSON_Object)) {
        tc__rd_shape_error(rd, p, "expected %s, got %s", what, tc__json_kind(obj));
        return -1;
    }
    for (int i = 0; i < nf + (with_opts ? tc_opt_count() : 0); i++) found[i] = NULL;
    for (const cJSON *m = obj->child; m; m = m->next) {
        const char *name = m->string ? m->string : "";
        tc__jpath pm = tc__jpath_key(p, name);
        int i = member_slot(fields, nf, with_opts, name);
        if (i < 0)
            warn_unknown(rd, &pm, name, fields, nf, with_opts);
        else if (found[i])
            tc__rd_shape_error(rd, &pm, "field '%s' given more than once", name);
        else
            found[i] = m;
    }
    return 0;
}

int tc__rd_members(tc__reader *rd, const cJSON *obj, const tc__jpath *p, const tc__field *fields, int nf,
                   const cJSON **found, const char *what) {
    return tc__rd_sort_members(rd, obj, p, fields, nf, 0, found, what);
}

/* A required integer member of an object entry (e.g. corner_values[2].triangle). */
void tc__rd_member_int(tc__reader *rd, const cJSON *v, const tc__jpath *obj, const char *name,
                       int32_t *out) {
    tc__jpath p = tc__jpath_key(obj, name);
    if (!v)
        tc__rd_shape_error(rd, &p, "missing required field '%s' (a %s index)", name, name);
    else
        tc__rd_int(rd, v, &p, out);
}

/* The element an entry names: "triangle" on a mesh of triangles, "quad" on
 * one of quads (found[0] and found[1] hold the two members); the other name is
 * refused, since its index would mean something else. Corner counts follow. */
void tc__rd_member_elem(tc__reader *rd, const cJSON *const found[2], const tc__jpath *obj, int required,
                        int32_t *out) {
    const char *want = rd->quads ? "quad" : "triangle", *other = rd->quads ? "triangle" : "quad";
    const cJSON *v = found[rd->quads], *bad = found[!rd->quads];
    if (bad) {
        tc__jpath p = tc__jpath_key(obj, other);
        tc__rd_value_error(rd, &p, "this mesh is given as %ss: name the %s ('%s': index)", want, want, want);
        return;
    }
    if (v || required) tc__rd_member_int(rd, v, obj, want, out);
}

int tc__rd_bool(tc__reader *rd, const cJSON *v, const tc__jpath *p, int *out) {
    if (!tc__json_is(v, cJSON_True) && !tc__json_is(v, cJSON_False)) {
        tc__rd_shape_error(rd, p, "expected true or false, got %s", tc__json_kind(v));
        return -1;
    }
    *out = tc__json_is(v, cJSON_True);
    return 0;
}
