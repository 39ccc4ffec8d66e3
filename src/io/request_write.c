/* request_write.c — writes a mesh description as a request (the format request.h
 * reads): the scene front-end's output, readable by tc_request_parse to the same doubles. */
#include "io/request_write.h"
#include "io/jsonout.h"
#include "io/options.h"

/* ",\n" before every member but the first, then "name":. */
static void member(tc_strbuf *b, const char *name) { tc_json_key(b, ",\n", name); }

/* The separator before element i of an array whose elements go one per line. */
static void item(tc_strbuf *b, size_t i) { tc_strbuf_puts(b, i ? ",\n " : "\n "); }


/* One sample of C channels: a plain number when C == 1, else [z1..zC]. */
static void sample(tc_strbuf *b, const double *z, int nc) {
    if (nc == 1) tc_strbuf_double(b, z[0]);
    else tc_json_numbers(b, z, nc);
}

/* One tangent datum of dim numbers per channel: one vector when C == 1, else
 * one per channel. */
static void vectors(tc_strbuf *b, const double *g, int nc, int dim) {
    if (nc == 1) {
        tc_json_numbers(b, g, dim);
        return;
    }
    tc_strbuf_putc(b, '[');
    for (int ch = 0; ch < nc; ch++) {
        if (ch) tc_strbuf_putc(b, ',');
        tc_json_numbers(b, g + (size_t)ch * (size_t)dim, dim);
    }
    tc_strbuf_putc(b, ']');
}

/* A mesh given as quads (and not triangles) has 4 corners per element, and
 * its per-corner entries name quads. */
static int is_quads(const tc_mesh_desc *d) { return d->nquads > 0 && d->ntris <= 0; }
static int corners(const tc_mesh_desc *d) { return is_quads(d) ? 4 : 3; }
static const char *element(const tc_mesh_desc *d) { return is_quads(d) ? "quad" : "triangle"; }

/* ,"triangle": t or ,"quad": q (without the comma when first). */
static void element_member(tc_strbuf *b, const tc_mesh_desc *d, int32_t e, int first) {
    tc_strbuf_puts(b, first ? "\"" : ",\"");
    tc_strbuf_puts(b, element(d));
    tc_strbuf_puts(b, "\":");
    tc_strbuf_int(b, e);
}

static void geometry(tc_strbuf *b, const tc_mesh_desc *d) {
    int nk = corners(d);
    int32_t n = is_quads(d) ? d->nquads : d->ntris;
    const int32_t *el = is_quads(d) ? d->quads : d->tris;
    member(b, "vertices");
    tc_strbuf_putc(b, '[');
    for (int32_t v = 0; v < d->nverts && !b->oom; v++) item(b, (size_t)v), tc_json_numbers(b, d->xy + 2 * (size_t)v, 2);
    tc_strbuf_puts(b, "]");
    member(b, is_quads(d) ? "quads" : "triangles");
    tc_strbuf_putc(b, '[');
    for (int32_t t = 0; t < n && !b->oom; t++) item(b, (size_t)t), tc_json_ints(b, el + (size_t)nk * (size_t)t, nk);
    tc_strbuf_puts(b, "]");
}

static void values(tc_strbuf *b, const tc_mesh_desc *d) {
    int nc = d->nchan;
    member(b, "values");
    tc_strbuf_putc(b, '[');
    for (int32_t v = 0; v < d->nverts && !b->oom; v++) item(b, (size_t)v), sample(b, d->values + (size_t)v * (size_t)nc, nc);
    tc_strbuf_puts(b, "]");
    if (!d->ncorner_values) return;
    member(b, "corner_values");
    tc_strbuf_putc(b, '[');
    int nk = corners(d);
    for (int32_t i = 0; i < d->ncorner_values && !b->oom; i++) {
        item(b, (size_t)i);
        tc_strbuf_putc(b, '{');
        element_member(b, d, d->corner_values_tri[i], 1);
        tc_strbuf_puts(b, ",\"values\":[");
        for (int k = 0; k < nk; k++) {
            if (k) tc_strbuf_putc(b, ',');
            sample(b, d->corner_values + ((size_t)nk * (size_t)i + (size_t)k) * (size_t)nc, nc);
        }
        tc_strbuf_puts(b, "]}");
    }
    tc_strbuf_puts(b, "]");
}

/* "gradients" or "normals": one entry per vertex, null where the mask says absent. */
static void vertex_vectors(tc_strbuf *b, const char *name, const double *x, const uint8_t *mask,
                           const tc_mesh_desc *d, int dim) {
    if (!x) return;
    member(b, name);
    tc_strbuf_putc(b, '[');
    for (int32_t v = 0; v < d->nverts && !b->oom; v++) {
        item(b, (size_t)v);
        if (mask && !mask[v]) tc_strbuf_puts(b, "null");
        else vectors(b, x + (size_t)v * (size_t)d->nchan * (size_t)dim, d->nchan, dim);
    }
    tc_strbuf_puts(b, "]");
}

static void corner_gradients(tc_strbuf *b, const tc_mesh_desc *d) {
    if (!d->ncorner_gradients) return;
    size_t stride = 2 * (size_t)d->nchan, nk = (size_t)corners(d);
    member(b, "corner_gradients");
    tc_strbuf_putc(b, '[');
    for (int32_t i = 0; i < d->ncorner_gradients && !b->oom; i++) {
        item(b, (size_t)i);
        tc_strbuf_putc(b, '{');
        element_member(b, d, d->corner_gradients_tri[i], 1);
        tc_strbuf_puts(b, ",\"gradients\":[");
        for (size_t k = 0; k < nk; k++) {
            if (k) tc_strbuf_putc(b, ',');
            if (d->corner_gradients_mask && !d->corner_gradients_mask[nk * (size_t)i + k]) tc_strbuf_puts(b, "null");
            else vectors(b, d->corner_gradients + (nk * (size_t)i + k) * stride, d->nchan, 2);
        }
        tc_strbuf_puts(b, "]}");
    }
    tc_strbuf_puts(b, "]");
}

static void midpoints(tc_strbuf *b, const tc_mesh_desc *d) {
    if (!d->nmidpoints) return;
    member(b, "midpoints");
    tc_strbuf_putc(b, '[');
    for (int32_t i = 0; i < d->nmidpoints && !b->oom; i++) {
        item(b, (size_t)i);
        tc_strbuf_puts(b, "{\"edge\":");
        tc_json_ints(b, d->midpoint_edge + 2 * (size_t)i, 2);
        tc_strbuf_puts(b, ",\"value\":");
        sample(b, d->midpoint_values + (size_t)i * (size_t)d->nchan, d->nchan);
        if (d->midpoint_tri && d->midpoint_tri[i] >= 0) element_member(b, d, d->midpoint_tri[i], 0);
        tc_strbuf_putc(b, '}');
    }
    tc_strbuf_puts(b, "]");
}

static void polylines(tc_strbuf *b, const char *name, const tc_polylines *p, int *first) {
    if (!p->count) return;
    if (!*first) tc_strbuf_putc(b, ',');
    *first = 0;
    tc_strbuf_json_string(b, name);
    tc_strbuf_putc(b, ':');
    tc_strbuf_putc(b, '[');
    for (int32_t i = 0; i < p->count && !b->oom; i++) {
        item(b, (size_t)i);
        tc_json_ints(b, p->verts + p->start[i], p->start[i + 1] - p->start[i]);
    }
    tc_strbuf_puts(b, "]");
}

/* The option rows in order: when o is not NULL, "method" and the options it
 * reads (the rest would change nothing); the mesh options that differ from the
 * request format's defaults (left out they would read back as those). */
static void options(tc_strbuf *b, const tc_mesh_desc *d, const tc_options *o) {
    for (int i = 0; i < tc_opt_count(); i++) {
        const tc_opt *row = tc_opt_at(i);
        if (row->target == TC_OPT_MESH && !tc_opt_is_default(row, d)) tc_opt_write(b, ",\n", row, d);
        if (o && tc_opt_read_by(row, o->method)) tc_opt_write(b, ",\n", row, o);
    }
}

void tc_json_request(tc_strbuf *b, const tc_mesh_desc *d, const tc_options *o) {
    tc_strbuf_putc(b, '{');
    geometry(b, d);
    values(b, d);
    vertex_vectors(b, "gradients", d->gradients, d->gradients_mask, d, 2);
    vertex_vectors(b, "normals", d->normals, d->normals_mask, d, 3);
    vertex_vectors(b, "hessians", d->hessians, d->hessians_mask, d, 3);
    corner_gradients(b, d);
    midpoints(b, d);
    if (d->c0.count || d->cm1.count) {
        int first = 1;
        member(b, "discontinuities");
        tc_strbuf_putc(b, '{');
        polylines(b, "c0", &d->c0, &first);
        polylines(b, "c-1", &d->cm1, &first);
        tc_strbuf_putc(b, '}');
    }
    options(b, d, o);
    tc_strbuf_puts(b, "}\n");
}
