/* config.h — the daemon's settings: defaults, then TOCHER_* environment
 * variables, then command-line flags (flags win); --help and --version. */
#ifndef TC_SERVER_CONFIG_H
#define TC_SERVER_CONFIG_H

typedef struct {
    char host[256];                /* address to bind, numeric or a name */
    long long port;                /* 0: any free port */
    long long threads;             /* libmicrohttpd pool threads */
    long long render_threads;      /* worker threads of one render */
    long long workers;             /* compute threads: POST routes run there, off the I/O threads */
    long long max_queue;           /* requests waiting for a worker; beyond, 503 */
    long long max_body;            /* bytes */
    long long max_vertices, max_triangles, max_points, max_pixels, max_samples; /* 0: no limit */
    long long max_memory;          /* bytes renders in flight may hold at once; 0: no limit */
    long long max_connections;     /* open connections at once */
    long long connection_timeout;  /* seconds a connection may stay idle; 0: forever */
    long long max_connections_per_ip; /* open connections from one address; 0: no limit */
    double header_timeout;         /* seconds from a connection's start to its request's headers; 0: none */
    double body_timeout;           /* seconds from the headers to the end of the body; 0: none */
    double request_timeout;        /* seconds of work per request; 0: no deadline */
    double shutdown_grace;         /* seconds to let requests finish on SIGTERM */
    char store[320];               /* the mesh store: "memory" or redis://HOST:PORT[/DB] */
    long long mesh_ttl;            /* seconds a stored mesh lives in Redis after its last use; 0: forever */
    long long cache_memory;        /* bytes of built reconstructions kept (the LRU's bound) */
    long long tile_cache_memory;   /* bytes of encoded tiles kept (an LRU by ETag); 0: none */
} tc_srv_config;

enum { TC_CONFIG_RUN, TC_CONFIG_EXIT_OK, TC_CONFIG_EXIT_USAGE };

/* Fills c from defaults, environment and argv. Prints --help / --version to
 * stdout and errors to stderr; returns what main should do. */
int tc_config_load(tc_srv_config *c, int argc, char **argv);

/* Online CPUs, at least 1. */
int tc_cpu_count(void);

#endif
