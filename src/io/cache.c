/* cache.c — the LRU of built values: one mutex over a chained hash table of
 * entries and the recency list of the ready ones, one condition variable for
 * builds finishing; values are built and freed outside the lock. */
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "io/cache.h"

enum { BUILDING, READY, FAILED };
enum { NBUCKETS = 4096, ID_MAX = 64 };

struct tc_cache_entry {
    char id[ID_MAX + 1];
    void *value;
    size_t bytes;
    int refs;    /* holders, the building thread and its waiters included */
    int state;
    int indexed; /* in the table (and, once READY, in the LRU list and in c->bytes) */
    tc_cache_entry *hnext, *prev, *next; /* bucket chain; LRU list (prev: more recent) */
};

struct tc_cache {
    pthread_mutex_t lock;
    pthread_cond_t built;
    size_t max_bytes, bytes;
    tc_cache_free_fn free_value;
    tc_cache_entry *buckets[NBUCKETS];
    tc_cache_entry *head, *tail; /* most and least recently used READY entries */
    long entries;
    unsigned long long hits, misses, evictions;
};

static size_t bucket_of(const char *id) {
    size_t h = 5381;
    for (; *id; id++) h = h * 33 + (unsigned char)*id;
    return h % NBUCKETS;
}

static tc_cache_entry *lookup(tc_cache *c, const char *id) {
    tc_cache_entry *e = c->buckets[bucket_of(id)];
    while (e && strcmp(e->id, id)) e = e->hnext;
    return e;
}

static void lru_unlink(tc_cache *c, tc_cache_entry *e) {
    if (e->prev) e->prev->next = e->next;
    else c->head = e->next;
    if (e->next) e->next->prev = e->prev;
    else c->tail = e->prev;
    e->prev = e->next = NULL;
}

static void lru_push(tc_cache *c, tc_cache_entry *e) {
    e->prev = NULL, e->next = c->head;
    if (c->head) c->head->prev = e;
    c->head = e;
    if (!c->tail) c->tail = e;
}

/* Takes e out of the table (and the LRU and byte count if READY). The caller
 * frees it if no reference is left. */
static void unindex(tc_cache *c, tc_cache_entry *e) {
    tc_cache_entry **p = &c->buckets[bucket_of(e->id)];
    while (*p != e) p = &(*p)->hnext;
    *p = e->hnext;
    e->hnext = NULL;
    e->indexed = 0;
    if (e->state == READY) {
        lru_unlink(c, e);
        c->bytes -= e->bytes;
        c->entries--;
    }
}

/* Entries to free once the lock is dropped (freeing a value may take long). */
typedef struct {
    tc_cache_entry *list;
} graveyard;

static void bury(graveyard *g, tc_cache_entry *e) { e->hnext = g->list, g->list = e; }

static void empty_graveyard(tc_cache *c, graveyard *g) {
    for (tc_cache_entry *e = g->list, *n; e; e = n) {
        n = e->hnext;
        if (e->state == READY && c->free_value) c->free_value(e->value);
        free(e);
    }
    g->list = NULL;
}

/* Evicts from the least recently used end until the bound holds. */
static void evict(tc_cache *c, graveyard *g) {
    while (c->bytes > c->max_bytes && c->tail) {
        tc_cache_entry *e = c->tail;
        unindex(c, e);
        c->evictions++;
        if (e->refs == 0) bury(g, e);
    }
}

tc_cache *tc_cache_new(size_t max_bytes, tc_cache_free_fn free_value) {
    tc_cache *c = calloc(1, sizeof *c);
    if (!c) return NULL;
    if (pthread_mutex_init(&c->lock, NULL)) return free(c), NULL;
    if (pthread_cond_init(&c->built, NULL)) return pthread_mutex_destroy(&c->lock), free(c), NULL;
    c->max_bytes = max_bytes;
    c->free_value = free_value;
    return c;
}

void tc_cache_free(tc_cache *c) {
    if (!c) return;
    graveyard g = {NULL};
    for (int b = 0; b < NBUCKETS; b++)
        while (c->buckets[b]) {
            tc_cache_entry *e = c->buckets[b];
            unindex(c, e);
            bury(&g, e);
        }
    empty_graveyard(c, &g);
    pthread_cond_destroy(&c->built);
    pthread_mutex_destroy(&c->lock);
    free(c);
}

/* Builds e (refs held by this thread) outside the lock, then publishes it. */
static int build_entry(tc_cache *c, tc_cache_entry *e, tc_cache_build_fn build, void *ctx, graveyard *g) {
    void *value = NULL;
    size_t bytes = 0;
    pthread_mutex_unlock(&c->lock);
    int rc = build(ctx, e->id, &value, &bytes);
    pthread_mutex_lock(&c->lock);
    if (rc != 0) {
        e->state = FAILED;
        if (e->indexed) unindex(c, e);
    } else {
        e->value = value, e->bytes = bytes, e->state = READY;
        if (e->indexed) { /* not removed meanwhile: it joins the LRU */
            lru_push(c, e);
            c->bytes += bytes;
            c->entries++;
            evict(c, g);
        }
    }
    pthread_cond_broadcast(&c->built);
    return rc;
}

static void drop_ref(tc_cache_entry *e, graveyard *g) {
    if (--e->refs == 0 && !e->indexed) bury(g, e);
}

int tc_cache_acquire(tc_cache *c, const char *id, tc_cache_build_fn build, void *ctx, tc_cache_entry **out) {
    graveyard g = {NULL};
    int rc = 0;
    *out = NULL;
    if (strlen(id) > ID_MAX) return -1; /* content ids are 24 characters */
    pthread_mutex_lock(&c->lock);
    for (;;) {
        tc_cache_entry *e = lookup(c, id);
        if (e && e->state == BUILDING) { /* another thread builds it: wait, then look again */
            e->refs++;
            while (e->state == BUILDING) pthread_cond_wait(&c->built, &c->lock);
            if (e->state == READY) {
                c->hits++, *out = e; /* keeps the reference */
                break;
            }
            drop_ref(e, &g); /* that build failed: try again, perhaps building it here */
            continue;
        }
        if (e) { /* READY */
            e->refs++, c->hits++, *out = e;
            lru_unlink(c, e), lru_push(c, e);
            break;
        }
        if (!build) break;
        e = calloc(1, sizeof *e);
        if (!e) {
            rc = -1;
            break;
        }
        strcpy(e->id, id);
        e->refs = 1, e->state = BUILDING, e->indexed = 1;
        tc_cache_entry **b = &c->buckets[bucket_of(id)];
        e->hnext = *b, *b = e;
        c->misses++;
        rc = build_entry(c, e, build, ctx, &g);
        if (rc == 0) *out = e;
        else drop_ref(e, &g);
        break;
    }
    pthread_mutex_unlock(&c->lock);
    empty_graveyard(c, &g);
    return rc;
}

void *tc_cache_value(const tc_cache_entry *e) { return e->value; }

void tc_cache_release(tc_cache *c, tc_cache_entry *e) {
    if (!e) return;
    graveyard g = {NULL};
    pthread_mutex_lock(&c->lock);
    drop_ref(e, &g);
    pthread_mutex_unlock(&c->lock);
    empty_graveyard(c, &g);
}

int tc_cache_remove(tc_cache *c, const char *id) {
    graveyard g = {NULL};
    pthread_mutex_lock(&c->lock);
    tc_cache_entry *e = lookup(c, id);
    if (e) {
        unindex(c, e);
        if (e->refs == 0) bury(&g, e);
    }
    pthread_mutex_unlock(&c->lock);
    empty_graveyard(c, &g);
    return e != NULL;
}

void tc_cache_get_stats(tc_cache *c, tc_cache_stats *s) {
    pthread_mutex_lock(&c->lock);
    s->hits = c->hits, s->misses = c->misses, s->evictions = c->evictions;
    s->bytes = c->bytes, s->entries = c->entries;
    pthread_mutex_unlock(&c->lock);
}
