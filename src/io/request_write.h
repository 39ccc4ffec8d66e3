/* request_write.h — the inverse of request.h: a tc_mesh_desc (and options) as a
 * complete JSON request in the format request.h reads, every number exact. */
#ifndef TC_IO_REQUEST_WRITE_H
#define TC_IO_REQUEST_WRITE_H

#include "io/strbuf.h"
#include "tocher.h"

/* Appends one JSON object followed by a newline: "vertices", "triangles"
 * (or "quads" for a mesh given as quads), "values" (plain numbers when there
 * is one channel), then whichever of "corner_values", "gradients", "normals",
 * "hessians", "corner_gradients", "midpoints" (with "triangle" when a sample
 * belongs to one side) and "discontinuities" the description has (entries a
 * mask marks absent are null; per-corner entries name a "quad" with 4 corners
 * on a quad mesh), then the option rows in their order (io/options.h): when o
 * is not NULL "method" and the options that method reads, and the mesh options
 * that differ from tc_mesh_desc_init's ("value_tolerance", "degenerate").
 * Numbers go through tc_strbuf_double, so tc_request_parse reads back the same
 * doubles.
 * Allocation failure is left in b->oom. */
void tc_json_request(tc_strbuf *b, const tc_mesh_desc *d, const tc_options *o);

#endif
