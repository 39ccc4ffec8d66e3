/* request_mesh.c — the request's mesh fields: vertices, triangles or quads, values, corner
 * values, midpoints, gradients, normals, hessians, corner gradients, discontinuities, points. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "io/reader.h"
#include "io/request_fields.h"
#include "io/typed.h"

/* ---- fields: geometry ------------------------------------------------------------- */

/* ---- typed arrays (io/typed.h) in place of the big JSON arrays ---------------------- */

/* The first length of t (its entries) must be at most max: 0, or -1 after reporting. */
static int typed_entries(tc__reader *rd, const tc__typed *t, const tc__jpath *p, size_t max) {
    if (t->shape[0] <= max) return 0;
    tc__rd_value_error(rd, p, "too many entries (%zu, at most %zu)", t->shape[0], max);
    return -1;
}

/* A typed [n, 2] array of points into a new [n][2] array. */
static int typed_xy(tc__reader *rd, const cJSON *v, const tc__jpath *p, size_t max, size_t *n_out, double **xy_out) {
    static const size_t dims[2] = {0, 2};
    tc__typed t;
    if (tc__rd_typed(rd, v, p, 0, &t) || tc__typed_dims(rd, &t, p, 2, dims, "[n, 2]") ||
        typed_entries(rd, &t, p, max))
        return -1;
    double *xy = tc__rd_alloc(rd, t.shape[0], 2 * sizeof *xy);
    if (t.count && !xy) return -1;
    tc__typed_doubles(rd, &t, p, xy); /* element errors are counted, as in the JSON form */
    *n_out = t.shape[0];
    *xy_out = xy;
    return 0;
}

/* A typed [n, k] array of int32 or uint32 indices into a new [n][k] array; n, or -1. */
static int64_t typed_elements(tc__reader *rd, const cJSON *v, const tc__jpath *p, int k, size_t max, int32_t **out) {
    size_t dims[2] = {0, (size_t)k};
    char expected[16];
    snprintf(expected, sizeof expected, "[n, %d]", k);
    tc__typed t;
    if (tc__rd_typed(rd, v, p, 1, &t) || tc__typed_dims(rd, &t, p, 2, dims, expected) ||
        typed_entries(rd, &t, p, max))
        return -1;
    int32_t *idx = tc__rd_alloc(rd, t.count, sizeof *idx);
    if (t.count && !idx) return -1;
    tc__typed_indices(rd, &t, p, idx);
    *out = idx;
    return (int64_t)t.shape[0];
}

/* A typed [n] (one channel, plain numbers) or [n, C] array of values. */
static void typed_values(tc__reader *rd, const cJSON *v, const tc__jpath *p) {
    tc__typed t;
    char shape[96];
    if (tc__rd_typed(rd, v, p, 0, &t)) return;
    if (t.ndim > 2) {
        tc__rd_shape_error(rd, p, "shape %s: expected [n] or [n, C]", tc__typed_shape_text(&t, shape, sizeof shape));
        return;
    }
    if (t.ndim == 2 && (t.shape[1] < 1 || t.shape[1] > TC_MAX_CHANNELS)) {
        tc__rd_value_error(rd, p, "shape %s: %zu channels, expected 1 to %d", tc__typed_shape_text(&t, shape, sizeof shape),
                           t.shape[1], TC_MAX_CHANNELS);
        return;
    }
    if (typed_entries(rd, &t, p, INT32_MAX)) return;
    rd->nchan = t.ndim == 2 ? (int)t.shape[1] : 1;
    rd->r->values_plain = t.ndim == 1;
    tc__rd_per_vertex(rd, p, t.shape[0]);
    double *z = tc__rd_alloc(rd, t.count, sizeof *z);
    if (t.count && !z) return;
    tc__typed_doubles(rd, &t, p, z);
    rd->r->desc.nchan = rd->nchan;
    rd->r->desc.values = z;
}

/* A typed [n, C, dim] array of per-vertex vectors (also [n, dim] for one channel):
 * every vertex has one (the JSON form's null is not expressible; mask stays NULL). */
static void typed_vertex_vectors(tc__reader *rd, const cJSON *v, const tc__jpath *p, int dim, const double **data) {
    size_t C = (size_t)rd->nchan, d3[3] = {0, C, (size_t)dim}, d2[2] = {0, (size_t)dim};
    char expected[64];
    if (C == 1) snprintf(expected, sizeof expected, "[n, %d] or [n, 1, %d]", dim, dim);
    else snprintf(expected, sizeof expected, "[n, %zu, %d] (%zu channels, as values)", C, dim, C);
    tc__typed t;
    if (tc__rd_typed(rd, v, p, 0, &t)) return;
    int plain = C == 1 && t.ndim == 2;
    if (tc__typed_dims(rd, &t, p, plain ? 2 : 3, plain ? d2 : d3, expected) || typed_entries(rd, &t, p, INT32_MAX))
        return;
    tc__rd_per_vertex(rd, p, t.shape[0]);
    double *g = tc__rd_alloc(rd, t.count, sizeof *g);
    if (t.count && !g) return;
    tc__typed_doubles(rd, &t, p, g);
    *data = g;
}

/* ---- fields: geometry ------------------------------------------------------------- */

/* [[x, y], ...] (or a typed [n, 2]) into a new [n][2] array (vertices, points). */
static int xy_list(tc__reader *rd, const cJSON *v, const tc__jpath *p, size_t max, size_t *n_out, double **xy_out);

/* A fast array (request_fast.c) of [x, y] entries: copied as is. */
static int fast_xy(tc__reader *rd, tc__fast *f, const tc__jpath *p, size_t max, size_t *n_out,
                   double **xy_out) {
    if (tc__rd_fast_entries(rd, f, p, max)) return -1;
    double *xy = tc__rd_fast_take(rd, f);
    if (!xy) return -1;
    *n_out = f->n;
    *xy_out = xy;
    return 0;
}

int tc__rd_xy_list(tc__reader *rd, const cJSON *v, const tc__jpath *p, size_t max, size_t *n_out,
                   double **xy_out) {
    tc__fast *f = tc__rd_fast(rd, v);
    if (f && f->d1 == 2 && f->d2 == 0) return fast_xy(rd, f, p, max, n_out, xy_out);
    if (!f) return xy_list(rd, v, p, max, n_out, xy_out);
    cJSON *tree = tc__rd_fast_json(rd, f);
    if (!tree) return -1;
    int rc = xy_list(rd, tree, p, max, n_out, xy_out);
    cJSON_Delete(tree);
    return rc;
}

static int xy_list(tc__reader *rd, const cJSON *v, const tc__jpath *p, size_t max, size_t *n_out, double **xy_out) {
    size_t n;
    if (tc__is_typed(v)) return typed_xy(rd, v, p, max, n_out, xy_out);
    if (tc__rd_array(rd, v, p, "an array of points [[x, y], ...]", max, &n)) return -1;
    double *xy = tc__rd_alloc(rd, n, 2 * sizeof *xy);
    if (n && !xy) return -1;
    size_t i = 0;
    for (const cJSON *e = v->child; e; e = e->next, i++) {
        tc__jpath pi = tc__jpath_index(p, i);
        tc__rd_numbers(rd, e, &pi, 2, xy + 2 * i, "[x, y]");
    }
    *n_out = n;
    *xy_out = xy;
    return 0;
}

void tc__parse_vertices(tc__reader *rd, const cJSON *v, const tc__jpath *p) {
    size_t n;
    double *xy;
    if (tc__rd_xy_list(rd, v, p, INT32_MAX, &n, &xy)) return;
    rd->r->desc.nverts = (int32_t)n;
    rd->r->desc.xy = xy;
    rd->nverts_known = 1;
}

/* [[i, j, ...], ...], k indices each (what: "[i, j, k]"), at most max of them, into a
 * new [n][k] array; returns n, or -1 after reporting. */
static int64_t elements_json(tc__reader *rd, const cJSON *v, const tc__jpath *p, int k, size_t max,
                             const char *array_what, const char *what, int32_t **out);

/* A fast array of k-index entries, all integers within int32 (as tc__rd_int requires):
 * converted; n, or -1. Returns -2, before any finding or allocation, when some entry is
 * not such an index: the caller then reads the text through cJSON for the messages. */
static int64_t fast_elements(tc__reader *rd, tc__fast *f, const tc__jpath *p, int k, size_t max,
                             int32_t **out) {
    size_t m = f->n * (size_t)k;
    for (size_t j = 0; j < m; j++) {
        double d = f->data[j];
        if (d != floor(d) || d < INT32_MIN || d > INT32_MAX) return -2;
    }
    if (tc__rd_fast_entries(rd, f, p, max)) return -1;
    char *buf = tc__rd_fast_take(rd, f);
    if (!buf) return -1;
    /* Narrowed in place: index j's 4 bytes go where double j/2 was, already read (j/2 <= j);
     * memcpy, as the bytes change type. */
    for (size_t j = 0; j < m; j++) {
        double d;
        memcpy(&d, buf + j * sizeof d, sizeof d);
        int32_t v = (int32_t)d;
        memcpy(buf + j * sizeof v, &v, sizeof v);
    }
    *out = (int32_t *)(void *)buf;
    return (int64_t)f->n;
}

static int64_t read_elements(tc__reader *rd, const cJSON *v, const tc__jpath *p, int k, size_t max,
                             const char *array_what, const char *what, int32_t **out) {
    tc__fast *f = tc__rd_fast(rd, v);
    int64_t n = f && f->d1 == k && f->d2 == 0 ? fast_elements(rd, f, p, k, max, out) : -2;
    if (n != -2) return n;
    if (!f) return elements_json(rd, v, p, k, max, array_what, what, out);
    cJSON *tree = tc__rd_fast_json(rd, f);
    if (!tree) return -1;
    n = elements_json(rd, tree, p, k, max, array_what, what, out);
    cJSON_Delete(tree);
    return n;
}

static int64_t elements_json(tc__reader *rd, const cJSON *v, const tc__jpath *p, int k, size_t max,
                             const char *array_what, const char *what, int32_t **out) {
    size_t n, i = 0;
    if (tc__is_typed(v)) return typed_elements(rd, v, p, k, max, out);
    if (tc__rd_array(rd, v, p, array_what, max, &n)) return -1;
    int32_t *idx = tc__rd_alloc(rd, n, (size_t)k * sizeof *idx);
    if (n && !idx) return -1;
    for (const cJSON *e = v->child; e; e = e->next, i++) {
        tc__jpath pi = tc__jpath_index(p, i);
        tc__rd_ints(rd, e, &pi, k, idx + (size_t)k * i, what);
    }
    *out = idx;
    return (int64_t)n;
}

void tc__parse_quads(tc__reader *rd, const cJSON *v, const tc__jpath *p) {
    int32_t *quads = NULL;
    int64_t n = read_elements(rd, v, p, 4, INT32_MAX / 2, "an array of quads [[a, b, c, d], ...]", "[a, b, c, d]",
                              &quads);
    if (n < 0) return;
    rd->r->desc.nquads = (int32_t)n;
    rd->r->desc.quads = quads;
}

void tc__parse_triangles(tc__reader *rd, const cJSON *v, const tc__jpath *p) {
    int32_t *tris = NULL;
    int64_t n = read_elements(rd, v, p, 3, INT32_MAX, "an array of triangles [[i, j, k], ...]", "[i, j, k]", &tris);
    if (n < 0) return;
    rd->r->desc.ntris = (int32_t)n;
    rd->r->desc.tris = tris;
}

void tc__parse_points(tc__reader *rd, const cJSON *v, const tc__jpath *p) {
    size_t n;
    double *xy;
    if (tc__rd_xy_list(rd, v, p, SIZE_MAX / 2 / sizeof(double), &n, &xy)) return;
    rd->r->npoints = n;
    rd->r->points = xy;
}

/* ---- fields: samples ------------------------------------------------------------- */

/* values[0] fixes the channel count C (and whether responses use plain numbers). */
static int channels_from_first(tc__reader *rd, const cJSON *first, const tc__jpath *p) {
    tc__jpath p0 = tc__jpath_index(p, 0);
    if (!first || tc__json_is(first, cJSON_Number)) { /* no entries: nothing to disagree with */
        rd->nchan = 1;
        rd->r->values_plain = 1;
        return 0;
    }
    if (!tc__json_is(first, cJSON_Array)) {
        tc__rd_shape_error(rd, &p0, "expected a number or an array of channel values [z1, ..., zC], got %s",
                           tc__json_kind(first));
        return -1;
    }
    size_t k = tc__json_count(first);
    if (k < 1 || k > TC_MAX_CHANNELS) {
        tc__rd_value_error(rd, &p0, "%zu channels, expected 1 to %d", k, TC_MAX_CHANNELS);
        return -1;
    }
    rd->nchan = (int)k;
    return 0;
}

static void values_json(tc__reader *rd, const cJSON *v, const tc__jpath *p);

/* A fast array of values: plain numbers (one channel) or [z1..zC] entries, C within
 * 1..TC_MAX_CHANNELS (tc__parse_values' checks, in its order); 0, or -1 for another shape. */
static int fast_values(tc__reader *rd, tc__fast *f, const tc__jpath *p) {
    if (f->d2 != 0 || f->d1 > TC_MAX_CHANNELS) return -1;
    if (tc__rd_fast_entries(rd, f, p, INT32_MAX)) return 0;
    rd->nchan = f->d1 ? f->d1 : 1;
    if (!f->d1) rd->r->values_plain = 1;
    tc__rd_per_vertex(rd, p, f->n);
    double *z = tc__rd_fast_take(rd, f);
    if (!z) return 0;
    rd->r->desc.nchan = rd->nchan;
    rd->r->desc.values = z;
    return 0;
}

void tc__parse_values(tc__reader *rd, const cJSON *v, const tc__jpath *p) {
    tc__fast *f = tc__rd_fast(rd, v);
    if (!f) return values_json(rd, v, p);
    if (!fast_values(rd, f, p)) return;
    cJSON *tree = tc__rd_fast_json(rd, f);
    if (!tree) return;
    values_json(rd, tree, p);
    cJSON_Delete(tree);
}

static void values_json(tc__reader *rd, const cJSON *v, const tc__jpath *p) {
    size_t n, i = 0;
    if (tc__is_typed(v)) {
        typed_values(rd, v, p);
        return;
    }
    if (tc__rd_array(rd, v, p, "an array of per-vertex values [z, ...] or [[z1, ..., zC], ...]",
                     INT32_MAX, &n))
        return;
    if (channels_from_first(rd, v->child, p)) return;
    tc__rd_per_vertex(rd, p, n);
    size_t C = (size_t)rd->nchan;
    double *z = tc__rd_alloc(rd, n, C * sizeof *z);
    if (n && !z) return;
    for (const cJSON *e = v->child; e; e = e->next, i++) {
        tc__jpath pi = tc__jpath_index(p, i);
        tc__rd_channels(rd, e, &pi, z + i * C);
    }
    rd->r->desc.nchan = rd->nchan;
    rd->r->desc.values = z;
}

static const tc__field corner_value_fields[] = {
    {"triangle", NULL, 0, "t"},
    {"quad", NULL, 0, "q"},
    {"values", NULL, 0, "[za, zb, zc]"},
};

/* Corners per entry, and how their list is shown in messages. */
static int entry_corners(const tc__reader *rd) { return rd->quads ? 4 : 3; }

/* The shape both per-corner lists share: {"triangle": t, key: [one per
 * corner]} (on a quad mesh {"quad": q, key: [four]}). Reads the element into
 * *tri and returns the corner array with its path in *pk, or NULL after
 * reporting what is wrong. fields: the entry's three fields (triangle, quad, key). */
static const cJSON *corner_entry(tc__reader *rd, const cJSON *e, const tc__jpath *p, const tc__field *fields,
                                 const char *tri_list, const char *quad_list, int32_t *tri, tc__jpath *pk) {
    const cJSON *f[3];
    char buf[48], what[96];
    int nk = entry_corners(rd);
    const char *key = fields[2].name, *list = rd->quads ? quad_list : tri_list;
    snprintf(what, sizeof what, "an object {\"%s\": %s, \"%s\": %s}", rd->quads ? "quad" : "triangle",
             rd->quads ? "q" : "t", key, list);
    if (tc__rd_members(rd, e, p, fields, 3, f, what)) return NULL;
    tc__rd_member_elem(rd, f, p, 1, tri);
    *pk = tc__jpath_key(p, key);
    const cJSON *list_v = f[2];
    if (!list_v) {
        tc__rd_shape_error(rd, pk, "missing required field '%s' (the %d corner %s %s)", key, nk, key, list);
        return NULL;
    }
    if (!tc__json_is(list_v, cJSON_Array) || tc__json_count(list_v) != (size_t)nk) {
        tc__rd_shape_error(rd, pk, "expected an array of %d corner %s %s, got %s", nk, key, list,
                           tc__json_describe(list_v, buf, sizeof buf));
        return NULL;
    }
    return list_v;
}

/* {"triangle": t, "values": [za, zb, zc]} into *tri and z[3][C]; on a quad
 * mesh {"quad": q, "values": [za, zb, zc, zd]} into *tri and z[4][C]. */
static void read_corner_value(tc__reader *rd, const cJSON *e, const tc__jpath *p, int32_t *tri, double *z) {
    tc__jpath pv;
    const cJSON *vals = corner_entry(rd, e, p, corner_value_fields, "[za, zb, zc]", "[za, zb, zc, zd]", tri, &pv);
    if (!vals) return;
    size_t k = 0, C = (size_t)rd->nchan;
    for (const cJSON *c = vals->child; c; c = c->next, k++) {
        tc__jpath pk = tc__jpath_index(&pv, k);
        tc__rd_channels(rd, c, &pk, z + k * C);
    }
}

void tc__parse_corner_values(tc__reader *rd, const cJSON *v, const tc__jpath *p) {
    size_t n, i = 0;
    if (!rd->nchan) return; /* values unreadable: already reported, C unknown */
    if (tc__rd_array(rd, v, p, "an array of {\"triangle\": t, \"values\": [za, zb, zc]}", INT32_MAX, &n))
        return;
    size_t C = (size_t)rd->nchan, nk = (size_t)entry_corners(rd);
    int32_t *tri = tc__rd_alloc(rd, n, sizeof *tri);
    double *z = tc__rd_alloc(rd, n, nk * C * sizeof *z);
    if (n && (!tri || !z)) return;
    for (const cJSON *e = v->child; e; e = e->next, i++) {
        tc__jpath pi = tc__jpath_index(p, i);
        read_corner_value(rd, e, &pi, &tri[i], z + i * nk * C);
    }
    rd->r->desc.ncorner_values = (int32_t)n;
    rd->r->desc.corner_values_tri = tri;
    rd->r->desc.corner_values = z;
}

static const tc__field midpoint_fields[] = {
    {"edge", NULL, 0, "[i, j]"},
    {"value", NULL, 0, "z or [z1, ..., zC]"},
    {"triangle", NULL, 0, "t"},
    {"quad", NULL, 0, "q"},
};
enum { MP_EDGE, MP_VALUE, MP_TRIANGLE, MP_QUAD, MP_NFIELDS };

/* {"edge": [i, j], "value": z, "triangle": t (optional)} into edge[2], *tri, z[C]. */
static void read_midpoint(tc__reader *rd, const cJSON *e, const tc__jpath *p, int32_t *edge, int32_t *tri,
                          double *z) {
    const cJSON *f[MP_NFIELDS];
    if (tc__rd_members(rd, e, p, midpoint_fields, MP_NFIELDS, f,
                       "an object {\"edge\": [i, j], \"value\": z}"))
        return;
    tc__jpath pe = tc__jpath_key(p, "edge"), pv = tc__jpath_key(p, "value");
    if (!f[MP_EDGE])
        tc__rd_shape_error(rd, &pe, "missing required field 'edge' (the edge's vertex indices [i, j])");
    else
        tc__rd_ints(rd, f[MP_EDGE], &pe, 2, edge, "[i, j]");
    if (!f[MP_VALUE])
        tc__rd_shape_error(rd, &pv, "missing required field 'value' (the sample at the edge midpoint)");
    else
        tc__rd_channels(rd, f[MP_VALUE], &pv, z);
    *tri = -1; /* both sides, unless it names one */
    tc__rd_member_elem(rd, f + MP_TRIANGLE, p, 0, tri);
}

void tc__parse_midpoints(tc__reader *rd, const cJSON *v, const tc__jpath *p) {
    size_t n, i = 0;
    if (!rd->nchan) return;
    if (tc__rd_array(rd, v, p, "an array of {\"edge\": [i, j], \"value\": z}", INT32_MAX, &n)) return;
    size_t C = (size_t)rd->nchan;
    int32_t *edge = tc__rd_alloc(rd, n, 2 * sizeof *edge);
    int32_t *tri = tc__rd_alloc(rd, n, sizeof *tri);
    double *z = tc__rd_alloc(rd, n, C * sizeof *z);
    if (n && (!edge || !tri || !z)) return;
    for (const cJSON *e = v->child; e; e = e->next, i++) {
        tc__jpath pi = tc__jpath_index(p, i);
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
static void vertex_vectors_json(tc__reader *rd, const cJSON *v, const tc__jpath *p, int dim,
                                const char *what, const double **data, const uint8_t **mask);

/* A fast array of per-vertex vectors (no nulls: the scan refuses them): one [dim] vector per
 * entry when there is one channel, or [C][dim]; 0, or -1 for another shape. */
static int fast_vertex_vectors(tc__reader *rd, tc__fast *f, const tc__jpath *p, int dim,
                               const double **data, const uint8_t **mask) {
    int C = rd->nchan;
    if (!((C == 1 && f->d1 == dim && f->d2 == 0) || (f->d1 == C && f->d2 == dim))) return -1;
    if (tc__rd_fast_entries(rd, f, p, INT32_MAX)) return 0;
    tc__rd_per_vertex(rd, p, f->n);
    double *g = tc__rd_fast_take(rd, f);
    uint8_t *m = g ? tc__rd_alloc(rd, f->n, 1) : NULL; /* as the JSON path, though every vertex has one */
    if (!g || !m) return 0;
    *data = g;
    *mask = NULL;
    return 0;
}

static void read_vertex_vectors(tc__reader *rd, const cJSON *v, const tc__jpath *p, int dim,
                                const char *what, const double **data, const uint8_t **mask) {
    if (!rd->nchan) return;
    tc__fast *f = tc__rd_fast(rd, v);
    if (!f) return vertex_vectors_json(rd, v, p, dim, what, data, mask);
    if (!fast_vertex_vectors(rd, f, p, dim, data, mask)) return;
    cJSON *tree = tc__rd_fast_json(rd, f);
    if (!tree) return;
    vertex_vectors_json(rd, tree, p, dim, what, data, mask);
    cJSON_Delete(tree);
}

static void vertex_vectors_json(tc__reader *rd, const cJSON *v, const tc__jpath *p, int dim,
                                const char *what, const double **data, const uint8_t **mask) {
    char shape[96];
    size_t n, i = 0;
    if (tc__is_typed(v)) {
        typed_vertex_vectors(rd, v, p, dim, data);
        return;
    }
    snprintf(shape, sizeof shape, "an array of per-vertex %s (null where not given)", what);
    if (tc__rd_array(rd, v, p, shape, INT32_MAX, &n)) return;
    tc__rd_per_vertex(rd, p, n);
    size_t stride = (size_t)rd->nchan * (size_t)dim;
    double *g = tc__rd_alloc(rd, n, stride * sizeof *g);
    uint8_t *m = tc__rd_alloc(rd, n, 1);
    if (n && (!g || !m)) return;
    int all = 1;
    for (const cJSON *e = v->child; e; e = e->next, i++) {
        tc__jpath pi = tc__jpath_index(p, i);
        if (tc__json_is(e, cJSON_NULL)) {
            all = 0; /* m[i] stays 0, g zero-filled */
            continue;
        }
        m[i] = 1;
        tc__rd_channel_vectors(rd, e, &pi, dim, what, g + i * stride);
    }
    *data = g;
    *mask = all ? NULL : m;
}

void tc__parse_gradients(tc__reader *rd, const cJSON *v, const tc__jpath *p) {
    read_vertex_vectors(rd, v, p, 2, "[gx, gy]", &rd->r->desc.gradients,
                        &rd->r->desc.gradients_mask);
}

void tc__parse_normals(tc__reader *rd, const cJSON *v, const tc__jpath *p) {
    read_vertex_vectors(rd, v, p, 3, "[nx, ny, nz]", &rd->r->desc.normals,
                        &rd->r->desc.normals_mask);
}

void tc__parse_hessians(tc__reader *rd, const cJSON *v, const tc__jpath *p) {
    read_vertex_vectors(rd, v, p, 3, "[fxx, fxy, fyy]", &rd->r->desc.hessians,
                        &rd->r->desc.hessians_mask);
}

static const tc__field corner_gradient_fields[] = {
    {"triangle", NULL, 0, "t"},
    {"quad", NULL, 0, "q"},
    {"gradients", NULL, 0, "[g_a, g_b, g_c]"},
};

/* {"triangle": t, "gradients": [g_a, g_b, g_c]} into *tri, g[3][C][2], mask[3]
 * (on a quad mesh {"quad": q, "gradients": [g_a, g_b, g_c, g_d]}, 4 corners);
 * returns 0 if some corner is null (not given). */
static int read_corner_gradient(tc__reader *rd, const cJSON *e, const tc__jpath *p, int32_t *tri,
                                double *g, uint8_t *mask) {
    tc__jpath pg;
    const cJSON *gs = corner_entry(rd, e, p, corner_gradient_fields, "[g_a, g_b, g_c]", "[g_a, g_b, g_c, g_d]", tri,
                                   &pg);
    if (!gs) return 1;
    int all = 1;
    size_t k = 0, stride = 2 * (size_t)rd->nchan;
    for (const cJSON *c = gs->child; c; c = c->next, k++) {
        tc__jpath pk = tc__jpath_index(&pg, k);
        if (tc__json_is(c, cJSON_NULL)) {
            all = 0;
            continue;
        }
        mask[k] = 1;
        tc__rd_channel_vectors(rd, c, &pk, 2, "[gx, gy]", g + k * stride);
    }
    return all;
}

void tc__parse_corner_gradients(tc__reader *rd, const cJSON *v, const tc__jpath *p) {
    size_t n, i = 0;
    if (!rd->nchan) return;
    if (tc__rd_array(rd, v, p, "an array of {\"triangle\": t, \"gradients\": [g_a, g_b, g_c]}",
                     INT32_MAX, &n))
        return;
    size_t nk = (size_t)entry_corners(rd), stride = nk * 2 * (size_t)rd->nchan;
    int32_t *tri = tc__rd_alloc(rd, n, sizeof *tri);
    double *g = tc__rd_alloc(rd, n, stride * sizeof *g);
    uint8_t *mask = tc__rd_alloc(rd, n, nk);
    if (n && (!tri || !g || !mask)) return;
    int all = 1;
    for (const cJSON *e = v->child; e; e = e->next, i++) {
        tc__jpath pi = tc__jpath_index(p, i);
        all &= read_corner_gradient(rd, e, &pi, &tri[i], g + i * stride, mask + nk * i);
    }
    rd->r->desc.ncorner_gradients = (int32_t)n;
    rd->r->desc.corner_gradients_tri = tri;
    rd->r->desc.corner_gradients = g;
    rd->r->desc.corner_gradients_mask = all ? NULL : mask;
}

/* ---- fields: discontinuities --------------------------------------------------------- */

/* Shapes of the polylines and their total length, so verts is allocated once. */
static size_t polyline_total(tc__reader *rd, const cJSON *v, const tc__jpath *p) {
    size_t total = 0, i = 0;
    for (const cJSON *e = v->child; e; e = e->next, i++) {
        tc__jpath pi = tc__jpath_index(p, i);
        if (!tc__json_is(e, cJSON_Array)) {
            tc__rd_shape_error(rd, &pi, "expected a polyline: an array of at least 2 vertex indices, got %s",
                               tc__json_kind(e));
            continue;
        }
        size_t k = tc__json_count(e);
        if (k < 2) tc__rd_shape_error(rd, &pi, "a polyline needs at least 2 vertices, got %zu", k);
        total += k;
    }
    return total;
}

/* [[i, j, ...], ...] into a tc_polylines (start[count + 1] offsets into verts). */
static void read_polylines(tc__reader *rd, const cJSON *v, const tc__jpath *p, tc_polylines *out) {
    size_t n, i = 0, off = 0;
    if (tc__rd_array(rd, v, p, "an array of polylines [[i, j, ...], ...]", INT32_MAX - 1, &n)) return;
    size_t total = polyline_total(rd, v, p);
    if (total > INT32_MAX) {
        tc__rd_value_error(rd, p, "too many polyline vertices (%zu, at most %d)", total, INT32_MAX);
        return;
    }
    int32_t *start = tc__rd_alloc(rd, n + 1, sizeof *start);
    int32_t *verts = tc__rd_alloc(rd, total, sizeof *verts);
    if (!start || (total && !verts)) return;
    for (const cJSON *e = v->child; e; e = e->next, i++) {
        start[i] = (int32_t)off;
        if (!tc__json_is(e, cJSON_Array)) continue; /* reported by polyline_total */
        tc__jpath pi = tc__jpath_index(p, i);
        size_t k = 0;
        for (const cJSON *c = e->child; c; c = c->next, k++, off++) {
            tc__jpath pk = tc__jpath_index(&pi, k);
            tc__rd_int(rd, c, &pk, &verts[off]);
        }
    }
    start[n] = (int32_t)off;
    out->count = (int32_t)n;
    out->start = start;
    out->verts = verts;
}

static const tc__field discontinuity_fields[] = {
    {"c0", NULL, 0, "[[i, j, ...], ...]"},
    {"c-1", NULL, 0, "[[i, j, ...], ...]"},
};
enum { DC_C0, DC_CM1, DC_NFIELDS };

void tc__parse_discontinuities(tc__reader *rd, const cJSON *v, const tc__jpath *p) {
    const cJSON *f[DC_NFIELDS];
    if (tc__rd_members(rd, v, p, discontinuity_fields, DC_NFIELDS, f,
                       "an object {\"c0\": [[i, j, ...], ...], \"c-1\": [[i, j, ...], ...]}"))
        return;
    if (f[DC_C0]) {
        tc__jpath pc = tc__jpath_key(p, "c0");
        read_polylines(rd, f[DC_C0], &pc, &rd->r->desc.c0);
    }
    if (f[DC_CM1]) {
        tc__jpath pc = tc__jpath_key(p, "c-1");
        read_polylines(rd, f[DC_CM1], &pc, &rd->r->desc.cm1);
    }
}
