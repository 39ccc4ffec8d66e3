/* store.h — the mesh store: canonical mesh bytes by content id, behind a small
 * vtable so that another backend (Redis, shared by replicas) fits the same calls. */
#ifndef TC_IO_STORE_H
#define TC_IO_STORE_H

#include <stddef.h>

/* Invariant of every backend: it holds ids and bytes only (no pointers, no
 * process state), so any replica can serve any id it holds. Thread-safe. */
typedef struct tc_store tc_store;

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
    void (*destroy)(tc_store *s);
} tc_store_ops;

struct tc_store {
    const tc_store_ops *ops;
    const char *name; /* "memory" */
};

/* The in-process backend (--store memory). NULL if out of memory. */
tc_store *tc_store_memory_new(void);

static inline int tc_store_put(tc_store *s, const char *id, const void *b, size_t n, int *existed) {
    return s->ops->put(s, id, b, n, existed);
}
static inline int tc_store_get(tc_store *s, const char *id, char **b, size_t *n) {
    return s->ops->get(s, id, b, n);
}
static inline int tc_store_del(tc_store *s, const char *id) { return s->ops->del(s, id); }
static inline long tc_store_count(tc_store *s) { return s->ops->count(s); }
static inline void tc_store_free(tc_store *s) {
    if (s) s->ops->destroy(s);
}

#endif
