/* reply.c — HTTP answers under construction, and the problem documents for
 * errors the server detects itself (the API renders its own with tc_api_problem). */
#include "server/reply.h"

void tc_reply_init(tc_reply *r) {
    r->status = 500;
    r->content_type = TC_PROBLEM_TYPE;
    tc_strbuf_init(&r->body);
    tc_api_result_init(&r->res);
    r->allow = NULL;
    r->retry_after = 0;
    r->etag[0] = r->location[0] = '\0';
    r->cache_control = r->vary = NULL;
}

void tc_reply_free(tc_reply *r) {
    tc_strbuf_free(&r->body);
    tc_api_result_free(&r->res);
}

static const struct {
    int status;
    const char *type, *title;
} problems[] = {
    [TC_PROBLEM_MALFORMED] = {400, "malformed-request", "Malformed request"},
    [TC_PROBLEM_NOT_FOUND] = {404, "not-found", "Not found"},
    [TC_PROBLEM_METHOD] = {405, "method-not-allowed", "Method not allowed"},
    [TC_PROBLEM_TOO_LARGE] = {413, "too-large", "Request too large"},
    [TC_PROBLEM_MEDIA_TYPE] = {415, "unsupported-media-type", "Unsupported media type"},
    [TC_PROBLEM_INTERNAL] = {500, "internal", "Internal error"},
    [TC_PROBLEM_BUSY] = {503, "busy", "Server busy"},
    [TC_PROBLEM_TIMEOUT] = {503, "timeout", "Request took too long"},
};

int tc_problem_status(tc_problem p) { return problems[p].status; }

void tc_reply_problem(tc_reply *r, tc_problem p, const char *detail) {
    tc_diags d;
    tc_diags_init(&d);
    tc_diags_add(&d, TC_SEV_ERROR, "", "%s", detail);
    r->status = problems[p].status;
    r->content_type = TC_PROBLEM_TYPE;
    tc_api_result_release(&r->res); /* the body it paid for is replaced */
    tc_strbuf_reset(&r->body);
    tc_api_problem_write(&r->body, r->status, problems[p].type, problems[p].title, &d);
    tc_diags_free(&d);
}

void tc_reply_api(tc_reply *r, int status, int json) {
    r->status = status;
    if (status == 200) {
        if (json) tc_api_add_timings(&r->body, &r->res);
        r->content_type = r->res.content_type ? r->res.content_type : "application/octet-stream";
        return;
    }
    tc_strbuf_reset(&r->body);
    tc_api_problem(&r->body, &r->res);
    r->retry_after = r->res.retry_after;
    r->content_type = TC_PROBLEM_TYPE;
}
