/* panels.c — a row of square picture panels with white gaps between them, written
 * as one PNG through tc_img_encode: grey or coloured pixels, a mesh's edges on top. */
#include "panels.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "image/image.h"
#include "util.h"

#define GAP 6

int bench_row_init(bench_row *r, int panel, int npanel) {
    r->panel = panel, r->npanel = npanel, r->width = npanel * panel + (npanel - 1) * GAP;
    size_t n = (size_t)r->width * (size_t)panel * 3;
    r->px = malloc(n * sizeof *r->px);
    for (size_t i = 0; r->px && i < n; i++) r->px[i] = 1.0f; /* white gaps */
    return r->px ? 0 : -1;
}

void bench_row_free(bench_row *r) {
    free(r->px);
    r->px = NULL;
}

void bench_row_put(bench_row *r, int k, int i, int j, const float rgb[3]) {
    if (i < 0 || j < 0 || i >= r->panel || j >= r->panel) return;
    float *p = r->px + 3 * ((size_t)j * (size_t)r->width + (size_t)k * (size_t)(r->panel + GAP) + (size_t)i);
    p[0] = rgb[0], p[1] = rgb[1], p[2] = rgb[2];
}

void bench_row_grey(bench_row *r, int k, const float *v) {
    for (int j = 0; j < r->panel; j++)
        for (int i = 0; i < r->panel; i++) {
            float g = v[(size_t)j * (size_t)r->panel + (size_t)i];
            const float rgb[3] = {g, g, g};
            bench_row_put(r, k, i, j, rgb);
        }
}

/* A line's pixel: nearest pixel centre, kept inside the panel so the mesh's
 * boundary (on the outermost pixel edges) shows. */
static int pix(double v, int p) {
    long k = lround(v);
    return k < 0 ? 0 : k >= p ? p - 1 : (int)k;
}

static void edge_colour(const tc_mesh *m, int32_t t, int e, float gain, float c[3]) {
    int nk;
    tc_continuity f = tc_mesh_edge_flag(m, t, e);
    c[0] = c[1] = c[2] = 0.4f;
    if (tc_mesh_neighbor(m, t, e, &nk) < 0) c[0] = c[1] = c[2] = 1.0f;
    else if (f == TC_CM1) c[0] = 1.0f, c[1] = 0.05f, c[2] = 0.05f;
    else if (f == TC_C0) c[0] = 1.0f, c[1] = 0.85f, c[2] = 0.0f;
    for (int i = 0; i < 3; i++) c[i] *= gain;
}

static void draw_edge(bench_row *r, int k, const double *a, const double *b, const tc_viewport *vp, const float c[3]) {
    int p = r->panel;
    double ax = (a[0] - vp->x0) / (vp->x1 - vp->x0) * p - 0.5, ay = (vp->y1 - a[1]) / (vp->y1 - vp->y0) * p - 0.5;
    double bx = (b[0] - vp->x0) / (vp->x1 - vp->x0) * p - 0.5, by = (vp->y1 - b[1]) / (vp->y1 - vp->y0) * p - 0.5;
    int steps = (int)ceil(fmax(fabs(bx - ax), fabs(by - ay))) + 1;
    for (int s = 0; s <= steps; s++) {
        double u = (double)s / steps;
        bench_row_put(r, k, pix(ax + u * (bx - ax), p), pix(ay + u * (by - ay), p), c);
    }
}

void bench_row_mesh(bench_row *r, int k, const tc_mesh *m, const tc_viewport *vp, float gain) {
    const double *xy = tc_mesh_xy(m);
    const int32_t *tri = tc_mesh_triangles(m);
    for (int pass = 0; pass < 2; pass++) /* C1 first, flags and boundary on top */
        for (int32_t t = 0; t < tc_mesh_triangle_count(m); t++)
            for (int e = 0; e < 3; e++) {
                int nk;
                int32_t nb = tc_mesh_neighbor(m, t, e, &nk);
                if (nb >= 0 && nb < t) continue; /* drawn from the other side */
                if ((pass == 0) != (nb >= 0 && tc_mesh_edge_flag(m, t, e) == TC_C1)) continue;
                float c[3];
                edge_colour(m, t, e, gain, c);
                draw_edge(r, k, xy + 2 * (size_t)tri[3 * t + e], xy + 2 * (size_t)tri[3 * t + (e + 1) % 3], vp, c);
            }
}

int bench_row_write_png(const bench_row *r, int linear, const char *path) {
    tc_img im = {r->width, r->panel, 3, r->px, NULL, 0.0, linear};
    unsigned char *png = NULL;
    size_t len = 0;
    char err[256];
    if (tc_img_encode(&im, TC_IMG_PNG, &png, &len, err, sizeof err) != 0) {
        fprintf(stderr, "report: %s: %s\n", path, err);
        return -1;
    }
    int st = bench_write_file(path, png, len);
    tc_img_free(png);
    return st;
}
