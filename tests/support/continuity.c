/* continuity.c — what several test files check of a reconstruction: interpolation and
 * every continuity the flags promise (residuals against local scales), on the shared
 * randomized flagged meshes and smooth test function. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "core/ct.h"
#include "core/geom.h"
#include "meshgen.h"
#include "props.h"

void smooth_f(const void *ctx, double x, double y, int ch, double *v, double g[2]) {
    (void)ctx;
    double a = 1.0 + 0.3 * ch;
    *v = sin(2 * a * x + 1) * cos(3 * y - 0.5 * a) + 0.5 * x * y;
    g[0] = 2 * a * cos(2 * a * x + 1) * cos(3 * y - 0.5 * a) + 0.5 * y;
    g[1] = -3 * sin(2 * a * x + 1) * sin(3 * y - 0.5 * a) + 0.5 * x;
}

/* Scales the residuals are relative to: the largest |value| and the largest
 * slope (corner planes, or value range over the mesh size). */
void recon_scales(const tc_recon *r, double *vs, double *gs) {
    const tc_mesh *m = tc_recon_mesh(r);
    int nc = tc_mesh_channel_count(m);
    int32_t nt = tc_mesh_triangle_count(m);
    const double *cg = tc_recon_corner_gradients(r);
    *vs = 1e-300, *gs = 1e-300;
    for (int32_t t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++)
            for (int ch = 0; ch < nc; ch++) {
                *vs = fmax(*vs, fabs(tc_mesh_corner_value(m, t, k)[ch]));
                size_t i = (3 * (size_t)t + (size_t)k) * (size_t)nc + (size_t)ch;
                if (cg) *gs = fmax(*gs, hypot(cg[i * 2], cg[i * 2 + 1]));
            }
    *gs = fmax(*gs, *vs);
}

static const double S[] = {0.0, 0.137, 0.5, 0.771, 1.0};

void edge_residual(const tc_recon *r, int32_t t, int k, double vs, double gs, double *rv, double *rg) {
    const tc_mesh *m = tc_recon_mesh(r);
    int nc = tc_mesh_channel_count(m);
    const int32_t *tri = tc_mesh_triangles(m);
    const double *xy = tc_mesh_xy(m);
    int32_t t2 = tc_mesh_neighbor(m, t, k, NULL);
    const double *a = xy + 2 * tri[3 * t + k], *b = xy + 2 * tri[3 * t + (k + 1) % 3];
    *rv = *rg = 0;
    for (size_t i = 0; i < sizeof S / sizeof S[0]; i++) {
        double x = a[0] + S[i] * (b[0] - a[0]), y = a[1] + S[i] * (b[1] - a[1]);
        double v1[TC_MAX_CHANNELS], v2[TC_MAX_CHANNELS], g1[2 * TC_MAX_CHANNELS], g2[2 * TC_MAX_CHANNELS];
        tc_eval_triangle(r, t, x, y, v1, g1);
        tc_eval_triangle(r, t2, x, y, v2, g2);
        for (int ch = 0; ch < nc; ch++) {
            *rv = fmax(*rv, fabs(v1[ch] - v2[ch]) / vs);
            *rg = fmax(*rg, hypot(g1[2 * ch] - g2[2 * ch], g1[2 * ch + 1] - g2[2 * ch + 1]) / gs);
        }
    }
}

/* Across the three internal edges (corner -> centroid) of every triangle. */
static double internal_residual(const tc_recon *r, double vs, double gs) {
    const tc_mesh *m = tc_recon_mesh(r);
    int nc = tc_mesh_channel_count(m);
    const double *coef = tc_recon_coefs(r);
    const double *xy = tc_mesh_xy(m);
    const int32_t *tri = tc_mesh_triangles(m);
    double worst = 0;
    for (int32_t t = 0; t < tc_mesh_triangle_count(m); t++) {
        double lam[3], dl1[2], dl2[2], p[2] = {xy[2 * tri[3 * t]], xy[2 * tri[3 * t] + 1]};
        tc__bary(m, t, p[0], p[1], lam, dl1, dl2); /* only dl1, dl2 are used */
        for (int i = 0; i < 3; i++)
            for (size_t j = 0; j < sizeof S / sizeof S[0]; j++) {
                double L[3];
                for (int q = 0; q < 3; q++) L[q] = (1 - S[j]) * (q == i) + S[j] / 3;
                for (int ch = 0; ch < nc; ch++) {
                    const double *o = coef + ((size_t)t * (size_t)nc + (size_t)ch) * TC_CT_ORDINATES;
                    double va, vb, ga[2], gb[2];
                    tc__ct_eval_sub(o, (i + 1) % 3, L, dl1, dl2, &va, ga);
                    tc__ct_eval_sub(o, (i + 2) % 3, L, dl1, dl2, &vb, gb);
                    worst = fmax(worst, fabs(va - vb) / vs);
                    worst = fmax(worst, hypot(ga[0] - gb[0], ga[1] - gb[1]) / gs);
                }
            }
    }
    return worst;
}

/* Vertex class as the paper defines it, from the generator's own flags. */
static int c1_vertex(const tmesh *g, int32_t v) {
    int ncm1 = 0, nc0 = 0;
    double d[2][2];
    for (int32_t c = 0; c < 3 * g->nt; c++) {
        int32_t t = c / 3, k = c % 3, a = g->tri[c], b = g->tri[3 * t + (k + 1) % 3];
        if ((a != v && b != v) || (g->enbr[c] >= 0 && g->enbr[c] < t)) continue;
        int32_t o = a == v ? b : a;
        if (g->eflag[c] == TC_CM1) ncm1++;
        if (g->eflag[c] == TC_C0 && nc0 < 2) {
            d[nc0][0] = g->xy[2 * o] - g->xy[2 * v];
            d[nc0][1] = g->xy[2 * o + 1] - g->xy[2 * v + 1];
        }
        nc0 += g->eflag[c] == TC_C0;
    }
    return !ncm1 && (nc0 <= 1 || (nc0 == 2 && !tc__antiparallel(d[0], d[1])));
}

/* Gradients of every incident piece at a C1 vertex agree. */
static double vertex_residual(const tc_recon *r, const tmesh *g, double gs) {
    int nc = g->nc;
    double worst = 0;
    for (int32_t v = 0; v < g->nv; v++) {
        if (!c1_vertex(g, v)) continue;
        double g0[2 * TC_MAX_CHANNELS], gi[2 * TC_MAX_CHANNELS], val[TC_MAX_CHANNELS];
        int first = 1;
        for (int32_t c = 0; c < 3 * g->nt; c++) {
            if (g->tri[c] != v) continue;
            tc_eval_triangle(r, c / 3, g->xy[2 * v], g->xy[2 * v + 1], val, first ? g0 : gi);
            if (!first)
                for (int ch = 0; ch < nc; ch++)
                    worst = fmax(worst, hypot(gi[2 * ch] - g0[2 * ch], gi[2 * ch + 1] - g0[2 * ch + 1]) / gs);
            first = 0;
        }
    }
    return worst;
}

/* All corners of vertex v carry the same values (no jump at v). */
static int single_valued(const tc_mesh *m, int32_t v) {
    const int32_t *tri = tc_mesh_triangles(m);
    int nc = tc_mesh_channel_count(m);
    const double *first = NULL;
    for (int32_t c = 0; c < 3 * tc_mesh_triangle_count(m); c++) {
        if (tri[c] != v) continue;
        const double *z = tc_mesh_corner_value(m, c / 3, c % 3);
        if (first && memcmp(first, z, (size_t)nc * sizeof *z)) return 0;
        first = z;
    }
    return 1;
}

/* Interpolation at every corner. With flags ignored (clough-tocher-c1) the
 * corner values of a vertex with a jump are merged, so only vertices without
 * one are checked there. */
static double corner_residual(const tc_recon *r, double vs) {
    const tc_mesh *m = tc_recon_mesh(r);
    const double *xy = tc_mesh_xy(m);
    const int32_t *tri = tc_mesh_triangles(m);
    int nc = tc_mesh_channel_count(m), honor = tc_recon_options(r)->method == TC_METHOD_CLOUGH_TOCHER;
    double worst = 0, val[TC_MAX_CHANNELS];
    for (int32_t t = 0; t < tc_mesh_triangle_count(m); t++)
        for (int k = 0; k < 3; k++) {
            if (!honor && !single_valued(m, tri[3 * t + k])) continue;
            const double *p = xy + 2 * tri[3 * t + k];
            tc_eval_triangle(r, t, p[0], p[1], val, NULL);
            for (int ch = 0; ch < nc; ch++)
                worst = fmax(worst, fabs(val[ch] - tc_mesh_corner_value(m, t, k)[ch]) / vs);
        }
    return worst;
}

void check_continuity(const tc_recon *r, const tmesh *g, double tol, cont_report *rep) {
    const tc_mesh *m = tc_recon_mesh(r);
    double vs, gs, rv, rg;
    int honor = tc_recon_options(r)->method == TC_METHOD_CLOUGH_TOCHER;
    recon_scales(r, &vs, &gs);
    memset(rep, 0, sizeof *rep);
    rep->corner = corner_residual(r, vs);
    for (int32_t t = 0; t < tc_mesh_triangle_count(m); t++)
        for (int k = 0; k < 3; k++) {
            int32_t t2 = tc_mesh_neighbor(m, t, k, NULL);
            int flag = honor ? tc_mesh_edge_flag(m, t, k) : TC_C1;
            if (t2 < t || flag == TC_CM1) continue;
            edge_residual(r, t, k, vs, gs, &rv, &rg);
            rep->c0 = fmax(rep->c0, rv);
            if (flag == TC_C1) rep->c1 = fmax(rep->c1, rg);
        }
    rep->vertex = honor ? vertex_residual(r, g, gs) : 0;
    rep->internal = internal_residual(r, vs, gs);
    CHECK_MSG(rep->corner <= tol, "interpolation residual %.3g", rep->corner);
    CHECK_MSG(rep->c0 <= tol, "C0 residual across C0/C1 edges %.3g", rep->c0);
    CHECK_MSG(rep->c1 <= tol, "C1 residual across C1 edges %.3g", rep->c1);
    CHECK_MSG(rep->vertex <= tol, "C1 residual at C1 vertices %.3g", rep->vertex);
    CHECK_MSG(rep->internal <= tol, "C1 residual across internal edges %.3g", rep->internal);
}

/* A randomized test mesh with every kind of delimiter configuration: a
 * straight C0 row (180-degree wedges), a C0 column crossing it (4 C0 edges at
 * a vertex), a C-1 crack along a row ending inside and continuing as C0 (the
 * collinear C0 + C-1 vertex), random C0 and C-1 walks, and the boundary. */
void random_flagged_mesh(tmesh *g, trng *r, int delaunay, int n) {
    tmesh_grid(g, n, n, delaunay ? 0.35 : 0.25, -1, r);
    if (delaunay) tmesh_delaunay_flips(g);
    int32_t row[64], col[64];
    for (int i = 0; i <= n; i++) row[i] = tmesh_gv(n, i, 4), col[i] = tmesh_gv(n, 4, i);
    tmesh_add_line(g, TC_C0, row, n + 1);
    tmesh_add_line(g, TC_C0, col, n + 1);
    for (int i = 0; i <= n; i++) row[i] = tmesh_gv(n, i, n - 4);
    tmesh_add_line(g, TC_CM1, row, n / 2 + 1);
    tmesh_add_line(g, TC_C0, row + n / 2, n / 2 + 1);
    for (int i = 0; i < 3; i++) tmesh_random_line(g, TC_C0, 2 + trng_int(r, 6), r);
    for (int i = 0; i < 2; i++) tmesh_random_line(g, TC_CM1, 2 + trng_int(r, 5), r);
}
