/* main.c — tocherd: reads the settings, starts the HTTP daemon, prints where
 * it listens, and on SIGTERM/SIGINT drains requests in flight and exits 0. */
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <time.h>

#include "core/leakcheck.h"
#include "core/parallel.h"
#include "io/api.h"
#include "server/config.h"
#include "server/log.h"
#include "server/metrics.h"
#include "server/routes.h"
#include "server/server.h"
#include "tocher.h"

/* SIGTERM and SIGINT are blocked in every thread (the pool inherits the mask
 * of the thread that starts it) and taken synchronously with sigwait here, so
 * no work ever happens in a signal handler. */
static void block_signals(sigset_t *set) {
    sigemptyset(set);
    sigaddset(set, SIGTERM);
    sigaddset(set, SIGINT);
    pthread_sigmask(SIG_BLOCK, set, NULL);
    struct sigaction ign;
    sigemptyset(&ign.sa_mask);
    ign.sa_flags = 0;
    ign.sa_handler = SIG_IGN;
    sigaction(SIGPIPE, &ign, NULL); /* a client gone mid-answer is an error code, not a death */
}

static void init_metrics(void) {
    const char *labels[TC_METRICS_MAX_ROUTES];
    int n = 0;
    while (n < TC_METRICS_MAX_ROUTES && tc_route_path(n)) labels[n] = tc_route_path(n), n++;
    tc_metrics_init(labels, n);
}

/* After the last request, how long an idle keep-alive connection is left
 * open: a request its client sends meanwhile still gets its 503 and
 * Connection: close, where closing it under the request would reset it. */
#define LINGER_MS 500.0

/* Waits until no connection is open (or none has a request in flight and the
 * others have been idle for LINGER_MS), the grace period is over, or a second
 * signal asks to stop at once. 0 if drained, else 1. */
static int drain(const sigset_t *sigs, tc_server *srv, double grace_s) {
    double now = tc_now_ms(), end = now + grace_s * 1e3, idle_since = 0;
    const struct timespec tick = {0, 20 * 1000 * 1000};
    long n;
    while (tc_server_connections(srv) > 0) {
        now = tc_now_ms();
        if ((n = tc_metrics_in_flight()) > 0) idle_since = 0;
        else if (!idle_since) idle_since = now;
        else if (now - idle_since >= LINGER_MS) return 0;
        if (now >= end) {
            tc_log_notice("grace period over with %ld request(s) in flight; stopping", n);
            return 1;
        }
        if (sigtimedwait(sigs, NULL, &tick) > 0) {
            tc_log_notice("second signal; stopping with %ld request(s) in flight", n);
            return 1;
        }
    }
    return 0;
}

int main(int argc, char **argv) {
    tc_srv_config cfg;
    int rc = tc_config_load(&cfg, argc, argv);
    if (rc != TC_CONFIG_RUN) return rc == TC_CONFIG_EXIT_OK ? 0 : 2;
    sigset_t sigs;
    block_signals(&sigs);
    init_metrics();
    char err[320];
    tc_server *srv = tc_server_start(&cfg, err, sizeof err);
    if (!srv) {
        tc_log_notice("%s", err);
        return 1;
    }
    printf("tocherd %s listening on http://%s\n", TC_VERSION, tc_server_address(srv));
    fflush(stdout);
    int sig = 0;
    while (sigwait(&sigs, &sig) != 0) continue;
    tc_log_notice("%s: no new connections; waiting for %ld request(s) in flight", sig == SIGINT ? "SIGINT" : "SIGTERM",
                  tc_metrics_in_flight());
    tc_server_quiesce(srv);
    if (drain(&sigs, srv, cfg.shutdown_grace)) {
        /* Requests still waiting for a worker get their 503 + Retry-After
         * (after those computing finish), and a moment to send it. */
        tc_server_cancel_waiting(srv);
        drain(&sigs, srv, 1.0);
    }
    tc_server_stop(srv);
    tc_log_notice("stopped");
    tc__parallel_stop(); /* the core's pool ended: no thread of it left for a leak check's scan */
    return tc__leak_checked_exit(0);
}
