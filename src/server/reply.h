/* reply.h — one HTTP answer as the route handlers build it and http.c sends
 * it: status, content type, body, and the API result behind it (timings, counts). */
#ifndef TC_SERVER_REPLY_H
#define TC_SERVER_REPLY_H

#include "io/api.h"
#include "io/strbuf.h"

#define TC_JSON_TYPE "application/json"
#define TC_PROBLEM_TYPE "application/problem+json"

typedef struct {
    int status;
    const char *content_type; /* static string */
    tc_strbuf body;
    tc_api_result res;        /* phase timings (Server-Timing), triangles, pixels */
    const char *allow;        /* Allow header of a 405, else NULL */
    int retry_after;          /* seconds for a Retry-After header, 0: none */
    const char *cache_control; /* Cache-Control header (static string), NULL: none */
} tc_reply;

void tc_reply_init(tc_reply *r);
void tc_reply_free(tc_reply *r);

/* Problems the server finds itself, before or around the API call. */
typedef enum {
    TC_PROBLEM_MALFORMED,         /* 400 */
    TC_PROBLEM_NOT_FOUND,         /* 404 */
    TC_PROBLEM_METHOD,            /* 405 */
    TC_PROBLEM_TOO_LARGE,         /* 413 */
    TC_PROBLEM_MEDIA_TYPE,        /* 415 */
    TC_PROBLEM_INTERNAL,          /* 500 */
    TC_PROBLEM_BUSY,              /* 503, try again later */
    TC_PROBLEM_TIMEOUT            /* 503, past the request deadline */
} tc_problem;

/* Replaces r's status, type and body with an application/problem+json document
 * of the same shape as tc_api_problem's: type, title, status, detail, path,
 * error_count, errors, warnings. */
void tc_reply_problem(tc_reply *r, tc_problem p, const char *detail);

int tc_problem_status(tc_problem p);

#endif
