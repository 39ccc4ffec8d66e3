/* test_stab_slivers.c — triangles of aspect ratio 1e2..1e8 (a sliver strip, a fan of needles, a
 * cap, thin quads) and the stiff scene's disc meshes: continuity, overshoot, aspect warnings. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "props.h"
#include "scenes/meshing.h"
#include "stab.h"

static const tc_tangents SOURCES[] = {TC_TANGENTS_GIVEN, TC_TANGENTS_MIDPOINTS, TC_TANGENTS_ESTIMATE};
#define NSRC 3
#define NX 8
/* Up to this aspect the C1 residual holds 1e-9 outright; beyond, the rounding of a
 * gradient read across the sliver grows as eps * aspect (stab.h, stab_c1_over_bound). */
#define STAB_C1_ASPECT 1.5e5

/* Rows y = -1/2, 0, eps, 1/2 over x = i/8: the middle row is a strip of cells 1/8 x eps,
 * aspect 1/(8 eps). C0 along y = 0, a C-1 crack along y = eps ending inside. */
static void strip(tmesh *g, double aspect) {
    double xy[4 * (NX + 1) * 2], ys[4] = {-0.5, 0, 0.125 / aspect, 0.5};
    int32_t tri[3 * 2 * NX * 3], nt = 0;
    for (int j = 0; j < 4; j++)
        for (int i = 0; i <= NX; i++) {
            double *p = xy + 2 * (j * (NX + 1) + i);
            p[0] = (double)i / NX, p[1] = ys[j];
        }
    for (int j = 0; j < 3; j++)
        for (int i = 0; i < NX; i++) {
            int32_t a = j * (NX + 1) + i, b = a + 1, c = a + NX + 2, d = a + NX + 1;
            int32_t q[6] = {a, b, c, a, c, d}, p[6] = {a, b, d, b, c, d};
            memcpy(tri + 3 * nt, (i + j) % 2 ? q : p, sizeof q);
            nt += 2;
        }
    stab_tmesh(g, 4 * (NX + 1), xy, nt, tri);
    int32_t c0[NX + 1], cm1[NX / 2 + 1];
    for (int i = 0; i <= NX; i++) c0[i] = NX + 1 + i;
    for (int i = 0; i <= NX / 2; i++) cm1[i] = 2 * (NX + 1) + i;
    tmesh_add_line(g, TC_C0, c0, NX + 1);
    tmesh_add_line(g, TC_CM1, cm1, NX / 2 + 1);
}

/* A vertex with 16 faces: 8 needles of angle 1/aspect between 8 wide faces; a C0
 * line through it. */
static void needles(tmesh *g, double aspect) {
    double xy[2 * 17] = {0, 0}, delta = asin(1 / aspect);
    int32_t tri[3 * 16];
    for (int j = 0; j < 16; j++) {
        double th = 2 * STAB_PI * (j / 2) / 8 + (j % 2) * delta;
        xy[2 + 2 * j] = cos(th), xy[3 + 2 * j] = sin(th);
        tri[3 * j] = 0, tri[3 * j + 1] = 1 + j, tri[3 * j + 2] = 1 + (j + 1) % 16;
    }
    stab_tmesh(g, 17, xy, 16, tri);
    int32_t line[3] = {1, 0, 9};
    tmesh_add_line(g, TC_C0, line, 3);
}

/* A cap: C = (1/2, 1/aspect) just above the straight C0 line G-A-B-H, so the
 * triangle A B C has an angle of nearly 180 degrees at C. */
static void cap(tmesh *g, double aspect) {
    const double xy[2 * 7] = {0, 0, 1, 0, 0.5, 1 / aspect, 0.5, -0.5, 0.5, 0.5, -0.5, 0, 1.5, 0};
    enum { A, B, C, D, E, G, H };
    const int32_t tri[3 * 8] = {A, D, B, A, B, C, A, C, E, C, B, E, G, D, A, G, A, E, B, D, H, B, H, E};
    stab_tmesh(g, 7, xy, 8, tri);
    int32_t line[4] = {G, A, B, H};
    tmesh_add_line(g, TC_C0, line, 4);
}

/* The same strip as quads (hermite): cells 1/8 x eps in the middle row, C0 along y = 0. */
static void quad_strip(sdesc *s, double aspect) {
    tmesh g;
    strip(&g, aspect);
    tmesh_sample(&g, 1, smooth_f, NULL, 1, 0, 0);
    tc_mesh_desc d;
    tmesh_desc(&g, &d);
    int32_t quads[4 * NX * 3];
    for (int j = 0; j < 3; j++)
        for (int i = 0; i < NX; i++) {
            int32_t a = j * (NX + 1) + i, *q = quads + 4 * (j * NX + i);
            q[0] = a, q[1] = a + 1, q[2] = a + NX + 2, q[3] = a + NX + 1;
        }
    d.ntris = 0, d.tris = NULL, d.nquads = 3 * NX, d.quads = quads;
    d.ncorner_values = 0, d.nmidpoints = 0, d.cm1.count = 0;
    sdesc_copy(s, &d);
    tmesh_free(&g);
    sdesc_add_midpoints(s, smooth_f, NULL);
}

static double tri_aspect(const double *p, const double *q, const double *r) {
    double e[3][2] = {{q[0] - p[0], q[1] - p[1]}, {r[0] - q[0], r[1] - q[1]}, {p[0] - r[0], p[1] - r[1]}}, l = 0;
    for (int k = 0; k < 3; k++) l = fmax(l, hypot(e[k][0], e[k][1]));
    return l * l / fabs(e[0][0] * e[2][1] - e[0][1] * e[2][0]);
}

/* 0 if some warning names one of the worst triangles (aspect >= half the worst) with
 * the word "aspect" and that triangle's figure; 1 if none does. */
static double aspect_warning_missing(const srun *x) {
    const double *xy = tc_mesh_xy(x->m);
    const int32_t *tv = tc_mesh_triangles(x->m);
    int32_t nt = tc_mesh_triangle_count(x->m);
    double worst = 0, ar[512];
    for (int32_t t = 0; t < nt && t < 512; t++) {
        ar[t] = tri_aspect(xy + 2 * tv[3 * t], xy + 2 * tv[3 * t + 1], xy + 2 * tv[3 * t + 2]);
        worst = fmax(worst, ar[t]);
    }
    int quads = tc_mesh_quad_count(x->m) > 0;
    for (int32_t t = 0; t < nt && t < 512; t++) {
        char path[48];
        snprintf(path, sizeof path, quads ? "quads[%d]" : "triangles[%d]", (int)(quads ? t / 2 : t));
        if (ar[t] >= 0.5 * worst && stab_has_warning(&x->dg, path, "aspect", ar[t])) return 0;
    }
    return 1;
}

typedef struct {
    stab_acc c0[STAB_NVAR], c1[STAB_NVAR], c1s[STAB_NVAR], over[STAB_NVAR], warn[STAB_NVAR];
    double by_aspect[2][9]; /* worst C0 and C1 residual over the variants, aspect 1e0..1e8 */
} sliver_figs;

static void measure(const tc_mesh_desc *d, int v, tc_tangents src, double aspect, const char *tag, sliver_figs *f) {
    tc_options o;
    stab_options(v, src, &o);
    srun x;
    char where[80];
    snprintf(where, sizeof where, "%saspect %.2g, tangents %s", tag, aspect, tc_tangents_name(src));
    if (srun_start(&x, d, &o)) {
        stab_acc_refusal(&f->c0[v], &x);
        stab_acc_refusal(&f->c1[v], &x);
        stab_acc_refusal(&f->c1s[v], &x);
        stab_acc_refusal(&f->over[v], &x);
    } else {
        stab_cont c;
        stab_range r;
        int fin = stab_measure(x.r, 30, 5, &c, &r);
        double r0 = fin ? fmax(c.corner, c.c0) : INFINITY, r1 = fin ? fmax(c.c1, fmax(c.vertex, c.internal)) : INFINITY;
        char w1[96];
        const char *which = c.internal >= fmax(c.c1, c.vertex) ? "internal" : c.c1 >= c.vertex ? "edge" : "vertex";
        snprintf(w1, sizeof w1, "%s (%s)", where, which);
        stab_acc_fig(&f->c0[v], r0, where);
        if (stab_has_planes(v) && v != STAB_HERMITE) {
            if (c.aspect <= STAB_C1_ASPECT) stab_acc_fig(&f->c1[v], r1, w1);
            stab_acc_fig(&f->c1s[v], fin ? stab_c1_over_bound(&c) : INFINITY, w1);
        }
        stab_acc_fig(&f->over[v], stab_overshoot(&r), where);
        if (aspect >= 1e6) stab_acc_fig(&f->warn[v], aspect_warning_missing(&x), where);
        int k = aspect >= 1 ? (int)lround(log10(aspect)) : 0;
        if (k >= 0 && k <= 8) {
            f->by_aspect[0][k] = fmax(f->by_aspect[0][k], r0);
            f->by_aspect[1][k] = fmax(f->by_aspect[1][k], r1);
        }
    }
    srun_end(&x);
}

static void report(const char *name, sliver_figs *f) {
    STAB_REPORT(name, "C0 residual (interpolation, values across C0/C1 edges; max rel.)", f->c0, 1e-9, 0);
    STAB_REPORT(name, "C1 residual (across C1 edges, at C1 vertices, split edges; max rel.), aspect <= 1e5", f->c1,
                1e-9, 0);
    STAB_REPORT(name, "C1 residual / max(1e-9, 100 eps aspect), aspect up to 1e8", f->c1s, 1, 0);
    STAB_REPORT(name, "overshoot beyond the data range / range", f->over, 0, STAB_INFO);
    STAB_REPORT(name, "aspect-ratio warning missing (1 = missing), aspect >= 1e6", f->warn, 0.5, 0);
    char line[400];
    int n = snprintf(line, sizeof line, "  [%s] worst C0 / C1 residual by aspect:", name);
    for (int k = 0; k <= 8; k++)
        if (f->by_aspect[0][k] > 0 || f->by_aspect[1][k] > 0)
            n += snprintf(line + n, sizeof line - (size_t)n, " 1e%d %.2g / %.2g,", k, f->by_aspect[0][k],
                          f->by_aspect[1][k]);
    line[n - 1] = 0;
    fprintf(stderr, "%s\n", line);
}

static void init_figs(sliver_figs *f) {
    memset(f, 0, sizeof *f);
    stab_acc_init(f->c0, STAB_NVAR);
    stab_acc_init(f->c1, STAB_NVAR);
    stab_acc_init(f->c1s, STAB_NVAR);
    stab_acc_init(f->over, STAB_NVAR);
    stab_acc_init(f->warn, STAB_NVAR);
}

typedef void (*builder)(tmesh *g, double aspect);

static void sliver_case(const char *name, builder b) {
    static sliver_figs f;
    init_figs(&f);
    for (int k = 2; k <= 8; k++) {
        double aspect = pow(10, k);
        tmesh g;
        b(&g, aspect);
        tmesh_sample(&g, 1, smooth_f, NULL, 1, 1, 0.3);
        tc_mesh_desc d;
        tmesh_desc(&g, &d);
        for (int v = 0; v < STAB_HERMITE; v++)
            for (int s = 0; s < NSRC; s++) measure(&d, v, SOURCES[s], aspect, "", &f);
        tmesh_free(&g);
    }
    report(name, &f);
}

TEST(stab_sliver_strip) { sliver_case("sliver-strip", strip); }
TEST(stab_sliver_needle_fan) { sliver_case("sliver-needle-fan", needles); }
TEST(stab_sliver_cap) { sliver_case("sliver-cap", cap); }

TEST(stab_sliver_quads) {
    static sliver_figs f;
    init_figs(&f);
    for (int k = 2; k <= 8; k++) {
        sdesc s;
        quad_strip(&s, pow(10, k));
        for (int src = 0; src < NSRC; src++) measure(&s.d, STAB_HERMITE, SOURCES[src], pow(10, k), "", &f);
        sdesc_free(&s);
    }
    report("sliver-quads", &f);
}

/* The stiff scene's disc meshes: penumbrae 3e-5 wide beside cells up to 1/N. */
TEST(stab_sliver_stiff_scene) {
    static sliver_figs f;
    init_figs(&f);
    tc_scene sc;
    CHECK(tc_scene_init(&sc, TC_SCENE_STIFF) == TC_OK);
    for (int n = 2; n <= 8; n *= 4)
        for (int grads = 0; grads < 2; grads++) {
            tc_scene_mesh_opts so;
            tc_scene_mesh_opts_default(&so);
            so.density = n, so.gradients = grads;
            tc_scene_mesh *sm = NULL;
            CHECK(tc_scene_mesh_new(&sc, &so, &sm) == TC_OK);
            if (!sm) continue;
            char tag[32];
            snprintf(tag, sizeof tag, "N=%d, ", n);
            for (int v = 0; v < STAB_HERMITE; v++)
                for (int s = grads ? 0 : 1; s < (grads ? 1 : NSRC); s++)
                    measure(&sm->desc, v, SOURCES[s], sm->worst_aspect, tag, &f);
            tc_scene_mesh_free(sm);
        }
    report("stiff-disc", &f);
}
