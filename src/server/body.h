/* body.h — request bodies: the Content-Type and Content-Length checks made
 * from the headers, accumulation under the size limit, the UTF-8 check. */
#ifndef TC_SERVER_BODY_H
#define TC_SERVER_BODY_H

#include <stddef.h>

typedef struct {
    char *buf;     /* NUL-terminated; NULL until the first byte */
    size_t len, cap;
    size_t limit;  /* most bytes accepted */
    size_t expect; /* the declared Content-Length (0: unknown): growth stops there */
} tc_body;

void tc_body_init(tc_body *b, size_t limit);
void tc_body_free(tc_body *b);
/* Notes a known Content-Length: the buffer grows as bytes arrive, to at most
 * that (plus the NUL). 0 (kept for callers that handled -1: out of memory). */
int tc_body_reserve(tc_body *b, size_t expect);
/* 0; 1 if the body would exceed the limit (nothing appended); -1 if out of memory. */
int tc_body_append(tc_body *b, const char *data, size_t n);

/* 1 if a Content-Type header value names application/json, with any
 * parameters but a charset other than UTF-8. NULL (no header) is not JSON. */
int tc_media_is_json(const char *content_type);

/* A Content-Length header value as a number; -1 if absent or not a number. */
long long tc_content_length(const char *value);

/* Offset of the first byte that is not part of well-formed UTF-8, or -1. */
long long tc_utf8_error(const char *s, size_t n);

#endif
