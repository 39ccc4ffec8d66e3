/* test_raster.c — tile rendering: every pixel centre owned by the triangle
 * tc_locate names, valued as tc_eval_points within the fast cubic's 1e-12 of the
 * data scale (exactly for the other methods and slivers), the same for any thread count. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "core/ct.h"
#include "core/ct_fast.h"
#include "core/eval.h"
#include "core/locate.h"
#include "core/recon.h"
#include "meshgen.h"
#include "props.h"

typedef struct {
    tmesh g;
    tc_mesh *m;
    tc_recon *r;
    tc_locator *L;
} scene;

/* The mesh, reconstruction and locator of s->g (sampled): 1, or 0 when any of them
 * failed (the failure checked; the caller frees s either way). */
static int scene_build(scene *s) {
    s->m = tmesh_build(&s->g);
    s->r = NULL, s->L = NULL;
    if (s->m) CHECK(tc_recon_new(s->m, NULL, &s->r, NULL) == TC_OK);
    if (s->m) CHECK(tc_locator_new(s->m, &s->L) == TC_OK);
    return s->r && s->L;
}

static void scene_init(scene *s, int n, double jitter, int nc, unsigned long seed) {
    trng rng;
    trng_seed(&rng, seed);
    random_flagged_mesh(&s->g, &rng, 0, n);
    (void)jitter;
    tmesh_sample(&s->g, nc, smooth_f, NULL, 0, 1, 0.3);
    (void)scene_build(s);
}

static void scene_free(scene *s) {
    tc_locator_free(s->L);
    tc_recon_free(s->r);
    tc_mesh_free(s->m);
    tmesh_free(&s->g);
}

/* s->g sampled from smooth_f (one channel, gradients given) and built: 1, or 0 when the build
 * failed (checked by scene_build) with s freed. */
static int scene_ready(scene *s) {
    tmesh_sample(&s->g, 1, smooth_f, NULL, 1, 0, 0);
    if (scene_build(s)) return 1;
    scene_free(s);
    return 0;
}

/* The largest |ordinate| of channel ch: the data's scale, give or take the
 * cubic's swing inside the range it is limited to. */
static double channel_scale(const tc_recon *r, int ch) {
    const tc_mesh *m = tc_recon_mesh(r);
    int nc = tc_mesh_channel_count(m), k = tc_recon_coef_count(r);
    double s = 0;
    for (int32_t t = 0; t < tc_mesh_triangle_count(m); t++)
        for (int i = 0; i < k; i++) s = fmax(s, fabs(tc_recon_coefs(r)[((size_t)t * (size_t)nc + (size_t)ch) * (size_t)k + (size_t)i]));
    return s;
}

/* The tile contract for one sample: (float) of a double within 1e-12 of the
 * scale of the value (the fast cubic; the other paths give (float) of v exactly). */
static int within_contract(float got, double v, double scale) {
    double d = 1e-12 * scale;
    return got >= (float)(v - d) && got <= (float)(v + d);
}

/* Renders vp and checks every pixel against tc_locate + tc_eval_points: within the contract,
 * or with exact, (float) of the double itself. */
static void check_tile_as(const scene *s, const tc_viewport *vp, int threads, int exact) {
    int nc = tc_mesh_channel_count(s->m);
    double scale[TC_MAX_CHANNELS];
    for (int ch = 0; ch < nc; ch++) scale[ch] = channel_scale(s->r, ch);
    size_t np = (size_t)vp->width * (size_t)vp->height;
    float *img = malloc(np * (size_t)nc * sizeof *img);
    int32_t *own = malloc(np * sizeof *own);
    double bg[TC_MAX_CHANNELS];
    for (int ch = 0; ch < nc; ch++) bg[ch] = -7.5 + ch;
    tc_render_options o = {.background = bg, .threads = threads};
    CHECK(tc_render(s->r, s->L, vp, &o, img, own) == TC_OK);
    int bad_owner = 0, bad_value = 0;
    for (int32_t j = 0; j < vp->height; j++)
        for (int32_t i = 0; i < vp->width; i++) {
            double xy[2], val[TC_MAX_CHANNELS];
            int32_t t;
            tc_viewport_pixel_center(vp, i, j, &xy[0], &xy[1]);
            tc_eval_points(s->r, s->L, 1, xy, val, NULL, &t);
            size_t p = (size_t)j * (size_t)vp->width + (size_t)i;
            bad_owner += own[p] != t;
            for (int ch = 0; ch < nc; ch++) {
                float got = img[p * (size_t)nc + (size_t)ch];
                bad_value += t < 0 ? got != (float)bg[ch]
                             : exact ? got != (float)val[ch] : !within_contract(got, val[ch], scale[ch]);
            }
        }
    CHECK_MSG(bad_owner == 0, "%d pixels owned differently from tc_locate", bad_owner);
    CHECK_MSG(bad_value == 0, "%d pixel values differ from tc_eval_points%s", bad_value, exact ? " (exactly)" : "");
    free(img), free(own);
}

static void check_tile(const scene *s, const tc_viewport *vp, int threads) {
    check_tile_as(s, vp, threads, 0);
}

/* Pixel centres on vertices and edges: a 12x12 grid (jittered off the straight
 * rows/columns) over [0,1]^2 rendered at 24 pixels per cell with the pixel grid
 * shifted so centres fall on the mesh's grid lines. */
TEST(raster_matches_locate_and_eval) {
    scene s;
    scene_init(&s, 12, 0.25, 2, tc_test_seed() + 20);
    if (!s.r) return;
    tc_viewport full = {-0.1, -0.1, 1.1, 1.1, 97, 83};
    check_tile(&s, &full, 1);
    double h = 1.0 / (12 * 8); /* centres at k/96: on every straight row/column of the mesh */
    tc_viewport aligned = {-0.5 * h, -0.5 * h, 1 + 0.5 * h, 1 + 0.5 * h, 97, 97};
    check_tile(&s, &aligned, 3);
    tc_viewport part = {0.3, 0.41, 0.52, 0.6, 40, 33}; /* a tile inside the mesh */
    check_tile(&s, &part, 2);
    scene_free(&s);
}

/* The row-run owner pass against tc_locate on many jittered meshes and tiles:
 * pixels from 1/5 of a cell to 1/200, tiles inside, across and beyond the mesh. */
TEST(raster_runs_match_locate_fuzz) {
    trng rng;
    trng_seed(&rng, tc_test_seed() + 25);
    for (int k = 0; k < 24; k++) {
        scene s;
        int n = 2 + trng_int(&rng, 14);
        tmesh_grid(&s.g, n, n, 0.3 * trng_uniform(&rng), -1, &rng);
        if (trng_int(&rng, 2)) tmesh_delaunay_flips(&s.g);
        if (!scene_ready(&s)) continue;
        double x0 = 1.2 * trng_uniform(&rng) - 0.3, y0 = 1.2 * trng_uniform(&rng) - 0.3;
        double w = 0.05 + trng_uniform(&rng), h = 0.05 + trng_uniform(&rng);
        tc_viewport vp = {x0, y0, x0 + w, y0 + h, 5 + trng_int(&rng, 120), 5 + trng_int(&rng, 120)};
        check_tile(&s, &vp, 1 + trng_int(&rng, 3));
        scene_free(&s);
    }
}

/* The covering of a band (raster_cover.c: ownership lanes, the fast cubic) and tc__ct_span each
 * have a portable and an AVX2 build: the same bits whichever runs (no contraction, no
 * reassociation; the fast cubic's explicit fma is the FMA instruction in one and libm's
 * correctly rounded fma in the other), and each within the contract. */
TEST(raster_portable_build_same_bits) {
    scene s;
    scene_init(&s, 9, 0.25, 3, tc_test_seed() + 28);
    if (!s.r) return;
    tc_viewport vp = {-0.07, -0.03, 1.05, 1.01, 83, 71};
    size_t n = (size_t)vp.width * (size_t)vp.height * 3;
    float *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b);
    CHECK(tc_render(s.r, s.L, &vp, NULL, a, NULL) == TC_OK);
    tc__ct_span_force_generic(1);
    tc__raster_force_generic(1);
    check_tile(&s, &vp, 2);
    CHECK(tc_render(s.r, s.L, &vp, NULL, b, NULL) == TC_OK);
    tc__raster_force_generic(0);
    tc__ct_span_force_generic(0);
    CHECK_MSG(memcmp(a, b, n * sizeof *a) == 0, "the portable build renders other bits than the AVX2 one");
    check_tile(&s, &vp, 1);
    free(a), free(b);
    scene_free(&s);
}

/* Where fma is not an instruction of the row loop (raster.c fast_form_here: an x86 CPU without
 * AVX2 and FMA, where libm's fma is software), no triangle takes the fast form: every pixel is
 * then tc_eval_points' double rounded to float, bit for bit, with either build of the exact span. */
TEST(raster_exact_without_inline_fma) {
    scene s;
    scene_init(&s, 9, 0.25, 3, tc_test_seed() + 29);
    if (!s.r) return;
    tc_viewport vp = {-0.07, -0.03, 1.05, 1.01, 83, 71}, part = {0.3, 0.41, 0.52, 0.6, 40, 33};
    tc__raster_force_generic(1); /* the fast form's portable build: it serves these triangles */
    check_tile(&s, &vp, 2);
    CHECK(tc__raster_fast_setups() > 0);
    tc__raster_force_generic(2);
    check_tile_as(&s, &vp, 2, 1);
    check_tile_as(&s, &part, 1, 1);
    tc__ct_span_force_generic(1);
    check_tile_as(&s, &vp, 3, 1);
    tc__ct_span_force_generic(0);
    CHECK_MSG(tc__raster_fast_setups() == 0, "%ld triangles in the fast form", tc__raster_fast_setups());
    tc__raster_force_generic(0);
    scene_free(&s);
}

/* The fast cubic's doubles against tc_eval_triangle's at points inside every
 * triangle it serves (aspect <= TC__CT_FAST_ASPECT): within 1e-12 of the
 * channel's scale, on jittered and flagged meshes, meshes sheared towards the
 * aspect limit, data far from zero (1e6 + f) and a mesh far from the origin. */
static double fast_worst(const scene *s, trng *rng, int *served) {
    const tc_mesh *m = tc_recon_mesh(s->r);
    int nc = tc_mesh_channel_count(m);
    double worst = 0, scale[TC_MAX_CHANNELS];
    for (int ch = 0; ch < nc; ch++) scale[ch] = channel_scale(s->r, ch);
    for (int32_t t = 0; t < tc_mesh_triangle_count(m); t++) {
        tc__eval_frame f;
        tc__frame(m, t, &f);
        double longest = 0;
        for (int q = 0; q < 3; q++) longest = fmax(longest, f.e[q][0] * f.e[q][0] + f.e[q][1] * f.e[q][1]);
        if (!(longest <= TC__CT_FAST_ASPECT * fabs(tc__cross(f.e[0], f.e[1])))) continue;
        ++*served;
        tc__ct_fast ff;
        tc__ct_fast_prepare(&f, tc_recon_coefs(s->r) + (size_t)t * (size_t)nc * TC_CT_ORDINATES, nc, &ff);
        for (int k = 0; k < 16; k++) {
            double u = trng_uniform(rng), v = trng_uniform(rng);
            if (u + v > 1) u = 1 - u, v = 1 - v;
            double x = f.p[0][0] + u * (f.p[1][0] - f.p[0][0]) + v * (f.p[2][0] - f.p[0][0]);
            double y = f.p[0][1] + u * (f.p[1][1] - f.p[0][1]) + v * (f.p[2][1] - f.p[0][1]);
            double K[3], want[TC_MAX_CHANNELS];
            tc__v4d got[TC_MAX_CHANNELS];
            tc__ct_fast_row(&ff, y, K);
            tc__ct_fast_lanes(&ff, K, tc__splat(x), got);
            tc_eval_triangle(s->r, t, x, y, want, NULL);
            for (int ch = 0; ch < nc; ch++) worst = fmax(worst, fabs(got[ch][0] - want[ch]) / scale[ch]);
        }
    }
    return worst;
}

static void offset_f(const void *ctx, double x, double y, int ch, double *val, double grad[2]) {
    smooth_f(ctx, x, y, ch, val, grad);
    *val += 1e6;
}

TEST(raster_fast_cubic_within_contract) {
    trng rng;
    trng_seed(&rng, tc_test_seed() + 31);
    double worst = 0;
    int served = 0, meshes = 0;
    for (int k = 0; k < 12; k++) {
        scene s;
        if (k < 4) {
            static const unsigned long seeds[4] = {20, 28, 29, 20}; /* flagged meshes the other tests build */
            scene_init(&s, 6 + 3 * (k % 2), 0.25, 1 + k % 3, tc_test_seed() + seeds[k]);
        } else {
            tmesh_grid(&s.g, 8, 8, 0.3, -1, &rng);
            double shear = k < 8 ? 3.0 * (k - 3) : 0, far = k >= 10 ? 1e5 : 0;
            for (int32_t v = 0; v < s.g.nv; v++) {
                s.g.xy[2 * v] = far + s.g.xy[2 * v] * (1 + shear) , s.g.xy[2 * v + 1] = far + s.g.xy[2 * v + 1] / (1 + shear);
            }
            tmesh_sample(&s.g, 2, k % 2 ? offset_f : smooth_f, NULL, k % 3 == 0, 0, 0);
            s.m = tmesh_build(&s.g);
            s.r = NULL, s.L = NULL;
            if (s.m) CHECK(tc_recon_new(s.m, NULL, &s.r, NULL) == TC_OK);
        }
        if (s.r) worst = fmax(worst, fast_worst(&s, &rng, &served)), meshes++;
        scene_free(&s);
    }
    CHECK_MSG(meshes >= 10 && served > 500, "%d meshes, %d triangles served by the fast cubic", meshes, served);
    CHECK_MSG(worst <= 1e-12, "fast cubic off by %.3g of the scale", worst);
    if (getenv("TC_TEST_VERBOSE")) printf("    fast cubic: worst %.3g of the scale over %d triangles\n", worst, served);
}

/* A pixel's fast value depends only on its triangle, row and x, not on its lane: four
 * lanes straddling inner edges (each lane's subtriangle selected) give the bits each
 * lane gives alone (one subtriangle for all four), and every group the bits it gives through
 * the permutation alone (tc__ct_fast_lanes_mix, as raster_cover.c's short runs take it), on
 * every triangle of a jittered mesh with two channels, rows and x's drawn across the whole
 * triangle. */
TEST(raster_fast_lanes_mixed_equal_single) {
    trng rng;
    trng_seed(&rng, tc_test_seed() + 35);
    scene s;
    scene_init(&s, 7, 0.25, 2, tc_test_seed() + 20);
    if (!s.r) return;
    const tc_mesh *m = tc_recon_mesh(s.r);
    int nc = tc_mesh_channel_count(m), mixed = 0, bad = 0;
    for (int32_t t = 0; t < tc_mesh_triangle_count(m); t++) {
        tc__eval_frame f;
        tc__frame(m, t, &f);
        tc__ct_fast ff;
        tc__ct_fast_prepare(&f, tc_recon_coefs(s.r) + (size_t)t * (size_t)nc * TC_CT_ORDINATES, nc, &ff);
        double xmin = fmin(f.p[0][0], fmin(f.p[1][0], f.p[2][0])), xmax = fmax(f.p[0][0], fmax(f.p[1][0], f.p[2][0]));
        double ymin = fmin(f.p[0][1], fmin(f.p[1][1], f.p[2][1])), ymax = fmax(f.p[0][1], fmax(f.p[1][1], f.p[2][1]));
        for (int k = 0; k < 24; k++) {
            double y = ymin + (ymax - ymin) * trng_uniform(&rng), K[3];
            tc__v4d x, v[TC_MAX_CHANNELS], one[TC_MAX_CHANNELS];
            for (int l = 0; l < 4; l++) x[l] = xmin + (xmax - xmin) * trng_uniform(&rng);
            tc__v4d forced[TC_MAX_CHANNELS];
            tc__ct_fast_row(&ff, y, K);
            tc__ct_fast_lanes(&ff, K, x, v);
            tc__ct_fast_lanes_mix(&ff, nc, K, x, forced, 1); /* every group through the permutation */
            for (int ch = 0; ch < nc; ch++) bad += memcmp(&v[ch], &forced[ch], sizeof v[ch]) != 0;
            tc__v4d dx = x - tc__splat(ff.x0), d01 = tc__splat(K[0]) + tc__splat(ff.gx[0]) * dx;
            tc__v4d d02 = tc__splat(K[1]) + tc__splat(ff.gx[1]) * dx; /* as tc__ct_fast_lanes: l0 - l1, l0 - l2 */
            unsigned b0 = tc__mask4((d01 <= tc__splat(0)) & (d02 <= tc__splat(0)));
            mixed += b0 != 0 && b0 != 15;
            for (int l = 0; l < 4; l++) {
                tc__ct_fast_lanes(&ff, K, tc__splat(x[l]), one);
                for (int ch = 0; ch < nc; ch++) bad += memcmp(&v[ch][l], &one[ch][0], sizeof(double)) != 0;
            }
        }
    }
    CHECK_MSG(mixed > 100, "only %d groups of lanes straddle an inner edge", mixed);
    CHECK_MSG(bad == 0, "%d lanes differ from the same pixel alone", bad);
    scene_free(&s);
}

/* tc__ct_span's doubles against tc_eval_triangle's, bit for bit, both builds:
 * rows through every triangle of a mesh, points inside and a little outside. */
TEST(ct_span_doubles_equal_point_evaluation) {
    scene s;
    scene_init(&s, 6, 0.25, 2, tc_test_seed() + 29);
    if (!s.r) return;
    trng rng;
    trng_seed(&rng, tc_test_seed() + 30);
    const tc_mesh *m = tc_recon_mesh(s.r);
    int nc = tc_mesh_channel_count(m), bad = 0;
    for (int generic = 0; generic < 2; generic++) {
        tc__ct_span_force_generic(generic);
        for (int32_t t = 0; t < tc_mesh_triangle_count(m); t++) {
            const int32_t *v = tc_mesh_triangles(m) + 3 * t;
            const double *xy = tc_mesh_xy(m);
            double lo = fmin(xy[2 * v[0]], fmin(xy[2 * v[1]], xy[2 * v[2]]));
            double hi = fmax(xy[2 * v[0]], fmax(xy[2 * v[1]], xy[2 * v[2]]));
            double y = xy[2 * v[0] + 1] + 0.2 * (trng_uniform(&rng) - 0.5) * (hi - lo);
            enum { N = 13 };
            double xs[N], dv[N * 3], pv[3];
            float fv[N * 3];
            for (int i = 0; i < N; i++) xs[i] = lo + (hi - lo) * (1.2 * trng_uniform(&rng) - 0.1);
            tc__eval_frame f;
            tc__frame(m, t, &f);
            tc__ct_span(&f, tc_recon_coefs(s.r) + (size_t)t * (size_t)nc * TC_CT_ORDINATES, nc, xs, y, N, fv, dv);
            for (int i = 0; i < N; i++) {
                tc_eval_triangle(s.r, t, xs[i], y, pv, NULL);
                bad += memcmp(pv, dv + i * nc, (size_t)nc * sizeof *pv) != 0;
            }
        }
    }
    tc__ct_span_force_generic(0);
    CHECK_MSG(bad == 0, "%d points differ from tc_eval_triangle", bad);
    scene_free(&s);
}

TEST(raster_same_bits_for_any_thread_count) {
    scene s;
    scene_init(&s, 16, 0.25, 3, tc_test_seed() + 21);
    if (!s.r) return;
    tc_viewport vp = {-0.05, 0, 1, 1.02, 211, 197};
    size_t n = (size_t)vp.width * (size_t)vp.height * 3;
    size_t np = (size_t)vp.width * (size_t)vp.height;
    float *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b);
    int32_t *oa = malloc(np * sizeof *oa), *ob = malloc(np * sizeof *ob);
    tc_render_options o = {.threads = 1};
    CHECK(tc_render(s.r, s.L, &vp, &o, a, oa) == TC_OK);
    /* 16 threads on 197 rows: bands of 8 rows from the start; 2 and 3: of 32, shrinking at the end */
    int threads[] = {2, 3, 4, 8, 16, 40};
    for (int k = 0; k < 6; k++) {
        o.threads = threads[k];
        memset(b, 0xff, n * sizeof *b), memset(ob, 0x7f, np * sizeof *ob);
        CHECK(tc_render(s.r, s.L, &vp, &o, b, ob) == TC_OK);
        CHECK_MSG(memcmp(a, b, n * sizeof *a) == 0, "%d threads differ from 1", threads[k]);
        CHECK_MSG(memcmp(oa, ob, np * sizeof *oa) == 0, "%d threads: owners differ from 1", threads[k]);
    }
    free(a), free(b), free(oa), free(ob);
    scene_free(&s);
}

/* tc_render_options.limit: every sample of magnitude >= the limit is stored as +-limit and
 * counted (added to *limited), every other sample is the unlimited tile's; the same on any
 * thread count, in bands, with the background past the limit too; no limit (0, NaN, or beyond
 * the float range) changes nothing and counts nothing. */
TEST(raster_limit_clamps_and_counts) {
    scene s;
    scene_init(&s, 16, 0.25, 3, tc_test_seed() + 23);
    if (!s.r) return;
    tc_viewport vp = {-0.1, 0, 1, 1.05, 173, 151}; /* a margin of background on two sides */
    size_t np = (size_t)vp.width * (size_t)vp.height, n = np * 3;
    float *free_tile = malloc(n * sizeof *free_tile), *got = malloc(n * sizeof *got);
    double bg[3] = {0.5, -1e6, 0}; /* channel 1's background is past any limit below */
    tc_render_options o = {.background = bg, .threads = 1};
    CHECK(tc_render(s.r, s.L, &vp, &o, free_tile, NULL) == TC_OK);
    float lim = 0;
    for (size_t i = 0; i < n; i += 3) lim = fmaxf(lim, fabsf(free_tile[i])); /* channel 0's largest */
    for (size_t i = 0; i < n; i += 3) /* the limit a sample itself (>=, not >), about 3/4 of that */
        if (fabsf(free_tile[i]) <= 0.75f * lim && fabsf(free_tile[i]) > 0.7f * lim) {
            lim = fabsf(free_tile[i]);
            break;
        }
    int64_t want = 0;
    for (size_t i = 0; i < n; i++) want += fabsf(free_tile[i]) >= lim;
    CHECK(want > (int64_t)np / 20 && want < (int64_t)n); /* some samples of the mesh, and the background */
    for (int threads = 1; threads <= 3; threads++)
        for (int32_t band = 0; band <= 40; band += 40) { /* the whole tile, then bands of 40 rows */
            int64_t count = 5; /* added to */
            o = (tc_render_options){.background = bg, .threads = threads, .limit = lim, .limited = &count};
            int ok = 1;
            for (int32_t j = 0; j < vp.height; j += band ? band : vp.height) {
                o.row0 = j, o.rows = band && vp.height - j > band ? band : vp.height - j;
                ok &= tc_render(s.r, s.L, &vp, &o, got + (size_t)j * (size_t)vp.width * 3, NULL) == TC_OK;
            }
            int same = ok;
            for (size_t i = 0; i < n; i++)
                same &= fabsf(free_tile[i]) >= lim ? got[i] == copysignf(lim, free_tile[i]) : got[i] == free_tile[i];
            CHECK_MSG(same, "%d threads, bands of %d: a sample is not the limited tile's", threads, (int)band);
            CHECK_MSG(count == 5 + want, "%d threads, bands of %d: %lld counted, %lld reach the limit", threads,
                      (int)band, (long long)(count - 5), (long long)want);
        }
    double none[] = {0, NAN, 1e39};
    for (int k = 0; k < 3; k++) {
        int64_t count = 0;
        o = (tc_render_options){.background = bg, .threads = 2, .limit = none[k], .limited = &count};
        CHECK(tc_render(s.r, s.L, &vp, &o, got, NULL) == TC_OK);
        CHECK_MSG(count == 0 && !memcmp(got, free_tile, n * sizeof *got), "limit %g changed the tile", none[k]);
    }
    free(free_tile), free(got);
    scene_free(&s);
}

/* A tile rendered in bands of rows (row0/rows), overlay included, is the whole
 * tile's pixels bit for bit; rows outside the viewport are refused. */
TEST(raster_bands_equal_the_whole_tile) {
    scene s;
    scene_init(&s, 16, 0.25, 3, tc_test_seed() + 24);
    if (!s.r) return;
    tc_viewport vp = {-0.05, 0, 1, 1.02, 131, 97};
    size_t row = (size_t)vp.width * 3, n = row * (size_t)vp.height;
    float *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b);
    int32_t *oa = malloc(n / 3 * sizeof *oa), *ob = malloc(n / 3 * sizeof *ob);
    tc_render_options o = {.threads = 2};
    CHECK(tc_render(s.r, s.L, &vp, &o, a, oa) == TC_OK);
    tc_render_overlay(s.r, &vp, 0.5, a);
    int steps[] = {1, 7, 16, 40, 97};
    for (int k = 0; k < 5; k++) {
        memset(b, 0xff, n * sizeof *b);
        for (int32_t y = 0; y < vp.height; y += steps[k]) {
            o.row0 = y, o.rows = vp.height - y < steps[k] ? vp.height - y : steps[k];
            CHECK(tc_render(s.r, s.L, &vp, &o, b + (size_t)y * row, ob + (size_t)y * (size_t)vp.width) == TC_OK);
            tc_render_overlay_rows(s.r, &vp, 0.5, o.row0, o.rows, b + (size_t)y * row);
        }
        CHECK_MSG(memcmp(a, b, n * sizeof *a) == 0, "bands of %d rows differ from the whole tile", steps[k]);
        CHECK_MSG(memcmp(oa, ob, n / 3 * sizeof *oa) == 0, "owners in bands of %d rows differ", steps[k]);
    }
    o.row0 = 90, o.rows = 8; /* past the last row */
    CHECK(tc_render(s.r, s.L, &vp, &o, b, ob) == TC_EINVAL);
    o.row0 = -1, o.rows = 1;
    CHECK(tc_render(s.r, s.L, &vp, &o, b, ob) == TC_EINVAL);
    free(a), free(b), free(oa), free(ob);
    scene_free(&s);
}

TEST(raster_outside_background_and_errors) {
    scene s;
    scene_init(&s, 12, 0.25, 1, tc_test_seed() + 22);
    if (!s.r) return;
    tc_viewport off = {2, 2, 3, 3, 8, 8}; /* entirely outside */
    float img[64];
    int32_t own[64];
    double bg = 0.25;
    tc_render_options o = {.background = &bg, .threads = 1};
    CHECK(tc_render(s.r, s.L, &off, &o, img, own) == TC_OK);
    int ok = 1;
    for (int p = 0; p < 64; p++) ok &= img[p] == 0.25f && own[p] == -1;
    CHECK(ok);
    tc_viewport bad = {0, 0, 0, 1, 8, 8}; /* empty rectangle */
    CHECK(tc_render(s.r, s.L, &bad, &o, img, own) == TC_EINVAL);
    bad = (tc_viewport){0, 0, 1, 1, 0, 8};
    CHECK(tc_render(s.r, s.L, &bad, &o, img, own) == TC_EINVAL);
    bad = (tc_viewport){0, 0, NAN, 1, 8, 8};
    CHECK(tc_render(s.r, s.L, &bad, &o, img, own) == TC_EINVAL);
    tc_render_options late = {.threads = 2, .deadline_ms = 1.0}; /* a deadline long past */
    tc_viewport vp = {0, 0, 1, 1, 8, 8};
    CHECK(tc_render(s.r, s.L, &vp, &late, img, own) == TC_ETIMEOUT);
    scene_free(&s);
}

/* The overlay marks C0 edges yellow and leaves cell interiors alone. */
/* A viewport narrower than a double's step per pixel (x1 - x0 subnormal: pixels per unit
 * overflow to infinity, 0 * infinity is NaN): the row guess must not turn a NaN into a
 * column (a fuzzer's find: undefined behaviour, and an index far outside the row). */
TEST(raster_viewport_of_subnormal_width) {
    scene s;
    scene_init(&s, 5, 0.25, 2, tc_test_seed() + 41);
    if (s.r) {
        tc_viewport wide = {0, 0, 2.1e-319, 1, 7, 5}, tall = {0, 0, 1, 3e-320, 6, 4};
        tc_viewport both = {0, 0, 1e-310, 1e-310, 9, 9};
        for (int threads = 1; threads <= 3; threads += 2) {
            check_tile(&s, &wide, threads);
            check_tile(&s, &tall, threads);
            check_tile(&s, &both, threads);
        }
        /* the overlay: vertices on x0 land at 0 * infinity; no line is drawn there (the
         * sanitized build, `make check`, traps the NaN index this once became) */
        const tc_viewport *vps[] = {&wide, &tall, &both};
        for (int k = 0; k < 3; k++) {
            size_t np = (size_t)vps[k]->width * (size_t)vps[k]->height * 2;
            float *img = calloc(np, sizeof *img);
            tc_render_overlay(s.r, vps[k], 1, img);
            int finite = 1;
            for (size_t p = 0; p < np; p++) finite &= isfinite(img[p]);
            CHECK_MSG(finite, "overlay on viewport %d wrote a non-finite pixel", k);
            free(img);
        }
    }
    scene_free(&s);
}

TEST(raster_overlay_colours_edges) {
    scene s;
    scene_init(&s, 12, 0.25, 3, tc_test_seed() + 23);
    if (!s.r) return;
    tc_viewport vp = {0, 0, 1, 1, 120, 120};
    size_t n = (size_t)vp.width * (size_t)vp.height * 3;
    float *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b);
    CHECK(tc_render(s.r, s.L, &vp, NULL, a, NULL) == TC_OK);
    memcpy(b, a, n * sizeof *a);
    tc_render_overlay(s.r, &vp, 2.0, b);
    /* Row 4 of the mesh (y = 1/3) is a straight C0 line: the pixel row at
     * y = 1/3 is j = 80 (centre 1 - 80.5/120 = 0.329...), painted yellow. */
    int yellow = 0, changed = 0;
    for (int32_t i = 0; i < vp.width; i++) {
        const float *p = b + ((size_t)80 * (size_t)vp.width + (size_t)i) * 3;
        yellow += p[0] == 2.0f && p[1] == 1.6f && p[2] == 0.0f;
    }
    for (size_t k = 0; k < n; k++) changed += a[k] != b[k];
    CHECK_MSG(yellow > vp.width / 2, "%d yellow pixels on the C0 row", yellow);
    CHECK_MSG(changed > 0 && (size_t)changed < n / 2, "%d channel values changed", changed);
    free(a), free(b);
    scene_free(&s);
}

/* The colour the overlay gives the pixel row j = 80 of a 120 x 120 tile of the
 * unit square (where the grid line y = 1/3 is drawn), counted over the row:
 * which of grey (C1), yellow (C0), red (C-1) is the majority; -2 if none is. */
static int overlay_row_kind(tc_method method, int kind, int jump) {
    trng rng;
    trng_seed(&rng, tc_test_seed() + 25);
    tmesh g;
    tmesh_grid(&g, 6, 6, 0, -1, &rng);
    int32_t line[7];
    for (int i = 0; i <= 6; i++) line[i] = tmesh_gv(6, i, 2);
    CHECK(tmesh_add_line(&g, kind, line, 7) == 0);
    tmesh_sample(&g, 3, smooth_f, NULL, 1, 0, jump ? 0.3 : 0);
    tc_mesh *m = tmesh_build(&g);
    tc_options o;
    tc_options_default(&o);
    o.method = method;
    tc_recon *r = NULL;
    int result = -2;
    tc_viewport vp = {0, 0, 1, 1, 120, 120};
    float *img = calloc((size_t)vp.width * (size_t)vp.height * 3, sizeof *img);
    if (m && img && tc_recon_new(m, &o, &r, NULL) == TC_OK) {
        tc_render_overlay(r, &vp, 1.0, img);
        int count[3] = {0, 0, 0}; /* C-1, C0, C1 */
        for (int32_t i = 0; i < vp.width; i++) {
            const float *p = img + ((size_t)80 * (size_t)vp.width + (size_t)i) * 3;
            count[0] += p[0] == 1.0f && p[1] == 0.1f && p[2] == 0.1f;
            count[1] += p[0] == 1.0f && p[1] == 0.8f && p[2] == 0.0f;
            count[2] += p[0] == 0.35f && p[1] == 0.35f && p[2] == 0.35f;
        }
        for (int k = 0; k < 3; k++)
            if (count[k] > vp.width / 2) result = k - 1;
    }
    free(img);
    tc_recon_free(r);
    tc_mesh_free(m);
    tmesh_free(&g);
    return result;
}

/* The overlay draws what each method does with an edge (its row in the method
 * table): powell-sabin keeps a C-1 cut (red) but smooths a C0 flag (grey);
 * clough-tocher-c1 smooths both; linear is C0 across every edge; constant
 * jumps across every edge. Today's code drew powell-sabin's cuts grey. */
TEST(raster_overlay_follows_the_method) {
    CHECK(overlay_row_kind(TC_METHOD_POWELL_SABIN, TC_CM1, 1) == TC_CM1);
    CHECK(overlay_row_kind(TC_METHOD_POWELL_SABIN, TC_C0, 0) == TC_C1);
    CHECK(overlay_row_kind(TC_METHOD_CLOUGH_TOCHER, TC_CM1, 1) == TC_CM1);
    CHECK(overlay_row_kind(TC_METHOD_CLOUGH_TOCHER, TC_C0, 0) == TC_C0);
    CHECK(overlay_row_kind(TC_METHOD_CLOUGH_TOCHER_C1, TC_CM1, 1) == TC_C1);
    CHECK(overlay_row_kind(TC_METHOD_LINEAR, TC_CM1, 1) == TC_CM1);
    CHECK(overlay_row_kind(TC_METHOD_LINEAR, TC_C0, 0) == TC_C0);
    CHECK(overlay_row_kind(TC_METHOD_LINEAR4, TC_C0, 0) == TC_C0);
    CHECK(overlay_row_kind(TC_METHOD_CONSTANT, TC_C0, 0) == TC_CM1);
}

/* Pixel centres exactly on vertices and edges: mesh vertices at k/8 and a tile
 * whose centres are exactly i/64 (x0 = -1/128, step 1/64), so every vertex and
 * every cell edge and diagonal passes through centres. */
TEST(raster_centres_exactly_on_vertices_and_edges) {
    trng rng;
    trng_seed(&rng, tc_test_seed() + 24);
    scene s;
    tmesh_grid(&s.g, 8, 8, 0, -1, &rng);
    int32_t row[9];
    for (int i = 0; i <= 8; i++) row[i] = tmesh_gv(8, i, 4);
    tmesh_add_line(&s.g, TC_C0, row, 9);
    if (!scene_ready(&s)) return;
    tc_viewport vp = {-1.0 / 128, -1.0 / 128, 1 - 1.0 / 128, 1 - 1.0 / 128, 64, 64};
    double x, y;
    tc_viewport_pixel_center(&vp, 8, 40, &x, &y);
    CHECK(x == 8.0 / 64 && y == 23.0 / 64); /* the centres really are the lattice */
    check_tile(&s, &vp, 1);
    check_tile(&s, &vp, 4);
    scene_free(&s);
}

/* Pixel centres on the diagonals and edges of an unjittered grid, the case raster_cover.c's
 * row runs settle from four lanes (an owned or touching lane at a run's end, the exact
 * signs of lanes on an edge, four at a time) and a tile whose first and last columns
 * cut triangles (the run clipped there): dyadic lattices (4 or 8 cells, 2..16 pixels
 * per cell: every orientation computed exactly, raster_cover.c's lattice_exact) and others
 * (3..6 cells, 2..9 pixels: signs certified, or exact because nothing rounded), both
 * diagonal directions, shifted by whole and half pixels, one mesh translated far from
 * the origin (differences round: the exact test decides), thread counts 1 and 3. */
TEST(raster_runs_on_lattice_edges) {
    trng rng;
    trng_seed(&rng, tc_test_seed() + 33);
    for (int k = 0; k < 20; k++) {
        scene s;
        int dyadic = k < 8, n = dyadic ? 4 << (k % 2) : 3 + k % 4, per = dyadic ? 2 << (k / 2 % 4) : 2 + k % 8;
        int diag = k % 3 == 2 ? -1 : k % 3;
        double far = k == 19 ? 1e6 + 0.5 : 0;
        tmesh_grid(&s.g, n, n, 0, diag, &rng);
        for (int32_t v = 0; v < s.g.nv; v++) s.g.xy[2 * v] += far, s.g.xy[2 * v + 1] += far;
        if (!scene_ready(&s)) continue;
        double h = 1.0 / (n * per), shift = k % 3 == 0 ? 0 : k % 3 == 1 ? 0.5 * h : h;
        int w = n * per; /* centres exactly at i h + shift: on the lattice for dyadic h */
        tc_viewport vp = {far - 0.5 * h + shift, far - 0.5 * h, far + (w - 0.5) * h + shift, far + (w - 0.5) * h, w, w};
        double cx, cy;
        tc_viewport_pixel_center(&vp, 3, w - 1 - 5, &cx, &cy);
        if (dyadic) CHECK(cx == 3 * h + shift && cy == 5 * h);
        check_tile(&s, &vp, 1 + 2 * (k % 2));
        tc_viewport inner = {far + 0.3 - 0.5 * h, far + 0.2 - 0.5 * h, far + 0.3 + (w / 2 - 0.5) * h,
                             far + 0.2 + (w / 2 - 0.5) * h, w / 2, w / 2}; /* columns cut triangles */
        check_tile(&s, &inner, 1);
        scene_free(&s);
    }
}

/* Vertices moved onto pixel centres of tiles that are no lattice (7 to ~210 pixels wide, some
 * far from the origin), so every edge runs through or within rounding of other centres and
 * the orientations there are a few ulps, their computed signs often wrong: the signs that
 * raster_cover.c certifies by orient_sign's bound (classify_at's lanes, edge_sign's pixels) must
 * leave exactly these to the exact tests. Either certifying by 2^-56 (|l| + |r|) instead of
 * ORIENT_ERRBOUND's ~2^-51.4 fails it; no other unit test caught either, down to 2^-60. */
TEST(raster_certified_signs_near_edges) {
    trng rng;
    trng_seed(&rng, tc_test_seed() + 37);
    for (int k = 0; k < 16; k++) {
        scene s;
        int n = 2 + k % 5, per = 3 + trng_int(&rng, 200 / n), w = n * per + 1 + trng_int(&rng, 3);
        double far = k % 4 == 3 ? 1e5 * trng_uniform(&rng) : 0, span = 0.3 + trng_uniform(&rng);
        tc_viewport vp = {far, far, far + span, far + span * (0.5 + trng_uniform(&rng)), w, w};
        tmesh_grid(&s.g, n, n, 0, k % 3 == 2 ? -1 : k % 3, &rng);
        for (int b = 0; b <= n; b++)
            for (int a = 0; a <= n; a++) {
                int32_t v = tmesh_gv(n, a, b);
                tc_viewport_pixel_center(&vp, a * per, w - 1 - b * per, &s.g.xy[2 * v], &s.g.xy[2 * v + 1]);
            }
        if (!scene_ready(&s)) continue;
        check_tile(&s, &vp, 1 + k % 3);
        scene_free(&s);
    }
}

/* The locator's across bits (locate.h), which spare raster_cover.c the closed-only claims of
 * centres inside an edge whose neighbour owns them: on a grid every interior edge has one,
 * on the side that is not left, and no boundary edge has any; none either where a coordinate
 * is beyond the range whose signs are taken exactly with a lattice's (2^260 here). The tiles of
 * raster_runs_on_lattice_edges check the pixels. */
typedef struct {
    int bits, bad;
} across_count;

static void count_across(void *ctx, const struct tc__slot *sl) {
    across_count *c = ctx;
    c->bits += __builtin_popcount(sl->across);
    c->bad += (sl->across & sl->left) != 0 || sl->across > 7;
}

TEST(raster_across_bits_on_interior_edges) {
    trng rng;
    trng_seed(&rng, tc_test_seed() + 36);
    for (int k = 0; k < 4; k++) {
        scene s;
        int n = 5 + k;
        tmesh_grid(&s.g, n, n, k == 3 ? 0.3 : 0, k % 3 == 2 ? -1 : k % 3, &rng);
        double scale = k == 1 ? 0x1p260 : 1;
        for (int32_t v = 0; v < s.g.nv; v++) s.g.xy[2 * v] *= scale, s.g.xy[2 * v + 1] *= scale;
        if (!scene_ready(&s)) continue;
        across_count c = {0, 0};
        const double lo[2] = {-INFINITY, -INFINITY}, hi[2] = {INFINITY, INFINITY};
        tc__locator_query_box(s.L, lo, hi, count_across, &c);
        int interior = 3 * n * n - 2 * n; /* (3 * 2n² sides - 4n on the boundary) / 2 */
        CHECK_MSG(c.bad == 0, "grid %d: %d slots with an across bit on a left edge", k, c.bad);
        CHECK_MSG(c.bits == (k == 1 ? 0 : interior), "grid %d: %d across bits, %d interior edges", k, c.bits,
                  interior);
        scene_free(&s);
    }
}

/* Tiles denser than their pixels (raster_cover.c's cover_few: a triangle under four pixels of area, or
 * whose box covers under 16 pixels, has its few centres classified and shaded exactly, and no
 * fast form set up): every owner tc_locate's and every value tc_eval_points' bit for bit, with
 * centres on the mesh's vertices and edges (a dyadic grid, the centres on its lattice, half of
 * the tiles with a column and a row of centres on its outer boundary, owned in the closed sense
 * only) and off them (jittered grids, some flipped), on 1 and 3 threads, with each build of the
 * covering (portable and AVX2), and the same bytes in bands of 5 rows. Two channels, one of them
 * floored (negative values clamped to 0); their pixels are shaded four at a time across triangles
 * (raster_cover.c's shade_queue), 32 to a batch. */
TEST(raster_triangles_under_four_pixels_exact) {
    trng rng;
    trng_seed(&rng, tc_test_seed() + 34);
    for (int k = 0; k < 10; k++) {
        scene s;
        int lattice = k < 4, n = lattice ? 32 : k < 8 ? 20 + 7 * (k % 4) : 40;
        tmesh_grid(&s.g, n, n, lattice ? 0 : 0.3, k % 3 == 2 ? -1 : k % 3, &rng);
        if (k >= 6) tmesh_delaunay_flips(&s.g);
        tmesh_sample(&s.g, 2, smooth_f, NULL, 1, 0, 0);
        if (!scene_build(&s)) {
            scene_free(&s);
            continue;
        }
        s.r->floor0[k % 2] = 1; /* smooth_f goes below 0: one channel's floor exercised */
        /* lattice: centres (2i + 1) / 32 or (4i + 2) / 32 on the grid's vertices, or (k = 2, 3)
         * i / 16 and i / 8, x = 0 and y = 0 among them; else pixels of ~2.3 cells, every
         * triangle well under a pixel of area, or (k >= 8) cells of ~1.7 pixels, triangles of
         * about 1.5 pixels (under 4 with the jitter) owning one to three centres each, some
         * across the end of a batch of the queue */
        int w = lattice ? 16 >> (k % 2) : k < 8 ? n / 2 : 2 * n;
        double h = k < 2 ? 0 : 0.5 / w;
        tc_viewport vp = lattice ? (tc_viewport){-h, -h, 1 - h, 1 - h, w, w}
                                 : (tc_viewport){-0.1, -0.05, 1.05, 1.1, w, w - 1};
        double cx, cy;
        tc_viewport_pixel_center(&vp, 3, 2, &cx, &cy);
        if (lattice) CHECK(cx * 32 == floor(cx * 32) && cy * 32 == floor(cy * 32));
        if (k >= 2 && lattice) {
            tc_viewport_pixel_center(&vp, 0, w - 1, &cx, &cy);
            CHECK(cx == 0 && cy == 0);
        }
        check_tile_as(&s, &vp, 1 + 2 * (k % 2), 1); /* the build the CPU picks (AVX2 here) */
        tc__raster_force_generic(1); /* the portable build; counts the triangles set up in the fast form */
        check_tile_as(&s, &vp, 1 + 2 * (k % 2), 1);
        CHECK_MSG(tc__raster_fast_setups() == 0, "mesh %d: %ld triangles under four pixels set up in the fast form", k,
                  tc__raster_fast_setups());
        tc__raster_force_generic(0);
        size_t np = (size_t)vp.width * (size_t)vp.height;
        float *a = malloc(np * 2 * sizeof *a), *b = malloc(np * 2 * sizeof *b);
        int32_t *oa = malloc(np * sizeof *oa), *ob = malloc(np * sizeof *ob);
        tc_render_options o = {.threads = 2};
        CHECK(tc_render(s.r, s.L, &vp, &o, a, oa) == TC_OK);
        for (int32_t y = 0; y < vp.height; y += 5) {
            o.row0 = y, o.rows = vp.height - y < 5 ? vp.height - y : 5;
            size_t at = (size_t)y * (size_t)vp.width;
            CHECK(tc_render(s.r, s.L, &vp, &o, b + 2 * at, ob + at) == TC_OK);
        }
        CHECK_MSG(memcmp(a, b, np * 2 * sizeof *a) == 0 && memcmp(oa, ob, np * sizeof *oa) == 0,
                  "mesh %d: bands of 5 rows differ from the whole tile", k);
        free(a), free(b), free(oa), free(ob);
        scene_free(&s);
    }
}

/* tc_eval_points visits large batches in Z order: every result must still be
 * the one tc_locate + tc_eval_triangle give for that point, bit for bit,
 * including points outside the mesh and duplicated points. */
TEST(eval_points_order_changes_no_bit) {
    scene s;
    scene_init(&s, 10, 0.25, 2, tc_test_seed() + 26);
    if (!s.r) return;
    trng rng;
    trng_seed(&rng, tc_test_seed() + 27);
    enum { N = 5000 };
    static double xy[2 * N], v[2 * N], g[4 * N], v1[2], g1[4];
    static int32_t tri[N];
    for (int i = 0; i < N; i++) {
        xy[2 * i] = 1.4 * trng_uniform(&rng) - 0.2, xy[2 * i + 1] = 1.4 * trng_uniform(&rng) - 0.2;
        if (i % 7 == 3) xy[2 * i] = xy[2 * i - 2], xy[2 * i + 1] = xy[2 * i - 1];
    }
    tc__eval_sort_min_triangles(0); /* the Z-ordered path, whatever the mesh size */
    tc_eval_points(s.r, s.L, N, xy, v, g, tri);
    tc__eval_sort_min_triangles(32768);
    int bad = 0;
    for (int i = 0; i < N; i++) {
        int32_t t = tc_locate(s.L, xy[2 * i], xy[2 * i + 1]);
        memset(v1, 0, sizeof v1), memset(g1, 0, sizeof g1);
        if (t >= 0) tc_eval_triangle(s.r, t, xy[2 * i], xy[2 * i + 1], v1, g1);
        bad += t != tri[i] || memcmp(v1, v + 2 * i, sizeof v1) || memcmp(g1, g + 4 * i, sizeof g1);
    }
    CHECK_MSG(bad == 0, "%d of %d points differ from one-by-one evaluation", bad, N);
    scene_free(&s);
}

/* Tiles that only touch the mesh: the last column of pixel centres exactly on the mesh's left
 * side x = 0, the first on its right side x = 1, the top row on its bottom y = 0, the bottom
 * row on its top y = 1. Those centres lie on the outer boundary, owned in the closed sense only
 * (tc_locate names the lowest index containing them), and the triangles there have a box whose
 * side is exactly the band's extreme centre: the locator's box query (locate.c's box_meets)
 * must take boxes that meet in a single line, or the whole column or row would get the
 * background instead. */
TEST(raster_tile_touching_mesh_boundary) {
    trng rng;
    trng_seed(&rng, tc_test_seed() + 38);
    scene s;
    tmesh_grid(&s.g, 4, 4, 0, -1, &rng);
    if (!scene_ready(&s)) return;
    const double e = 1.0 / 16; /* half a pixel of 1/8 */
    const tc_viewport vps[4] = {
        {-1 + e, e, e, 1 + e, 8, 8},          /* last column at x = 0 */
        {1 - e, e, 2 - e, 1 + e, 8, 8},       /* first column at x = 1 */
        {e, e - 1, 1 + e, e, 8, 8},           /* top row at y = 0 */
        {e, 1 - e, 1 + e, 2 - e, 8, 8},       /* bottom row at y = 1 */
    };
    for (int v = 0; v < 4; v++) {
        double x, y;
        int32_t i = v == 0 ? 7 : 0, j = v == 2 ? 0 : 7;
        tc_viewport_pixel_center(&vps[v], v < 2 ? i : 3, v < 2 ? 3 : j, &x, &y);
        CHECK_MSG(v == 0 ? x == 0 : v == 1 ? x == 1 : v == 2 ? y == 0 : y == 1, "tile %d: centre (%g, %g)", v, x, y);
        CHECK(tc_locate(s.L, x, y) >= 0); /* the closed mesh holds it */
        check_tile(&s, &vps[v], 1);
    }
    scene_free(&s);
}

/* One cell of tmesh_grid, triangles (v00, v10, v11) and (v00, v11, v01), its corners moved to
 * xy (v00, v10, v01, v11), then scene_ready. */
static int quad_scene(scene *s, trng *rng, const double xy[4][2]) {
    tmesh_grid(&s->g, 1, 1, 0, 0, rng);
    for (int k = 0; k < 4; k++) {
        int32_t v = tmesh_gv(1, k % 2, k / 2);
        s->g.xy[2 * v] = xy[k][0], s->g.xy[2 * v + 1] = xy[k][1];
    }
    return scene_ready(s);
}

/* raster_cover.c's lattice_exact trusts the plain floating-point orientation of a triangle at
 * the tile's centres only when every corner and centre is a multiple of 2^g below 2^E with
 * E - g <= 25, so that no product rounds. Here E - g = 27 (multiples of 2^-26 below 2): the
 * quad's diagonal A-B passes one unit (2^-52) of orientation from the centre P = (x_11, y_17),
 * exactly on its right, while both products of the orientation round and their computed
 * difference is 0 in either direction, which would give P to the left triangle. The owner
 * must still be tc_locate's (the signs certified or taken exactly instead). */
TEST(raster_lattice_bound_beyond_exact_products) {
    trng rng;
    trng_seed(&rng, tc_test_seed() + 39);
    scene s;
    const double u = 0x1p-26;
    const double xy[4][2] = {{-111884504 * u, -124772064 * u}, /* A */
                             {1.75, -1.75},                    /* right of A -> B */
                             {-1.75, 1.75},                    /* left of it */
                             {-15904807 * u, 133141712 * u}};  /* B */
    if (!quad_scene(&s, &rng, xy)) return; /* diagonal A - B */
    /* centres x_i = -1.5 + u + i / 16, y_j = 1.5 - u - j / 16: 48 x 48 of them, all below 2 */
    tc_viewport vp = {-1.5 + u - 1.0 / 32, 1.5 - u + 1.0 / 32 - 3, -1.5 + u - 1.0 / 32 + 3, 1.5 - u + 1.0 / 32, 48, 48};
    double px, py;
    tc_viewport_pixel_center(&vp, 11, 17, &px, &py);
    CHECK(px == -54525951 * u && py == 29360127 * u);
    const double *A = xy[0], *B = xy[3];
    /* the exact orientation of P against A -> B is -1 unit of 2^-52, the computed one 0 */
    int64_t ax = (int64_t)(A[0] / u), ay = (int64_t)(A[1] / u), bx = (int64_t)(B[0] / u), by = (int64_t)(B[1] / u);
    int64_t qx = (int64_t)(px / u), qy = (int64_t)(py / u);
    __extension__ __int128 det = (__int128)(bx - ax) * (qy - ay) - (__int128)(by - ay) * (qx - ax);
    CHECK(det == -1);
    CHECK((B[0] - A[0]) * (py - A[1]) - (B[1] - A[1]) * (px - A[0]) == 0);
    check_tile(&s, &vp, 1);
    scene_free(&s);
}

/* A pixel centre one unit of orientation outside a mesh's boundary edge, for a triangle small
 * in pixels (raster_cover.c's cover_few: each centre classified by classify_one's edge_sign).
 * The edge runs from A = (0, 0) to B = (2^31, c) and P = (d, b) with b = fl(c d) 2^-31: the
 * product a b = 2^31 b is exact, c d = 987654327000000006913289 rounds down by 1, so the
 * computed orientation is exactly 0 while the true one is -1: P is outside. edge_sign may
 * take a computed sign as exact only when neither product rounded (checked by fma for each),
 * else the exact test decides; P must get the background, as tc_locate finds no triangle. */
TEST(raster_edge_sign_rounded_product_not_trusted) {
    trng rng;
    trng_seed(&rng, tc_test_seed() + 40);
    scene s;
    const double c = 1000000007.0, d = 987654327.0, b = c * d * 0x1p-31;
    const double xy[4][2] = {{0, 0}, {0x1p31, c}, {0, 0x1p30}, {0x1p31, c + 0x1p30}}; /* v00 v10 v01 v11 */
    if (!quad_scene(&s, &rng, xy)) return;
    __extension__ __int128 det = (__int128)(b * 0x1p31) - (__int128)1000000007 * 987654327; /* a b - c d */
    CHECK(det == -1); /* P strictly right of A -> B, outside the mesh */
    CHECK(0x1p31 * b - c * d == 0); /* while the computed orientation is 0 */
    /* one row of 8 pixels of 2^29: the centre of pixel 2 is P */
    tc_viewport vp = {d - 2.5 * 0x1p29, b + 0x1p28 - 0x1p29, d + 5.5 * 0x1p29, b + 0x1p28, 8, 1};
    double px, py;
    tc_viewport_pixel_center(&vp, 2, 0, &px, &py);
    CHECK(px == d && py == b);
    CHECK(tc_locate(s.L, px, py) == -1);
    check_tile(&s, &vp, 1);
    scene_free(&s);
}

/* The fast cubic's error grows with a triangle's aspect (longest edge squared over twice the
 * area: ct_fast.h), so raster_cover.c gives it only triangles of aspect <= TC__CT_FAST_ASPECT
 * (64). A grid stretched 30 times along x and squeezed 30 times along y has triangles of
 * aspect ~900: none may be set up in the fast form, and the tile must still be within the
 * contract; the same grid unstretched (aspect ~2) is served by the fast form. */
TEST(raster_slivers_not_in_fast_form) {
    trng rng;
    trng_seed(&rng, tc_test_seed() + 42);
    for (int k = 0; k < 2; k++) {
        scene s;
        double st = k ? 30 : 1;
        tmesh_grid(&s.g, 8, 8, 0.2, -1, &rng);
        for (int32_t v = 0; v < s.g.nv; v++) s.g.xy[2 * v] *= st, s.g.xy[2 * v + 1] /= st;
        if (!scene_ready(&s)) continue;
        tc_viewport vp = {-0.01 * st, -0.01 / st, 1.01 * st, 1.01 / st, 64, 64};
        tc__raster_force_generic(1); /* the fast form's portable build, counting its setups */
        check_tile(&s, &vp, 1);
        long fast = tc__raster_fast_setups();
        tc__raster_force_generic(0);
        if (k) CHECK_MSG(fast == 0, "%ld triangles of aspect ~900 in the fast form", fast);
        else CHECK_MSG(fast > 0, "no triangle of the plain grid in the fast form");
        scene_free(&s);
    }
}

/* The other end of the range whose signs are taken exactly with a lattice's (locate.c's
 * tame_coordinate: 0, or 2^-250 <= |v| <= 2^250): a grid scaled by 2^-255 has every nonzero
 * coordinate below 2^-250, so no across bits at all; scaled by 2^-240 it has every interior
 * edge's, as at scale 1 (raster_across_bits_on_interior_edges). */
TEST(raster_across_bits_small_coordinates) {
    trng rng;
    trng_seed(&rng, tc_test_seed() + 43);
    for (int k = 0; k < 2; k++) {
        scene s;
        int n = 6;
        tmesh_grid(&s.g, n, n, 0, k, &rng);
        double scale = k ? 0x1p-240 : 0x1p-255;
        for (int32_t v = 0; v < s.g.nv; v++) s.g.xy[2 * v] *= scale, s.g.xy[2 * v + 1] *= scale;
        if (!scene_ready(&s)) continue;
        across_count c = {0, 0};
        const double lo[2] = {-INFINITY, -INFINITY}, hi[2] = {INFINITY, INFINITY};
        tc__locator_query_box(s.L, lo, hi, count_across, &c);
        int interior = 3 * n * n - 2 * n;
        CHECK_MSG(c.bad == 0, "scale 2^%d: %d slots with an across bit on a left edge", k ? -240 : -255, c.bad);
        CHECK_MSG(c.bits == (k ? interior : 0), "scale 2^%d: %d across bits, %d interior edges", k ? -240 : -255,
                  c.bits, interior);
        scene_free(&s);
    }
}

/* The lanes' exact-product test (raster_cover.c's prod_exact4, Dekker's product with all four
 * partial products) on a product whose rounding error is exactly the product of the factors'
 * low halves: c = d = 1 + 2^-30 (high half 1, low half 2^-30) give c d = 1 + 2^-29 + 2^-60,
 * rounded to 1 + 2^-29. The mesh's lower boundary runs from (0, 0) to N = (2, 1 + 2^-30) and
 * the pixel centre P = (1 + 2^-30, 1/2 + 2^-30) lies 2^-60 of orientation below it (outside),
 * while the computed orientation 2 (1/2 + 2^-30) - fl(c d) is 0: only a product test that
 * sees the rounding leaves P to the exact test, which gives it the background. */
TEST(raster_lane_product_rounding_seen) {
    trng rng;
    trng_seed(&rng, tc_test_seed() + 44);
    scene s;
    const double e = 0x1p-30;
    const double xy[4][2] = {{0, 0}, {2, 1 + e}, {0, 2}, {2, 3}}; /* v00 v10 v01 v11 */
    if (!quad_scene(&s, &rng, xy)) return;
    /* 40 x 40 centres of 1/16, pixel (16, 16) at P */
    tc_viewport vp = {-0.03125 + e, -0.96875 + e, 2.46875 + e, 1.53125 + e, 40, 40};
    double px, py;
    tc_viewport_pixel_center(&vp, 16, 16, &px, &py);
    CHECK(px == 1 + e && py == 0.5 + e);
    CHECK(2 * py - (1 + e) * px == 0); /* the computed orientation; the exact one is -2^-60 */
    CHECK(tc_locate(s.L, px, py) == -1);
    check_tile(&s, &vp, 1);
    scene_free(&s);
}

/* Values beyond float's range on the exact path: a constant -1e300 (and +1e300) renders as
 * -FLT_MAX (+FLT_MAX) in every owned pixel, as tile_float clamps a double, the sign kept;
 * (float) alone would give an infinity. */
TEST(raster_exact_path_clamps_keep_sign) {
    trng rng;
    trng_seed(&rng, tc_test_seed() + 47);
    for (int k = 0; k < 2; k++) {
        scene s;
        tmesh_grid(&s.g, 3, 3, 0.2, -1, &rng);
        tmesh_sample(&s.g, 1, smooth_f, NULL, 1, 0, 0);
        double c = k ? 1e300 : -1e300;
        for (int32_t v = 0; v < s.g.nv; v++) {
            s.g.values[v] = c;
            if (s.g.grads) s.g.grads[2 * v] = s.g.grads[2 * v + 1] = 0;
        }
        if (!scene_build(&s)) {
            scene_free(&s);
            continue;
        }
        tc_viewport vp = {0, 0, 1, 1, 24, 24};
        float img[24 * 24];
        int32_t own[24 * 24];
        tc__raster_force_generic(2);
        CHECK(tc_render(s.r, s.L, &vp, NULL, img, own) == TC_OK);
        tc__raster_force_generic(0);
        int bad = 0, owned = 0;
        for (int p = 0; p < 24 * 24; p++)
            if (own[p] >= 0) owned++, bad += img[p] != (k ? FLT_MAX : -FLT_MAX);
        CHECK_MSG(owned == 24 * 24 && bad == 0, "%d of %d owned pixels not %s", bad, owned, k ? "FLT_MAX" : "-FLT_MAX");
        scene_free(&s);
    }
}

/* Pixels a quarter of an ulp wide (2^-34 near 2^20, where an ulp is 2^-32), so four centres of
 * a row or a column are often one double: jittered 6 x 6 grids 24 ulps across with their
 * vertices on the ulp grid, tiles of 32 x 32 pixels at several offsets, on the fast path, the
 * portable one and the exact one. raster.c's range_margin: with one pixel of margin alone, a
 * triangle's range of columns (pixel_range) missed the column of centres exactly on its right
 * edge, which it owns (its left edge by the canonical direction), and the neighbour that only
 * touches it took those pixels (20 of them, on all three paths). */
TEST(raster_subulp_pixels_owned_as_located) {
    trng rng;
    trng_seed(&rng, tc_test_seed() + 45);
    const double X = 0x1p20, u = 0x1p-34; /* a pixel */
    for (int k = 0; k < 6; k++) {
        scene s;
        tmesh_grid(&s.g, 6, 6, 0.2, -1, &rng);
        for (int32_t v = 0; v < s.g.nv; v++) /* 24 ulps across: cells of 4, corners moved by 1 at most */
            for (int a = 0; a < 2; a++) s.g.xy[2 * v + a] = X + ldexp(nearbyint(s.g.xy[2 * v + a] * 24), -32);
        if (!scene_ready(&s)) continue;
        for (int t = 0; t < 4; t++) {
            double ox = X + (double)(12 * t - 8 + 2 * (k % 3)) * u, oy = X + (double)(24 - 8 * t + 2 * (k % 2)) * u;
            tc_viewport vp = {ox, oy, ox + 32 * u, oy + 32 * u, 32, 32};
            for (int g = 0; g < 3; g++) {
                tc__raster_force_generic(g);
                check_tile(&s, &vp, 1 + t % 2);
            }
            tc__raster_force_generic(0);
        }
        scene_free(&s);
    }
}
