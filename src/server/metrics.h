/* metrics.h — the daemon's counters (requests by route and status, latency
 * histogram, triangles and pixels, requests in flight) and their Prometheus text. */
#ifndef TC_SERVER_METRICS_H
#define TC_SERVER_METRICS_H

#include <stdint.h>

#include "io/budget.h"
#include "io/strbuf.h"

#define TC_METRICS_MAX_ROUTES 24

/* Names the route slots 0 .. n-1 (labels must outlive the process); requests
 * matching no route are counted under "unmatched". Call once, before serving. */
void tc_metrics_init(const char *const *route_labels, int n);

/* A request arrived / finished. route: a slot, or -1 for no route; status: the
 * status answered, or 0 if the connection ended before an answer. Thread-safe. */
void tc_metrics_begin(void);
/* A request's answer was queued: its status, latency (first byte to queued
 * answer), and the triangles and pixels it processed. */
void tc_metrics_answered(int route, int status, double seconds, int64_t triangles, int64_t pixels);
/* A request is over, answered or not (then counted as aborted). */
void tc_metrics_end(int route, int answered);

/* Adds to the requests waiting for a worker and to those computing on one. */
void tc_metrics_workers(int waiting, int running);

/* A stored mesh was parsed, validated and built (POST, or a rebuild after an
 * eviction) in this many seconds: the tocher_mesh_build_seconds histogram. */
void tc_metrics_mesh_built(double seconds);

/* Requests begun and not yet ended. */
long tc_metrics_in_flight(void);

/* Appends the text exposition format (version 0.0.4). */
void tc_metrics_write(tc_strbuf *out);
/* A connection closed because its request headers (body 0) or body (1) were late. */
void tc_metrics_deadline_closed(int body);
/* The budget whose reserved bytes /metrics shows (the server's), or NULL. */
void tc_metrics_budget(const tc_budget *b);

#define TC_METRICS_CONTENT_TYPE "text/plain; version=0.0.4; charset=utf-8"

#endif
