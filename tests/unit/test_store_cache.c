/* test_store_cache.c — the mesh store (io/store.h), the cache of built values
 * (io/cache.h: LRU bound, eviction and rebuild, build-once under threads,
 * references against removal and eviction) and content ids of stored-mesh
 * jobs (io/api.h): the same mesh spelled differently gets the same id. */
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "check.h"
#include "io/api.h"
#include "io/cache.h"
#include "io/sha256.h"
#include "io/store.h"

TEST(store_memory_put_get_delete) {
    tc_store *s = tc_store_memory_new();
    CHECK(s && !strcmp(s->name, "memory"));
    int existed = -1;
    char id[32];
    for (int i = 0; i < 300; i++) { /* past the first table sizes: it grows */
        snprintf(id, sizeof id, "id%d", i);
        CHECK(tc_store_put(s, id, id, strlen(id), &existed) == 0 && existed == 0);
    }
    CHECK(tc_store_count(s) == 300);
    CHECK(tc_store_put(s, "id7", "other", 5, &existed) == 0 && existed == 1); /* an id keeps its bytes */
    char *b = NULL;
    size_t n = 0;
    CHECK(tc_store_get(s, "id7", &b, &n) == 1 && n == 3 && !memcmp(b, "id7", 3));
    free(b);
    CHECK(tc_store_get(s, "id299", NULL, NULL) == 1);
    CHECK(tc_store_get(s, "nope", NULL, NULL) == 0);
    CHECK(tc_store_del(s, "id7") == 1);
    CHECK(tc_store_del(s, "id7") == 0);
    CHECK(tc_store_get(s, "id7", &b, &n) == 0);
    CHECK(tc_store_count(s) == 299);
    tc_store_free(s);
}

/* ---- the cache, over values that count their builds and frees ---- */

typedef struct {
    atomic_int builds, frees;
    size_t bytes;     /* size each build reports */
    int fail;         /* nonzero: builds fail with this code */
    int sleep_ms;     /* builds take this long */
} counters;

typedef struct {
    counters *k;
    char id[32];
} value;

static counters *current; /* the free function has no context */

static int build_value(void *ctx, const char *id, void **out, size_t *bytes) {
    counters *k = ctx;
    atomic_fetch_add(&k->builds, 1);
    if (k->sleep_ms) nanosleep(&(struct timespec){0, k->sleep_ms * 1000000L}, NULL);
    if (k->fail) return k->fail;
    value *v = calloc(1, sizeof *v);
    v->k = k;
    snprintf(v->id, sizeof v->id, "%s", id);
    *out = v, *bytes = k->bytes;
    return 0;
}

static void free_value(void *p) {
    atomic_fetch_add(&current->frees, 1);
    free(p);
}

static tc_cache_entry *take(tc_cache *c, const char *id, counters *k) {
    tc_cache_entry *e = NULL;
    CHECK(tc_cache_acquire(c, id, build_value, k, &e) == 0 && e);
    return e;
}

TEST(cache_lru_bound_and_rebuild) {
    static counters k;
    memset(&k, 0, sizeof k), k.bytes = 100, current = &k;
    tc_cache *c = tc_cache_new(350, free_value); /* room for 3 */
    tc_cache_stats st;
    const char *ids[] = {"a", "b", "c", "d"};
    for (int i = 0; i < 4; i++) tc_cache_release(c, take(c, ids[i], &k));
    tc_cache_get_stats(c, &st);
    CHECK(st.bytes == 300 && st.entries == 3 && st.evictions == 1 && st.misses == 4 && st.hits == 0);
    CHECK(atomic_load(&k.frees) == 1); /* "a", the least recently used */
    tc_cache_release(c, take(c, "b", &k)); /* a hit makes "b" the most recent */
    tc_cache_release(c, take(c, "a", &k)); /* rebuilt; evicts "c" now, not "b" */
    CHECK(atomic_load(&k.builds) == 5);
    tc_cache_entry *e = NULL;
    CHECK(tc_cache_acquire(c, "c", NULL, NULL, &e) == 0 && e == NULL); /* look only: gone */
    CHECK(tc_cache_acquire(c, "b", NULL, NULL, &e) == 0 && e != NULL);
    tc_cache_release(c, e);
    tc_cache_get_stats(c, &st);
    CHECK(st.bytes <= 350 && st.entries == 3 && st.evictions == 2 && st.hits == 2);
    tc_cache_free(c);
    CHECK(atomic_load(&k.frees) == atomic_load(&k.builds)); /* every value freed once */
}

TEST(cache_value_larger_than_bound_is_not_kept) {
    static counters k;
    memset(&k, 0, sizeof k), k.bytes = 1000, current = &k;
    tc_cache *c = tc_cache_new(500, free_value);
    tc_cache_entry *e = take(c, "big", &k);
    value *v = tc_cache_value(e);
    CHECK(!strcmp(v->id, "big") && atomic_load(&k.frees) == 0); /* held: usable */
    tc_cache_stats st;
    tc_cache_get_stats(c, &st);
    CHECK(st.bytes == 0 && st.entries == 0);
    tc_cache_release(c, e);
    CHECK(atomic_load(&k.frees) == 1);
    tc_cache_free(c);
}

TEST(cache_reference_outlives_remove_and_eviction) {
    static counters k;
    memset(&k, 0, sizeof k), k.bytes = 100, current = &k;
    tc_cache *c = tc_cache_new(150, free_value);
    tc_cache_entry *a = take(c, "a", &k);
    CHECK(tc_cache_remove(c, "a") == 1); /* a DELETE during a render */
    CHECK(tc_cache_remove(c, "a") == 0);
    CHECK(atomic_load(&k.frees) == 0 && !strcmp(((value *)tc_cache_value(a))->id, "a"));
    tc_cache_entry *b = take(c, "b", &k);
    tc_cache_entry *b2 = take(c, "c", &k); /* evicts "b", which is held */
    CHECK(atomic_load(&k.frees) == 0 && !strcmp(((value *)tc_cache_value(b))->id, "b"));
    tc_cache_release(c, a);
    tc_cache_release(c, b);
    CHECK(atomic_load(&k.frees) == 2);
    tc_cache_release(c, b2);
    CHECK(atomic_load(&k.frees) == 2); /* "c" stays cached */
    tc_cache_free(c);
    CHECK(atomic_load(&k.frees) == 3);
}

TEST(cache_failed_build_is_retried) {
    static counters k;
    memset(&k, 0, sizeof k), k.bytes = 10, k.fail = 503, current = &k;
    tc_cache *c = tc_cache_new(1000, free_value);
    tc_cache_entry *e = NULL;
    CHECK(tc_cache_acquire(c, "x", build_value, &k, &e) == 503 && e == NULL);
    k.fail = 0;
    tc_cache_release(c, take(c, "x", &k));
    CHECK(atomic_load(&k.builds) == 2);
    tc_cache_free(c);
}

typedef struct {
    tc_cache *c;
    counters *k;
    value *seen;
} racer;

static void *race(void *arg) {
    racer *r = arg;
    tc_cache_entry *e = NULL;
    if (tc_cache_acquire(r->c, "same", build_value, r->k, &e) == 0) {
        r->seen = tc_cache_value(e);
        tc_cache_release(r->c, e);
    }
    return NULL;
}

TEST(cache_concurrent_misses_build_once) {
    static counters k;
    memset(&k, 0, sizeof k), k.bytes = 10, k.sleep_ms = 50, current = &k;
    tc_cache *c = tc_cache_new(1000, free_value);
    enum { N = 8 };
    pthread_t t[N];
    racer r[N];
    for (int i = 0; i < N; i++) {
        r[i] = (racer){c, &k, NULL};
        CHECK(pthread_create(&t[i], NULL, race, &r[i]) == 0);
    }
    for (int i = 0; i < N; i++) pthread_join(t[i], NULL);
    CHECK_MSG(atomic_load(&k.builds) == 1, "%d builds", atomic_load(&k.builds));
    for (int i = 0; i < N; i++) CHECK(r[i].seen && r[i].seen == r[0].seen);
    tc_cache_stats st;
    tc_cache_get_stats(c, &st);
    CHECK(st.misses == 1 && st.hits == N - 1);
    tc_cache_free(c);
}

/* ---- content ids of stored-mesh jobs ---- */

static int job_id(const char *json, char id[TC_CONTENT_ID_LEN + 1]) {
    tc_api_result res;
    tc_api_result_init(&res);
    tc_api_job *J = NULL;
    int st = tc_api_job_build(json, strlen(json), NULL, &J, &res);
    if (st == 200) {
        tc_strbuf b;
        tc_strbuf_init(&b);
        tc_api_job_canonical(J, &b);
        tc_content_id(b.buf, b.len, id);
        tc_strbuf_free(&b);
    }
    tc_api_job_free(J);
    tc_api_result_free(&res);
    return st;
}

#define MESH_A "\"vertices\":[[0,0],[1,0],[0,1],[1,1]],\"triangles\":[[0,1,2],[1,3,2]]"

TEST(content_id_is_canonical) {
    static const char *same[] = {
        "{" MESH_A ",\"values\":[0.5,1,2,3]}",
        "{ \"values\" : [ 5e-1, 1.0, 2, 3e0 ] ,\n " MESH_A " }",
        "{" MESH_A ",\"values\":[0.5,1,2,3],\"method\":\"clough-tocher\"}",
        "{" MESH_A ",\"values\":[0.50000,1,2,3],\"cross_boundary\":\"normal\",\"wedges\":\"corrected\"}",
    };
    static const char *other[] = {
        "{" MESH_A ",\"values\":[0.5,1,2,3.0000000001]}",
        "{" MESH_A ",\"values\":[0.5,1,2,3],\"method\":\"linear\"}",
        "{" MESH_A ",\"values\":[0.5,1,2,3],\"cross_boundary\":\"affine\"}",
        "{\"vertices\":[[0,0],[1,0],[0,1],[1,1]],\"triangles\":[[0,1,3],[0,3,2]],\"values\":[0.5,1,2,3]}",
        "{" MESH_A ",\"values\":[[0.5,0],[1,0],[2,0],[3,0]]}",
    };
    char id0[TC_CONTENT_ID_LEN + 1], id[TC_CONTENT_ID_LEN + 1];
    CHECK(job_id(same[0], id0) == 200 && tc_content_id_valid(id0));
    for (size_t i = 1; i < sizeof same / sizeof same[0]; i++)
        CHECK_MSG(job_id(same[i], id) == 200 && !strcmp(id, id0), "same[%zu]: %s vs %s", i, id, id0);
    for (size_t i = 0; i < sizeof other / sizeof other[0]; i++)
        CHECK_MSG(job_id(other[i], id) == 200 && strcmp(id, id0), "other[%zu] has the same id %s", i, id);
}

TEST(stored_job_refuses_other_parts) {
    char id[TC_CONTENT_ID_LEN + 1];
    CHECK(job_id("{" MESH_A ",\"values\":[0,1,2,3],\"points\":[[0.1,0.1]]}", id) == 400);
    CHECK(job_id("{" MESH_A ",\"values\":[0,1,2,3],\"viewport\":{\"x0\":0,\"y0\":0,\"x1\":1,\"y1\":1,"
                 "\"width\":2,\"height\":2}}", id) == 400);
    CHECK(job_id("{" MESH_A ",\"values\":[0,1]}", id) == 422);
}
