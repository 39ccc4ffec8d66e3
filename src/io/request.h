/* request.h — reads a JSON request (the format of README.md and api/openapi.yaml) into a
 * tc_mesh_desc, options and points.
 * Shape errors and value errors are told apart so the server can answer 400 or 422. */
#ifndef TC_IO_REQUEST_H
#define TC_IO_REQUEST_H

#include <stddef.h>

#include "io/prescan.h"
#include "tocher.h"

/* Which parts a caller expects (bit flags for tc_request_parse's `expect`). */
enum { TC_REQ_MESH = 1, TC_REQ_POINTS = 2, TC_REQ_VIEWPORT = 4, TC_REQ_REFERENCE = 8 };

typedef enum {
    TC_REQ_OK = 0,
    TC_REQ_MALFORMED = 1, /* not JSON, or wrong JSON types/shapes, missing field -> HTTP 400 */
    TC_REQ_INVALID = 2,   /* well-formed JSON whose values are invalid -> HTTP 422 */
    TC_REQ_NOMEM = 3,     /* an allocation failed -> HTTP 500/503 */
    TC_REQ_OVER_LIMIT = 4 /* tc_request_parse_limited: an array over its limit -> HTTP 413 */
} tc_req_status;

/* Most reconstructions one /v1/compare request may ask for. */
#define TC_REQ_MAX_METHODS 32

/* Number of arrays a request can own; every parsed field owns at most a few. */
#define TC_REQ_OWNED_MAX 32

typedef struct tc_request {
    tc_mesh_desc desc;  /* every array owned by the request (valid while it lives); the
                         * mesh options default as tc_mesh_desc_init sets them */
    tc_options opt;     /* defaults (tc_options_default) unless the request names them */
    int has_mesh;       /* vertices/triangles/values were present */
    int values_plain;   /* "values" were plain numbers -> respond with plain numbers */
    size_t npoints;     /* "points": [[x,y],...] */
    double *points;     /* [npoints][2], NULL when npoints == 0 */
    int with_gradients; /* "with_gradients": true asks /v1/evaluate for gradients */
    int encoding_base64; /* "encoding": "base64": the answer's big arrays as typed arrays (float64) */

    /* /v1/render */
    int has_viewport;
    tc_viewport viewport; /* "viewport": {x0, y0, x1, y1, width, height} */
    int format;           /* "format" as a tc_img_format, or -1 when absent */
    double exposure;      /* "exposure": stops, for PNG (default 0) */
    int overlay;          /* "overlay": draw the mesh edges */
    int linear;           /* "linear": PNG without the sRGB transfer */
    int has_background;
    double background[TC_MAX_CHANNELS]; /* "background": value of pixels outside the mesh */

    /* /v1/compare */
    size_t nreference;         /* "reference": {"points": [[x, y], ...], "values": [...], "scale": s} */
    double *reference_points;  /* [nreference][2] */
    double *reference_values;  /* [nreference][C] */
    double reference_scale;    /* full scale for the mean relative error; 0 = max |values| */
    int nmethods;              /* "methods": ["linear", {"method": ..., "cross_boundary": ...}, ...] */
    tc_options methods[TC_REQ_MAX_METHODS];

    /* private: the allocations behind desc and points, freed by tc_request_free */
    void *owned_[TC_REQ_OWNED_MAX];
    int nowned_;
} tc_request;

/* Parses len bytes of JSON (no NUL terminator needed; trailing whitespace allowed).
 * expect: TC_REQ_MESH requires vertices, triangles and values; TC_REQ_POINTS
 * requires points. Parts not expected are still parsed when present.
 * Returns a tc_req_status. On TC_REQ_OK *out is a new request (warnings, such
 * as unknown fields, may be in diags). Otherwise *out is NULL and diags holds the
 * findings, each with the JSON path of the offending element; when both shape
 * and value errors occur the result is TC_REQ_MALFORMED. diags may be NULL. */
int tc_request_parse(const char *json, size_t len, unsigned expect, tc_request **out,
                     tc_diags *diags);
/* The same for a document about a mesh parsed before (a stored one): its
 * channel count, nchan, is known, so per-channel fields ("background") are
 * read against it. The document must not hold a mesh itself (has_mesh then
 * says it did; the caller refuses it). nchan = 0: tc_request_parse. */
int tc_request_parse_for(const char *json, size_t len, unsigned expect, int nchan, tc_request **out,
                         tc_diags *diags);
/* The limits tc_request_parse_limited checks (io/prescan.h's), and its finding. */
typedef struct {
    const tc_scan_limit *lim;
    int n;
    int over;      /* out: the index of the first limit passed, in text order, or -1 */
    int64_t count; /* out: that array's full element count */
} tc_req_limits;

/* tc_request_parse, refusing first (TC_REQ_OVER_LIMIT, *out NULL, nothing in diags) a body
 * whose limited arrays hold more elements than L allows: the same answer as tc_prescan on the
 * body, found in one walk with the fast path's (io/request_fast.c): the arrays it reads are
 * counted there and left to the prescan once over their limit (so no array over a limit is
 * ever converted), and the prescan walks only the skeleton, the rest of the body. */
int tc_request_parse_limited(const char *json, size_t len, unsigned expect, tc_req_limits *L, tc_request **out,
                             tc_diags *diags);
void tc_request_free(tc_request *r);

/* For tests only: make the n-th following allocation (1-based) of the reader on
 * this thread fail, once, to exercise the out-of-memory paths; 0 disables. It
 * counts the request and its arrays, not cJSON's nodes. */
void tc_request__fail_alloc_after(long n);
/* For tests only: on = 0 reads every array of this thread's requests through cJSON, as
 * before the fast path (io/request_fast.c); 1 (the default) takes the fast path. */
void tc_request__fast_arrays(int on);
/* For tests only: how many arrays the last successful parse on this thread read fast. */
int tc_request__fast_taken(void);
/* Test hook: typed arrays' "data" strings the last parse read from the body (not cJSON). */
int tc_request__fast_spans(void);

#endif /* TC_IO_REQUEST_H */
