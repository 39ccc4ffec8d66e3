/* meshes.c — the stored-mesh handlers. The store is the truth (an id exists
 * while the store holds its bytes, on any replica); the cache only saves the
 * build: every answer first asks the store, then takes the built job from the
 * cache, which rebuilds it from the store's bytes after an eviction. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/cache.h"
#include "io/sha256.h"
#include "io/store.h"
#include "server/config.h"
#include "server/etag.h"
#include "server/log.h"
#include "server/meshes.h"
#include "server/metrics.h"
#include "server/tiles.h"

struct tc_meshes {
    tc_store *store;
    tc_cache *cache;
    tc_cache *tiles; /* encoded tiles by ETag (--tile-cache-memory), or NULL: none */
};

/* A tile's answer as the cache keeps it: the encoded bytes and their type. */
typedef struct {
    char *bytes;
    size_t len;
    const char *content_type; /* static string */
} tile_answer;

static void free_tile(void *v) {
    tile_answer *a = v;
    if (a) free(a->bytes);
    free(a);
}

#define IMMUTABLE "public, max-age=31536000, immutable"
static const char not_found[] = "mesh not found; POST it again";
static const char unavailable[] = "the mesh store is unavailable (unreachable or out of memory); retry later";

static void free_job(void *v) { tc_api_job_free(v); }

static void log_line(const char *line) { tc_log_notice("%s", line); }

/* Redis's timeouts: a connect and a command each take at most a quarter of
 * the request deadline (a request makes at most two round trips and one retry
 * on a new connection), and never more than 0.5 s and 1 s. */
static tc_store *redis_store(const tc_srv_config *cfg, char *err, size_t errlen) {
    double quarter = cfg->request_timeout > 0 ? cfg->request_timeout / 4 : 1e9;
    tc_redis_opts o = {cfg->store, cfg->mesh_ttl, quarter < 0.5 ? quarter : 0.5, quarter < 1.0 ? quarter : 1.0,
                       (int)(cfg->workers + cfg->threads), log_line};
    return tc_store_redis_new(&o, err, errlen);
}

tc_meshes *tc_meshes_new(const tc_srv_config *cfg, char *err, size_t errlen) {
    int redis = strncmp(cfg->store, "redis://", 8) == 0;
    if (!redis && strcmp(cfg->store, "memory"))
        return snprintf(err, errlen, "unknown store '%s' (memory, redis://HOST:PORT[/DB])", cfg->store), NULL;
    tc_meshes *m = calloc(1, sizeof *m);
    if (!m) return snprintf(err, errlen, "out of memory for the mesh store"), NULL;
    snprintf(err, errlen, "out of memory for the mesh store");
    m->store = redis ? redis_store(cfg, err, errlen) : tc_store_memory_new();
    if (m->store) m->cache = tc_cache_new((size_t)cfg->cache_memory, free_job);
    if (m->cache && cfg->tile_cache_memory > 0) m->tiles = tc_cache_new((size_t)cfg->tile_cache_memory, free_tile);
    if (!m->cache || (cfg->tile_cache_memory > 0 && !m->tiles)) {
        tc_cache_free(m->cache);
        tc_store_free(m->store);
        free(m);
        return NULL;
    }
    return m;
}

/* The store cannot answer now: 503 busy, retry in a second (its backoff). */
static void store_unavailable(tc_reply *out) {
    tc_reply_problem(out, TC_PROBLEM_BUSY, unavailable);
    out->retry_after = 1;
}

void tc_meshes_write_store(tc_meshes *m, tc_strbuf *o) {
    tc_store_health h;
    tc_store_health_of(m->store, &h);
    tc_strbuf_printf(o, "{\"backend\":\"%s\",\"state\":\"%s\"}", m->store->name, h.up ? "up" : "down");
}

int tc_meshes_ready(tc_meshes *m) { return tc_store_probe(m->store); }

void tc_meshes_free(tc_meshes *m) {
    if (!m) return;
    tc_cache_free(m->tiles);
    tc_cache_free(m->cache);
    tc_store_free(m->store);
    free(m);
}

void tc_meshes_write_metrics(tc_meshes *m, tc_strbuf *o) {
    tc_cache_stats s;
    tc_cache_get_stats(m->cache, &s);
    tc_strbuf_printf(o, "# HELP tocher_cache_hits_total Uses of a stored mesh whose reconstruction was built.\n"
                        "# TYPE tocher_cache_hits_total counter\ntocher_cache_hits_total %llu\n", s.hits);
    tc_strbuf_printf(o, "# HELP tocher_cache_misses_total Uses of a stored mesh that had to build it.\n"
                        "# TYPE tocher_cache_misses_total counter\ntocher_cache_misses_total %llu\n", s.misses);
    tc_strbuf_printf(o, "# HELP tocher_cache_evictions_total Reconstructions dropped to keep the cache bound.\n"
                        "# TYPE tocher_cache_evictions_total counter\ntocher_cache_evictions_total %llu\n",
                     s.evictions);
    tc_strbuf_printf(o, "# HELP tocher_cache_bytes Memory of the cached reconstructions (estimated).\n"
                        "# TYPE tocher_cache_bytes gauge\ntocher_cache_bytes %zu\n", s.bytes);
    tc_cache_stats t = {0};
    if (m->tiles) tc_cache_get_stats(m->tiles, &t);
    tc_strbuf_printf(o, "# HELP tocher_tile_cache_hits_total Tile GETs answered from the encoded-tile cache.\n"
                        "# TYPE tocher_tile_cache_hits_total counter\ntocher_tile_cache_hits_total %llu\n", t.hits);
    tc_strbuf_printf(o, "# HELP tocher_tile_cache_misses_total Tile GETs that rendered and encoded their tile.\n"
                        "# TYPE tocher_tile_cache_misses_total counter\ntocher_tile_cache_misses_total %llu\n",
                     t.misses);
    tc_strbuf_printf(o, "# HELP tocher_tile_cache_bytes Encoded tiles kept (--tile-cache-memory bounds it).\n"
                        "# TYPE tocher_tile_cache_bytes gauge\ntocher_tile_cache_bytes %zu\n", t.bytes);
    long stored = tc_store_count(m->store);
    if (stored >= 0) /* not for Redis: its INFO keyspace counts the keys */
        tc_strbuf_printf(o, "# HELP tocher_meshes_stored Meshes in the store.\n"
                            "# TYPE tocher_meshes_stored gauge\ntocher_meshes_stored %ld\n", stored);
    tc_store_health h;
    tc_store_health_of(m->store, &h);
    tc_strbuf_printf(o, "# HELP tocher_store_up Whether the mesh store answered its last use (1) or not (0).\n"
                        "# TYPE tocher_store_up gauge\ntocher_store_up %d\n", h.up);
    tc_strbuf_printf(o, "# HELP tocher_store_errors_total Mesh store calls that failed (store down, error reply).\n"
                        "# TYPE tocher_store_errors_total counter\ntocher_store_errors_total %llu\n", h.errors);
    tc_strbuf_printf(o, "# HELP tocher_store_reconnects_total Times the mesh store came back after being down.\n"
                        "# TYPE tocher_store_reconnects_total counter\ntocher_store_reconnects_total %llu\n",
                     h.reconnects);
}

/* ---- the job of an id ---- */

/* What a cache miss needs: a job already built (POST), else the store's bytes
 * to build it from, under the asking request's limits. */
typedef struct {
    tc_meshes *m;
    const tc_api_limits *lim;
    tc_api_job *prebuilt;
    tc_api_result res; /* the rebuild's own result: its warnings are the job's */
} build_ctx;

enum { BUILD_GONE = 404, BUILD_STORE_FAILED = 503 };

static int build_job(void *arg, const char *id, void **value, size_t *bytes) {
    build_ctx *b = arg;
    tc_api_job *J = b->prebuilt;
    b->prebuilt = NULL;
    if (!J) {
        char *text = NULL;
        size_t n = 0;
        int got = tc_store_get(b->m->store, id, &text, &n);
        if (got <= 0) return got == 0 ? BUILD_GONE : BUILD_STORE_FAILED;
        double t0 = tc_now_ms();
        int rc = tc_api_job_build(text, n, b->lim, &J, &b->res);
        free(text);
        tc_metrics_mesh_built((tc_now_ms() - t0) * 1e-3);
        if (rc != 200) return rc;
    }
    *value = J;
    *bytes = tc_api_job_info(J)->bytes;
    return 0;
}

/* The job of in's {id} in *e (release it), or 0 with the reply filled: 404
 * for ids the store does not hold, the rebuild's problem if it failed. */
static int acquire(const tc_route_input *in, tc_reply *out, tc_cache_entry **e) {
    build_ctx b = {in->meshes, &in->lim, NULL, {0}};
    tc_api_result_init(&b.res);
    int rc = tc_cache_acquire(in->meshes->cache, in->params->seg[0], build_job, &b, e);
    for (int p = 0; p < TC_NPHASES; p++) out->res.ms[p] += b.res.ms[p];
    if (rc == BUILD_GONE) tc_reply_problem(out, TC_PROBLEM_NOT_FOUND, not_found);
    else if (rc == BUILD_STORE_FAILED) store_unavailable(out);
    else if (rc < 0) tc_reply_problem(out, TC_PROBLEM_INTERNAL, "out of memory caching the mesh");
    else if (rc) {
        out->status = rc;
        tc_strbuf_reset(&out->body);
        tc_api_problem(&out->body, &b.res);
        out->content_type = TC_PROBLEM_TYPE;
    }
    tc_api_result_free(&b.res);
    return rc == 0;
}

/* Whether the store holds in's {id} (a use: Redis renews its TTL); else the
 * 404 (or the 503 of a store that cannot answer) is in out. Asked on every
 * request, cached or not: a mesh expired or evicted from a shared store is
 * gone on every replica at once, whatever their caches hold. */
static int exists(const tc_route_input *in, tc_reply *out) {
    const char *id = in->params->seg[0];
    int got = tc_content_id_valid(id) ? tc_store_get(in->meshes->store, id, NULL, NULL) : 0;
    if (got < 0) store_unavailable(out);
    else if (got == 0) tc_reply_problem(out, TC_PROBLEM_NOT_FOUND, not_found);
    return got == 1;
}

/* Sets the caching headers of a stored-mesh GET; 1 if the client's copy is
 * current (then the reply is a 304 with no body, and no work is done). */
static int not_modified(const tc_route_input *in, tc_reply *out, const char *meaning) {
    tc_etag_make(out->etag, sizeof out->etag, in->params->seg[0], meaning);
    out->cache_control = IMMUTABLE;
    if (!tc_etag_none_match(in->if_none_match, out->etag)) return 0;
    out->status = 304;
    out->content_type = NULL;
    tc_strbuf_reset(&out->body);
    return 1;
}

/* A successful or not-modified GET keeps its caching headers; an error drops them. */
static void keep_cache_headers_if_ok(tc_reply *out) {
    if (out->status == 200 || out->status == 304) return;
    out->etag[0] = '\0';
    out->cache_control = NULL;
}

/* ---- the routes ---- */

/* Whether a POST may go on: a store known to be down that still does not
 * answer a probe gets its 503 before the (perhaps long) build, not after. */
static int store_usable(tc_meshes *m) {
    tc_store_health h;
    tc_store_health_of(m->store, &h);
    return h.up || tc_store_probe(m->store);
}

void tc_meshes_post(const tc_route_input *in, tc_reply *out) {
    if (!store_usable(in->meshes)) return store_unavailable(out);
    double t0 = tc_now_ms();
    tc_api_job *J = NULL;
    int rc = tc_api_job_build(in->body, in->len, &in->lim, &J, &out->res);
    if (rc != 200) return tc_reply_api(out, rc, 1);
    tc_metrics_mesh_built((tc_now_ms() - t0) * 1e-3);
    tc_strbuf canon;
    tc_strbuf_init(&canon);
    tc_api_job_canonical(J, &canon);
    char id[TC_CONTENT_ID_LEN + 1];
    tc_content_id(canon.buf, canon.len, id);
    int existed = 0;
    int oom = canon.oom;
    int stored = oom ? -1 : tc_store_put(in->meshes->store, id, canon.buf, canon.len, &existed);
    tc_strbuf_free(&canon);
    if (stored) {
        tc_api_job_free(J);
        if (oom) return tc_reply_problem(out, TC_PROBLEM_INTERNAL, "out of memory storing the mesh");
        return store_unavailable(out);
    }
    /* Into the cache (when another request put it there first, this job is freed instead). */
    build_ctx b = {in->meshes, &in->lim, J, {0}};
    tc_api_result_init(&b.res);
    tc_cache_entry *e = NULL;
    int got = tc_cache_acquire(in->meshes->cache, id, build_job, &b, &e);
    tc_api_job_free(b.prebuilt);
    tc_api_result_free(&b.res);
    if (got) return tc_reply_problem(out, TC_PROBLEM_INTERNAL, "out of memory caching the mesh");
    tc_api_job_describe(tc_cache_value(e), id, &out->body);
    tc_cache_release(in->meshes->cache, e);
    tc_reply_api(out, 200, 1);
    out->status = existed ? 200 : 201;
    snprintf(out->location, sizeof out->location, "/v1/meshes/%s", id);
}

void tc_meshes_get(const tc_route_input *in, tc_reply *out) {
    tc_cache_entry *e;
    if (!exists(in, out) || not_modified(in, out, "mesh") || !acquire(in, out, &e)) return keep_cache_headers_if_ok(out);
    tc_api_job_describe(tc_cache_value(e), in->params->seg[0], &out->body);
    tc_cache_release(in->meshes->cache, e);
    out->status = 200;
    out->content_type = TC_JSON_TYPE; /* no "timings": a strong ETag promises the same bytes */
}

void tc_meshes_delete(const tc_route_input *in, tc_reply *out) {
    const char *id = in->params->seg[0];
    int gone = tc_content_id_valid(id) ? tc_store_del(in->meshes->store, id) : 0;
    /* After the store: a render holding the job keeps it until it releases it. */
    if (gone >= 0) tc_cache_remove(in->meshes->cache, id);
    if (gone < 0) return store_unavailable(out);
    if (gone == 0) return tc_reply_problem(out, TC_PROBLEM_NOT_FOUND, not_found);
    out->status = 204;
    out->content_type = NULL;
    tc_strbuf_reset(&out->body);
}

void tc_meshes_ordinates(const tc_route_input *in, tc_reply *out) {
    tc_cache_entry *e;
    if (!exists(in, out) || not_modified(in, out, "ordinates") || !acquire(in, out, &e))
        return keep_cache_headers_if_ok(out);
    int rc = tc_api_job_ordinates(tc_cache_value(e), &in->lim, &out->body, &out->res);
    tc_cache_release(in->meshes->cache, e);
    tc_reply_api(out, rc, 0); /* no "timings": see tc_meshes_get */
    keep_cache_headers_if_ok(out);
}

void tc_meshes_evaluate(const tc_route_input *in, tc_reply *out) {
    tc_cache_entry *e;
    if (!exists(in, out) || !acquire(in, out, &e)) return;
    int rc = tc_api_job_evaluate(tc_cache_value(e), in->body, in->len, &in->lim, &out->body, &out->res);
    tc_cache_release(in->meshes->cache, e);
    tc_reply_api(out, rc, 1);
}

void tc_meshes_render(const tc_route_input *in, tc_reply *out) {
    tc_cache_entry *e;
    if (!exists(in, out) || !acquire(in, out, &e)) return;
    int rc = tc_api_job_render(tc_cache_value(e), in->body, in->len, in->accept, &in->lim, &out->body, &out->res);
    tc_cache_release(in->meshes->cache, e);
    tc_reply_api(out, rc, 0);
    out->vary = "Accept";
}

/* The tile's look: its query over the defaults of a /v1/render body. 0, or
 * 400 in out when the background does not fit the mesh's channels. */
static int tile_look(const tc_tile_req *t, const tc_api_mesh_info *info, tc_api_look *look, tc_reply *out) {
    memset(look, 0, sizeof *look);
    tc_tile_viewport(t, info->bbox, &look->viewport);
    look->format = t->format, look->exposure = t->exposure, look->overlay = t->overlay, look->linear = t->linear;
    if (t->nbackground > 1 && t->nbackground != info->channels) {
        char detail[128];
        snprintf(detail, sizeof detail, "background: %d values for a mesh of %d channels (give 1 or %d)",
                 t->nbackground, info->channels, info->channels);
        tc_reply_problem(out, TC_PROBLEM_MALFORMED, detail);
        return 400;
    }
    look->has_background = t->nbackground > 0;
    for (int c = 0; c < info->channels && look->has_background; c++)
        look->background[c] = t->background[t->nbackground > 1 ? c : 0];
    return 0;
}

/* Renders the tile of job J into out (the answer as /v1/render gives it). */
static void render_tile(const tc_route_input *in, const tc_tile_req *t, const tc_api_job *J, tc_reply *out) {
    tc_api_look look;
    if (tile_look(t, tc_api_job_info(J), &look, out) != 0) return;
    int rc = tc_api_job_render_look(J, &look, &in->lim, &out->body, &out->res);
    tc_reply_api(out, rc, 0);
}

/* What a tile-cache miss needs: the request, its tile, and the reply the
 * render fills (the miss answers from it whether or not it is kept). */
typedef struct {
    const tc_route_input *in;
    const tc_tile_req *t;
    tc_reply *out;
    int answered; /* out holds the answer (rendered, or the job's problem) */
} tile_ctx;

enum { TILE_NOT_KEPT = 1 }; /* answered, but not a plain 200 to keep: the caller sends out as it is */

/* A miss: the job, the render, and a copy of the bytes to keep when the answer
 * is a 200 without warnings (a warning is sent as a header the cache does not keep). */
static int build_tile(void *arg, const char *key, void **value, size_t *bytes) {
    (void)key;
    tile_ctx *c = arg;
    tc_cache_entry *e;
    c->answered = 1;
    if (!acquire(c->in, c->out, &e)) return TILE_NOT_KEPT;
    render_tile(c->in, c->t, tc_cache_value(e), c->out);
    tc_cache_release(c->in->meshes->cache, e);
    if (c->out->status != 200 || c->out->res.diags.count) return TILE_NOT_KEPT;
    tile_answer *a = malloc(sizeof *a);
    char *copy = malloc(c->out->body.len + 1);
    if (!a || !copy) return free(a), free(copy), TILE_NOT_KEPT;
    memcpy(copy, c->out->body.buf, c->out->body.len);
    *a = (tile_answer){copy, c->out->body.len, c->out->content_type};
    *value = a;
    *bytes = a->len + sizeof *a + 128; /* + the entry */
    return 0;
}

/* The tile from the encoded-tile cache (keyed by its ETag: an id never changes
 * meaning, so neither does a tile's URL), rendering it on a miss; two requests
 * for the same missing tile render it once. */
static void cached_tile(const tc_route_input *in, const tc_tile_req *t, tc_reply *out) {
    tile_ctx c = {in, t, out, 0};
    tc_cache_entry *e = NULL;
    char key[96];
    size_t n = strlen(out->etag);
    snprintf(key, sizeof key, "%.*s", n >= 2 ? (int)(n - 2) : 0, out->etag + 1); /* without the quotes */
    int rc = tc_cache_acquire(in->meshes->tiles, key, build_tile, &c, &e);
    if (rc == 0 && !c.answered) { /* a hit (or another request's render) */
        const tile_answer *a = tc_cache_value(e);
        tc_strbuf_append(&out->body, a->bytes, a->len);
        out->res.content_type = a->content_type;
        tc_reply_api(out, out->body.oom ? 500 : 200, 0);
        tc_cache_release(in->meshes->tiles, e);
    } else if (rc != 0 && !c.answered && acquire(in, out, &e)) { /* the cache had no room for an entry */
        render_tile(in, t, tc_cache_value(e), out);
        tc_cache_release(in->meshes->cache, e);
    }
}

void tc_meshes_tile(const tc_route_input *in, tc_reply *out) {
    tc_tile_req t;
    char detail[200], meaning[600];
    int bad = tc_tile_parse(in->params, in->query, &t, detail, sizeof detail);
    if (bad) return tc_reply_problem(out, bad == 404 ? TC_PROBLEM_NOT_FOUND : TC_PROBLEM_MALFORMED, detail);
    tc_tile_meaning(&t, meaning, sizeof meaning);
    if (!exists(in, out) || not_modified(in, out, meaning)) return keep_cache_headers_if_ok(out);
    if (in->meshes->tiles) {
        cached_tile(in, &t, out);
    } else {
        tc_cache_entry *e;
        if (acquire(in, out, &e)) render_tile(in, &t, tc_cache_value(e), out), tc_cache_release(in->meshes->cache, e);
    }
    keep_cache_headers_if_ok(out);
}
