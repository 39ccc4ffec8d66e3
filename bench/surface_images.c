/* surface_images.c — the pictures of a realistic surface: exact | the pictured methods
 * as sRGB(B / scale), and under them each one's excursion beyond its triangles' corners. */
#include "surface_images.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "panels.h"
#include "plan.h"

#define P BENCH_SURF_PANEL
#define NPANEL (1 + BENCH_SURF_NPICTURED)

void bench_surface_image_name(const char *surface, int no_c0, const char *what, char *buf, size_t n) {
    snprintf(buf, n, "surface-%s%s-%s.png", surface, no_c0 ? "-noc0" : "", what);
}

static float clamp01(double v) { return v < 0 ? 0.0f : v > 1 ? 1.0f : (float)v; }

/* Signed excursion of v in triangle t, in units of unit: > 0 above its corner
 * values, < 0 below (as tc_overshoot measures it: the corners rounded to float). */
static double excursion(const tc_mesh *m, int32_t t, float v, double unit) {
    float lo = INFINITY, hi = -INFINITY;
    for (int k = 0; k < 3; k++) {
        float z = (float)tc_mesh_corner_value(m, t, k)[0];
        lo = fminf(lo, z), hi = fmaxf(hi, z);
    }
    return v > hi ? ((double)v - hi) / unit : v < lo ? ((double)v - lo) / unit : 0;
}

/* Panel k of both rows from tile (values and owners). */
static void panels(const bench_surface *b, const float *tile, const int32_t *owner, double unit, int k,
                   const tc_viewport *vp, bench_row *img, bench_row *exc) {
    const double thr = BENCH_OVER_THRESHOLD;
    for (int j = 0; j < P; j++)
        for (int i = 0; i < P; i++) {
            float v = tile[(size_t)j * P + (size_t)i], g = clamp01(v / b->s.scale);
            const float grey[3] = {g, g, g}, black[3] = {0, 0, 0};
            bench_row_put(img, k, i, j, grey);
            bench_row_put(exc, k, i, j, black);
        }
    bench_row_mesh(exc, k, b->m, vp, 0.45f);
    for (int j = 0; j < P; j++)
        for (int i = 0; i < P; i++) {
            size_t p = (size_t)j * P + (size_t)i;
            double e = owner[p] >= 0 ? excursion(b->m, owner[p], tile[p], unit) : 0;
            if (!(fabs(e) > thr)) continue;
            float a = clamp01(log(fabs(e) / thr) / log(1 / thr));
            const float above[3] = {1, a, 0}, below[3] = {0, a, 1};
            bench_row_put(exc, k, i, j, e > 0 ? above : below);
        }
}

/* The exact B at the panel's pixel centres and their owners; unit = R of the mesh's data. */
static int exact_tile(const bench_surface *b, const tc_viewport *vp, float *tile, int32_t *owner, double *unit) {
    for (int32_t j = 0; j < P; j++)
        for (int32_t i = 0; i < P; i++) {
            double x, y;
            tc_viewport_pixel_center(vp, i, j, &x, &y);
            tile[(size_t)j * P + (size_t)i] = (float)bench_surface_exact(b, x, y);
            owner[(size_t)j * P + (size_t)i] = tc_locate(b->L, x, y);
        }
    tc_overshoot_stats o;
    int st = tc_overshoot(b->m, tile, owner, P, P, BENCH_OVER_THRESHOLD, &o);
    *unit = o.unit;
    return st == TC_OK ? 0 : -1;
}

static int method_tile(const bench_surface *b, const char *name, const tc_viewport *vp, float *tile, int32_t *owner) {
    int k = bench_surface_method_find(name);
    tc_recon *r = NULL;
    tc_render_options ro = {.threads = 2};
    int st = k < 0 ? TC_EINVAL : tc_recon_new(b->m, &bench_surface_methods[k].opt, &r, NULL);
    if (st == TC_OK) st = tc_render(r, b->L, vp, &ro, tile, owner);
    tc_recon_free(r);
    if (st != TC_OK) fprintf(stderr, "report: surface %s: %s failed with status %d\n", b->f->name, name, st);
    return st == TC_OK ? 0 : -1;
}

static int write_rows(const bench_surface *b, const bench_row *img, const bench_row *exc, const char *dir) {
    char name[256], path[1400];
    bench_surface_image_name(b->f->name, b->no_c0, "images", name, sizeof name);
    snprintf(path, sizeof path, "%s/%s", dir, name);
    int st = bench_row_write_png(img, 0, path);
    bench_surface_image_name(b->f->name, b->no_c0, "excursion", name, sizeof name);
    snprintf(path, sizeof path, "%s/%s", dir, name);
    return st | bench_row_write_png(exc, 1, path);
}

int bench_surface_images_write(const bench_surface *b, const char *dir) {
    const char *methods[BENCH_SURF_NPICTURED] = BENCH_SURF_PICTURED;
    const double *w = b->f->window;
    const tc_viewport vp = {w[0], w[1], w[2], w[3], P, P};
    float *tile = malloc((size_t)P * P * sizeof *tile);
    int32_t *owner = malloc((size_t)P * P * sizeof *owner);
    bench_row img = {0}, exc = {0};
    double unit = 1;
    int st = tile && owner && bench_row_init(&img, P, NPANEL) == 0 && bench_row_init(&exc, P, NPANEL) == 0 ? 0 : -1;
    if (st == 0) st = exact_tile(b, &vp, tile, owner, &unit);
    if (st == 0) panels(b, tile, owner, unit, 0, &vp, &img, &exc);
    for (int k = 0; st == 0 && k < BENCH_SURF_NPICTURED; k++) {
        st = method_tile(b, methods[k], &vp, tile, owner);
        if (st == 0) panels(b, tile, owner, unit, k + 1, &vp, &img, &exc);
    }
    if (st == 0) st = write_rows(b, &img, &exc, dir);
    free(tile), free(owner);
    bench_row_free(&img), bench_row_free(&exc);
    return st;
}
