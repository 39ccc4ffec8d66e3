/* images.c — the side-by-side pictures (Salesin et al. Fig. 7/8): reference |
 * linear | clough-tocher-c1 | clough-tocher, and their error maps, as PNG rows. */
#include "images.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "measure.h"
#include "panels.h"

#define P BENCH_FIG_PANEL
#define NPANEL 4

static float clamp01(double v) { return v < 0 ? 0.0f : v > 1 ? 1.0f : (float)v; }

/* Panel 0 of both rows: the reference, and black (the mesh goes on it later). */
static void reference_panels(const tc_scene *s, const tc_viewport *vp, double *ref, float *panel, bench_row *img,
                             bench_row *err) {
    for (int32_t j = 0; j < P; j++)
        for (int32_t i = 0; i < P; i++) {
            double x, y;
            tc_viewport_pixel_center(vp, i, j, &x, &y);
            ref[(size_t)j * P + (size_t)i] = tc_scene_value(s, x, y);
            panel[(size_t)j * P + (size_t)i] = clamp01(ref[(size_t)j * P + (size_t)i] / s->scale);
        }
    bench_row_grey(img, 0, panel);
    for (size_t i = 0; i < (size_t)P * P; i++) panel[i] = 0;
    bench_row_grey(err, 0, panel);
}

/* Panel k of both rows: method's picture and its error map (grey when it cannot run). */
static void method_panels(const tc_scene *s, const tc_scene_mesh *sm, const char *method, int k, const double *ref,
                          float *tile, float *panel, bench_row *img, bench_row *err) {
    size_t np = (size_t)P * P;
    const tc_viewport vp = {s->domain[0], s->domain[1], s->domain[2], s->domain[3], P, P};
    bench_prepared p;
    char note[320];
    if (bench_prepare(sm, &bench_methods[bench_method_find(method)], &p, NULL, note, sizeof note) != 0) {
        fprintf(stderr, "report: %s images: %s: %s (panel left grey)\n", tc_scene_name(s->id), method, note);
        for (size_t i = 0; i < np; i++) panel[i] = 0.5f;
        bench_row_grey(img, k, panel);
        bench_row_grey(err, k, panel);
        return;
    }
    tc_render_options ro = {.threads = 2};
    tc_render(p.recon, p.loc, &vp, &ro, tile, NULL);
    for (size_t i = 0; i < np; i++) panel[i] = clamp01(tile[i] / s->scale);
    bench_row_grey(img, k, panel);
    for (size_t i = 0; i < np; i++) panel[i] = clamp01(BENCH_ERR_GAIN * fabs(ref[i] - tile[i]) / s->scale);
    bench_row_grey(err, k, panel);
    if (k == NPANEL - 1) bench_row_mesh(err, 0, p.mesh, &vp, 1.0f);
    bench_prepared_free(&p);
}

int bench_images_write(const tc_scene *s, const tc_scene_mesh *sm, const char *dir) {
    const char *methods[NPANEL - 1] = {M_LINEAR, M_CT_C1, M_CT};
    tc_viewport vp = {s->domain[0], s->domain[1], s->domain[2], s->domain[3], P, P};
    size_t np = (size_t)P * P;
    double *ref = malloc(np * sizeof *ref);
    float *tile = malloc(np * sizeof *tile), *panel = malloc(np * sizeof *panel);
    bench_row img = {0}, err = {0};
    int st = ref && tile && panel && bench_row_init(&img, P, NPANEL) == 0 && bench_row_init(&err, P, NPANEL) == 0
                 ? 0
                 : -1;
    if (st == 0) reference_panels(s, &vp, ref, panel, &img, &err);
    for (int k = 0; st == 0 && k < NPANEL - 1; k++)
        method_panels(s, sm, methods[k], k + 1, ref, tile, panel, &img, &err);
    char path[1024];
    if (st == 0) {
        snprintf(path, sizeof path, "%s/%s-images.png", dir, tc_scene_name(s->id));
        st |= bench_row_write_png(&img, 0, path);
        snprintf(path, sizeof path, "%s/%s-errors.png", dir, tc_scene_name(s->id));
        st |= bench_row_write_png(&err, 1, path);
    }
    free(ref), free(tile), free(panel);
    bench_row_free(&img), bench_row_free(&err);
    return st ? -1 : 0;
}
