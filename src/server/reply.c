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
    r->cache_control = NULL;
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
    tc_strbuf_reset(&r->body);
    tc_api_problem_write(&r->body, r->status, problems[p].type, problems[p].title, &d);
    tc_diags_free(&d);
}
