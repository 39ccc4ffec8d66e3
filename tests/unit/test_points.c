/* test_points.c — scattered points (issue 17 §3): the locator's grid gives every point the owner
 * the bounding-volume tree gives (tc__locate_tree), and the batch evaluation the bits of the old path. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "core/ct_points.h"
#include "core/eval.h"
#include "core/locate.h"
#include "core/mesh.h"
#include "core/recon.h"
#include "io/response.h"
#include "io/strbuf.h"
#include "meshgen.h"
#include "props.h"

/* ---- owners -------------------------------------------------------------------- */

/* tc_locate and tc__locate_many against the tree, point by point. */
static int owners_differ(const tc_locator *L, size_t n, const double *xy) {
    int32_t *many = malloc((n ? n : 1) * sizeof *many);
    if (!many) abort();
    tc__locate_many(L, n, xy, many);
    int bad = 0;
    for (size_t i = 0; i < n; i++) {
        int32_t want = tc__locate_tree(L, xy[2 * i], xy[2 * i + 1]), got = tc_locate(L, xy[2 * i], xy[2 * i + 1]);
        if ((got != want || many[i] != want) && bad++ < 5)
            CHECK_MSG(0, "(%.17g, %.17g): grid %d, batch %d, tree %d", xy[2 * i], xy[2 * i + 1], (int)got,
                      (int)many[i], (int)want);
    }
    free(many);
    return bad;
}

typedef struct {
    double *xy;
    size_t n, cap;
} pts;

static void put(pts *p, double x, double y) {
    if (p->n == p->cap) {
        p->cap = p->cap ? 2 * p->cap : 1024;
        p->xy = realloc(p->xy, 2 * p->cap * sizeof *p->xy);
        if (!p->xy) abort();
    }
    p->xy[2 * p->n] = x, p->xy[2 * p->n + 1] = y;
    p->n++;
}

/* Points that stress the rule on mesh m: random ones over its box and a margin
 * around it, every vertex, points along every edge (its ends' exact midpoint
 * and quarter points, which lie on the edge or within an ulp of it), the box's
 * corners and sides, NaN and infinities. */
static void stress_points(const struct tc_mesh *m, trng *r, pts *p) {
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int32_t v = 0; v < m->nv; v++)
        for (int a = 0; a < 2; a++) lo[a] = fmin(lo[a], m->xy[2 * v + a]), hi[a] = fmax(hi[a], m->xy[2 * v + a]);
    double w = hi[0] - lo[0], h = hi[1] - lo[1];
    for (int i = 0; i < 4000; i++)
        put(p, lo[0] - 0.1 * w + 1.2 * w * trng_uniform(r), lo[1] - 0.1 * h + 1.2 * h * trng_uniform(r));
    for (int32_t v = 0; v < m->nv; v++) put(p, m->xy[2 * v], m->xy[2 * v + 1]);
    for (int32_t t = 0; t < m->nt; t++)
        for (int k = 0; k < 3; k++) {
            const double *a = m->xy + 2 * m->tri[3 * t + k], *b = m->xy + 2 * m->tri[3 * t + (k + 1) % 3];
            put(p, 0.5 * a[0] + 0.5 * b[0], 0.5 * a[1] + 0.5 * b[1]);
            put(p, 0.75 * a[0] + 0.25 * b[0], 0.75 * a[1] + 0.25 * b[1]);
        }
    for (int i = 0; i <= 64; i++) {
        double s = i / 64.0;
        put(p, lo[0] + s * w, lo[1]), put(p, lo[0] + s * w, hi[1]);
        put(p, lo[0], lo[1] + s * h), put(p, hi[0], lo[1] + s * h);
        put(p, nextafter(lo[0], -INFINITY), lo[1] + s * h), put(p, hi[0], nextafter(hi[1], INFINITY));
    }
    put(p, NAN, 0.5), put(p, 0.5, NAN), put(p, INFINITY, 0.5), put(p, -INFINITY, -INFINITY);
}

static void check_mesh_owners(const struct tc_mesh *m, unsigned long seed) {
    tc_locator *L = NULL;
    CHECK(tc_locator_new(m, &L) == TC_OK);
    if (!L) return;
    tc__locator_grid_now(L);
    trng r;
    trng_seed(&r, seed);
    pts p = {0};
    stress_points(m, &r, &p);
    CHECK_MSG(owners_differ(L, p.n, p.xy) == 0, "owners differ (%d triangles)", (int)m->nt);
    free(p.xy);
    tc_locator_free(L);
}

/* Validated meshes: grids with and without jitter (the unjittered ones have
 * vertices i/n: points on their lines are exact for n a power of 2, within an
 * ulp otherwise), and Delaunay-like ones (jittered grids, flipped). */
TEST(points_owner_same_as_tree_valid_meshes) {
    int built = 0;
    for (int trial = 0; trial < 12; trial++) {
        trng r;
        trng_seed(&r, tc_test_seed() + 100 + (unsigned long)trial);
        tmesh g;
        tmesh_grid(&g, 4 + 3 * trial, 3 + 2 * trial, trial % 3 ? 0.3 : 0, trial % 2 ? -1 : 0, &r);
        if (trial % 3 == 1) tmesh_delaunay_flips(&g);
        tmesh_sample(&g, 1, smooth_f, NULL, 0, 0, 0);
        tc_mesh *m = tmesh_build(&g);
        CHECK_MSG(m != NULL, "trial %d: mesh refused", trial);
        if (m) check_mesh_owners(m, tc_test_seed() + 200 + (unsigned long)trial);
        built += m != NULL;
        tc_mesh_free(m);
        tmesh_free(&g);
    }
    CHECK_MSG(built == 12, "only %d meshes built", built);
}

/* A bare struct tc_mesh (what tc_locator_new reads: nv, nt, xy, tri, orient). */
typedef struct {
    struct tc_mesh m;
    double xy[2 * 600];
    int32_t tri[3 * 200];
    int8_t orient[200];
} bare;

static void bare_tri(bare *b, const double p[6]) {
    int32_t t = b->m.nt++, v = b->m.nv;
    for (int k = 0; k < 6; k++) b->xy[2 * v + k] = p[k];
    b->m.nv += 3;
    for (int k = 0; k < 3; k++) b->tri[3 * t + k] = v + k;
    double a = (p[2] - p[0]) * (p[5] - p[1]) - (p[3] - p[1]) * (p[4] - p[0]);
    b->orient[t] = a >= 0 ? 1 : -1;
}

static void bare_init(bare *b) {
    memset(&b->m, 0, sizeof b->m);
    b->m.xy = b->xy, b->m.tri = b->tri, b->m.orient = b->orient;
}

/* Meshes tc_mesh_new would refuse, which the locator still indexes: triangles
 * overlapping at random (the tree answers the first strict owner in its slot
 * order; the grid must too), a fan of long needles around one point (lists
 * past TC_LOCGRID_MAX walk the tree), one huge triangle over many small ones,
 * a NaN vertex (no grid at all). */
TEST(points_owner_same_as_tree_invalid_meshes) {
    static bare b;
    trng r;
    trng_seed(&r, tc_test_seed() + 300);
    for (int trial = 0; trial < 6; trial++) {
        bare_init(&b);
        for (int t = 0; t < 150; t++) {
            double p[6];
            for (int k = 0; k < 6; k++) p[k] = ldexp(floor(ldexp(trng_uniform(&r), 10)), -10);
            if ((p[2] - p[0]) * (p[5] - p[1]) == (p[3] - p[1]) * (p[4] - p[0])) continue;
            bare_tri(&b, p);
        }
        check_mesh_owners(&b.m, tc_test_seed() + 310 + (unsigned long)trial);
    }
    bare_init(&b); /* a fan of needles */
    for (int t = 0; t < 120; t++) {
        double a0 = 6.283185307179586 * t / 120, a1 = 6.283185307179586 * (t + 1) / 120;
        double p[6] = {0.5, 0.5, 0.5 + 0.5 * cos(a0), 0.5 + 0.5 * sin(a0), 0.5 + 0.5 * cos(a1), 0.5 + 0.5 * sin(a1)};
        bare_tri(&b, p);
    }
    check_mesh_owners(&b.m, tc_test_seed() + 320);
    bare_init(&b); /* one huge triangle over small ones */
    bare_tri(&b, (const double[6]){-1, -1, 3, -1, -1, 3});
    for (int t = 0; t < 100; t++) {
        double x = (t % 10) / 10.0, y = (t / 10) / 10.0;
        bare_tri(&b, (const double[6]){x, y, x + 0.1, y, x, y + 0.1});
    }
    check_mesh_owners(&b.m, tc_test_seed() + 330);
    bare_tri(&b, (const double[6]){NAN, 0, 1, 1, 0, 1}); /* and a NaN vertex */
    tc_locator *L = NULL;
    CHECK(tc_locator_new(&b.m, &L) == TC_OK);
    int64_t cells, held;
    CHECK_MSG(tc__locator_grid_cells(L, &cells, &held) == 0, "a mesh with a NaN vertex got a grid");
    tc_locator_free(L);
    check_mesh_owners(&b.m, tc_test_seed() + 340);
}

/* The fast path is there: a grid mesh's locator gets its grid once enough
 * points were asked for (not before: a request of a few points on a fresh
 * mesh must not pay for it), and most of its cells lie inside one triangle
 * (answered with no test). */
TEST(points_grid_built) {
    trng r;
    trng_seed(&r, 7);
    tmesh g;
    tmesh_grid(&g, 16, 16, 0, 0, &r);
    tmesh_sample(&g, 1, smooth_f, NULL, 0, 0, 0);
    tc_mesh *m = tmesh_build(&g);
    tc_recon *rec = NULL;
    tc_locator *L = NULL;
    CHECK(m && tc_recon_new(m, NULL, &rec, NULL) == TC_OK && tc_locator_new(m, &L) == TC_OK);
    int64_t cells = 0, held = 0;
    CHECK_MSG(tc__locator_grid_cells(L, &cells, &held) == 0, "a fresh locator has a grid already");
    enum { N = 8192 };
    static double xy[2 * N], v[N];
    for (int i = 0; i < 2 * N; i++) xy[i] = trng_uniform(&r);
    tc_eval_points(rec, L, N, xy, v, NULL, NULL);
    CHECK_MSG(tc__locator_grid_cells(L, &cells, &held) == 0, "a grid after %d points", N);
    for (int k = 0; k < 40 && !tc__locator_grid_cells(L, &cells, &held); k++) tc_eval_points(rec, L, N, xy, v, NULL, NULL);
    CHECK_MSG(cells >= 512 && held * 2 > cells, "%lld cells, %lld held", (long long)cells, (long long)held);
    tc_locator_free(L);
    tc_recon_free(rec);
    tc_mesh_free(m);
    tmesh_free(&g);
}

/* ---- values -------------------------------------------------------------------- */

/* tc_eval_points(_mt) against tc__eval_points_ref: values, gradients, owners. */
static void check_batch(const tc_recon *r, const tc_locator *L, size_t n, const double *xy, int nc, const char *what) {
    size_t nv = (n ? n : 1) * (size_t)nc;
    double *v0 = malloc(nv * sizeof *v0), *g0 = malloc(2 * nv * sizeof *g0);
    double *v1 = malloc(nv * sizeof *v1), *g1 = malloc(2 * nv * sizeof *g1);
    int32_t *t0 = malloc((n ? n : 1) * sizeof *t0), *t1 = malloc((n ? n : 1) * sizeof *t1);
    if (!v0 || !g0 || !v1 || !g1 || !t0 || !t1) abort();
    tc__eval_points_ref(r, L, n, xy, v0, g0, t0);
    for (int threads = 1; threads <= 3; threads++)
        for (int grads = 0; grads < 2; grads++) {
            memset(v1, 0x55, nv * sizeof *v1), memset(g1, 0x55, 2 * nv * sizeof *g1);
            tc_eval_points_mt(r, L, n, xy, v1, grads ? g1 : NULL, t1, threads);
            int bad = 0;
            size_t c = (size_t)nc;
            for (size_t i = 0; i < n; i++) {
                int d = t0[i] != t1[i] || memcmp(v0 + i * c, v1 + i * c, c * sizeof *v0) ||
                        (grads && memcmp(g0 + 2 * i * c, g1 + 2 * i * c, 2 * c * sizeof *g0));
                if (d && bad++ < 3)
                    CHECK_MSG(0, "%s, %d threads%s: point %zu (%.17g, %.17g): tri %d / %d, value %.17g / %.17g", what,
                              threads, grads ? ", gradients" : "", i, xy[2 * i], xy[2 * i + 1], (int)t1[i], (int)t0[i],
                              v1[i * c], v0[i * c]);
            }
        }
    free(v0), free(g0), free(v1), free(g1), free(t0), free(t1);
}

/* Every method (the Clough-Tocher one through the four-lane kernel, AVX2 and
 * portable, the others one point at a time), 1 and 3 channels, a batch smaller
 * than the mesh (a frame per run of points) and larger (a table of frames),
 * in given and in Z order, the floor at 0 on a channel that goes negative. */
TEST(points_values_same_as_reference) {
    trng r;
    trng_seed(&r, tc_test_seed() + 400);
    for (int nc = 1; nc <= 3; nc += 2) {
        tmesh g;
        tmesh_grid(&g, 9, 7, 0.35, -1, &r);
        tmesh_delaunay_flips(&g);
        tmesh_sample(&g, nc, smooth_f, NULL, 0, 1, 0.3);
        tc_mesh *m = tmesh_build(&g);
        CHECK(m != NULL);
        if (!m) {
            tmesh_free(&g);
            continue;
        }
        tc_locator *L = NULL;
        CHECK(tc_locator_new(m, &L) == TC_OK);
        tc__locator_grid_now(L);
        pts p = {0};
        stress_points(m, &r, &p);
        for (int meth = 0; meth < tc_method_count(); meth++) {
            if (tc_method_quads_only((tc_method)meth)) continue;
            tc_options o;
            tc_options_default(&o);
            o.method = (tc_method)meth;
            tc_recon *rec = NULL;
            if (tc_recon_new(m, &o, &rec, NULL) != TC_OK) continue;
            rec->floor0[0] = 1; /* smooth_f goes below 0: the floor is exercised */
            for (int generic = 0; generic < 2; generic++) {
                tc__ct_points_force_generic(generic);
                char what[96];
                snprintf(what, sizeof what, "%s, %d channels%s", tc_method_name((tc_method)meth), nc,
                         generic ? ", portable" : "");
                check_batch(rec, L, 37, p.xy, nc, what);        /* fewer points than triangles */
                check_batch(rec, L, p.n, p.xy, nc, what);       /* more */
                tc__eval_sort_min_triangles(0);                 /* the Z-ordered visit */
                check_batch(rec, L, p.n, p.xy, nc, what);
                tc__eval_sort_min_triangles(32768);
            }
            tc__ct_points_force_generic(0);
            tc_recon_free(rec);
        }
        free(p.xy);
        tc_locator_free(L);
        tc_mesh_free(m);
        tmesh_free(&g);
    }
}

/* Large batches over threads: every result the one-thread result, for 1..5 threads. */
TEST(points_threads_same_bits) {
    trng r;
    trng_seed(&r, tc_test_seed() + 500);
    tmesh g;
    tmesh_grid(&g, 20, 20, 0.3, -1, &r);
    tmesh_sample(&g, 2, smooth_f, NULL, 1, 0, 0);
    tc_mesh *m = tmesh_build(&g);
    tc_recon *rec = NULL;
    tc_locator *L = NULL;
    CHECK(m && tc_recon_new(m, NULL, &rec, NULL) == TC_OK && tc_locator_new(m, &L) == TC_OK);
    enum { N = 40000 };
    double *xy = malloc(2 * N * sizeof *xy), *v1 = malloc(2 * N * sizeof *v1), *g1 = malloc(4 * N * sizeof *g1);
    double *vk = malloc(2 * N * sizeof *vk), *gk = malloc(4 * N * sizeof *gk);
    int32_t *t1 = malloc(N * sizeof *t1), *tk = malloc(N * sizeof *tk);
    if (!xy || !v1 || !g1 || !vk || !gk || !t1 || !tk) abort();
    for (int i = 0; i < 2 * N; i++) xy[i] = 1.2 * trng_uniform(&r) - 0.1;
    if (rec && L) {
        tc_eval_points(rec, L, N, xy, v1, g1, t1);
        for (int th = 2; th <= 5; th++) {
            tc_eval_points_mt(rec, L, N, xy, vk, gk, tk, th);
            CHECK_MSG(!memcmp(v1, vk, 2 * N * sizeof *v1) && !memcmp(g1, gk, 4 * N * sizeof *g1) &&
                          !memcmp(t1, tk, N * sizeof *t1),
                      "%d threads differ from one", th);
        }
    }
    free(xy), free(v1), free(g1), free(vk), free(gk), free(t1), free(tk);
    tc_locator_free(L);
    tc_recon_free(rec);
    tc_mesh_free(m);
    tmesh_free(&g);
}

/* ---- the answer's printer ------------------------------------------------------------ */

static int stop_calls;
static int stop_after_two(void *ctx) {
    (void)ctx;
    return ++stop_calls > 2;
}

/* With evaluation fast, printing is most of a large /v1/evaluate answer: the
 * printer polls the deadline every few thousand points and gives up when told
 * (tests/endpoint's deadline check sees the 503 through the daemon); left
 * alone, it writes exactly what tc_json_points_enc writes. */
TEST(points_answer_printing_stops) {
    enum { N = 50000 };
    static double v[N], g[2 * N];
    static int32_t tri[N];
    for (int i = 0; i < N; i++) v[i] = i * 0.25, g[2 * i] = -i, g[2 * i + 1] = 1.0 / (i + 1), tri[i] = i % 7 ? 0 : -1;
    tc_strbuf a, b;
    tc_strbuf_init(&a), tc_strbuf_init(&b);
    tc_json_points_enc(&a, 1, N, v, g, tri, 1, 0);
    CHECK(tc_json_points_enc_until(&b, 1, N, v, g, tri, 1, 0, NULL, NULL) == 0);
    CHECK(a.len == b.len && memcmp(a.buf, b.buf, a.len) == 0);
    tc_strbuf_free(&b), tc_strbuf_init(&b);
    stop_calls = 0;
    CHECK(tc_json_points_enc_until(&b, 1, N, v, g, tri, 1, 0, stop_after_two, NULL) == -1);
    CHECK_MSG(stop_calls == 3 && b.len < a.len / 2, "%d checks, %zu of %zu bytes", stop_calls, b.len, a.len);
    tc_strbuf_free(&a), tc_strbuf_free(&b);
}
