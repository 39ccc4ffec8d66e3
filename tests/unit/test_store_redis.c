/* test_store_redis.c — the Redis mesh store (io/store_redis.c) against a real
 * redis-server this test starts on a free loopback port: URLs, bytes in and out
 * (zstd or not), TTL set and renewed, down (refused, killed, hung) and back. */
#include <arpa/inet.h>
#include <netinet/in.h>
#include <pthread.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <hiredis/hiredis.h>

#include "check.h"
#include "io/store.h"

static double ms_now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

static void sleep_ms(long ms) { nanosleep(&(struct timespec){ms / 1000, (ms % 1000) * 1000000L}, NULL); }

/* A loopback port nothing listens on now. */
static int free_port(void) {
    int fd = socket(AF_INET, SOCK_STREAM, 0);
    struct sockaddr_in a = {0};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t n = sizeof a;
    if (fd < 0 || bind(fd, (struct sockaddr *)&a, sizeof a) || getsockname(fd, (struct sockaddr *)&a, &n)) {
        if (fd >= 0) close(fd);
        return -1;
    }
    close(fd);
    return ntohs(a.sin_port);
}

/* redis-server on 127.0.0.1:port, no persistence; its pid once it answers, else -1. */
static pid_t redis_start(int port) {
    char p[16];
    snprintf(p, sizeof p, "%d", port);
    pid_t pid = fork();
    if (pid == 0) {
        /* Dies with this test (a crash included): an orphan would hold the runner's pipe open. */
        prctl(PR_SET_PDEATHSIG, SIGKILL);
        if (!freopen("/dev/null", "w", stdout) || !freopen("/dev/null", "w", stderr)) _exit(126);
        execlp("redis-server", "redis-server", "--port", p, "--bind", "127.0.0.1", "--save", "", "--appendonly", "no",
               (char *)NULL);
        _exit(127);
    }
    for (int i = 0; pid > 0 && i < 100; i++) {
        redisContext *c = redisConnect("127.0.0.1", port);
        int ok = c && !c->err;
        if (c) redisFree(c);
        if (ok) return pid;
        if (waitpid(pid, NULL, WNOHANG) == pid) return -1;
        sleep_ms(50);
    }
    if (pid > 0) kill(pid, SIGKILL), waitpid(pid, NULL, 0);
    return -1;
}

static void redis_kill(pid_t pid) {
    kill(pid, SIGKILL);
    waitpid(pid, NULL, 0);
}

static int have_redis_server(void) { return system("command -v redis-server >/dev/null 2>&1") == 0; }

static tc_store *open_store(int port, long long ttl, double command_s) {
    char url[64], err[200];
    snprintf(url, sizeof url, "redis://127.0.0.1:%d/3", port); /* DB 3: SELECT on every connect */
    tc_redis_opts o = {url, ttl, 0.5, command_s, 4, NULL};
    return tc_store_redis_new(&o, err, sizeof err);
}

/* A side connection to the same DB, to look at what the store wrote. */
static redisContext *side(int port) {
    redisContext *c = redisConnect("127.0.0.1", port);
    if (c && !c->err) freeReplyObject(redisCommand(c, "SELECT 3"));
    return c;
}

static long long side_int(redisContext *c, const char *fmt, const char *key) {
    redisReply *r = redisCommand(c, fmt, key);
    long long v = r && r->type == REDIS_REPLY_INTEGER ? r->integer : -999;
    if (r) freeReplyObject(r);
    return v;
}

TEST(redis_url_parse) {
    char h[64];
    int port = 0, db = -1;
    CHECK(tc_redis_url_parse("redis://127.0.0.1:6379", h, sizeof h, &port, &db) == 0 && !strcmp(h, "127.0.0.1") &&
          port == 6379 && db == 0);
    CHECK(tc_redis_url_parse("redis://cache.local:7000/5", h, sizeof h, &port, &db) == 0 &&
          !strcmp(h, "cache.local") && port == 7000 && db == 5);
    CHECK(tc_redis_url_parse("redis://[::1]:6380/0", h, sizeof h, &port, &db) == 0 && !strcmp(h, "::1") &&
          port == 6380 && db == 0);
    const char *bad[] = {"redis://", "redis://host", "redis://:6379", "redis://h:0", "redis://h:65536",
                         "redis://h:63x9", "redis://h:6379/", "redis://h:6379/x", "redis://h:6379/70000",
                         "http://h:6379", "redis://::1:6379", "redis://user@h:6379", "memory", "",
                         "redis://h:6379/1/2"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
        CHECK_MSG(tc_redis_url_parse(bad[i], h, sizeof h, &port, &db) == -1, "accepted '%s'", bad[i]);
    CHECK(tc_redis_url_parse("redis://a-very-long-host-name-indeed:1", h, 8, &port, &db) == -1); /* too long */
    char err[128];
    tc_redis_opts o = {"redis://nowhere", 0, 0.1, 0.1, 1, NULL};
    CHECK(tc_store_redis_new(&o, err, sizeof err) == NULL && strstr(err, "redis://nowhere"));
}

/* Nothing listens: every call is "cannot answer now" (-1), never "not found". */
TEST(redis_store_down_is_not_not_found) {
    signal(SIGPIPE, SIG_IGN);
    int port = free_port();
    tc_store *s = open_store(port, 60, 0.2);
    CHECK(s && !strcmp(s->name, "redis"));
    if (!s) return;
    tc_store_health h;
    tc_store_health_of(s, &h);
    CHECK(h.up == 0);
    char *b = NULL;
    size_t n = 0;
    int existed = -1;
    double t0 = ms_now();
    for (int i = 0; i < 100; i++) {
        CHECK(tc_store_put(s, "abc", "x", 1, &existed) == -1);
        CHECK(tc_store_get(s, "abc", &b, &n) == -1 && b == NULL);
        CHECK(tc_store_get(s, "abc", NULL, NULL) == -1);
        CHECK(tc_store_del(s, "abc") == -1);
    }
    CHECK_MSG(ms_now() - t0 < 500, "400 calls to a Redis that is down took %.0f ms", ms_now() - t0);
    CHECK(tc_store_probe(s) == 0 && tc_store_count(s) == -1);
    tc_store_health_of(s, &h);
    CHECK(h.up == 0 && h.errors >= 400 && h.reconnects == 0);
    tc_store_free(s);
}

static void roundtrip(tc_store *s, redisContext *c, const char *id, const char *v, size_t n, int compressed) {
    int existed = -1;
    CHECK(tc_store_put(s, id, v, n, &existed) == 0 && existed == 0);
    CHECK(tc_store_put(s, id, "other", 5, &existed) == 0 && existed == 1); /* an id keeps its bytes */
    char *b = NULL, key[64];
    size_t bn = 0;
    CHECK(tc_store_get(s, id, &b, &bn) == 1 && bn == n && b && !memcmp(b, v, n));
    free(b);
    snprintf(key, sizeof key, "tocher:mesh:%s", id);
    redisReply *r = redisCommand(c, "GET %s", key);
    int is_zstd = r && r->type == REDIS_REPLY_STRING && r->len >= 4 && !memcmp(r->str, "\x28\xb5\x2f\xfd", 4);
    CHECK_MSG(is_zstd == compressed, "%s: stored %s", id, is_zstd ? "compressed" : "as it is");
    if (compressed && n > 1000) CHECK(r && r->len < n / 4); /* the text repeats: zstd pays */
    if (!compressed) CHECK(r && r->len == n && !memcmp(r->str, v, n));
    if (r) freeReplyObject(r);
}

typedef struct {
    tc_store *s;
    int k, bad;
} worker;

static void *hammer(void *arg) {
    worker *w = arg;
    char id[32], v[64];
    for (int i = 0; i < 200; i++) {
        snprintf(id, sizeof id, "w%d-%d", w->k, i % 20);
        int n = snprintf(v, sizeof v, "value of %s", id);
        char *b = NULL;
        size_t bn = 0;
        if (tc_store_put(w->s, id, v, (size_t)n, NULL) != 0 || tc_store_get(w->s, id, &b, &bn) != 1 ||
            bn != (size_t)n || memcmp(b, v, bn))
            w->bad++;
        free(b);
    }
    return NULL;
}

TEST(redis_store_live) {
    signal(SIGPIPE, SIG_IGN);
    if (!have_redis_server()) {
        printf("   note: redis_store_live skipped: no redis-server (make deps installs it)\n");
        return;
    }
    int port = free_port();
    pid_t pid = redis_start(port);
    CHECK_MSG(pid > 0, "redis-server did not start on port %d", port);
    if (pid <= 0) return;
    tc_store *s = open_store(port, 100, 0.3);
    redisContext *c = side(port);
    tc_store_health h;
    tc_store_health_of(s, &h);
    CHECK(h.up == 1 && tc_store_probe(s) == 1);
    /* Small: as it is; NUL bytes; large JSON-like text: zstd; bytes that look like zstd: always compressed. */
    roundtrip(s, c, "small", "{\"vertices\":[]}", 15, 0);
    roundtrip(s, c, "binary", "a\0b\0c", 5, 0);
    size_t big = 200000;
    char *text = malloc(big);
    for (size_t i = 0; i < big; i++) text[i] = (char)("[0.125,1.5],"[i % 12] + (i % 997 == 0));
    roundtrip(s, c, "big", text, big, 1);
    static const char magic[] = "\x28\xb5\x2f\xfd-not-a-frame";
    roundtrip(s, c, "magic", magic, sizeof magic - 1, 1);
    free(text);
    /* The TTL: set on put, renewed by a get with or without the bytes. */
    long long ttl = side_int(c, "TTL %s", "tocher:mesh:small");
    CHECK_MSG(ttl > 95 && ttl <= 100, "TTL %lld", ttl);
    side_int(c, "EXPIRE %s 5", "tocher:mesh:small");
    CHECK(tc_store_get(s, "small", NULL, NULL) == 1);
    CHECK(side_int(c, "TTL %s", "tocher:mesh:small") > 95);
    side_int(c, "EXPIRE %s 5", "tocher:mesh:big");
    char *b = NULL;
    size_t bn = 0;
    CHECK(tc_store_get(s, "big", &b, &bn) == 1 && bn == big);
    free(b);
    CHECK(side_int(c, "TTL %s", "tocher:mesh:big") > 95);
    /* Gone: deleted, or evicted behind the store's back. */
    CHECK(tc_store_del(s, "small") == 1 && tc_store_del(s, "small") == 0);
    CHECK(tc_store_get(s, "small", NULL, NULL) == 0 && tc_store_get(s, "small", &b, &bn) == 0);
    side_int(c, "DEL %s", "tocher:mesh:binary");
    CHECK(tc_store_get(s, "binary", &b, &bn) == 0);
    /* Threads share the pool (4 idle connections for 8 threads). */
    pthread_t th[8];
    worker w[8];
    for (int k = 0; k < 8; k++) w[k] = (worker){s, k, 0}, pthread_create(&th[k], NULL, hammer, &w[k]);
    int bad = 0;
    for (int k = 0; k < 8; k++) pthread_join(th[k], NULL), bad += w[k].bad;
    CHECK_MSG(bad == 0, "%d of 1600 put+get failed under 8 threads", bad);
    /* Hung (SIGSTOP): each call gives up within its timeouts, as -1. */
    kill(pid, SIGSTOP);
    double t0 = ms_now();
    CHECK(tc_store_get(s, "big", NULL, NULL) == -1);
    CHECK_MSG(ms_now() - t0 < 1500, "a call to a hung Redis took %.0f ms", ms_now() - t0);
    kill(pid, SIGCONT);
    /* Killed, then back empty on the same port: found again without a new store. */
    redis_kill(pid);
    CHECK(tc_store_get(s, "big", NULL, NULL) == -1);
    tc_store_health_of(s, &h);
    CHECK(h.up == 0);
    pid = redis_start(port);
    CHECK(pid > 0);
    int got = -1;
    for (int i = 0; i < 40 && got < 0; i++) got = tc_store_get(s, "big", NULL, NULL), sleep_ms(got < 0 ? 100 : 0);
    CHECK_MSG(got == 0, "after Redis came back empty: %d", got);
    tc_store_health_of(s, &h);
    CHECK(h.up == 1 && h.reconnects >= 1 && tc_store_probe(s) == 1);
    CHECK(tc_store_put(s, "again", "x", 1, NULL) == 0);
    redisFree(c);
    tc_store_free(s);
    if (pid > 0) redis_kill(pid);
}
