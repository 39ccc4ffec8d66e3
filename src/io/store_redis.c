/* store_redis.c — the mesh store in Redis (--store redis://HOST:PORT[/DB]), shared
 * by replicas: key tocher:mesh:<id>, value the canonical bytes (zstd when it pays). */
#include <errno.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/time.h>
#include <time.h>

#include <hiredis/hiredis.h>
#include <zstd.h>

#include "io/store.h"

/* Compression. The canonical form is JSON text with every number exact; on the
 * benchmark's meshes (bench/perf/meshes.py, grids of f(x,y) = sin(3x+1)cos(2y)+x²/2)
 * zstd level 1 gives 22.9 MB -> 5.5 MB (4.2x) for 524k triangles in 0.15 s, and
 * 473 kB -> 112 kB for 10k; level 3 is larger *and* slower here, level 9 only
 * 7 % smaller for 4x the time. A miss then moves a quarter of the bytes from
 * Redis and Redis holds a quarter of the memory, for a decompression (~1 GB/s)
 * far cheaper than the build that follows. So: level 1, for values of at least
 * COMPRESS_MIN bytes, kept only if it saves at least an eighth (a tiny mesh is
 * stored as it is, readable with redis-cli). A value is read as zstd when it
 * starts with the zstd frame magic; the canonical form starts with '{', and any
 * other value that starts with the magic is always stored compressed, so the
 * rule holds for arbitrary bytes. */
enum { COMPRESS_LEVEL = 1, COMPRESS_MIN = 1024 };
static const unsigned char zstd_magic[4] = {0x28, 0xb5, 0x2f, 0xfd};
/* A stored frame claiming more than this is refused (a corrupt or foreign value). */
#define DECODED_MAX ((unsigned long long)4 << 30)

/* Lifetime: every key gets the TTL on SET and again on each use (EXPIRE on
 * the existence check every mesh request makes, GETEX on a read), so a mesh
 * lives ttl_s after its last use. Under maxmemory-policy allkeys-lru Redis
 * evicts the least recently used keys when full; an evicted key reads as
 * absent (0), which the routes answer 404 "POST it again", and a re-POST
 * stores it under the same id. Under noeviction a full Redis answers SET
 * with an error reply: -1, a 503 for the POST. */
#define KEY_PREFIX "tocher:mesh:"
/* Backoff while Redis is down: no connect attempt sooner than this after the
 * last failed one, doubling up to BACKOFF_MAX_MS (a dead Redis is not hammered,
 * and one that is back is found within a second). */
#define BACKOFF_MIN_MS 200.0
#define BACKOFF_MAX_MS 1000.0
#define ERROR_LOG_MS 1000.0 /* at most one logged error reply per second */
enum { MAX_IDLE = 256 }; /* the most connections kept open between calls */

/* Invariants (all under lock): up == 0 => no idle connection is kept; while
 * !up, at most one thread at a time (probing) talks to Redis, and not before
 * retry_at; a connection taken from idle is used by one thread only; gen
 * changes whenever the idle connections are dropped, and a connection taken
 * under an older gen is not put back. */
typedef struct {
    tc_store base; /* first: a tc_store * is a redis_store * */
    char host[256], url[300];
    int port, db;
    long long ttl_s;
    struct timeval connect_tv, command_tv;
    int max_idle;
    void (*log)(const char *line);
    pthread_mutex_t lock;
    redisContext **idle;
    int nidle;
    unsigned gen;
    int up, probing;
    double retry_at_ms, backoff_ms, last_error_log_ms;
    atomic_ullong errors, reconnects;
} redis_store;

static double now_ms(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

static struct timeval timeval_of(double s) {
    if (s < 1e-3) s = 1e-3; /* hiredis reads 0 as "no timeout" */
    struct timeval tv;
    tv.tv_sec = (time_t)s;
    tv.tv_usec = (suseconds_t)((s - (double)tv.tv_sec) * 1e6);
    return tv;
}

static void say(redis_store *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void say(redis_store *r, const char *fmt, ...) {
    if (!r->log) return;
    char line[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    r->log(line);
}

/* ---- the URL ---- */

static int parse_int(const char *s, size_t n, long lo, long hi, int *out) {
    if (n == 0 || n > 5) return -1;
    long v = 0;
    for (size_t i = 0; i < n; i++) {
        if (s[i] < '0' || s[i] > '9') return -1;
        v = v * 10 + (s[i] - '0');
    }
    if (v < lo || v > hi) return -1;
    *out = (int)v;
    return 0;
}

int tc_redis_url_parse(const char *url, char *host, size_t hostlen, int *port, int *db) {
    const char *scheme = "redis://";
    if (strncmp(url, scheme, strlen(scheme))) return -1;
    const char *h = url + strlen(scheme), *slash = strchr(h, '/');
    const char *end = slash ? slash : h + strlen(h);
    const char *colon = NULL;
    for (const char *p = h; p < end; p++)
        if (*p == ':') colon = p; /* the last: [::1]:6379 */
    if (!colon || colon == h) return -1;
    const char *hs = h, *he = colon;
    if (*h == '[') {
        if (colon[-1] != ']' || colon - h < 3) return -1;
        hs = h + 1, he = colon - 1;
    } else if (memchr(h, ':', (size_t)(colon - h))) {
        return -1; /* an IPv6 address needs its brackets */
    }
    if ((size_t)(he - hs) >= hostlen) return -1;
    for (const char *p = hs; p < he; p++)
        if (*p <= ' ' || *p == '@' || *p == '[' || *p == ']' || *p == '/') return -1;
    int d = 0;
    if (parse_int(colon + 1, (size_t)(end - colon - 1), 1, 65535, port)) return -1;
    if (slash && parse_int(slash + 1, strlen(slash + 1), 0, 65535, &d)) return -1;
    memcpy(host, hs, (size_t)(he - hs));
    host[he - hs] = '\0';
    *db = d;
    return 0;
}

/* ---- the state: up, down, backoff ---- */

/* Whether this call may talk to Redis now; *probing = 1 when it is the one
 * call that tries a Redis found down (then mark_up or mark_down must follow). */
static int admit(redis_store *r, int *probing) {
    int ok = 1;
    *probing = 0;
    pthread_mutex_lock(&r->lock);
    if (!r->up) {
        if (r->probing || now_ms() < r->retry_at_ms) ok = 0;
        else r->probing = *probing = 1;
    }
    pthread_mutex_unlock(&r->lock);
    return ok;
}

static void mark_up(redis_store *r, int probing) {
    pthread_mutex_lock(&r->lock);
    int was_down = !r->up;
    r->up = 1, r->backoff_ms = BACKOFF_MIN_MS;
    if (probing) r->probing = 0;
    pthread_mutex_unlock(&r->lock);
    if (!was_down) return;
    atomic_fetch_add(&r->reconnects, 1);
    say(r, "mesh store %s reachable again", r->url);
}

/* Takes the idle connections out (the caller frees them) and changes gen. */
static int take_idle(redis_store *r, redisContext **out) {
    int n = r->nidle;
    memcpy(out, r->idle, (size_t)n * sizeof *out);
    r->nidle = 0;
    r->gen++;
    return n;
}

static void free_all(redisContext **c, int n) {
    for (int i = 0; i < n; i++) redisFree(c[i]);
}

/* Redis did not answer: down until a probe after the backoff finds it. A
 * failure seen by a call admitted while up (there may be many at once) starts
 * the backoff once; a failed probe doubles it. */
static void mark_down(redis_store *r, int probing, const char *why) {
    redisContext *old[MAX_IDLE];
    pthread_mutex_lock(&r->lock);
    int was_up = r->up;
    if (was_up || probing) {
        r->retry_at_ms = now_ms() + r->backoff_ms;
        r->backoff_ms = r->backoff_ms * 2 < BACKOFF_MAX_MS ? r->backoff_ms * 2 : BACKOFF_MAX_MS;
    }
    r->up = 0;
    if (probing) r->probing = 0;
    int n = take_idle(r, old);
    pthread_mutex_unlock(&r->lock);
    free_all(old, n);
    if (was_up) say(r, "mesh store %s unreachable (%s): mesh routes answer 503 until it is back", r->url, why);
}

/* ---- connections ---- */

static redisContext *connect_one(redis_store *r, char *why, size_t whylen) {
    redisContext *c = redisConnectWithTimeout(r->host, r->port, r->connect_tv);
    if (!c || c->err) {
        snprintf(why, whylen, "connect: %s", c ? c->errstr : "out of memory");
        if (c) redisFree(c);
        return NULL;
    }
    if (redisSetTimeout(c, r->command_tv) != REDIS_OK) {
        snprintf(why, whylen, "cannot set the command timeout");
        return redisFree(c), NULL;
    }
    if (r->db == 0) return c;
    redisReply *rep = redisCommand(c, "SELECT %d", r->db);
    int ok = rep && rep->type == REDIS_REPLY_STATUS;
    if (!ok) snprintf(why, whylen, "SELECT %d: %s", r->db, rep ? rep->str : c->errstr);
    if (rep) freeReplyObject(rep);
    if (!ok) redisFree(c), c = NULL;
    return c;
}

/* An idle connection (*fresh = 0) or a new one (*fresh = 1), and the gen it
 * belongs to; NULL with the reason in why. */
static redisContext *take(redis_store *r, unsigned *gen, int *fresh, char *why, size_t whylen) {
    pthread_mutex_lock(&r->lock);
    *gen = r->gen;
    redisContext *c = r->nidle ? r->idle[--r->nidle] : NULL;
    pthread_mutex_unlock(&r->lock);
    *fresh = c == NULL;
    return c ? c : connect_one(r, why, whylen);
}

static void give(redis_store *r, redisContext *c, unsigned gen) {
    pthread_mutex_lock(&r->lock);
    if (gen == r->gen && r->up && r->nidle < r->max_idle) r->idle[r->nidle++] = c, c = NULL;
    pthread_mutex_unlock(&r->lock);
    if (c) redisFree(c);
}

/* A connection that failed after being idle may only be stale (Redis was
 * restarted): the other idle ones are dropped too, and the command is tried
 * once more on a new connection before Redis is called down. Every command
 * here is idempotent (SET NX included), so the retry is safe. */
static redisReply *command(redis_store *r, int argc, const char **argv, const size_t *lens) {
    for (int attempt = 0; attempt < 2; attempt++) {
        int probing, fresh;
        unsigned gen;
        char why[160] = "";
        if (!admit(r, &probing)) return NULL;
        redisContext *c = take(r, &gen, &fresh, why, sizeof why);
        redisReply *rep = c ? redisCommandArgv(c, argc, argv, lens) : NULL;
        if (rep) {
            mark_up(r, probing);
            give(r, c, gen);
            return rep;
        }
        if (c) snprintf(why, sizeof why, "%s", c->errstr[0] ? c->errstr : strerror(errno)), redisFree(c);
        if (c && !fresh && !probing) {
            redisContext *old[MAX_IDLE];
            pthread_mutex_lock(&r->lock);
            int n = take_idle(r, old);
            pthread_mutex_unlock(&r->lock);
            free_all(old, n);
            continue;
        }
        mark_down(r, probing, why);
        return NULL;
    }
    return NULL;
}

/* An error reply (OOM under maxmemory-policy noeviction, LOADING, a command
 * this Redis lacks): Redis is up, the call fails; logged at most once a second. */
static void error_reply(redis_store *r, const redisReply *rep) {
    double t = now_ms();
    pthread_mutex_lock(&r->lock);
    int log = t - r->last_error_log_ms >= ERROR_LOG_MS;
    if (log) r->last_error_log_ms = t;
    pthread_mutex_unlock(&r->lock);
    if (log) say(r, "mesh store %s: %.*s", r->url, (int)(rep->len < 200 ? rep->len : 200), rep->str);
}

/* The reply, or NULL (counted as an error) when Redis failed to give one of
 * the wanted type. */
static redisReply *expect(redis_store *r, redisReply *rep, int type1, int type2) {
    if (rep && (rep->type == type1 || rep->type == type2)) return rep;
    if (rep && rep->type == REDIS_REPLY_ERROR) error_reply(r, rep);
    if (rep) freeReplyObject(rep);
    atomic_fetch_add(&r->errors, 1);
    return NULL;
}

/* ---- values ---- */

static int has_magic(const void *b, size_t n) { return n >= 4 && !memcmp(b, zstd_magic, 4); }

/* The bytes to store for (b, n): *out (malloc'd, the caller frees it) when
 * compressed, else NULL and b itself is stored. -1: no memory. */
static int encode(const void *b, size_t n, char **out, size_t *outn) {
    *out = NULL;
    int must = has_magic(b, n);
    if (n < COMPRESS_MIN && !must) return 0;
    size_t cap = ZSTD_compressBound(n);
    char *z = malloc(cap);
    if (!z) return -1;
    size_t zn = ZSTD_compress(z, cap, b, n, COMPRESS_LEVEL);
    if (ZSTD_isError(zn)) return free(z), must ? -1 : 0;
    if (!must && zn > n - n / 8) return free(z), 0;
    *out = z, *outn = zn;
    return 0;
}

/* The stored value back to the canonical bytes (malloc'd): 0, or -1. */
static int decode(redis_store *r, const char *v, size_t n, char **bytes, size_t *outn) {
    if (!has_magic(v, n)) {
        *bytes = malloc(n ? n : 1);
        if (!*bytes) return -1;
        memcpy(*bytes, v, n), *outn = n;
        return 0;
    }
    unsigned long long size = ZSTD_getFrameContentSize(v, n);
    if (size == ZSTD_CONTENTSIZE_ERROR || size == ZSTD_CONTENTSIZE_UNKNOWN || size > DECODED_MAX) {
        say(r, "mesh store %s: a value that is not a zstd frame of this program's", r->url);
        return -1;
    }
    *bytes = malloc(size ? (size_t)size : 1);
    if (!*bytes) return -1;
    size_t got = ZSTD_decompress(*bytes, (size_t)size, v, n);
    if (ZSTD_isError(got) || got != size) {
        say(r, "mesh store %s: a corrupt zstd value", r->url);
        return free(*bytes), *bytes = NULL, -1;
    }
    *outn = (size_t)size;
    return 0;
}

/* ---- the operations ---- */

static void key_of(const char *id, char *key, size_t n) { snprintf(key, n, KEY_PREFIX "%s", id); }

/* SET key value NX [EX ttl]: stored (OK) or there already (nil, whose TTL is
 * then renewed: a POST is a use). */
static int redis_put(tc_store *s, const char *id, const void *bytes, size_t n, int *existed) {
    redis_store *r = (redis_store *)s;
    char key[128], ttl[32];
    char *z;
    size_t zn = 0;
    if (encode(bytes, n, &z, &zn)) return atomic_fetch_add(&r->errors, 1), -1;
    key_of(id, key, sizeof key);
    snprintf(ttl, sizeof ttl, "%lld", r->ttl_s);
    const char *argv[] = {"SET", key, z ? z : bytes, "NX", "EX", ttl};
    size_t lens[] = {3, strlen(key), z ? zn : n, 2, 2, strlen(ttl)};
    redisReply *rep = expect(r, command(r, r->ttl_s > 0 ? 6 : 4, argv, lens), REDIS_REPLY_STATUS, REDIS_REPLY_NIL);
    free(z);
    if (!rep) return -1;
    int was = rep->type == REDIS_REPLY_NIL;
    freeReplyObject(rep);
    if (was && r->ttl_s > 0) {
        const char *ex[] = {"EXPIRE", key, ttl};
        size_t exl[] = {6, strlen(key), strlen(ttl)};
        rep = expect(r, command(r, 3, ex, exl), REDIS_REPLY_INTEGER, REDIS_REPLY_INTEGER);
        if (!rep) return -1;
        freeReplyObject(rep);
    }
    if (existed) *existed = was;
    return 0;
}

/* Whether the key is there, renewing its TTL: EXPIRE (or EXISTS without a TTL). */
static int redis_exists(redis_store *r, const char *key, const char *ttl) {
    const char *argv[] = {r->ttl_s > 0 ? "EXPIRE" : "EXISTS", key, ttl};
    size_t lens[] = {strlen(argv[0]), strlen(key), strlen(ttl)};
    redisReply *rep = expect(r, command(r, r->ttl_s > 0 ? 3 : 2, argv, lens), REDIS_REPLY_INTEGER, REDIS_REPLY_INTEGER);
    if (!rep) return -1;
    int there = rep->integer > 0;
    freeReplyObject(rep);
    return there;
}

/* GETEX key EX ttl (Redis >= 6.2: the read renews the TTL), or GET without one. */
static int redis_get(tc_store *s, const char *id, char **bytes, size_t *n) {
    redis_store *r = (redis_store *)s;
    char key[128], ttl[32];
    key_of(id, key, sizeof key);
    snprintf(ttl, sizeof ttl, "%lld", r->ttl_s);
    if (!bytes) return redis_exists(r, key, ttl);
    const char *argv[] = {r->ttl_s > 0 ? "GETEX" : "GET", key, "EX", ttl};
    size_t lens[] = {strlen(argv[0]), strlen(key), 2, strlen(ttl)};
    redisReply *rep = expect(r, command(r, r->ttl_s > 0 ? 4 : 2, argv, lens), REDIS_REPLY_STRING, REDIS_REPLY_NIL);
    if (!rep) return -1;
    int rc = rep->type == REDIS_REPLY_NIL ? 0 : decode(r, rep->str, rep->len, bytes, n) ? -1 : 1;
    freeReplyObject(rep);
    if (rc < 0) atomic_fetch_add(&r->errors, 1);
    return rc;
}

static int redis_del(tc_store *s, const char *id) {
    redis_store *r = (redis_store *)s;
    char key[128];
    key_of(id, key, sizeof key);
    const char *argv[] = {"DEL", key};
    size_t lens[] = {3, strlen(key)};
    redisReply *rep = expect(r, command(r, 2, argv, lens), REDIS_REPLY_INTEGER, REDIS_REPLY_INTEGER);
    if (!rep) return -1;
    int gone = rep->integer > 0;
    freeReplyObject(rep);
    return gone;
}

/* Counting the keys would be a SCAN of the whole keyspace: Redis's own
 * INFO keyspace tells an operator more. */
static long redis_count(tc_store *s) {
    (void)s;
    return -1;
}

/* PING; while Redis is down and its backoff runs, 0 without a try. */
static int redis_probe(tc_store *s) {
    redis_store *r = (redis_store *)s;
    const char *argv[] = {"PING"};
    size_t lens[] = {4};
    redisReply *rep = expect(r, command(r, 1, argv, lens), REDIS_REPLY_STATUS, REDIS_REPLY_STATUS);
    int ok = rep && rep->len == 4 && !memcmp(rep->str, "PONG", 4);
    if (rep) freeReplyObject(rep);
    return ok;
}

static void redis_health(tc_store *s, tc_store_health *h) {
    redis_store *r = (redis_store *)s;
    pthread_mutex_lock(&r->lock);
    h->up = r->up;
    pthread_mutex_unlock(&r->lock);
    h->errors = atomic_load(&r->errors);
    h->reconnects = atomic_load(&r->reconnects);
}

static void redis_destroy(tc_store *s) {
    redis_store *r = (redis_store *)s;
    free_all(r->idle, r->nidle);
    pthread_mutex_destroy(&r->lock);
    free(r->idle);
    free(r);
}

static const tc_store_ops redis_ops = {redis_put,   redis_get,    redis_del,    redis_count,
                                       redis_probe, redis_health, redis_destroy};

/* Starts down with no backoff: the first call (the PING below) probes at once. */
tc_store *tc_store_redis_new(const tc_redis_opts *o, char *err, size_t errlen) {
    redis_store *r = calloc(1, sizeof *r);
    if (!r) return snprintf(err, errlen, "out of memory for the mesh store"), NULL;
    if (tc_redis_url_parse(o->url, r->host, sizeof r->host, &r->port, &r->db)) {
        snprintf(err, errlen, "bad store URL '%s' (redis://HOST:PORT[/DB])", o->url);
        return free(r), NULL;
    }
    snprintf(r->url, sizeof r->url, "%s", o->url);
    r->ttl_s = o->ttl_s > 0 ? o->ttl_s : 0;
    r->connect_tv = timeval_of(o->connect_timeout_s);
    r->command_tv = timeval_of(o->command_timeout_s);
    r->max_idle = o->max_idle < 1 ? 1 : o->max_idle > MAX_IDLE ? MAX_IDLE : o->max_idle;
    r->idle = calloc((size_t)r->max_idle, sizeof *r->idle);
    if (!r->idle || pthread_mutex_init(&r->lock, NULL)) {
        free(r->idle), free(r);
        return snprintf(err, errlen, "out of memory for the mesh store"), NULL;
    }
    r->backoff_ms = BACKOFF_MIN_MS;
    atomic_init(&r->errors, 0);
    atomic_init(&r->reconnects, 0);
    r->base.ops = &redis_ops;
    r->base.name = "redis";
    int up = redis_probe(&r->base); /* before r->log: the first connect is no "again" */
    atomic_store(&r->reconnects, 0);
    atomic_store(&r->errors, 0);
    r->log = o->log;
    if (up) say(r, "mesh store %s reachable (TTL %lld s)", r->url, r->ttl_s);
    else say(r, "mesh store %s not reachable yet: mesh routes answer 503 until it is", r->url);
    return &r->base;
}
