/* store.h — the mesh store: canonical mesh bytes by content id, behind a small
 * vtable so that another backend (Redis, shared by replicas) fits the same calls. */
#ifndef TC_IO_STORE_H
#define TC_IO_STORE_H

#include <stddef.h>

/* Invariant of every backend: it holds ids and bytes only (no pointers, no
 * process state), so any replica can serve any id it holds. Thread-safe.
 * Every call answers -1 when the store cannot answer now (a backend out of
 * reach or out of memory): not "not found" — the caller answers 503 with
 * Retry-After, and the same call may succeed later. */
typedef struct tc_store tc_store;

/* What /healthz and /metrics report of a backend. */
typedef struct {
    int up;                        /* 1: the last use (or probe) reached it; 0: it is down */
    unsigned long long errors;     /* calls answered -1 */
    unsigned long long reconnects; /* times it came back after being down */
} tc_store_health;

typedef struct {
    /* Stores n bytes under id; *existed (if not NULL) says whether id was there
     * already (its bytes are then left as they were: an id names one content).
     * 0, or -1 when out of memory / the backend failed. */
    int (*put)(tc_store *s, const char *id, const void *bytes, size_t n, int *existed);
    /* 1 and a malloc'd copy in *bytes, *n (the caller frees it) when id is
     * there, 0 when not, -1 on failure. bytes == NULL: only whether it is there. */
    int (*get)(tc_store *s, const char *id, char **bytes, size_t *n);
    /* 1 if id was there (now gone), 0 if not, -1 on failure. */
    int (*del)(tc_store *s, const char *id);
    /* Ids stored now (for /metrics), or -1 when the backend cannot tell. */
    long (*count)(tc_store *s);
    /* Readiness: 1 if the backend answers now, else 0 (bounded in time; it
     * does not retry a backend found down sooner than its backoff allows). */
    int (*probe)(tc_store *s);
    void (*health)(tc_store *s, tc_store_health *h);
    void (*destroy)(tc_store *s);
} tc_store_ops;

struct tc_store {
    const tc_store_ops *ops;
    const char *name; /* "memory", "redis" */
};

/* The in-process backend (--store memory). NULL if out of memory. */
tc_store *tc_store_memory_new(void);

/* The Redis backend (--store redis://HOST:PORT[/DB], store_redis.c). */
typedef struct {
    const char *url;          /* redis://HOST:PORT[/DB] */
    long long ttl_s;          /* each key's time to live, set on put and renewed on get; 0: none */
    double connect_timeout_s; /* one connect attempt */
    double command_timeout_s; /* one command's round trip */
    int max_idle;             /* connections kept open between calls */
    void (*log)(const char *line); /* state changes (down, back), or NULL */
} tc_redis_opts;

/* Whether url is redis://HOST:PORT[/DB] (HOST a name, an IPv4 address or
 * [IPv6]; PORT 1-65535; DB 0-65535, default 0): 0 and its parts, else -1. */
int tc_redis_url_parse(const char *url, char *host, size_t hostlen, int *port, int *db);
/* NULL with the reason in err only for a bad URL or no memory: a Redis that
 * is not reachable yet is a store that is down (it answers -1 until it is up). */
tc_store *tc_store_redis_new(const tc_redis_opts *o, char *err, size_t errlen);

static inline int tc_store_put(tc_store *s, const char *id, const void *b, size_t n, int *existed) {
    return s->ops->put(s, id, b, n, existed);
}
static inline int tc_store_get(tc_store *s, const char *id, char **b, size_t *n) {
    return s->ops->get(s, id, b, n);
}
static inline int tc_store_del(tc_store *s, const char *id) { return s->ops->del(s, id); }
static inline long tc_store_count(tc_store *s) { return s->ops->count(s); }
static inline int tc_store_probe(tc_store *s) { return s->ops->probe(s); }
static inline void tc_store_health_of(tc_store *s, tc_store_health *h) { s->ops->health(s, h); }
static inline void tc_store_free(tc_store *s) {
    if (s) s->ops->destroy(s);
}

#endif
