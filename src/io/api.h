/* api.h — the JSON API shared by the daemon and the CLI: request bytes in,
 * response bytes out, with a status and per-phase timings. */
#ifndef TC_IO_API_H
#define TC_IO_API_H

#include <stddef.h>
#include <stdint.h>

#include "io/budget.h"
#include "io/strbuf.h"
#include "tocher.h"

enum { TC_PHASE_PARSE, TC_PHASE_VALIDATE, TC_PHASE_BUILD, TC_PHASE_EVALUATE, TC_PHASE_ENCODE, TC_NPHASES };
/* "parse", "validate", "build", "evaluate", "encode" (rendering counts as evaluate). */
extern const char *const tc_phase_names[TC_NPHASES];

/* What one request may ask for; 0 means no limit. */
typedef struct {
    int64_t max_vertices, max_triangles, max_points, max_pixels;
    int64_t max_samples; /* pixels x channels of one render: what its answer holds */
    int render_threads;  /* worker threads for one render, and for the validation and
                          * build of one mesh (>= 1) */
    double deadline_ms;  /* tc_now_ms() time after which work stops; 0 = none */
    tc_budget *memory;   /* requests in flight (--max-memory): a render reserves its peak
                          * here first, or is refused (503, or 413 if it could never fit);
                          * NULL: no budget */
} tc_api_limits;

typedef struct {
    int status;             /* 200, 400 malformed, 413 over a limit, 422 invalid mesh,
                             * 500 internal (out of memory, image library), 503 past the deadline */
    tc_diags diags;         /* errors (status != 200) and warnings */
    int second_doc;         /* diags.items[second_doc ..] are about the points document */
    double ms[TC_NPHASES];  /* wall time of each phase in milliseconds */
    int64_t triangles;      /* triangles reconstructed */
    int64_t pixels;         /* pixels rendered */
    const char *content_type; /* of the 200 body: "application/json" or an image type */
    tc_budget *budget;      /* where `held` is reserved (lim->memory), or NULL */
    int retry_after;        /* seconds a refused request should wait (503 of a full budget), or 0 */
    int64_t held;           /* bytes the 200 body holds in budget: given back when the body is
                             * freed (tc_api_result_release; the daemon, once it is sent) */
} tc_api_result;

void tc_api_result_init(tc_api_result *res);
void tc_api_result_free(tc_api_result *res); /* releases `held` too */
/* Gives `held` back to its budget (the body it paid for is gone or handed on). */
void tc_api_result_release(tc_api_result *res);

/* POST /v1/ordinates. On 200 `out` holds the JSON response object; else `out`
 * is untouched and res->diags says why (tc_api_problem renders it). lim may be NULL. */
int tc_api_ordinates(const char *body, size_t len, const tc_api_limits *lim, tc_strbuf *out, tc_api_result *res);

/* POST /v1/evaluate: mesh and "points" in one body, or the points (and
 * "with_gradients") in a second document when points != NULL. */
int tc_api_evaluate(const char *body, size_t len, const char *points, size_t plen, const tc_api_limits *lim,
                    tc_strbuf *out, tc_api_result *res);

/* POST /v1/render: mesh + "viewport" {x0,y0,x1,y1,width,height} + "format"
 * (else the one the Accept header asks for, io/accept.h, else png) + "exposure",
 * "overlay", "background", "linear". On 200 `out` holds the encoded image,
 * res->content_type its type. */
int tc_api_render(const char *body, size_t len, const char *accept, const tc_api_limits *lim, tc_strbuf *out,
                  tc_api_result *res);
/* The same with the format for a request without "format" given directly: a
 * tc_img_format (the CLI's output extension), or -1 for the default. */
int tc_api_render_as(const char *body, size_t len, int fallback, const tc_api_limits *lim, tc_strbuf *out,
                     tc_api_result *res);

/* POST /v1/compare: mesh + "reference" {points, values, scale} + "methods"
 * (names or option objects; default every method) -> for each method its
 * error against the reference (max_abs, rms, mean_rel) and the time it took to
 * build and to evaluate. A method that cannot run on this mesh gets an "error". */
int tc_api_compare(const char *body, size_t len, const tc_api_limits *lim, tc_strbuf *out, tc_api_result *res);

/* An application/problem+json body for a failed result. */
void tc_api_problem(tc_strbuf *out, const tc_api_result *res);

/* The problem document itself, for any status: "type": "/problems/<type>",
 * title, status, detail and path (of d's first error), error_count, errors[],
 * warnings[]. The daemon uses it for the errors it finds on its own. */
void tc_api_problem_write(tc_strbuf *out, int status, const char *type, const char *title, const tc_diags *d);

/* Adds "timings":{"parse":ms,...,"total":ms} as the last member of the JSON
 * object in `out` (which must end with "}\n"). */
void tc_api_add_timings(tc_strbuf *out, const tc_api_result *res);

/* ---- stored meshes (POST /v1/meshes and /v1/meshes/{id}/...) ----
 * A job is a parsed, validated, built mesh request with its point locator,
 * immutable once built: any number of threads may use one at once. */
typedef struct tc_api_job tc_api_job;

typedef struct {
    int64_t vertices, triangles; /* triangles: a quad counts as 2 */
    int channels;
    double bbox[4];              /* x0, y0, x1, y1 of the vertices */
    size_t bytes;                /* memory the job holds (an estimate from its counts) */
} tc_api_mesh_info;

/* Parses (a mesh request: a body with points, viewport, format, reference or
 * methods is refused, 400 naming the field), validates and builds, under the
 * limits. 200 and *out, or the status with res->diags saying why. The job
 * keeps the warnings found, and repeats them in every answer it gives. */
int tc_api_job_build(const char *body, size_t len, const tc_api_limits *lim, tc_api_job **out, tc_api_result *res);
void tc_api_job_free(tc_api_job *J);
const tc_api_mesh_info *tc_api_job_info(const tc_api_job *J);

/* The canonical form (io/request_write.h): the request as complete JSON with
 * every number exact. Equal for requests that parse to the same mesh and
 * options; what a mesh's content id hashes, and what the store keeps. */
void tc_api_job_canonical(const tc_api_job *J, tc_strbuf *out);

/* {"id", "vertices", "triangles", "channels", "bbox", "method", <options>, "warnings"}\n */
void tc_api_job_describe(const tc_api_job *J, const char *id, tc_strbuf *out);

/* The answers of /v1/ordinates, /v1/evaluate (body: {"points", "with_gradients"})
 * and /v1/render (body: {"viewport", "format", "exposure", "overlay",
 * "background", "linear"}; accept as tc_api_render's) for the stored mesh,
 * equal to theirs for the same mesh. A body that holds a mesh is refused (400). */
int tc_api_job_ordinates(const tc_api_job *J, const tc_api_limits *lim, tc_strbuf *out, tc_api_result *res);
int tc_api_job_evaluate(const tc_api_job *J, const char *body, size_t len, const tc_api_limits *lim, tc_strbuf *out,
                        tc_api_result *res);
int tc_api_job_render(const tc_api_job *J, const char *body, size_t len, const char *accept,
                      const tc_api_limits *lim, tc_strbuf *out, tc_api_result *res);

/* A render's parameters given directly (a tile): what tc_request_parse reads
 * from those members of a /v1/render body. */
typedef struct {
    tc_viewport viewport;
    int format; /* a tc_img_format */
    double exposure;
    int overlay, linear, has_background;
    double background[TC_MAX_CHANNELS];
} tc_api_look;

int tc_api_job_render_look(const tc_api_job *J, const tc_api_look *look, const tc_api_limits *lim, tc_strbuf *out,
                           tc_api_result *res);

#endif
