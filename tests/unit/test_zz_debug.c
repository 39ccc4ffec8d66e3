/* temporary: excursion images */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "scenes/scene.h"
#include "scenes/meshing.h"
#include "scenes/surfaces.h"
static void dump(const char *name, const tc_mesh *m, const float *val, const int32_t *own, int W) {
    double lo = INFINITY, hi = -INFINITY;
    for (int32_t t = 0; t < tc_mesh_triangle_count(m); t++) for (int k = 0; k < 3; k++) { double z = tc_mesh_corner_value(m, t, k)[0]; lo = fmin(lo, z), hi = fmax(hi, z); }
    FILE *f = fopen(name, "wb"); fprintf(f, "P6 %d %d 255\n", W, W);
    for (int i = 0; i < W * W; i++) {
        unsigned char rgb[3] = {0, 0, 0};
        int32_t t = own[i];
        if (t >= 0) {
            double a = INFINITY, b = -INFINITY; for (int k = 0; k < 3; k++) { double z = tc_mesh_corner_value(m, t, k)[0]; a = fmin(a, z), b = fmax(b, z); }
            double v = val[i], g = (v - lo) / (hi - lo); unsigned char gray = (unsigned char)(255 * fmin(fmax(g, 0), 1));
            rgb[0] = rgb[1] = rgb[2] = gray;
            double e = fmax(0, fmax(v - b, a - v)) / (hi - lo);
            if (e > 0.05) { rgb[0] = v > b ? 255 : 0; rgb[1] = 0; rgb[2] = v > b ? 0 : 255; }
        }
        fwrite(rgb, 1, 3, f);
    }
    fclose(f);
}
TEST(zz_box) {
    for (int i = 0; i < tc_dm_surface_count(); i++) {
        const tc_dm_surface *f = tc_dm_surface_get(i);
        if (strcmp(f->name, getenv("SURF") ? getenv("SURF") : "box")) continue;
        tc_scene s; tc_scene_mesh_opts so; tc_scene_mesh *sm = NULL;
        tc_dm_surface_setup(f, 1, &s, &so); tc_scene_mesh_new(&s, &so, &sm);
        tc_mesh *m = NULL; tc_mesh_new(&sm->desc, &m, NULL);
        for (int range = 0; range < 2; range++) {
            tc_options o; tc_options_default(&o); o.range = range ? TC_RANGE_FREE : TC_RANGE_LOCAL;
            tc_recon *r = NULL; tc_recon_new(m, &o, &r, NULL);
            tc_locator *L = NULL; tc_locator_new(m, &L);
            int W = 512; tc_viewport vp = {f->window[0], f->window[1], f->window[2], f->window[3], W, W};
            float *val = malloc(sizeof(float) * W * W); int32_t *own = malloc(sizeof(int32_t) * W * W);
            tc_render(r, L, &vp, NULL, val, own);
            dump(range ? "/tmp/dbg/exc_free.ppm" : "/tmp/dbg/exc_local.ppm", m, val, own, W);
            free(val); free(own); tc_locator_free(L); tc_recon_free(r);
        }
        tc_mesh_free(m); tc_scene_mesh_free(sm);
    }
}
