/* test_stab_fuzz.c — thousands of small random meshes (fixed seeds) with random flags, data, methods
 * and options: no NaN or Inf, interpolation and continuity where promised, refusals named. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "quadgen.h"
#include "stab.h"

#define MESHES 8000

/* Random smooth data: a quadratic plus a wave, per channel. */
typedef struct {
    double a[3][9];
} rfunc;

static void rfunc_init(rfunc *f, trng *r) {
    for (int ch = 0; ch < 3; ch++)
        for (int i = 0; i < 9; i++) f->a[ch][i] = 4 * trng_uniform(r) - 2;
}

static void rf(const void *ctx, double x, double y, int ch, double *v, double g[2]) {
    const double *a = ((const rfunc *)ctx)->a[ch];
    double s = sin(a[7] * x + a[8] * y), c = cos(a[7] * x + a[8] * y);
    *v = a[0] + a[1] * x + a[2] * y + a[3] * x * x + a[4] * x * y + a[5] * y * y + a[6] * s;
    g[0] = a[1] + 2 * a[3] * x + a[4] * y + a[6] * a[7] * c;
    g[1] = a[2] + a[4] * x + 2 * a[5] * y + a[6] * a[8] * c;
}

static void qrf(const void *ctx, double x, double y, int ch, double *v, double g[2], double h[3]) {
    rf(ctx, x, y, ch, v, g);
    h[0] = h[1] = h[2] = 0;
}

/* A random triangle mesh (grid, maybe flipped, random C0 / C-1 walks, random samples). */
static void random_tri(trng *r, const rfunc *fn, tmesh *g, sdesc *s) {
    int nx = 1 + trng_int(r, 4), ny = 1 + trng_int(r, 4);
    tmesh_grid(g, nx, ny, 0.45 * trng_uniform(r), -1, r);
    if (trng_int(r, 2)) tmesh_delaunay_flips(g);
    for (int i = trng_int(r, 4); i > 0; i--)
        tmesh_random_line(g, trng_int(r, 2) ? TC_C0 : TC_CM1, 1 + trng_int(r, 4), r);
    tmesh_sample(g, 1 + trng_int(r, 3), rf, fn, trng_int(r, 2), trng_int(r, 2), trng_int(r, 2) ? 0.7 : 0);
    tc_mesh_desc d;
    tmesh_desc(g, &d);
    sdesc_copy(s, &d);
}

/* A random quad mesh (hermite): jittered grid, maybe a flagged grid row, gradients, midpoints. */
static void random_quad(trng *r, const rfunc *fn, sdesc *s) {
    qmesh q;
    qgrid_opts o = {.jitter = 0.4 * trng_uniform(r), .uneven = trng_int(r, 2)};
    int nx = 1 + trng_int(r, 4), ny = 2 + trng_int(r, 3);
    qmesh_grid(&q, nx, ny, &o, r);
    qmesh_sample(&q, 1 + trng_int(r, 3), qrf, fn);
    tc_mesh_desc d;
    qmesh_desc(&q, trng_int(r, 2), 0, &d);
    sdesc_copy(s, &d);
    int32_t seg[2 * 5 + 1], n = 0, j = 1 + trng_int(r, ny - 1);
    for (int i = 0; i < nx; i++) seg[2 * n] = j * (nx + 1) + i, seg[2 * n + 1] = j * (nx + 1) + i + 1, n++;
    seg[2 * n] = -1;
    int kind = trng_int(r, 3);
    sdesc_set_lines(s, kind == 1 ? seg : NULL, kind == 2 ? seg : NULL);
    if (trng_int(r, 2)) sdesc_add_midpoints(s, rf, fn);
    qmesh_free(&q);
}

/* Sometimes tiny or huge, far from the origin (at most 1e4 of its size away, so that the
 * coordinates keep 1e-12 of the mesh's size and points on edges stay on them to 1e-12),
 * or with tiny or huge values. */
static void random_transform(trng *r, sdesc *s) {
    double scale = trng_int(r, 5) == 0 ? pow(10, 12 * trng_uniform(r) - 6) : 1;
    double off = trng_int(r, 5) == 0 ? scale * pow(10, 4 * trng_uniform(r)) : 0;
    if (scale != 1 || off != 0) sdesc_move(s, scale, off, -0.75 * off);
    if (trng_int(r, 5) == 0) sdesc_scale_values(s, pow(10, 16 * trng_uniform(r) - 8));
}

/* No NaN or Inf at random points over and around the mesh; 0 outside. */
static int points_finite(const srun *x, trng *r) {
    const tc_mesh *m = x->m;
    const double *p = tc_mesh_xy(m);
    double lo[2] = {p[0], p[1]}, hi[2] = {p[0], p[1]}, xy[2 * 64], v[64 * 3], g[64 * 6];
    int32_t tri[64];
    for (int32_t i = 0; i < tc_mesh_vertex_count(m); i++)
        for (int k = 0; k < 2; k++) lo[k] = fmin(lo[k], p[2 * i + k]), hi[k] = fmax(hi[k], p[2 * i + k]);
    for (int i = 0; i < 64; i++)
        for (int k = 0; k < 2; k++) xy[2 * i + k] = lo[k] + (1.2 * trng_uniform(r) - 0.1) * (hi[k] - lo[k]);
    tc_eval_points(x->r, x->L, 64, xy, v, g, tri);
    int nc = tc_mesh_channel_count(m);
    for (int i = 0; i < 64 * nc; i++)
        if (!isfinite(v[i]) || !isfinite(g[2 * i] + g[2 * i + 1]) || (tri[i / nc] < 0 && v[i] != 0)) return 0;
    return 1;
}

typedef struct {
    stab_acc c0[STAB_NVAR], c1[STAB_NVAR];
} fuzz_figs;

static void fuzz_one(uint64_t seed, fuzz_figs *f) {
    trng r;
    trng_seed(&r, seed);
    rfunc fn;
    rfunc_init(&fn, &r);
    int v = trng_int(&r, STAB_NVAR);
    tmesh g;
    sdesc s;
    memset(&g, 0, sizeof g);
    if (v == STAB_HERMITE) random_quad(&r, &fn, &s);
    else random_tri(&r, &fn, &g, &s);
    random_transform(&r, &s);
    tc_options o;
    stab_options(v, (tc_tangents)trng_int(&r, 4), &o);
    o.twist = (tc_twist)trng_int(&r, 2);
    srun x;
    char where[48];
    snprintf(where, sizeof where, "seed %llu", (unsigned long long)seed);
    if (srun_start(&x, &s.d, &o)) {
        stab_acc_refusal(&f->c0[v], &x);
    } else {
        stab_cont c;
        stab_continuity(x.r, &c);
        int fin = stab_recon_finite(x.r) && points_finite(&x, &r);
        stab_acc_fig(&f->c0[v], fin ? fmax(c.corner, c.c0) : INFINITY, where);
        if (stab_has_planes(v) && v != STAB_HERMITE)
            stab_acc_fig(&f->c1[v], fin ? fmax(c.c1, fmax(c.vertex, c.internal)) : INFINITY, where);
    }
    srun_end(&x);
    sdesc_free(&s);
    if (v != STAB_HERMITE) tmesh_free(&g);
}

TEST(stab_fuzz) {
    static fuzz_figs f;
    stab_acc_init(f.c0, STAB_NVAR), stab_acc_init(f.c1, STAB_NVAR);
    uint64_t base = tc_test_seed();
    for (int i = 0; i < MESHES; i++) fuzz_one(base * 1000003u + (uint64_t)i, &f);
    STAB_REPORT("fuzz", "C0 residual, interpolation; non-finite; unnamed refusals", f.c0, 1e-9, 0);
    STAB_REPORT("fuzz", "C1 residual", f.c1, 1e-9, 0);
}
