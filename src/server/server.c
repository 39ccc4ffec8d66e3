/* server.c — the listening daemon: address resolution, the libmicrohttpd
 * options (thread pool, limits, timeouts, callbacks), quiesce and stop. */
#include <arpa/inet.h>
#include <errno.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "server/conns.h"
#include "server/drain.h"
#include "server/http.h"
#include "server/log.h"
#include "server/metrics.h"
#include "server/meshes.h"
#include "server/server.h"

struct tc_server {
    struct MHD_Daemon *d;
    tc_http_state state;
    tc_conns *conns; /* header and body deadlines */
    MHD_socket quiesced; /* the listen socket handed back by quiesce; closed after stop */
    char address[INET6_ADDRSTRLEN + 16];
};

/* libmicrohttpd's own messages (bad requests it answers itself, socket
 * errors) go to the same log as ours. */
static void mhd_log(void *cls, const char *fmt, va_list ap) {
    (void)cls;
    char msg[512];
    vsnprintf(msg, sizeof msg, fmt, ap);
    size_t n = strlen(msg);
    while (n && (msg[n - 1] == '\n' || msg[n - 1] == '\r')) msg[--n] = '\0';
    tc_log_notice("libmicrohttpd: %s", msg);
}

static int resolve(const tc_srv_config *cfg, struct sockaddr_storage *ss, char *err, size_t errlen) {
    struct addrinfo hints, *ai = NULL;
    memset(&hints, 0, sizeof hints);
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    hints.ai_flags = AI_NUMERICSERV;
    char port[16];
    snprintf(port, sizeof port, "%lld", cfg->port);
    int rc = getaddrinfo(cfg->host, port, &hints, &ai);
    if (rc) {
        snprintf(err, errlen, "cannot use listen address %s: %s", cfg->host, gai_strerror(rc));
        return -1;
    }
    memset(ss, 0, sizeof *ss);
    memcpy(ss, ai->ai_addr, ai->ai_addrlen);
    freeaddrinfo(ai);
    return 0;
}

/* "HOST:PORT" of the bound socket, the port as the kernel chose it. */
static void describe(tc_server *s, const struct sockaddr_storage *ss) {
    char host[INET6_ADDRSTRLEN] = "?";
    const void *a = ss->ss_family == AF_INET6 ? (const void *)&((const struct sockaddr_in6 *)ss)->sin6_addr
                                              : (const void *)&((const struct sockaddr_in *)ss)->sin_addr;
    inet_ntop(ss->ss_family, a, host, sizeof host);
    const union MHD_DaemonInfo *info = MHD_get_daemon_info(s->d, MHD_DAEMON_INFO_BIND_PORT);
    unsigned port = info ? info->port : 0;
    const char *fmt = ss->ss_family == AF_INET6 ? "[%s]:%u" : "%s:%u";
    snprintf(s->address, sizeof s->address, fmt, host, port);
}

static struct MHD_Daemon *start(tc_server *s, const tc_srv_config *cfg, struct sockaddr_storage *ss) {
    /* Suspend/resume: POST routes run on the worker pool (http.c). */
    unsigned flags = MHD_USE_AUTO_INTERNAL_THREAD | MHD_USE_ERROR_LOG | MHD_USE_ITC | MHD_ALLOW_SUSPEND_RESUME;
    if (ss->ss_family == AF_INET6) flags |= MHD_USE_IPv6;
    /* The port is taken from ss; libmicrohttpd only quotes it in messages. */
    return MHD_start_daemon(flags, (uint16_t)cfg->port, NULL, NULL, tc_http_access, &s->state,
                            MHD_OPTION_EXTERNAL_LOGGER, mhd_log, NULL,
                            MHD_OPTION_SOCK_ADDR, (struct sockaddr *)ss,
                            MHD_OPTION_THREAD_POOL_SIZE, (unsigned)cfg->threads,
                            MHD_OPTION_CONNECTION_LIMIT, (unsigned)cfg->max_connections,
                            MHD_OPTION_CONNECTION_TIMEOUT, (unsigned)cfg->connection_timeout,
                            MHD_OPTION_NOTIFY_COMPLETED, tc_http_completed, &s->state,
                            /* slow clients: one address holds at most so many connections, and
                             * tc_conns closes those whose headers or body are late */
                            MHD_OPTION_PER_IP_CONNECTION_LIMIT, (unsigned)cfg->max_connections_per_ip,
                            MHD_OPTION_NOTIFY_CONNECTION, tc_conns_notify, s->conns,
                            MHD_OPTION_END);
}

tc_server *tc_server_start(const tc_srv_config *cfg, char *err, size_t errlen) {
    struct sockaddr_storage ss;
    if (resolve(cfg, &ss, err, errlen)) return NULL;
    tc_server *s = calloc(1, sizeof *s);
    if (!s) return snprintf(err, errlen, "out of memory"), NULL;
    s->state.cfg = cfg;
    atomic_init(&s->state.draining, 0);
    tc_budget_init(&s->state.memory, cfg->max_memory);
    tc_metrics_budget(&s->state.memory);
    s->quiesced = MHD_INVALID_SOCKET;
    s->conns = tc_conns_start(cfg);
    if (!s->conns) return free(s), snprintf(err, errlen, "cannot start the deadline thread"), NULL;
    s->state.meshes = tc_meshes_new(cfg, err, errlen);
    if (!s->state.meshes) return tc_conns_stop(s->conns), free(s), NULL;
    s->state.pool = tc_pool_new((int)cfg->workers, (int)cfg->max_queue);
    if (!s->state.pool) {
        tc_meshes_free(s->state.meshes);
        tc_conns_stop(s->conns);
        free(s);
        return snprintf(err, errlen, "cannot start %lld worker threads", cfg->workers), NULL;
    }
    s->d = start(s, cfg, &ss);
    if (!s->d) {
        tc_pool_free(s->state.pool);
        tc_meshes_free(s->state.meshes);
        tc_conns_stop(s->conns);
        snprintf(err, errlen, "cannot listen on %s:%lld (in use, or not an address of this host?)", cfg->host,
                 cfg->port);
        free(s);
        return NULL;
    }
    describe(s, &ss);
    return s;
}

const char *tc_server_address(const tc_server *s) { return s->address; }

/* Connections the kernel completed before the quiesce wait in the listen
 * queue, their requests perhaps sent: shutting the socket would reset them.
 * Each is handed to the daemon, which answers it 503 (draining) with
 * Retry-After and Connection: close. */
static void take_backlog(tc_server *s) {
    int fl = fcntl(s->quiesced, F_GETFL);
    if (fl < 0 || fcntl(s->quiesced, F_SETFL, fl | O_NONBLOCK) < 0) return;
    for (;;) {
        struct sockaddr_storage a;
        socklen_t n = sizeof a;
        int fd = accept(s->quiesced, (struct sockaddr *)&a, &n);
        if (fd < 0 && errno == EINTR) continue;
        if (fd < 0) return;
        /* On failure libmicrohttpd closes fd itself. */
        if (MHD_add_connection(s->d, fd, (struct sockaddr *)&a, n) != MHD_YES)
            tc_log_notice("draining: could not take a queued connection (%s)", strerror(errno));
    }
}

/* How long handshakes under way may take to complete once new ones are dropped: many round
 * trips on loopback or a LAN (a proxy in front), a short pause of a stop that waits for the
 * requests in flight anyway. */
#define HANDSHAKE_GRACE_NS 20000000L

void tc_server_quiesce(tc_server *s) {
    atomic_store(&s->state.draining, 1);
    s->quiesced = MHD_quiesce_daemon(s->d);
    if (s->quiesced == MHD_INVALID_SOCKET) return;
    /* No new connection joins the queue from here (drain.h), so the queue can be emptied for
     * good: what is there now, then what the handshakes under way add in the grace. Without
     * it, a connection the kernel completed after the last accept was reset by the shutdown
     * with its request sent (1 request in 6584 of test_daemon_load's SIGTERM rounds, once). */
    if (tc_drain_refuse_new(s->quiesced) != 0)
        tc_log_notice("draining: new connections may still queue until the socket is shut (%s)", strerror(errno));
    take_backlog(s);
    struct timespec grace = {0, HANDSHAKE_GRACE_NS};
    while (nanosleep(&grace, &grace) != 0 && errno == EINTR) {
    }
    take_backlog(s);
    /* The socket stays open until MHD_stop_daemon (the library's rule), but it
     * must stop taking connections now: shutting it down makes new connects
     * fail at once instead of hanging until exit. */
    shutdown(s->quiesced, SHUT_RDWR);
}

unsigned tc_server_connections(const tc_server *s) {
    const union MHD_DaemonInfo *info = MHD_get_daemon_info(s->d, MHD_DAEMON_INFO_CURRENT_CONNECTIONS);
    return info ? info->num_connections : 0;
}

void tc_server_cancel_waiting(tc_server *s) { tc_pool_stop(s->state.pool); }

void tc_server_stop(tc_server *s) {
    if (!s) return;
    /* Before the daemon: every suspended connection must be resumed first. */
    tc_pool_free(s->state.pool);
    MHD_stop_daemon(s->d);
    tc_conns_stop(s->conns); /* after the daemon: no connection is left to notify */
    if (s->quiesced != MHD_INVALID_SOCKET) close(s->quiesced); /* only after stop: see MHD_quiesce_daemon */
    tc_meshes_free(s->state.meshes); /* after the pool and the daemon: no route holds a job */
    free(s);
}
