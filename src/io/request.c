/* request.c — the JSON request reader: the table of top-level fields and their
 * presence rules, JSON syntax errors with line and column, tc_request_parse. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/options.h"
#include "io/reader.h"
#include "io/request_fields.h"
#include "io/typed.h"

/* Roles of top-level fields, for the presence rules. */
enum {
    ROLE_MESH = 1,      /* vertices, triangles, values: all or none */
    ROLE_MESH_DATA = 2, /* meaningless without a mesh: makes the mesh required */
    ROLE_POINTS = 4,    /* required when TC_REQ_POINTS is expected */
    ROLE_VIEWPORT = 8,  /* required when TC_REQ_VIEWPORT is expected */
    ROLE_REFERENCE = 16 /* required when TC_REQ_REFERENCE is expected */
};

/* ---- the request ------------------------------------------------------------------- */

/* Every top-level field the service knows but the options (io/options.c). To
 * add one, add a row (and its parser).
 * Invariant: rows are parsed in this order, so a field comes after those it
 * depends on (vertices before per-vertex data; values, which fix the channel
 * count, before every other per-channel field). */
static const tc__field top_fields[] = {
    {"vertices", tc__parse_vertices, ROLE_MESH, "[[x, y], ...]"},
    {"triangles", tc__parse_triangles, ROLE_MESH, "[[i, j, k], ...] (or \"quads\": [[a, b, c, d], ...])"},
    {"quads", tc__parse_quads, ROLE_MESH_DATA, ""}, /* instead of triangles */
    {"values", tc__parse_values, ROLE_MESH, "[z, ...] or [[z1, ..., zC], ...]"},
    {"corner_values", tc__parse_corner_values, ROLE_MESH_DATA, ""},
    {"gradients", tc__parse_gradients, ROLE_MESH_DATA, ""},
    {"normals", tc__parse_normals, ROLE_MESH_DATA, ""},
    {"hessians", tc__parse_hessians, ROLE_MESH_DATA, ""},
    {"corner_gradients", tc__parse_corner_gradients, ROLE_MESH_DATA, ""},
    {"midpoints", tc__parse_midpoints, ROLE_MESH_DATA, ""},
    {"discontinuities", tc__parse_discontinuities, ROLE_MESH_DATA, ""},
    {"points", tc__parse_points, ROLE_POINTS, "[[x, y], ...]"},
    {"with_gradients", tc__parse_with_gradients, 0, ""},
    {"viewport", tc__parse_viewport, ROLE_VIEWPORT, "{x0, y0, x1, y1, width, height}"},
    {"format", tc__parse_format, 0, ""},
    {"exposure", tc__parse_exposure, 0, ""},
    {"overlay", tc__parse_overlay, 0, ""},
    {"linear", tc__parse_linear, 0, ""},
    {"background", tc__parse_background, 0, ""},
    {"reference", tc__parse_reference, ROLE_REFERENCE, "{points, values}"},
    {"encoding", tc__parse_encoding, 0, ""},
    {"methods", NULL, 0, ""}, /* after the options, which its entries start from */
};
#define NTOP ((int)(sizeof top_fields / sizeof top_fields[0]))

/* The mesh is all-or-nothing: required when the caller expects it or when any
 * mesh field is present. Points are required when expected. */
static void check_required(tc__reader *rd, const cJSON *const *found) {
    int want_mesh = (rd->expect & TC_REQ_MESH) != 0;
    for (int i = 0; i < NTOP; i++)
        if (found[i] && (top_fields[i].role & (ROLE_MESH | ROLE_MESH_DATA))) want_mesh = 1;
    for (int i = 0; i < NTOP; i++) {
        unsigned role = top_fields[i].role;
        int quads_instead =
            !strcmp(top_fields[i].name, "triangles") && found[tc__field_index(top_fields, NTOP, "quads")];
        int required = ((role & ROLE_MESH) && want_mesh && !quads_instead) ||
                       ((role & ROLE_POINTS) && (rd->expect & TC_REQ_POINTS)) ||
                       ((role & ROLE_VIEWPORT) && (rd->expect & TC_REQ_VIEWPORT)) ||
                       ((role & ROLE_REFERENCE) && (rd->expect & TC_REQ_REFERENCE));
        if (required && !found[i]) {
            tc__jpath p = tc__jpath_key(NULL, top_fields[i].name);
            tc__rd_shape_error(rd, &p, "missing required field '%s': expected %s", top_fields[i].name,
                               top_fields[i].shape);
        }
    }
    rd->r->has_mesh = want_mesh;
}

static void check_exclusive(tc__reader *rd, const cJSON *const *found) {
    if (found[tc__field_index(top_fields, NTOP, "gradients")] &&
        found[tc__field_index(top_fields, NTOP, "normals")]) {
        tc__jpath p = tc__jpath_key(NULL, "normals");
        tc__rd_value_error(rd, &p, "give either gradients or normals, not both");
    }
    if (found[tc__field_index(top_fields, NTOP, "triangles")] && found[tc__field_index(top_fields, NTOP, "quads")]) {
        tc__jpath p = tc__jpath_key(NULL, "quads");
        tc__rd_value_error(rd, &p, "give either triangles or quads, not both");
    }
}

static void read_request(tc__reader *rd, const cJSON *root) {
    const cJSON *found[NTOP + TC_OPT_MAX];
    if (tc__rd_sort_members(rd, root, NULL, top_fields, NTOP, 1, found, "a JSON object (the request)")) return;
    check_required(rd, found);
    rd->quads =
        found[tc__field_index(top_fields, NTOP, "quads")] && !found[tc__field_index(top_fields, NTOP, "triangles")];
    for (int i = 0; i < NTOP && !rd->nomem; i++) {
        if (!found[i] || !top_fields[i].parse) continue;
        tc__jpath p = tc__jpath_key(NULL, top_fields[i].name);
        top_fields[i].parse(rd, found[i], &p);
    }
    tc__rd_options(rd, found + NTOP);
    int methods = tc__field_index(top_fields, NTOP, "methods");
    if (found[methods] && !rd->nomem) {
        tc__jpath p = tc__jpath_key(NULL, "methods");
        tc__parse_methods(rd, found[methods], &p);
    }
    check_exclusive(rd, found);
}

/* ---- JSON syntax ------------------------------------------------------------------- */

/* Reports a syntax problem at byte pos as "line L, column C" (columns count
 * UTF-8 characters), with a short printable excerpt of the text there. */
static void syntax_error(tc__reader *rd, const char *json, size_t len, size_t pos, const char *what) {
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
        tc__rd_shape_error(rd, NULL, "%s at line %zu, column %zu (end of input)", what, line, col);
    else
        tc__rd_shape_error(rd, NULL, "%s at line %zu, column %zu, near '%s'", what, line, col, near);
}

/* Parses the text, requiring only whitespace (or NULs) after the value. Returns
 * the tree or NULL after reporting. */
static cJSON *parse_json(tc__reader *rd, const char *json, size_t len) {
    if (!json || len == 0) {
        tc__rd_shape_error(rd, NULL, "empty request: expected a JSON object");
        return NULL;
    }
    const char *end = json;
    /* require_null_terminated = 0: the buffer need not end in NUL; end marks
     * where parsing stopped (the error position on failure). A failed
     * allocation inside cJSON is indistinguishable from a syntax error here.
     * (cJSON also records the position in a global it never synchronizes; we
     * read only our own `end`, so concurrent parses do not mix positions.) */
    size_t tlen = len;
    char *skel = tc__rd_fast_scan(rd, json, len, &tlen); /* the big arrays, read here or not */
    const char *text = skel ? skel : json;
    if (rd->limits) { /* the arrays read fast are within theirs: count the rest of the body */
        tc_req_limits *L = rd->limits;
        L->over = tc_prescan(text, tlen, L->lim, L->n, &L->count);
        if (L->over >= 0) {
            free(skel);
            return NULL;
        }
    }
    end = text;
    cJSON *root = cJSON_ParseWithLengthOpts(text, tlen, &end, 0);
    size_t pos = (size_t)(end - text);
    if (skel) pos = tc__rd_fast_origin(rd, pos); /* errors point into json */
    free(skel);
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
    if (tc__rd_fast_bind(rd, root)) { /* never seen: the walk and the tree disagree; be safe */
        cJSON_Delete(root);
        tc__rd_fast_free(rd);
        root = cJSON_ParseWithLength(json, len);
        if (!root) rd->nomem = 1; /* the skeleton parsed, so the body does: only memory fails */
    }
    return root;
}

int tc_request_parse(const char *json, size_t len, unsigned expect, tc_request **out,
                     tc_diags *diags) {
    return tc_request_parse_for(json, len, expect, 0, out, diags);
}

static int parse(const char *json, size_t len, unsigned expect, int nchan, tc_req_limits *L, tc_request **out,
                 tc_diags *diags);

int tc_request_parse_for(const char *json, size_t len, unsigned expect, int nchan, tc_request **out,
                         tc_diags *diags) {
    return parse(json, len, expect, nchan, NULL, out, diags);
}

int tc_request_parse_limited(const char *json, size_t len, unsigned expect, tc_req_limits *L, tc_request **out,
                             tc_diags *diags) {
    return parse(json, len, expect, 0, L, out, diags);
}

static int parse(const char *json, size_t len, unsigned expect, int nchan, tc_req_limits *L, tc_request **out,
                 tc_diags *diags) {
    tc__reader rd = {.diags = diags, .expect = expect, .nchan = nchan, .json = json, .limits = L};
    if (L) L->over = -1, L->count = 0;
    *out = NULL;
    tc_request *r = tc__rd_injected_failure() ? NULL : calloc(1, sizeof *r);
    if (!r) {
        tc_diags_add(diags, TC_SEV_ERROR, "", "out of memory reading the request");
        return TC_REQ_NOMEM;
    }
    tc_options_default(&r->opt);
    tc_mesh_desc_init(&r->desc);
    r->format = -1;
    rd.r = r;
    cJSON *root = parse_json(&rd, json, len);
    if (L && L->over >= 0) { /* refused before any tree was built */
        tc__rd_fast_free(&rd);
        tc_request_free(r);
        return TC_REQ_OVER_LIMIT;
    }
    if (root) {
        tc__rd_expand_nested(&rd, root); /* typed arrays inside per-entry fields, as JSON */
        if (!rd.nomem) read_request(&rd, root);
        cJSON_Delete(root); /* the request keeps only its own arrays */
    }
    tc__rd_fast_free(&rd);
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
