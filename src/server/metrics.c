/* metrics.c — lock-free counters (C11 atomics, relaxed: each number is
 * independent) and their Prometheus text exposition. */
#include <stdatomic.h>

#include "server/metrics.h"
#include "tocher.h"

/* Slot TC_METRICS_MAX_ROUTES counts requests that matched no route. */
enum { SLOTS = TC_METRICS_MAX_ROUTES + 1, STATUS_MIN = 100, STATUS_MAX = 599 };
enum { NSTATUS = STATUS_MAX - STATUS_MIN + 1 };

/* Upper bounds in seconds; a last, implicit bucket holds everything slower. */
static const double bounds[] = {0.0005, 0.001, 0.0025, 0.005, 0.01, 0.025, 0.05,
                                0.1,    0.25,  0.5,    1,     2.5,  5,     10};
enum { NB = sizeof bounds / sizeof bounds[0] };

static const char *labels[SLOTS];
static int nroutes;

static atomic_ullong by_status[SLOTS][NSTATUS];
static atomic_ullong aborted[SLOTS];
static atomic_ullong buckets[SLOTS][NB + 1]; /* not cumulative; summed on output */
static atomic_ullong sum_ns[SLOTS];
static atomic_ullong triangles_total, pixels_total;
static atomic_long in_flight;
static atomic_long jobs_waiting, jobs_running; /* the worker pool's, as http.c moves jobs */
static atomic_ullong build_buckets[NB + 1], build_sum_ns; /* tocher_mesh_build_seconds, as buckets[] */

void tc_metrics_init(const char *const *route_labels, int n) {
    nroutes = n < TC_METRICS_MAX_ROUTES ? n : TC_METRICS_MAX_ROUTES;
    for (int i = 0; i < nroutes; i++) labels[i] = route_labels[i];
    labels[TC_METRICS_MAX_ROUTES] = "unmatched";
}

static void add(atomic_ullong *a, unsigned long long n) { atomic_fetch_add_explicit(a, n, memory_order_relaxed); }

static unsigned long long get(atomic_ullong *a) { return atomic_load_explicit(a, memory_order_relaxed); }

void tc_metrics_begin(void) { atomic_fetch_add(&in_flight, 1); }

long tc_metrics_in_flight(void) { return atomic_load(&in_flight); }

void tc_metrics_workers(int waiting, int running) {
    atomic_fetch_add(&jobs_waiting, waiting);
    atomic_fetch_add(&jobs_running, running);
}

static int slot_of(int route) { return route >= 0 && route < nroutes ? route : TC_METRICS_MAX_ROUTES; }

/* Counted when the answer is queued, before the client can read it: a client
 * that has its answer and then reads /metrics always finds it counted. */
void tc_metrics_answered(int route, int status, double seconds, int64_t triangles, int64_t pixels) {
    int s = slot_of(route);
    if (status >= STATUS_MIN && status <= STATUS_MAX) add(&by_status[s][status - STATUS_MIN], 1);
    int b = 0;
    while (b < NB && seconds > bounds[b]) b++;
    add(&buckets[s][b], 1);
    add(&sum_ns[s], seconds > 0 ? (unsigned long long)(seconds * 1e9) : 0);
    if (triangles > 0) add(&triangles_total, (unsigned long long)triangles);
    if (pixels > 0) add(&pixels_total, (unsigned long long)pixels);
}

void tc_metrics_mesh_built(double seconds) {
    int b = 0;
    while (b < NB && seconds > bounds[b]) b++;
    add(&build_buckets[b], 1);
    add(&build_sum_ns, seconds > 0 ? (unsigned long long)(seconds * 1e9) : 0);
}

void tc_metrics_end(int route, int answered) {
    if (!answered) add(&aborted[slot_of(route)], 1);
    /* Last, so that a drain waiting for zero sees the request fully accounted. */
    atomic_fetch_sub(&in_flight, 1);
}

static void header(tc_strbuf *o, const char *name, const char *type, const char *help) {
    tc_strbuf_printf(o, "# HELP %s %s\n# TYPE %s %s\n", name, help, name, type);
}

static int slot_used(int s) { return s < nroutes || s == TC_METRICS_MAX_ROUTES; }

static void write_requests(tc_strbuf *o) {
    header(o, "tocher_http_requests_total", "counter", "HTTP requests answered, by route and status.");
    for (int s = 0; s < SLOTS; s++)
        for (int k = 0; slot_used(s) && k < NSTATUS; k++) {
            unsigned long long n = get(&by_status[s][k]);
            if (n) tc_strbuf_printf(o, "tocher_http_requests_total{route=\"%s\",status=\"%d\"} %llu\n", labels[s],
                                    k + STATUS_MIN, n);
        }
    header(o, "tocher_http_requests_aborted_total", "counter",
           "HTTP requests whose connection ended before an answer (client gone, idle timeout).");
    for (int s = 0; s < SLOTS; s++)
        if (slot_used(s)) tc_strbuf_printf(o, "tocher_http_requests_aborted_total{route=\"%s\"} %llu\n", labels[s],
                                           get(&aborted[s]));
}

static void write_histogram(tc_strbuf *o) {
    const char *h = "tocher_http_request_duration_seconds";
    header(o, h, "histogram", "Time from the request headers to the answer being queued.");
    for (int s = 0; s < SLOTS; s++) {
        if (!slot_used(s)) continue;
        unsigned long long cum = 0;
        for (int b = 0; b <= NB; b++) {
            cum += get(&buckets[s][b]);
            if (b < NB) tc_strbuf_printf(o, "%s_bucket{route=\"%s\",le=\"%g\"} %llu\n", h, labels[s], bounds[b], cum);
            else tc_strbuf_printf(o, "%s_bucket{route=\"%s\",le=\"+Inf\"} %llu\n", h, labels[s], cum);
        }
        tc_strbuf_printf(o, "%s_sum{route=\"%s\"} %.9f\n", h, labels[s], (double)get(&sum_ns[s]) * 1e-9);
        tc_strbuf_printf(o, "%s_count{route=\"%s\"} %llu\n", h, labels[s], cum);
    }
}

static const tc_budget *memory_budget;
static atomic_ullong closed_late[2]; /* [0] headers, [1] body */

void tc_metrics_deadline_closed(int body) { atomic_fetch_add(&closed_late[body ? 1 : 0], 1); }

void tc_metrics_budget(const tc_budget *b) { memory_budget = b; }

static void write_build_histogram(tc_strbuf *o) {
    const char *h = "tocher_mesh_build_seconds";
    header(o, h, "histogram", "Time to parse, validate and build a stored mesh (POST, or a rebuild after eviction).");
    unsigned long long cum = 0;
    for (int b = 0; b <= NB; b++) {
        cum += get(&build_buckets[b]);
        if (b < NB) tc_strbuf_printf(o, "%s_bucket{le=\"%g\"} %llu\n", h, bounds[b], cum);
        else tc_strbuf_printf(o, "%s_bucket{le=\"+Inf\"} %llu\n", h, cum);
    }
    tc_strbuf_printf(o, "%s_sum %.9f\n%s_count %llu\n", h, (double)get(&build_sum_ns) * 1e-9, h, cum);
}

void tc_metrics_write(tc_strbuf *o) {
    write_requests(o);
    write_histogram(o);
    write_build_histogram(o);
    header(o, "tocher_triangles_processed_total", "counter", "Triangles reconstructed.");
    tc_strbuf_printf(o, "tocher_triangles_processed_total %llu\n", get(&triangles_total));
    header(o, "tocher_pixels_processed_total", "counter", "Pixels rendered.");
    tc_strbuf_printf(o, "tocher_pixels_processed_total %llu\n", get(&pixels_total));
    header(o, "tocher_http_requests_in_flight", "gauge", "HTTP requests being received or worked on.");
    tc_strbuf_printf(o, "tocher_http_requests_in_flight %ld\n", tc_metrics_in_flight());
    header(o, "tocher_worker_queue_length", "gauge", "Requests waiting for a worker thread.");
    tc_strbuf_printf(o, "tocher_worker_queue_length %ld\n", atomic_load(&jobs_waiting));
    header(o, "tocher_workers_busy", "gauge", "Worker threads computing an answer.");
    tc_strbuf_printf(o, "tocher_workers_busy %ld\n", atomic_load(&jobs_running));
    header(o, "tocher_connections_closed_late_total", "counter",
           "Connections closed unanswered because their request headers or body passed their deadline.");
    tc_strbuf_printf(o, "tocher_connections_closed_late_total{part=\"headers\"} %llu\n", get(&closed_late[0]));
    tc_strbuf_printf(o, "tocher_connections_closed_late_total{part=\"body\"} %llu\n", get(&closed_late[1]));
    header(o, "tocher_memory_reserved_bytes", "gauge",
           "Bytes renders in flight hold or may hold (answers being sent, reserved peaks); --max-memory bounds it.");
    tc_strbuf_printf(o, "tocher_memory_reserved_bytes %lld\n", (long long)tc_budget_used(memory_budget));
    header(o, "tocher_build_info", "gauge", "Version of this daemon; always 1.");
    tc_strbuf_printf(o, "tocher_build_info{version=\"%s\"} 1\n", TC_VERSION);
}
