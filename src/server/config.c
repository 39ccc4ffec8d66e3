/* config.c — the daemon's settings: one table of options drives the
 * environment, the flags and --help, so the three cannot disagree. */
#include <errno.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "io/store.h"
#include "server/config.h"
#include "tocher.h"

typedef enum { K_LISTEN, K_INT, K_BYTES, K_SECONDS, K_STORE } kind;

typedef struct {
    const char *flag, *env, *arg, *help;
    kind k;
    size_t off;          /* of the field in tc_srv_config */
    double min, max;     /* accepted range */
} option;

#define F(field) offsetof(tc_srv_config, field)
static const option options[] = {
    {"--listen", "TOCHER_LISTEN", "HOST:PORT", "address to bind; port 0 picks a free port", K_LISTEN, 0, 0, 0},
    {"--threads", "TOCHER_THREADS", "N", "HTTP worker threads (requests served side by side)", K_INT, F(threads), 1,
     1024},
    {"--workers", "TOCHER_WORKERS", "N", "threads that compute answers (the HTTP threads only move bytes)", K_INT,
     F(workers), 1, 1024},
    {"--max-queue", "TOCHER_MAX_QUEUE", "N", "requests waiting for a worker; more get 503 with Retry-After", K_INT,
     F(max_queue), 1, 1e6},
    {"--render-threads", "TOCHER_RENDER_THREADS", "N", "threads one request may use: its render, its mesh's validation and build, printing its big answer", K_INT, F(render_threads), 1, 1024},
    {"--max-body", "TOCHER_MAX_BODY", "BYTES", "largest request body (suffix k, M, G: binary units)", K_BYTES,
     F(max_body), 1, 1LL << 40},
    {"--max-vertices", "TOCHER_MAX_VERTICES", "N", "most vertices in one mesh (0: no limit)", K_INT, F(max_vertices), 0,
     1e15},
    {"--max-triangles", "TOCHER_MAX_TRIANGLES", "N", "most triangles in one mesh (0: no limit)", K_INT,
     F(max_triangles), 0, 1e15},
    {"--max-points", "TOCHER_MAX_POINTS", "N", "most points in one evaluate request (0: no limit)", K_INT,
     F(max_points), 0, 1e15},
    {"--max-pixels", "TOCHER_MAX_PIXELS", "N", "most pixels in one render (0: no limit)", K_INT, F(max_pixels), 0,
     1e15},
    {"--max-samples", "TOCHER_MAX_SAMPLES", "N",
     "most samples (pixels x channels) in one render: its answer's size (0: no limit)", K_INT, F(max_samples), 0,
     1e15},
    {"--max-memory", "TOCHER_MAX_MEMORY", "BYTES",
     "memory renders in flight may hold at once (answers + working bands); a render that does not fit now gets "
     "503 with Retry-After, one that never fits 413 (suffix k, M, G; 0: no limit)",
     K_BYTES, F(max_memory), 0, 1LL << 50},
    {"--max-connections", "TOCHER_MAX_CONNECTIONS", "N", "open connections at once; more wait to be accepted", K_INT,
     F(max_connections), 1, 1e6},
    {"--request-timeout", "TOCHER_REQUEST_TIMEOUT", "SECONDS",
     "work allowed per request, then 503 (0: none)", K_SECONDS, F(request_timeout), 0, 86400},
    {"--connection-timeout", "TOCHER_CONNECTION_TIMEOUT", "SECONDS",
     "idle time before a connection is closed (0: never)", K_INT, F(connection_timeout), 0, 86400},
    {"--max-connections-per-ip", "TOCHER_MAX_CONNECTIONS_PER_IP", "N",
     "open connections from one address; more are closed at once (0: no limit)", K_INT,
     F(max_connections_per_ip), 0, 1e6},
    {"--header-timeout", "TOCHER_HEADER_TIMEOUT", "SECONDS",
     "time from a connection's start to its request headers' end, bytes or not (0: none)", K_SECONDS,
     F(header_timeout), 0, 86400},
    {"--body-timeout", "TOCHER_BODY_TIMEOUT", "SECONDS", "time from the headers to the body's end (0: none)",
     K_SECONDS, F(body_timeout), 0, 86400},
    {"--shutdown-grace", "TOCHER_SHUTDOWN_GRACE", "SECONDS",
     "on SIGTERM/SIGINT, time left to requests in flight", K_SECONDS, F(shutdown_grace), 0, 86400},
    {"--store", "TOCHER_STORE", "STORE",
     "where POSTed meshes are kept: memory (in this process) or redis://HOST:PORT[/DB] (shared by replicas)",
     K_STORE, F(store), 0, 0},
    {"--mesh-ttl", "TOCHER_MESH_TTL", "SECONDS",
     "with a Redis store: a stored mesh expires this long after its last use (0: never)", K_INT, F(mesh_ttl), 0,
     1e9},
    {"--cache-memory", "TOCHER_CACHE_MEMORY", "BYTES",
     "built reconstructions of stored meshes kept in memory (LRU; suffix k, M, G; 0: none)", K_BYTES,
     F(cache_memory), 0, 1LL << 50},
    {"--tile-cache-memory", "TOCHER_TILE_CACHE_MEMORY", "BYTES",
     "encoded tiles of stored meshes kept in memory, by ETag (LRU; suffix k, M, G; 0: none)", K_BYTES,
     F(tile_cache_memory), 0, 1LL << 50},
};
#undef F
enum { NOPTIONS = sizeof options / sizeof options[0] };

int tc_cpu_count(void) {
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : n > 1024 ? 1024 : (int)n;
}

/* Half the machine's memory, at least 512 MiB: room for a few of the largest
 * renders the default limits accept (an RGBA 4096^2 raw answer is 256 MiB). */
static long long default_max_memory(void) {
    long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGESIZE);
    long long half = pages > 0 && size > 0 ? (long long)pages * size / 2 : 0;
    return half > (512LL << 20) ? half : 512LL << 20;
}

/* A quarter of the RAM, at most 4 GiB (256 MiB if the RAM cannot be read). */
static long long default_cache_memory(void) {
    long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    long long cap = 4LL << 30, q = pages > 0 && page > 0 ? (long long)pages * page / 4 : 256LL << 20;
    return q < cap ? q : cap;
}

static void defaults(tc_srv_config *c) {
    int ncpu = tc_cpu_count();
    memset(c, 0, sizeof *c);
    strcpy(c->host, "127.0.0.1");
    c->port = 8080;
    c->threads = ncpu < 2 ? 2 : ncpu;
    c->render_threads = ncpu;
    c->workers = 2 * c->threads; /* long renders up to --threads leave workers for small requests */
    c->max_queue = 256;
    c->max_body = 64LL << 20;
    c->max_vertices = 2000000;
    c->max_triangles = 4000000;
    c->max_points = 10000000;
    c->max_pixels = 4096LL * 4096;
    c->max_samples = 4LL * 4096 * 4096; /* an RGBA 4096^2 tile: 256 MiB of float samples */
    c->max_memory = default_max_memory();
    c->max_connections = 1024;
    c->connection_timeout = 10;
    c->max_connections_per_ip = 128;
    c->header_timeout = 10;
    c->body_timeout = 60;
    c->request_timeout = 30;
    c->shutdown_grace = 30;
    strcpy(c->store, "memory");
    c->mesh_ttl = 7 * 86400;
    c->cache_memory = default_cache_memory();
    c->tile_cache_memory = 256LL << 20; /* ~3 000 256^2 PNG tiles of a typical solution */
}

/* "HOST:PORT" or "[V6ADDR]:PORT". */
static int parse_listen(tc_srv_config *c, const char *s) {
    const char *colon = strrchr(s, ':');
    if (!colon || colon == s) return -1;
    const char *h = s, *he = colon;
    if (*s == '[') {
        if (colon[-1] != ']' || colon - s < 3) return -1;
        h = s + 1, he = colon - 1;
    }
    if ((size_t)(he - h) >= sizeof c->host) return -1;
    char *end;
    errno = 0;
    long p = strtol(colon + 1, &end, 10);
    if (errno || end == colon + 1 || *end || p < 0 || p > 65535) return -1;
    memcpy(c->host, h, (size_t)(he - h));
    c->host[he - h] = '\0';
    c->port = p;
    return 0;
}

/* A number in the option's range; K_BYTES takes a k/M/G suffix. */
static int parse_number(const option *o, const char *s, double *out) {
    char *end;
    errno = 0;
    double v = o->k == K_SECONDS ? strtod(s, &end) : (double)strtoll(s, &end, 10);
    if (errno || end == s) return -1;
    if (o->k == K_BYTES && *end) {
        const char *units = "kKmMgG";
        const char *u = strchr(units, *end);
        if (!u || end[1]) return -1;
        v *= (double)(1LL << (10 * (1 + (u - units) / 2)));
        end++;
    }
    if (*end || !(v >= o->min && v <= o->max)) return -1;
    *out = v;
    return 0;
}

/* The store backends this build has: memory, or Redis by URL. */
static int parse_store(tc_srv_config *c, const char *s) {
    char host[256];
    int port, db;
    if (strcmp(s, "memory") && tc_redis_url_parse(s, host, sizeof host, &port, &db)) return -1;
    if (strlen(s) >= sizeof c->store) return -1;
    strcpy(c->store, s);
    return 0;
}

/* source: the environment variable, or NULL for the flag. */
static int set_option(tc_srv_config *c, const option *o, const char *value, const char *source) {
    double v = 0;
    int bad = o->k == K_LISTEN  ? parse_listen(c, value)
              : o->k == K_STORE ? parse_store(c, value)
                                : parse_number(o, value, &v);
    if (bad) {
        fprintf(stderr, "tocherd: %s%s%s: bad value for %s %s", source ? source : o->flag, source ? "=" : " ",
                value, o->flag, o->arg);
        if (o->k == K_LISTEN) fprintf(stderr, " (e.g. 127.0.0.1:8080, [::1]:0)\n");
        else if (o->k == K_STORE) fprintf(stderr, " (memory, or redis://HOST:PORT[/DB])\n");
        else fprintf(stderr, " (%.0f to %.0f%s)\n", o->min, o->max, o->k == K_SECONDS ? ", fractions allowed" : "");
        return -1;
    }
    if (o->k == K_SECONDS) *(double *)((char *)c + o->off) = v;
    else if (o->k != K_LISTEN && o->k != K_STORE) *(long long *)((char *)c + o->off) = (long long)v;
    return 0;
}

static int load_env(tc_srv_config *c) {
    for (int i = 0; i < NOPTIONS; i++) {
        const char *v = getenv(options[i].env);
        if (v && *v && set_option(c, &options[i], v, options[i].env)) return -1;
    }
    return 0;
}

/* The default of option o, as text for --help. */
static void default_text(const option *o, const tc_srv_config *d, char *buf, size_t n) {
    const char *p = (const char *)d + o->off;
    if (o->k == K_LISTEN) snprintf(buf, n, "%s:%lld", d->host, d->port);
    else if (o->k == K_STORE) snprintf(buf, n, "%s", p);
    else if (o->k == K_SECONDS) snprintf(buf, n, "%g", *(const double *)p);
    else snprintf(buf, n, "%lld", *(const long long *)p);
}

static void help(void) {
    tc_srv_config d;
    defaults(&d);
    printf("usage: tocherd [options]\n\n"
           "The tocher HTTP daemon: POST /v1/ordinates, /v1/evaluate, /v1/render, /v1/compare;\n"
           "stored meshes at /v1/meshes (POST, then GET tiles); GET /healthz, /readyz, /metrics, /v1/version. Each option may also be given by the\n"
           "environment variable shown; flags override the environment.\n\n");
    for (int i = 0; i < NOPTIONS; i++) {
        const option *o = &options[i];
        char flag[64], def[300];
        snprintf(flag, sizeof flag, "%s %s", o->flag, o->arg);
        default_text(o, &d, def, sizeof def);
        printf("  %-30s %s\n  %-30s   env %s, default %s\n", flag, o->help, "", o->env, def);
    }
    printf("  %-30s %s\n  %-30s %s\n\n", "--help", "this text", "--version", "print the version");
    printf("Defaults of --threads (at least 2), --workers (twice that) and --render-threads follow the\n"
           "number of CPUs (%d here); --cache-memory's is a quarter of the RAM, at most 4G.\n"
           "Listening on all interfaces needs an explicit --listen 0.0.0.0:PORT.\n",
           tc_cpu_count());
}

static const option *find_flag(const char *arg, const char **inline_value) {
    for (int i = 0; i < NOPTIONS; i++) {
        size_t n = strlen(options[i].flag);
        if (strncmp(arg, options[i].flag, n)) continue;
        if (arg[n] == '\0') return *inline_value = NULL, &options[i];
        if (arg[n] == '=') return *inline_value = arg + n + 1, &options[i];
    }
    return NULL;
}

/* --help and --version answer before anything else is looked at, even a bad
 * environment. Returns 1 if one of them was printed. */
static int help_or_version(int argc, char **argv) {
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) return help(), 1;
        if (!strcmp(argv[i], "--version")) return printf("tocherd %s\n", TC_VERSION), 1;
    }
    return 0;
}

/* --flag VALUE or --flag=VALUE. */
static int load_args(tc_srv_config *c, int argc, char **argv) {
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v;
        const option *o = find_flag(a, &v);
        if (!o) {
            fprintf(stderr, "tocherd: unknown argument '%s' (try --help)\n", a);
            return TC_CONFIG_EXIT_USAGE;
        }
        if (!v && i + 1 == argc) {
            fprintf(stderr, "tocherd: %s needs a value %s\n", o->flag, o->arg);
            return TC_CONFIG_EXIT_USAGE;
        }
        if (set_option(c, o, v ? v : argv[++i], NULL)) return TC_CONFIG_EXIT_USAGE;
    }
    return TC_CONFIG_RUN;
}

int tc_config_load(tc_srv_config *c, int argc, char **argv) {
    defaults(c);
    if (help_or_version(argc, argv)) return TC_CONFIG_EXIT_OK;
    if (load_env(c)) return TC_CONFIG_EXIT_USAGE;
    return load_args(c, argc, argv);
}
