/* cache.h — the per-process cache of built reconstructions: values by content id
 * in an LRU bounded by bytes, reference-counted, each id built once at a time. */
#ifndef TC_IO_CACHE_H
#define TC_IO_CACHE_H

#include <stddef.h>

typedef struct tc_cache tc_cache;
typedef struct tc_cache_entry tc_cache_entry;

/* Builds the value for id: 0 with *value and its size in *bytes, or a nonzero
 * code of the caller's (tc_cache_acquire returns it). Runs without the cache's
 * lock held, on the thread that missed. */
typedef int (*tc_cache_build_fn)(void *ctx, const char *id, void **value, size_t *bytes);
typedef void (*tc_cache_free_fn)(void *value);

typedef struct {
    unsigned long long hits, misses, evictions;
    size_t bytes;  /* sizes of the values the cache holds now (the LRU's bound applies to it) */
    long entries;  /* values it holds now */
} tc_cache_stats;

/* Invariants:
 *  - bytes <= max_bytes after every acquire returns (a value larger than the
 *    bound is handed to its caller and then dropped: it is never kept);
 *  - a value is freed only when it is out of the cache (evicted, removed or
 *    replaced) and no reference to it is held: evicting or removing an id in
 *    use never frees what a holder reads;
 *  - while one thread builds an id, others acquiring it wait for that build
 *    instead of starting their own; if it fails, one of them builds next. */
tc_cache *tc_cache_new(size_t max_bytes, tc_cache_free_fn free_value);
/* Frees the cache and every value in it; no reference may be held. NULL: no-op. */
void tc_cache_free(tc_cache *c);

/* A reference to id's value in *out: the cached one (a hit), the one another
 * thread is building (waited for), or a new one from build(ctx, ...) (a miss).
 * Returns 0, or build's nonzero code with *out = NULL. build == NULL only looks:
 * 0 with *out NULL when the id holds no value, and counts neither hit nor miss. */
int tc_cache_acquire(tc_cache *c, const char *id, tc_cache_build_fn build, void *ctx, tc_cache_entry **out);
void *tc_cache_value(const tc_cache_entry *e);
/* Drops a reference from tc_cache_acquire (NULL: no-op). */
void tc_cache_release(tc_cache *c, tc_cache_entry *e);
/* Takes id out of the cache (its value is freed once no one holds it): 1 if it was there. */
int tc_cache_remove(tc_cache *c, const char *id);
void tc_cache_get_stats(tc_cache *c, tc_cache_stats *s);

#endif
