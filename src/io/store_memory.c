/* store_memory.c — the in-process mesh store (--store memory): a chained hash
 * table of id -> bytes under one mutex; the bytes are copied in and out. */
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "io/store.h"

typedef struct item {
    struct item *next;
    char *id;
    char *bytes;
    size_t n;
} item;

typedef struct {
    tc_store base; /* first: a tc_store * is a mem_store * */
    pthread_mutex_t lock;
    item **slots;
    size_t nslots; /* a power of two */
    long count;
} mem_store;

static size_t hash(const char *s) { /* FNV-1a: the ids are already uniform */
    size_t h = 1469598103934665603ULL & (size_t)-1;
    for (; *s; s++) h = (h ^ (unsigned char)*s) * (size_t)1099511628211ULL;
    return h;
}

static item **find(mem_store *m, const char *id) {
    item **p = &m->slots[hash(id) & (m->nslots - 1)];
    while (*p && strcmp((*p)->id, id)) p = &(*p)->next;
    return p;
}

/* Doubles the table when it holds more items than slots (keeps chains short). */
static void grow(mem_store *m) {
    size_t n = m->nslots * 2;
    item **s = calloc(n, sizeof *s);
    if (!s) return; /* still correct, only slower */
    for (size_t i = 0; i < m->nslots; i++)
        for (item *it = m->slots[i], *next; it; it = next) {
            next = it->next;
            item **p = &s[hash(it->id) & (n - 1)];
            it->next = *p, *p = it;
        }
    free(m->slots);
    m->slots = s, m->nslots = n;
}

static int mem_put(tc_store *s, const char *id, const void *bytes, size_t n, int *existed) {
    mem_store *m = (mem_store *)s;
    item *it = calloc(1, sizeof *it);
    if (it) it->id = strdup(id), it->bytes = malloc(n ? n : 1), it->n = n;
    if (!it || !it->id || !it->bytes) {
        if (it) free(it->id), free(it->bytes), free(it);
        return -1;
    }
    memcpy(it->bytes, bytes, n);
    pthread_mutex_lock(&m->lock);
    item **p = find(m, id);
    int was = *p != NULL;
    if (!was) {
        it->next = NULL, *p = it, it = NULL;
        if (++m->count > (long)m->nslots) grow(m);
    }
    pthread_mutex_unlock(&m->lock);
    if (it) free(it->id), free(it->bytes), free(it);
    if (existed) *existed = was;
    return 0;
}

static int mem_get(tc_store *s, const char *id, char **bytes, size_t *n) {
    mem_store *m = (mem_store *)s;
    int rc = 0;
    pthread_mutex_lock(&m->lock);
    item *it = *find(m, id);
    if (it && bytes) {
        *bytes = malloc(it->n ? it->n : 1);
        if (*bytes) memcpy(*bytes, it->bytes, it->n), *n = it->n;
        rc = *bytes ? 1 : -1;
    } else if (it) {
        rc = 1;
    }
    pthread_mutex_unlock(&m->lock);
    return rc;
}

static int mem_del(tc_store *s, const char *id) {
    mem_store *m = (mem_store *)s;
    pthread_mutex_lock(&m->lock);
    item **p = find(m, id), *it = *p;
    if (it) *p = it->next, m->count--;
    pthread_mutex_unlock(&m->lock);
    if (!it) return 0;
    free(it->id), free(it->bytes), free(it);
    return 1;
}

static long mem_count(tc_store *s) {
    mem_store *m = (mem_store *)s;
    pthread_mutex_lock(&m->lock);
    long n = m->count;
    pthread_mutex_unlock(&m->lock);
    return n;
}

/* In this process: always there. */
static int mem_probe(tc_store *s) {
    (void)s;
    return 1;
}

static void mem_health(tc_store *s, tc_store_health *h) {
    (void)s;
    h->up = 1, h->errors = h->reconnects = 0;
}

static void mem_destroy(tc_store *s) {
    mem_store *m = (mem_store *)s;
    for (size_t i = 0; i < m->nslots; i++)
        for (item *it = m->slots[i], *next; it; it = next) {
            next = it->next;
            free(it->id), free(it->bytes), free(it);
        }
    pthread_mutex_destroy(&m->lock);
    free(m->slots);
    free(m);
}

static const tc_store_ops mem_ops = {mem_put, mem_get, mem_del, mem_count, mem_probe, mem_health, mem_destroy};

tc_store *tc_store_memory_new(void) {
    mem_store *m = calloc(1, sizeof *m);
    if (!m) return NULL;
    m->nslots = 64;
    m->slots = calloc(m->nslots, sizeof *m->slots);
    if (!m->slots || pthread_mutex_init(&m->lock, NULL)) return free(m->slots), free(m), NULL;
    m->base.ops = &mem_ops;
    m->base.name = "memory";
    return &m->base;
}
