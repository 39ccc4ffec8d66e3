/* tile_error.c — what a rendered tile owes /v1/evaluate: renders a bench mesh's square tile on
 * the unit square with 1 and 3 threads and compares every pixel with tc_eval_points at its centre.
 *
 *     build/bench_tile_error MESH.json [SIZE [RAW_OUT]]      (default 1024)
 *
 * Prints one JSON object: owners differing from the locator's, whether 1 and 3 threads gave the
 * same bytes, and the worst |pixel - value| and |pixel - (float)value| over the largest
 * |ordinate| (the contract: within 1e-12 of the data scale, then rounded to float). RAW_OUT, if
 * given, receives the floats then the owners, to compare two builds byte for byte (cmp). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/mesh.h"
#include "core/recon.h"
#include "io/request.h"
#include "tocher.h"
#include "benchmesh.h"

int main(int argc, char **argv) {
    if (argc < 2) {
        fprintf(stderr, "usage: %s MESH.json [SIZE [RAW_OUT]]\n", argv[0]);
        return 2;
    }
    int32_t size = argc > 2 ? atoi(argv[2]) : 1024;
    bench_mesh bm;
    if (bench_mesh_load(argv[1], &bm)) return 1;
    const tc_mesh *m = bm.m;
    const tc_recon *r = bm.r;
    const tc_locator *L = bm.L;
    tc_viewport vp = {0, 0, 1, 1, size, size};
    size_t np = (size_t)size * (size_t)size, nc = (size_t)tc_mesh_channel_count(m);
    float *a = malloc(np * nc * sizeof *a), *b = malloc(np * nc * sizeof *b);
    int32_t *own = malloc(np * sizeof *own), *own3 = malloc(np * sizeof *own3), *t = malloc(np * sizeof *t);
    double *xy = malloc(2 * np * sizeof *xy), *val = malloc(np * nc * sizeof *val);
    if (!a || !b || !own || !own3 || !t || !xy || !val) return 1;
    tc_render_options o1 = {.threads = 1}, o3 = {.threads = 3};
    if (tc_render(r, L, &vp, &o1, a, own) != TC_OK || tc_render(r, L, &vp, &o3, b, own3) != TC_OK) return 1;
    int same = !memcmp(a, b, np * nc * sizeof *a) && !memcmp(own, own3, np * sizeof *own);
    size_t ncoef = (size_t)tc_mesh_triangle_count(m) * nc * (size_t)tc_recon_coef_count(r);
    double scale = 0, worst = 0, worst_float = 0;
    for (size_t k = 0; k < ncoef; k++) scale = fmax(scale, fabs(tc_recon_coefs(r)[k]));
    for (int32_t j = 0; j < size; j++)
        for (int32_t i = 0; i < size; i++) {
            size_t p = (size_t)j * (size_t)size + (size_t)i;
            tc_viewport_pixel_center(&vp, i, j, &xy[2 * p], &xy[2 * p + 1]);
        }
    tc_eval_points(r, L, np, xy, val, NULL, t);
    long bad_owner = 0;
    for (size_t p = 0; p < np; p++) {
        bad_owner += t[p] != own[p];
        for (size_t ch = 0; t[p] >= 0 && ch < nc; ch++) {
            double got = a[p * nc + ch], want = val[p * nc + ch];
            worst = fmax(worst, fabs(got - want) / scale);
            worst_float = fmax(worst_float, fabs(got - (double)(float)want) / scale);
        }
    }
    printf("{\"mesh\": \"%s\", \"size\": %d, \"owners_differing\": %ld, \"threads_1_3_identical\": %s, "
           "\"worst_vs_value\": %.3g, \"worst_vs_float_value\": %.3g}\n",
           argv[1], (int)size, bad_owner, same ? "true" : "false", worst, worst_float);
    if (argc > 3) {
        FILE *f = fopen(argv[3], "wb");
        if (!f || fwrite(a, sizeof *a, np * nc, f) != np * nc || fwrite(own, sizeof *own, np, f) != np) return 1;
        fclose(f);
    }
    free(a), free(b), free(own), free(own3), free(t), free(xy), free(val);
    bench_mesh_free(&bm);
    return bad_owner || !same;
}
