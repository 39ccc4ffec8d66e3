/* main.c — tocherd: reads the settings, starts the HTTP daemon, prints where
 * it listens, and on SIGTERM/SIGINT drains requests in flight and exits 0. */
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <time.h>

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

/* Waits until no request is in flight, the grace period is over, or a second
 * signal asks to stop at once. */
static void drain(const sigset_t *sigs, double grace_s) {
    double end = tc_now_ms() + grace_s * 1e3;
    const struct timespec tick = {0, 20 * 1000 * 1000};
    long n;
    while ((n = tc_metrics_in_flight()) > 0) {
        if (tc_now_ms() >= end) {
            tc_log_notice("grace period over with %ld request(s) in flight; stopping", n);
            return;
        }
        if (sigtimedwait(sigs, NULL, &tick) > 0) {
            tc_log_notice("second signal; stopping with %ld request(s) in flight", n);
            return;
        }
    }
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
    drain(&sigs, cfg.shutdown_grace);
    tc_server_stop(srv);
    tc_log_notice("stopped");
    return 0;
}
