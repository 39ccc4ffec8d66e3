/* etag.h — entity tags of the stored-mesh answers and the If-None-Match test
 * (RFC 9110 §13.1.2) that turns a repeated GET into a 304 before any work. */
#ifndef TC_SERVER_ETAG_H
#define TC_SERVER_ETAG_H

#include <stddef.h>

/* "\"<id>-<16 hex digits>\"": the id, then a hash of what else the URL means
 * (the route, the tile, its normalized query). An id never changes meaning, so
 * equal tags mean equal bytes: strong tags. out holds at least 96 bytes. */
void tc_etag_make(char *out, size_t n, const char *id, const char *meaning);

/* 1 if the If-None-Match header value (NULL: absent) matches etag: "*", or
 * any entity tag of the comma-separated list, W/ or not (weak comparison). */
int tc_etag_none_match(const char *header, const char *etag);

#endif
