/* test_stab_steep.c — steep and vertical tangent planes: normals with N.z from 1 to 1e-12 and 0,
 * gradients up to 1e12, one steep face in a flat wedge; finite, bounded or refused by name. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "props.h"
#include "stab.h"

#define GRAD_FACTOR 10.0 /* as for nearly straight wedges: max |grad| <= 10 x the largest given */
#define N 4
#define NV ((N + 1) * (N + 1))
#define CENTER (2 * (N + 1) + 2)

/* A 4 x 4 grid over [0,1]^2 (triangles, or quads for hermite), smooth data, C0 along y = 1/2. */
typedef struct {
    double xy[2 * NV], z[NV], grad[2 * NV], normal[3 * NV], cg[2 * N * N * 3 * 2];
    int32_t tri[3 * 2 * N * N], quad[4 * N * N], cg_tri[2 * N * N], c0s[2], c0v[N + 1];
} grid;

static void grid_init(grid *g) {
    for (int j = 0; j <= N; j++)
        for (int i = 0; i <= N; i++) {
            int v = j * (N + 1) + i;
            g->xy[2 * v] = (double)i / N, g->xy[2 * v + 1] = (double)j / N;
            smooth_f(NULL, g->xy[2 * v], g->xy[2 * v + 1], 0, &g->z[v], g->grad + 2 * v);
            double len = hypot(1, hypot(g->grad[2 * v], g->grad[2 * v + 1]));
            g->normal[3 * v] = -g->grad[2 * v] / len, g->normal[3 * v + 1] = -g->grad[2 * v + 1] / len;
            g->normal[3 * v + 2] = 1 / len;
        }
    for (int j = 0; j < N; j++)
        for (int i = 0; i < N; i++) {
            int32_t a = j * (N + 1) + i, q[4] = {a, a + 1, a + N + 2, a + N + 1}, c = j * N + i;
            memcpy(g->quad + 4 * c, q, sizeof q);
            int32_t t[6] = {a, a + 1, a + N + 2, a, a + N + 2, a + N + 1};
            memcpy(g->tri + 6 * c, t, sizeof t);
        }
    for (int i = 0; i <= N; i++) g->c0v[i] = (N / 2) * (N + 1) + i;
    g->c0s[0] = 0, g->c0s[1] = N + 1;
}

enum { WITH_NORMALS, WITH_GRADIENTS, WITH_CORNERS };

static void grid_desc(grid *g, int quads, int kind, int flags, tc_mesh_desc *d) {
    memset(d, 0, sizeof *d);
    d->nverts = NV, d->xy = g->xy, d->nchan = 1, d->values = g->z;
    if (quads) d->nquads = N * N, d->quads = g->quad;
    else d->ntris = 2 * N * N, d->tris = g->tri;
    if (kind == WITH_NORMALS) d->normals = g->normal;
    if (kind == WITH_GRADIENTS) d->gradients = g->grad;
    if (kind == WITH_CORNERS) { /* per corner: every corner its vertex's plane (set by the caller) */
        int32_t ne = quads ? N * N : 2 * N * N, nk = quads ? 4 : 3;
        for (int32_t e = 0; e < ne; e++) {
            g->cg_tri[e] = e;
            for (int k = 0; k < nk; k++) {
                int32_t v = quads ? g->quad[4 * e + k] : g->tri[3 * e + k];
                memcpy(g->cg + 2 * ((size_t)e * (size_t)nk + (size_t)k), g->grad + 2 * v, 2 * sizeof(double));
            }
        }
        d->ncorner_gradients = ne, d->corner_gradients_tri = g->cg_tri, d->corner_gradients = g->cg;
    }
    if (flags) d->c0 = (tc_polylines){1, g->c0s, g->c0v};
}

/* The planes the reconstruction uses at `center`'s corners differ from the given one
 * (per-vertex data at a C1 vertex is used as given unless the core limits it). */
static int plane_changed(const tc_recon *r, const double given[2]) {
    const double *cg = tc_recon_corner_gradients(r);
    const tc_mesh *m = tc_recon_mesh(r);
    const int32_t *tv = tc_mesh_triangles(m);
    for (int32_t c = 0; cg && c < 3 * tc_mesh_triangle_count(m); c++)
        if (tv[c] == CENTER &&
            hypot(cg[2 * c] - given[0], cg[2 * c + 1] - given[1]) > 1e-12 * hypot(given[0], given[1]))
            return 1;
    return 0;
}

/* 0 if a warning names the center vertex (its plane was clamped), else 1. */
static double clamp_warning_missing(const srun *x) {
    static const char *const paths[] = {"vertices[12]", "normals[12]", "gradients[12]"};
    for (int i = 0; i < 3; i++)
        if (stab_has_warning(&x->dg, paths[i], "", 0)) return 0;
    return 1;
}

typedef struct {
    stab_acc grad[STAB_NVAR], over[STAB_NVAR], warn[STAB_NVAR];
} steep_figs;

static void measure(const tc_mesh_desc *d, int v, const char *where, const double *given_center, steep_figs *f) {
    tc_options o;
    stab_options(v, TC_TANGENTS_GIVEN, &o);
    srun x;
    if (srun_start(&x, d, &o)) {
        stab_acc_refusal(&f->grad[v], &x);
    } else {
        stab_range r;
        stab_sample(x.r, 60, 3, &r);
        double fig = r.nonfinite || !stab_recon_finite(x.r) ? INFINITY : r.gmax / stab_given_gradient(d);
        stab_acc_fig(&f->grad[v], fig, where);
        stab_acc_fig(&f->over[v], stab_overshoot(&r), where);
        if (given_center && plane_changed(x.r, given_center))
            stab_acc_fig(&f->warn[v], clamp_warning_missing(&x), where);
    }
    srun_end(&x);
}

static void report(const char *name, steep_figs *f) {
    STAB_REPORT(name, "max |grad| / max given gradient", f->grad, GRAD_FACTOR, 0);
    STAB_REPORT(name, "overshoot beyond the data range / range", f->over, -1, STAB_INFO);
    STAB_REPORT(name, "plane changed without a warning at the vertex (1 = missing)", f->warn, 0.5, 0);
}

static void init(steep_figs *f) {
    stab_acc_init(f->grad, STAB_NVAR), stab_acc_init(f->over, STAB_NVAR), stab_acc_init(f->warn, STAB_NVAR);
}

/* The center vertex's normal tilts from vertical (N.z = 1) to N.z = 1e-12. */
TEST(stab_steep_normals) {
    static grid g;
    static steep_figs f;
    init(&f);
    grid_init(&g);
    for (int k = 0; k <= 12; k++)
        for (int flags = 0; flags < 2; flags++) {
            double nz = pow(10, -k), *n = g.normal + 3 * CENTER, given[2];
            n[0] = sqrt((1 - nz) * (1 + nz)), n[1] = 0, n[2] = nz;
            given[0] = -n[0] / nz, given[1] = 0;
            char where[48];
            snprintf(where, sizeof where, "N.z = %g%s", nz, flags ? ", C0 row" : "");
            for (int v = 0; v < STAB_NVAR; v++) {
                tc_mesh_desc d;
                grid_desc(&g, v == STAB_HERMITE, WITH_NORMALS, flags, &d);
                measure(&d, v, where, flags ? NULL : given, &f);
            }
        }
    report("steep-normals", &f);
}

/* N.z <= 0 must be refused naming normals[12] (0 / 1); N.z = 1e-300: refused by name, or finite. */
static void vertical_one(grid *g, int v, double nz, stab_acc *a) {
    double *n = g->normal + 3 * CENTER;
    n[0] = sqrt(1 - nz * nz), n[1] = 0, n[2] = nz;
    tc_mesh_desc d;
    grid_desc(g, v == STAB_HERMITE, WITH_NORMALS, 0, &d);
    tc_options o;
    stab_options(v, TC_TANGENTS_GIVEN, &o);
    srun x;
    char where[32];
    snprintf(where, sizeof where, "N.z = %g", nz);
    int refused = srun_start(&x, &d, &o) != 0;
    const tc_diag *e = srun_error(&x);
    if (!(nz > 0)) {
        stab_acc_fig(a, refused && e && !strncmp(e->path, "normals[12]", 11) ? 0 : 1, where);
    } else if (refused) {
        stab_acc_refusal(a, &x);
    } else {
        stab_range r;
        stab_sample(x.r, 20, 3, &r);
        stab_acc_fig(a, r.nonfinite || !stab_recon_finite(x.r) ? INFINITY : 0, where);
    }
    srun_end(&x);
}

TEST(stab_vertical_normal) {
    static grid g;
    stab_acc acc[STAB_NVAR];
    stab_acc_init(acc, STAB_NVAR);
    grid_init(&g);
    const double nzs[] = {0.0, -0.0, -1e-3, 1e-300};
    for (int i = 0; i < 4; i++)
        for (int v = 0; v < STAB_NVAR; v++) vertical_one(&g, v, nzs[i], &acc[v]);
    STAB_REPORT("vertical-normal", "N.z <= 0 not refused at normals[12] (1), or N.z = 1e-300 non-finite", acc, 0.5, 0);
}

/* Per-vertex gradients up to 1e12 at the center. */
TEST(stab_steep_gradients) {
    static grid g;
    static steep_figs f;
    init(&f);
    for (int k = 0; k <= 12; k += 2)
        for (int flags = 0; flags < 2; flags++) {
            grid_init(&g);
            double given[2] = {pow(10, k), -0.5 * pow(10, k)};
            memcpy(g.grad + 2 * CENTER, given, sizeof given);
            char where[48];
            snprintf(where, sizeof where, "|g| = %.2g%s", hypot(given[0], given[1]), flags ? ", C0 row" : "");
            for (int v = 0; v < STAB_NVAR; v++) {
                tc_mesh_desc d;
                grid_desc(&g, v == STAB_HERMITE, WITH_GRADIENTS, flags, &d);
                measure(&d, v, where, flags ? NULL : given, &f);
            }
        }
    report("steep-gradients", &f);
}

/* Per-corner planes: at the center one face's corner has |g| = 10^k, the others the smooth
 * function's plane; with a C0 row through the center the steep face shares its wedge with
 * flat ones. */
TEST(stab_steep_mixed_wedge) {
    static grid g;
    static steep_figs f;
    init(&f);
    grid_init(&g);
    for (int k = 0; k <= 12; k += 3)
        for (int flags = 0; flags < 2; flags++)
            for (int v = 0; v < STAB_NVAR; v++) {
                tc_mesh_desc d;
                int quads = v == STAB_HERMITE;
                grid_desc(&g, quads, WITH_CORNERS, flags, &d);
                /* cell (2, 2): quad 10, triangle 20, whose first corner is the center */
                double *c = g.cg + 2 * (quads ? 4 * 10 : 3 * 20);
                c[0] = pow(10, k), c[1] = pow(10, k);
                char where[48];
                snprintf(where, sizeof where, "one corner |g| = %.2g%s", hypot(c[0], c[1]), flags ? ", C0 row" : "");
                measure(&d, v, where, NULL, &f);
            }
    report("steep-mixed-wedge", &f);
}
