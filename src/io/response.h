/* response.h — JSON text of the core's results: ordinates, point values,
 * diagnostics and problem documents, every number printed exactly. */
#ifndef TC_IO_RESPONSE_H
#define TC_IO_RESPONSE_H

#include "io/strbuf.h"
#include "tocher.h"

/* The writers append object members ("name":value, comma-separated, no outer
 * braces) so callers can compose one object from several writers. */

/* "method", the options it used, "channels", "labels", "ordinates":
 * [triangle][channel][coefficient]. */
void tc_json_ordinates(tc_strbuf *b, const tc_recon *r);
/* The same; base64: "ordinates" as a typed float64 array [T][C][K] (T the triangles
 * given, K the coefficients), NaN rows where the JSON form has null (dropped triangles). */
void tc_json_ordinates_enc(tc_strbuf *b, const tc_recon *r, int base64);

/* "values" ([n] plain numbers when plain and one channel, else [n][C]),
 * "gradients" ([n][2] or [n][C][2]) when grads != NULL, "outside" (indices
 * of points outside the mesh, whose values and gradients are null). */
void tc_json_points(tc_strbuf *b, int nc, size_t n, const double *values, const double *grads,
                    const int32_t *tri, int plain);
/* The same; base64: "values" and "gradients" as typed float64 arrays of the JSON
 * form's shape ([n] or [n][C]; [n][2] or [n][C][2]), NaN where it has null. */
void tc_json_points_enc(tc_strbuf *b, int nc, size_t n, const double *values, const double *grads,
                        const int32_t *tri, int plain, int base64);
/* The same, calling stop(ctx) every few thousand points of the JSON form: when
 * it returns non-zero the output is abandoned unfinished and -1 returned (a
 * request past its deadline stops printing). 0 when written whole. */
int tc_json_points_enc_until(tc_strbuf *b, int nc, size_t n, const double *values, const double *grads,
                             const int32_t *tri, int plain, int base64, int (*stop)(void *), void *ctx);

/* "warnings": [{"path","message"}...] or "errors": [...] from d. */
void tc_json_diags(tc_strbuf *b, const char *member, const tc_diags *d, tc_severity sev);

#endif
