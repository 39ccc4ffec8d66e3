/* images.c — the side-by-side pictures (Salesin et al. Fig. 7/8): reference |
 * linear | clough-tocher-c1 | clough-tocher, and their error maps, as PNG rows. */
#include "images.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image/image.h"
#include "measure.h"
#include "util.h"

#define P BENCH_FIG_PANEL
#define GAP 6
#define NPANEL 4
#define ROW_W (NPANEL * P + (NPANEL - 1) * GAP)

static float clamp01(double v) { return v < 0 ? 0.0f : v > 1 ? 1.0f : (float)v; }

/* A line's pixel: nearest pixel centre, kept inside the panel so the mesh's
 * boundary (on the outermost pixel edges) shows. */
static int pix(double v) {
    long k = lround(v);
    return k < 0 ? 0 : k >= P ? P - 1 : (int)k;
}

/* Sets pixel (i, j) of panel k of a 3-channel row. */
static void put(float *row, int k, int i, int j, float r, float g, float b) {
    if (i < 0 || j < 0 || i >= P || j >= P) return;
    float *px = row + 3 * ((size_t)j * ROW_W + (size_t)k * (P + GAP) + i);
    px[0] = r, px[1] = g, px[2] = b;
}

static void grey_panel(float *row, int k, const float *v) {
    for (int j = 0; j < P; j++)
        for (int i = 0; i < P; i++) {
            float g = v[(size_t)j * P + i];
            put(row, k, i, j, g, g, g);
        }
}

/* The mesh's edges in panel k: C1 grey, C0 yellow, C-1 red, boundary white. */
static void mesh_panel(float *row, int k, const tc_mesh *m, const tc_viewport *vp) {
    const double *xy = tc_mesh_xy(m);
    const int32_t *tri = tc_mesh_triangles(m);
    for (int pass = 0; pass < 2; pass++)
        for (int32_t t = 0; t < tc_mesh_triangle_count(m); t++)
            for (int e = 0; e < 3; e++) {
                int nk;
                int32_t nb = tc_mesh_neighbor(m, t, e, &nk);
                if (nb >= 0 && nb < t) continue; /* drawn from the other side */
                tc_continuity f = tc_mesh_edge_flag(m, t, e);
                if ((pass == 0) != (nb >= 0 && f == TC_C1)) continue; /* C1 first, flags on top */
                float c[3] = {0.4f, 0.4f, 0.4f};
                if (nb < 0) c[0] = c[1] = c[2] = 1.0f;
                else if (f == TC_CM1) c[0] = 1.0f, c[1] = 0.05f, c[2] = 0.05f;
                else if (f == TC_C0) c[0] = 1.0f, c[1] = 0.85f, c[2] = 0.0f;
                const double *a = xy + 2 * (size_t)tri[3 * t + e], *b = xy + 2 * (size_t)tri[3 * t + (e + 1) % 3];
                double ax = (a[0] - vp->x0) / (vp->x1 - vp->x0) * P - 0.5, ay = (vp->y1 - a[1]) / (vp->y1 - vp->y0) * P - 0.5;
                double bx = (b[0] - vp->x0) / (vp->x1 - vp->x0) * P - 0.5, by = (vp->y1 - b[1]) / (vp->y1 - vp->y0) * P - 0.5;
                int steps = (int)ceil(fmax(fabs(bx - ax), fabs(by - ay))) + 1;
                for (int s = 0; s <= steps; s++) {
                    double u = (double)s / steps;
                    put(row, k, pix(ax + u * (bx - ax)), pix(ay + u * (by - ay)), c[0], c[1], c[2]);
                }
            }
}

/* linear: 1 = values written as they are, 0 = through the sRGB transfer. */
static int write_png(const float *row, int linear, const char *path) {
    tc_img im = {ROW_W, P, 3, row, NULL, 0.0, linear};
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

int bench_images_write(const tc_scene *s, const tc_scene_mesh *sm, const char *dir) {
    const char *methods[NPANEL - 1] = {M_LINEAR, M_CT_C1, M_CT};
    tc_viewport vp = {s->domain[0], s->domain[1], s->domain[2], s->domain[3], P, P};
    size_t np = (size_t)P * P, nrow = (size_t)ROW_W * P * 3;
    double *ref = malloc(np * sizeof *ref);
    float *tile = malloc(np * sizeof *tile), *panel = malloc(np * sizeof *panel);
    float *img = malloc(nrow * sizeof *img), *err = malloc(nrow * sizeof *err);
    int st = ref && tile && panel && img && err ? 0 : -1;
    if (st == 0) {
        for (size_t i = 0; i < nrow; i++) img[i] = err[i] = 1.0f; /* white gaps */
        for (int32_t j = 0; j < P; j++)
            for (int32_t i = 0; i < P; i++) {
                double x, y;
                tc_viewport_pixel_center(&vp, i, j, &x, &y);
                ref[(size_t)j * P + i] = tc_scene_value(s, x, y);
                panel[(size_t)j * P + i] = clamp01(ref[(size_t)j * P + i] / s->scale);
            }
        grey_panel(img, 0, panel);
        for (size_t i = 0; i < np; i++) panel[i] = 0;
        grey_panel(err, 0, panel);
    }
    for (int k = 0; st == 0 && k < NPANEL - 1; k++) {
        bench_prepared p;
        char note[320];
        if (bench_prepare(sm, &bench_methods[bench_method_find(methods[k])], &p, NULL, note, sizeof note) != 0) {
            fprintf(stderr, "report: %s images: %s: %s (panel left grey)\n", tc_scene_name(s->id), methods[k], note);
            for (size_t i = 0; i < np; i++) panel[i] = 0.5f;
            grey_panel(img, k + 1, panel);
            grey_panel(err, k + 1, panel);
            continue;
        }
        tc_render_options ro = {NULL, 2, 0};
        tc_render(p.recon, p.loc, &vp, &ro, tile, NULL);
        for (size_t i = 0; i < np; i++) panel[i] = clamp01(tile[i] / s->scale);
        grey_panel(img, k + 1, panel);
        for (size_t i = 0; i < np; i++) panel[i] = clamp01(BENCH_ERR_GAIN * fabs(ref[i] - tile[i]) / s->scale);
        grey_panel(err, k + 1, panel);
        if (k == NPANEL - 2) mesh_panel(err, 0, p.mesh, &vp);
        bench_prepared_free(&p);
    }
    char path[1024];
    if (st == 0) {
        snprintf(path, sizeof path, "%s/%s-images.png", dir, tc_scene_name(s->id));
        st |= write_png(img, 0, path);
        snprintf(path, sizeof path, "%s/%s-errors.png", dir, tc_scene_name(s->id));
        st |= write_png(err, 1, path);
    }
    free(ref), free(tile), free(panel), free(img), free(err);
    return st ? -1 : 0;
}
