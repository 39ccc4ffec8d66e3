/* test_drain.c — the daemon's stop lets no new connection into its listen queue while it takes
 * the ones already there (src/server/drain.c), on real loopback sockets. */
#define _DEFAULT_SOURCE /* INADDR_LOOPBACK */
#include <arpa/inet.h>
#include <errno.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "check.h"
#include "server/drain.h"

/* A listening socket on 127.0.0.1 and an ephemeral port (its address in *a), or -1. */
static int listener(struct sockaddr_in *a) {
    int fd = socket(AF_INET, SOCK_STREAM, 0);
    socklen_t n = sizeof *a;
    memset(a, 0, sizeof *a);
    a->sin_family = AF_INET, a->sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (fd < 0 || bind(fd, (struct sockaddr *)a, sizeof *a) != 0 || listen(fd, 16) != 0 ||
        getsockname(fd, (struct sockaddr *)a, &n) != 0) {
        if (fd >= 0) close(fd);
        return -1;
    }
    return fd;
}

/* A connect started without waiting: the socket, its handshake under way or done. */
static int connect_async(const struct sockaddr_in *a) {
    int fd = socket(AF_INET, SOCK_STREAM, 0);
    if (fd < 0) return -1;
    fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK);
    if (connect(fd, (const struct sockaddr *)a, sizeof *a) != 0 && errno != EINPROGRESS) {
        close(fd);
        return -1;
    }
    return fd;
}

/* Whether fd's connect completed within ms milliseconds (writable, no error). */
static int connected_within(int fd, int ms) {
    struct pollfd p = {fd, POLLOUT, 0};
    int err = 0;
    socklen_t n = sizeof err;
    return poll(&p, 1, ms) == 1 && getsockopt(fd, SOL_SOCKET, SO_ERROR, &err, &n) == 0 && err == 0;
}

/* Before the filter a connect completes at once; after it, a new one does not (its SYN is
 * dropped: no connection joins the queue), while the connection queued before it is taken
 * and carries its request and answer as before. */
TEST(drain_refuses_new_connections_keeps_queued) {
    struct sockaddr_in a;
    int L = listener(&a);
    CHECK(L >= 0);
    if (L < 0) return;
    int early = connect_async(&a);
    CHECK(early >= 0 && connected_within(early, 1000));
    CHECK(send(early, "ask", 3, 0) == 3);
    CHECK_MSG(tc_drain_refuse_new(L) == 0, "SO_ATTACH_FILTER: %s", strerror(errno));
    int late = connect_async(&a);
    CHECK_MSG(late >= 0 && !connected_within(late, 300), "a connect after the filter completed");
    int c = accept(L, NULL, NULL);
    char buf[8] = "";
    CHECK(c >= 0 && recv(c, buf, sizeof buf, 0) == 3 && memcmp(buf, "ask", 3) == 0);
    CHECK(c >= 0 && send(c, "ok", 2, 0) == 2);
    struct pollfd p = {early, POLLIN, 0};
    CHECK(poll(&p, 1, 1000) == 1 && recv(early, buf, sizeof buf, 0) == 2 && memcmp(buf, "ok", 2) == 0);
    fcntl(L, F_SETFL, fcntl(L, F_GETFL) | O_NONBLOCK);
    CHECK_MSG(accept(L, NULL, NULL) < 0 && (errno == EAGAIN || errno == EWOULDBLOCK), "the late connect was queued");
    if (c >= 0) close(c);
    if (late >= 0) close(late);
    close(early), close(L);
}
