/* test_stab_edges.c — points exactly on edges and vertices: evaluation and rendering give no NaN,
 * no gap, one owner, and the same value from tc_eval_points and tc_render at 1, 2 and 5 threads. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "props.h"
#include "stab.h"

/* 128 x 128 pixels whose centres are the multiples of 1/64 in [0, 127/64]: x0 = -1/128,
 * x1 = x0 + 2, so x = -1/128 + 2 (i + 1/2) / 128 = i / 64 exactly (likewise y from the top).
 * The mesh's vertices are multiples of 1/8: every vertex, every edge midpoint and many other
 * edge points are pixel centres. */
#define W 128
static const tc_viewport VP = {-1.0 / 128, 1 - 2 + 1.0 / 128, -1.0 / 128 + 2, 1 + 1.0 / 128, W, W};

/* An 8 x 8 grid over [0,1]^2 (random diagonals), a C0 row, a C-1 column with a jump,
 * gradients and midpoints; as quads (hermite) with the same flags. */
static void edge_mesh(tmesh *g, sdesc *q) {
    trng r;
    trng_seed(&r, 555);
    tmesh_grid(g, 8, 8, 0, -1, &r);
    int32_t row[9], col[9];
    for (int i = 0; i <= 8; i++) row[i] = tmesh_gv(8, i, 4), col[i] = tmesh_gv(8, 3, i);
    tmesh_add_line(g, TC_C0, row, 9);
    tmesh_add_line(g, TC_CM1, col, 9);
    tmesh_sample(g, 2, smooth_f, NULL, 1, 1, 0.5);
    tc_mesh_desc d;
    tmesh_desc(g, &d);
    int32_t quads[4 * 64];
    for (int j = 0; j < 8; j++)
        for (int i = 0; i < 8; i++) {
            int32_t a = tmesh_gv(8, i, j), *p = quads + 4 * (j * 8 + i);
            p[0] = a, p[1] = a + 1, p[2] = a + 10, p[3] = a + 9;
        }
    tc_mesh_desc qd = d;
    qd.ntris = 0, qd.tris = NULL, qd.nquads = 64, qd.quads = quads, qd.ncorner_values = 0, qd.nmidpoints = 0;
    sdesc_copy(q, &qd);
    sdesc_add_midpoints(q, smooth_f, NULL);
}

/* The point lies in triangle t, closed (exact here: all coordinates are dyadic and small). */
static int contains(const tc_mesh *m, int32_t t, double x, double y) {
    const double *p = tc_mesh_xy(m);
    const int32_t *v = tc_mesh_triangles(m) + 3 * t;
    double s[3];
    for (int k = 0; k < 3; k++) {
        const double *a = p + 2 * v[k], *b = p + 2 * v[(k + 1) % 3];
        s[k] = (b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0]);
    }
    return (s[0] >= 0 && s[1] >= 0 && s[2] >= 0) || (s[0] <= 0 && s[1] <= 0 && s[2] <= 0);
}

/* Counts every disagreement: a non-finite value, a centre inside [0,1]^2 without an owner
 * or with one that does not contain it, an outside centre with an owner or a non-zero value,
 * render != (float) tc_eval_points, and any difference between thread counts. */
static long disagreements(const srun *x) {
    static double xy[2 * W * W], val[W * W * 2];
    static int32_t tri[W * W], own[3][W * W];
    static float img[3][W * W * 2];
    int nc = tc_mesh_channel_count(x->m);
    for (int j = 0; j < W; j++)
        for (int i = 0; i < W; i++) tc_viewport_pixel_center(&VP, i, j, &xy[2 * (j * W + i)], &xy[2 * (j * W + i) + 1]);
    tc_eval_points(x->r, x->L, W * W, xy, val, NULL, tri);
    long bad = 0;
    const int threads[3] = {1, 2, 5};
    for (int k = 0; k < 3; k++) {
        tc_render_options o = {.threads = threads[k]};
        if (tc_render(x->r, x->L, &VP, &o, img[k], own[k]) != TC_OK) bad++;
        if (k && (memcmp(img[k], img[0], sizeof img[0]) || memcmp(own[k], own[0], sizeof own[0]))) bad++;
    }
    for (int p = 0; p < W * W; p++) {
        double px = xy[2 * p], py = xy[2 * p + 1];
        int inside = px >= 0 && px <= 1 && py >= 0 && py <= 1;
        bad += inside != (tri[p] >= 0) || own[0][p] != tri[p];
        bad += tri[p] >= 0 && !contains(x->m, tri[p], px, py);
        for (int ch = 0; ch < nc; ch++) {
            double v = val[p * nc + ch];
            bad += !isfinite(v) || (!inside && v != 0) || img[0][p * nc + ch] != (float)v;
        }
    }
    return bad;
}

TEST(stab_points_on_edges) {
    tmesh g;
    sdesc q;
    edge_mesh(&g, &q);
    tc_mesh_desc d;
    tmesh_desc(&g, &d);
    stab_acc acc[STAB_NVAR];
    stab_acc_init(acc, STAB_NVAR);
    for (int v = 0; v < STAB_NVAR; v++) {
        tc_options o;
        stab_options(v, TC_TANGENTS_AUTO, &o);
        srun x;
        if (srun_start(&x, v == STAB_HERMITE ? &q.d : &d, &o)) stab_acc_refusal(&acc[v], &x);
        else stab_acc_fig(&acc[v], (double)disagreements(&x), "pixel centres on vertices and edges");
        srun_end(&x);
    }
    STAB_REPORT("points-on-edges", "disagreements (NaN, gap, owner, eval vs render, 1/2/5 threads)", acc, 0, 0);
    sdesc_free(&q);
    tmesh_free(&g);
}
