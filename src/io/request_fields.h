/* request_fields.h — the parsers of the request's top-level fields, one file per
 * group (request_mesh.c, request_options.c, request_render.c); request.c's table lists them. */
#ifndef TC_IO_REQUEST_FIELDS_H
#define TC_IO_REQUEST_FIELDS_H

#include "io/reader.h"

/* request_mesh.c: the mesh and its samples. */
void tc__parse_vertices(tc__reader *rd, const cJSON *v, const tc__jpath *p);
void tc__parse_triangles(tc__reader *rd, const cJSON *v, const tc__jpath *p);
void tc__parse_quads(tc__reader *rd, const cJSON *v, const tc__jpath *p);
void tc__parse_values(tc__reader *rd, const cJSON *v, const tc__jpath *p);
void tc__parse_corner_values(tc__reader *rd, const cJSON *v, const tc__jpath *p);
void tc__parse_gradients(tc__reader *rd, const cJSON *v, const tc__jpath *p);
void tc__parse_normals(tc__reader *rd, const cJSON *v, const tc__jpath *p);
void tc__parse_hessians(tc__reader *rd, const cJSON *v, const tc__jpath *p);
void tc__parse_corner_gradients(tc__reader *rd, const cJSON *v, const tc__jpath *p);
void tc__parse_midpoints(tc__reader *rd, const cJSON *v, const tc__jpath *p);
void tc__parse_discontinuities(tc__reader *rd, const cJSON *v, const tc__jpath *p);
void tc__parse_points(tc__reader *rd, const cJSON *v, const tc__jpath *p);
/* [[x, y], ...] of at most max entries into a new [n][2] array (vertices, points,
 * reference points): 0, or -1 after reporting. */
int tc__rd_xy_list(tc__reader *rd, const cJSON *v, const tc__jpath *p, size_t max, size_t *n_out, double **xy_out);

/* request_options.c: the options found at the top level (found[j] for row j of
 * tc_opt_at) into the request's, then "methods", whose entries start from them. */
void tc__rd_options(tc__reader *rd, const cJSON *const *found);
void tc__parse_methods(tc__reader *rd, const cJSON *v, const tc__jpath *p);

/* request_render.c: what is answered. */
void tc__parse_with_gradients(tc__reader *rd, const cJSON *v, const tc__jpath *p);
void tc__parse_viewport(tc__reader *rd, const cJSON *v, const tc__jpath *p);
void tc__parse_format(tc__reader *rd, const cJSON *v, const tc__jpath *p);
void tc__parse_exposure(tc__reader *rd, const cJSON *v, const tc__jpath *p);
void tc__parse_overlay(tc__reader *rd, const cJSON *v, const tc__jpath *p);
void tc__parse_linear(tc__reader *rd, const cJSON *v, const tc__jpath *p);
void tc__parse_background(tc__reader *rd, const cJSON *v, const tc__jpath *p);
/* "encoding": how the answer's big arrays are written. */
void tc__parse_encoding(tc__reader *rd, const cJSON *v, const tc__jpath *p);
void tc__parse_reference(tc__reader *rd, const cJSON *v, const tc__jpath *p);

#endif
