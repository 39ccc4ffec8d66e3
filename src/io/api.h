/* api.h — the JSON API shared by the daemon and the CLI: request bytes in,
 * response bytes out, with a status and per-phase timings. */
#ifndef TC_IO_API_H
#define TC_IO_API_H

#include <stddef.h>

#include "io/strbuf.h"
#include "tocher.h"

enum { TC_PHASE_PARSE, TC_PHASE_VALIDATE, TC_PHASE_BUILD, TC_PHASE_EVALUATE, TC_PHASE_ENCODE, TC_NPHASES };
extern const char *const tc_phase_names[TC_NPHASES];

typedef struct {
    int status;             /* 200, 400 (malformed), 422 (invalid mesh), 500 (out of memory) */
    tc_diags diags;         /* errors (status != 200) and warnings */
    int second_doc;         /* diags.items[second_doc ..] are about the points document */
    double ms[TC_NPHASES];  /* wall time of each phase in milliseconds */
} tc_api_result;

void tc_api_result_init(tc_api_result *res);
void tc_api_result_free(tc_api_result *res);

/* POST /v1/ordinates. On 200 `out` holds the JSON response object; else it is
 * untouched and res->diags says why (tc_api_problem renders it). */
int tc_api_ordinates(const char *body, size_t len, tc_strbuf *out, tc_api_result *res);

/* POST /v1/evaluate: mesh and "points" in one body, or the points (and
 * "with_gradients") in a second document when points != NULL. */
int tc_api_evaluate(const char *body, size_t len, const char *points, size_t plen, tc_strbuf *out,
                    tc_api_result *res);

/* An application/problem+json body for a failed result. */
void tc_api_problem(tc_strbuf *out, const tc_api_result *res);

#endif
