/* conns.c — closes connections whose request headers or body are late, counting
 * from their start: libmicrohttpd's idle timeout restarts at every byte, so a client
 * sending a header byte every few seconds would otherwise hold its connection forever. */
#include <pthread.h>
#include <stdlib.h>
#include <sys/socket.h>
#include <time.h>

#include "server/conns.h"
#include "server/log.h"
#include "server/metrics.h"

/* One open connection. deadline: seconds on the monotonic clock; 0: none. */
typedef struct conn {
    struct conn *prev, *next;
    struct tc_conns *owner;
    MHD_socket fd;
    double deadline;
    int in_body; /* the deadline is the body's (else the headers') */
} conn;

struct tc_conns {
    pthread_mutex_t lock;
    pthread_cond_t wake;
    pthread_t thread;
    int running, stop;
    double header_s, body_s, idle_s;
    conn head; /* sentinel of a circular list */
};

enum { SWEEP_MS = 100 }; /* how late a deadline may be enforced */

static double now_s(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static double after(double seconds) { return seconds > 0 ? now_s() + seconds : 0; }

/* Shuts late sockets down (libmicrohttpd then sees the end of input and closes
 * the connection itself). The fd is still open: removal at CLOSED, which
 * libmicrohttpd announces before closing it, takes the same lock. */
static int sweep(tc_conns *t) {
    int closed = 0;
    double now = now_s();
    for (conn *k = t->head.next; k != &t->head; k = k->next) {
        if (k->deadline <= 0 || now < k->deadline) continue;
        shutdown(k->fd, SHUT_RDWR);
        tc_metrics_deadline_closed(k->in_body);
        k->deadline = 0;
        closed++;
    }
    return closed;
}

static void *sweeper(void *arg) {
    tc_conns *t = arg;
    pthread_mutex_lock(&t->lock);
    while (!t->stop) {
        int closed = sweep(t);
        if (closed) tc_log_notice("closed %d connection%s past the header or body deadline", closed, closed > 1 ? "s" : "");
        struct timespec ts;
        clock_gettime(CLOCK_REALTIME, &ts);
        ts.tv_nsec += SWEEP_MS * 1000000L;
        if (ts.tv_nsec >= 1000000000L) ts.tv_sec++, ts.tv_nsec -= 1000000000L;
        pthread_cond_timedwait(&t->wake, &t->lock, &ts);
    }
    pthread_mutex_unlock(&t->lock);
    return NULL;
}

tc_conns *tc_conns_start(const tc_srv_config *cfg) {
    tc_conns *t = calloc(1, sizeof *t);
    if (!t) return NULL;
    pthread_mutex_init(&t->lock, NULL);
    pthread_cond_init(&t->wake, NULL);
    t->head.next = t->head.prev = &t->head;
    t->header_s = cfg->header_timeout;
    t->body_s = cfg->body_timeout;
    t->idle_s = (double)cfg->connection_timeout;
    if (t->header_s <= 0 && t->body_s <= 0) return t; /* nothing to enforce */
    if (pthread_create(&t->thread, NULL, sweeper, t)) {
        pthread_cond_destroy(&t->wake);
        pthread_mutex_destroy(&t->lock);
        free(t);
        return NULL;
    }
    t->running = 1;
    return t;
}

void tc_conns_stop(tc_conns *t) {
    if (!t) return;
    pthread_mutex_lock(&t->lock);
    t->stop = 1;
    pthread_cond_signal(&t->wake);
    pthread_mutex_unlock(&t->lock);
    if (t->running) pthread_join(t->thread, NULL);
    for (conn *k = t->head.next, *next; k != &t->head; k = next) next = k->next, free(k);
    pthread_cond_destroy(&t->wake);
    pthread_mutex_destroy(&t->lock);
    free(t);
}

static void opened(tc_conns *t, struct MHD_Connection *c, void **ctx) {
    const union MHD_ConnectionInfo *fd = MHD_get_connection_info(c, MHD_CONNECTION_INFO_CONNECTION_FD);
    conn *k = fd ? calloc(1, sizeof *k) : NULL;
    if (!k) return; /* untracked: only the idle timeout applies */
    k->owner = t;
    k->fd = fd->connect_fd;
    k->deadline = after(t->header_s);
    pthread_mutex_lock(&t->lock);
    k->next = t->head.next, k->prev = &t->head;
    t->head.next->prev = k, t->head.next = k;
    pthread_mutex_unlock(&t->lock);
    *ctx = k;
}

static void closed(tc_conns *t, conn *k) {
    pthread_mutex_lock(&t->lock);
    k->prev->next = k->next, k->next->prev = k->prev;
    pthread_mutex_unlock(&t->lock);
    free(k);
}

void tc_conns_notify(void *cls, struct MHD_Connection *c, void **socket_context,
                     enum MHD_ConnectionNotificationCode code) {
    if (code == MHD_CONNECTION_NOTIFY_STARTED) opened(cls, c, socket_context);
    else if (code == MHD_CONNECTION_NOTIFY_CLOSED && *socket_context) closed(cls, *socket_context);
    if (code == MHD_CONNECTION_NOTIFY_CLOSED) *socket_context = NULL;
}

void tc_conns_phase(struct MHD_Connection *c, tc_conn_phase p) {
    const union MHD_ConnectionInfo *info = c ? MHD_get_connection_info(c, MHD_CONNECTION_INFO_SOCKET_CONTEXT) : NULL;
    conn *k = info ? info->socket_context : NULL;
    if (!k) return;
    tc_conns *t = k->owner;
    /* The next request's headers: the idle timeout closes a silent connection;
     * one that trickles gets --header-timeout after it. */
    double d = p == TC_CONN_BODY ? after(t->body_s)
               : p == TC_CONN_IDLE && t->header_s > 0 ? after(t->header_s + t->idle_s)
                                                      : 0;
    pthread_mutex_lock(&t->lock);
    k->deadline = d;
    k->in_body = p == TC_CONN_BODY;
    pthread_mutex_unlock(&t->lock);
}
