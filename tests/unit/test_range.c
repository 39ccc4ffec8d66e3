/* test_range.c — range "local" and "positive": every Bézier ordinate inside its
 * triangle's bound, continuity kept, rough data on long obtuse triangles included. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "core/range.h"
#include "meshgen.h"
#include "props.h"

/* ---- meshes and data that make the free cubic overshoot ---- */

/* Rough data: a value in [0, 1] and a gradient per point from a hash of its
 * coordinates (channel-dependent), so nothing smooth ties neighbours together. */
static double hash01(double x, double y, int salt) {
    uint64_t h = (uint64_t)(int64_t)llround(x * 1e9) * 0x9E3779B97F4A7C15ULL ^
                 (uint64_t)(int64_t)llround(y * 1e9) * 0xC2B2AE3D27D4EB4FULL ^ (uint64_t)(unsigned)salt * 0x165667B19E3779F9ULL;
    h ^= h >> 31, h *= 0xBF58476D1CE4E5B9ULL, h ^= h >> 29;
    return (double)(h >> 11) * 0x1.0p-53;
}

static void rough_f(const void *ctx, double x, double y, int ch, double *v, double g[2]) {
    double slope = ctx ? *(const double *)ctx : 1;
    *v = hash01(x, y, 3 * ch);
    g[0] = slope * (2 * hash01(x, y, 3 * ch + 1) - 1);
    g[1] = slope * (2 * hash01(x, y, 3 * ch + 2) - 1);
}

/* A grid sheared and stretched into long obtuse triangles (aspect up to about
 * `stretch` x 2, largest angles past 150 degrees), random diagonals, flags. */
static void obtuse_mesh(tmesh *g, trng *r, double stretch) {
    random_flagged_mesh(g, r, 0, 12);
    double shear = stretch * (0.5 + trng_uniform(r));
    for (int32_t i = 0; i < g->nv; i++) {
        double *p = g->xy + 2 * i;
        p[0] = stretch * p[0] + shear * p[1];
    }
}

/* What the bound of range "local" may use besides the corner values (range.h):
 * the corner planes before limiting (the free reconstruction's), and whether
 * they are data (given) or estimated (believed only as far as the values
 * around go). NULL planes: the corner range and its 5 % margin only. */
typedef struct {
    const double *cg;
    int estimated;
    const tmesh *g;  /* the generator's midpoint samples, or NULL */
} evidence;

/* The midpoint sample of edge (a, b) on triangle t's side, if g has one. */
static int midpoint_of(const tmesh *g, int32_t t, int32_t a, int32_t b, int ch, double *z) {
    for (int32_t i = 0; g && i < g->nmid; i++) {
        const int32_t *e = g->mid_edge + 2 * i;
        int same = (e[0] == a && e[1] == b) || (e[0] == b && e[1] == a);
        if (same && (!g->mid_tri || g->mid_tri[i] < 0 || g->mid_tri[i] == t)) {
            *z = g->mid_val[(size_t)i * (size_t)g->nc + (size_t)ch];
            return 1;
        }
    }
    return 0;
}

static double minmod(double a, double b) { return a > 0 && b > 0 ? fmin(a, b) : a < 0 && b < 0 ? fmax(a, b) : 0; }

/* The range of every corner value the reconstruction interpolates (its
 * corner ordinates: clough-tocher-c1 merges a jump's two sides) over the
 * triangles sharing a vertex with t: a superset of what range.h calls the
 * values around t. */
static void around_range(const tc_recon *rec, int32_t t, int ch, double *lo, double *hi) {
    const tc_mesh *m = tc_recon_mesh(rec);
    const int32_t *tri = tc_mesh_triangles(m);
    int nc = tc_mesh_channel_count(m), ncoef = tc_recon_coef_count(rec);
    *lo = INFINITY, *hi = -INFINITY;
    for (int32_t u = 0; u < tc_mesh_triangle_count(m); u++) {
        int touch = 0;
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++) touch |= tri[3 * u + a] == tri[3 * t + b];
        const double *o = tc_recon_coefs(rec) + ((size_t)u * (size_t)nc + (size_t)ch) * (size_t)ncoef;
        for (int k = 0; touch && k < 3; k++) *lo = fmin(*lo, o[k]), *hi = fmax(*hi, o[k]);
    }
}

/* Whether a triangle is well shaped (range.h): its longest edge squared over
 * twice its area at most TC_RANGE_SHAPED_ASPECT. Estimated planes of a
 * well-shaped triangle count as data; on others only as far as the values around. */
static int shaped(const double *xy, const int32_t *v) {
    const double *p[3] = {xy + 2 * v[0], xy + 2 * v[1], xy + 2 * v[2]};
    double longest = 0;
    for (int k = 0; k < 3; k++) {
        double dx = p[(k + 1) % 3][0] - p[k][0], dy = p[(k + 1) % 3][1] - p[k][1];
        longest = fmax(longest, dx * dx + dy * dy);
    }
    double twice_area = fabs((p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]));
    return longest <= TC_RANGE_SHAPED_ASPECT * twice_area;
}

/* Triangle t's bound in channel ch as range.h states it (with an estimate's
 * reach taken over a superset of the values around). o: its ordinates, whose
 * first three are the corner values the reconstruction interpolates. */
static void spec_bound(const tc_recon *rec, const evidence *ev, int32_t t, int ch, const double *o, double *lo,
                       double *hi) {
    const tc_mesh *m = tc_recon_mesh(rec);
    const double *xy = tc_mesh_xy(m);
    const int32_t *tri = tc_mesh_triangles(m);
    int nc = tc_mesh_channel_count(m);
    double a = fmin(o[0], fmin(o[1], o[2])), b = fmax(o[0], fmax(o[1], o[2])), hump = 0, dip = 0;
    for (int i = 0; ev && i < 3; i++) { /* a midpoint sample beyond both ends: 4/3 of its excess */
        double mid, zi = o[i], zj = o[(i + 1) % 3];
        if (!midpoint_of(ev->g, t, tri[3 * t + i], tri[3 * t + (i + 1) % 3], ch, &mid)) continue;
        hump = fmax(hump, 4.0 / 3 * (mid - fmax(zi, zj))), dip = fmax(dip, 4.0 / 3 * (fmin(zi, zj) - mid));
    }
    double phump = 0, pdip = 0;
    for (int i = 0; ev && ev->cg && i < 3; i++) {
        int j = (i + 1) % 3;
        const double *gi = ev->cg + ((3 * (size_t)t + (size_t)i) * (size_t)nc + (size_t)ch) * 2;
        const double *gj = ev->cg + ((3 * (size_t)t + (size_t)j) * (size_t)nc + (size_t)ch) * 2;
        double e[2] = {xy[2 * tri[3 * t + j]] - xy[2 * tri[3 * t + i]], xy[2 * tri[3 * t + j] + 1] - xy[2 * tri[3 * t + i] + 1]};
        double di = gi[0] * e[0] + gi[1] * e[1], dj = gj[0] * e[0] + gj[1] * e[1];
        phump = fmax(phump, minmod(di, -dj) / 3), pdip = fmax(pdip, minmod(-di, dj) / 3);
    }
    if (ev && ev->estimated && !shaped(xy, tri + 3 * t)) {
        double rlo, rhi;
        around_range(rec, t, ch, &rlo, &rhi);
        phump = fmin(phump, fmax(0, rhi - b)), pdip = fmin(pdip, fmax(0, a - rlo));
    }
    hump = fmax(hump, phump), dip = fmax(dip, pdip);
    double margin = TC_RANGE_MARGIN * (b - a);
    *lo = a - fmax(margin, dip);
    if (a >= 0) *lo = fmax(*lo, 0);
    *hi = b + fmax(margin, hump);
}

/* The worst distance of a Bézier ordinate (the first 19: clough-tocher's, or
 * powell-sabin's) outside its triangle's bound, relative to the channel's
 * largest |value|. */
static double worst_outside(const tc_recon *rec, const evidence *ev) {
    const tc_mesh *m = tc_recon_mesh(rec);
    int nc = tc_mesh_channel_count(m), ncoef = tc_recon_coef_count(rec);
    const double *coef = tc_recon_coefs(rec);
    double scale = 1e-300, worst = 0;
    for (int32_t t = 0; t < tc_mesh_triangle_count(m); t++)
        for (int k = 0; k < 3; k++)
            for (int ch = 0; ch < nc; ch++) scale = fmax(scale, fabs(tc_mesh_corner_value(m, t, k)[ch]));
    for (int32_t t = 0; t < tc_mesh_triangle_count(m); t++)
        for (int ch = 0; ch < nc; ch++) {
            const double *o = coef + ((size_t)t * (size_t)nc + (size_t)ch) * (size_t)ncoef;
            double lo, hi;
            spec_bound(rec, ev, t, ch, o, &lo, &hi);
            for (int i = 0; i < TC_CT_ORDINATES; i++) worst = fmax(worst, fmax(lo - o[i], o[i] - hi) / scale);
        }
    return worst;
}

static tc_recon *make(const tc_mesh *m, tc_method method, tc_cross cross, tc_tangents tan, tc_range range,
                      tc_diags *dg) {
    tc_options o;
    tc_options_default(&o);
    o.method = method, o.cross_boundary = cross, o.tangents = tan, o.range = range;
    tc_recon *r = NULL;
    CHECK_MSG(tc_recon_new(m, &o, &r, dg) == TC_OK, "%s/%s: %s", tc_method_name(method), tc_cross_name(cross),
              dg && dg->count ? dg->items[0].message : "refused");
    return r;
}

/* Warnings whose message contains needle. */
static int count_warnings(const tc_diags *dg, const char *needle) {
    int n = 0;
    for (int i = 0; i < dg->count; i++) n += dg->items[i].severity == TC_SEV_WARNING && strstr(dg->items[i].message, needle);
    return n;
}

/* ---- the bound and continuity ---- */

/* The acceptance test of the limiter: random flagged meshes sheared into
 * long obtuse triangles (aspect to ~400), rough random data and slopes,
 * every cross-boundary rule, both cubic methods, every tangent source. The
 * free cubic leaves the bound by far (checked, so the test can fail); the
 * limited one never does, and interpolation, C0 and C1 hold as for free. */
TEST(range_local_bounds_every_ordinate_and_keeps_continuity) {
    trng r;
    trng_seed(&r, tc_test_seed() + 900);
    const tc_tangents sources[] = {TC_TANGENTS_GIVEN, TC_TANGENTS_MIDPOINTS, TC_TANGENTS_ESTIMATE};
    double free_worst = 0, local_worst = 0;
    cont_report worst = {0};
    int kinks = 0, runs = 0;
    for (int trial = 0; trial < 12; trial++) {
        tmesh g;
        obtuse_mesh(&g, &r, trial < 4 ? 1 : trial < 8 ? 30 : 200);
        double slope = 3;
        tc_tangents src = sources[trial % 3];
        tmesh_sample(&g, 1 + trial % 3, rough_f, &slope, src == TC_TANGENTS_GIVEN, src == TC_TANGENTS_MIDPOINTS,
                     0.4);
        tc_mesh *m = tmesh_build(&g);
        for (int ci = 0; m && ci < 4; ci++) {
            tc_method method = ci < 3 ? TC_METHOD_CLOUGH_TOCHER : TC_METHOD_CLOUGH_TOCHER_C1;
            tc_cross cross = (tc_cross)(ci % 3);
            tc_recon *fr = make(m, method, cross, src, TC_RANGE_FREE, NULL);
            evidence ev = {fr ? tc_recon_corner_gradients(fr) : NULL, src == TC_TANGENTS_ESTIMATE, &g};
            if (fr) free_worst = fmax(free_worst, worst_outside(fr, NULL));
            tc_diags dg;
            tc_diags_init(&dg);
            tc_recon *rec = make(m, method, cross, src, TC_RANGE_LOCAL, &dg);
            if (rec) {
                double out = worst_outside(rec, &ev);
                local_worst = fmax(local_worst, out);
                CHECK_MSG(out <= 1e-12, "trial %d %s/%s: an ordinate leaves its bound by %.3g", trial,
                          tc_method_name(method), tc_cross_name(cross), out);
                cont_report rep;
                check_continuity(rec, &g, 1e-10, &rep);
                worst.corner = fmax(worst.corner, rep.corner), worst.c0 = fmax(worst.c0, rep.c0);
                worst.c1 = fmax(worst.c1, rep.c1), worst.vertex = fmax(worst.vertex, rep.vertex);
                worst.internal = fmax(worst.internal, rep.internal);
                kinks += count_warnings(&dg, "joined C0");
                runs++;
            }
            tc_recon_free(rec);
            tc_recon_free(fr);
            tc_diags_free(&dg);
        }
        tc_mesh_free(m);
        tmesh_free(&g);
    }
    CHECK_MSG(free_worst > 0.1, "the free cubic should overshoot these meshes (worst %.3g)", free_worst);
    CHECK_MSG(kinks == 0, "%d edges gave up C1 (no dart on these meshes)", kinks);
    fprintf(stderr, "  [range local] %d runs: worst ordinate outside its bound %.2g (free: %.3g of the scale); "
                    "residuals corner %.2g, C0 %.2g, C1 edge %.2g, C1 vertex %.2g, internal %.2g\n",
            runs, local_worst, free_worst, worst.corner, worst.c0, worst.c1, worst.vertex, worst.internal);
}

/* Where the free cubic stays inside the bound the limiter changes nothing:
 * linear data (every ordinate on the triangle's plane) give the same bits. */
TEST(range_local_leaves_data_inside_alone) {
    trng r;
    trng_seed(&r, tc_test_seed() + 901);
    tmesh g;
    obtuse_mesh(&g, &r, 50);
    tmesh_sample(&g, 2, linear_data, NULL, 1, 0, 0);
    tc_mesh *m = tmesh_build(&g);
    for (int ci = 0; m && ci < 3; ci++) {
        tc_diags dg;
        tc_diags_init(&dg);
        tc_recon *a = make(m, TC_METHOD_CLOUGH_TOCHER, (tc_cross)ci, TC_TANGENTS_GIVEN, TC_RANGE_FREE, NULL);
        tc_recon *b = make(m, TC_METHOD_CLOUGH_TOCHER, (tc_cross)ci, TC_TANGENTS_GIVEN, TC_RANGE_LOCAL, &dg);
        size_t n = (size_t)tc_mesh_triangle_count(m) * 2 * TC_CT_ORDINATES;
        CHECK(a && b && !memcmp(tc_recon_coefs(a), tc_recon_coefs(b), n * sizeof(double)));
        CHECK_MSG(count_warnings(&dg, "range") == 0, "a warning where nothing was limited: %s",
                  dg.count ? dg.items[0].message : "");
        tc_recon_free(a);
        tc_recon_free(b);
        tc_diags_free(&dg);
    }
    tc_mesh_free(m);
    tmesh_free(&g);
}

/* The single triangles: long and obtuse, corner values in [0, 1], flat
 * planes (all gradients 0). The free cubic's `normal` rule carries the short
 * edges' slopes into the interior times the aspect ratio; local stays inside. */
TEST(range_local_single_obtuse_triangles) {
    trng r;
    trng_seed(&r, tc_test_seed() + 902);
    double free_worst = 0, local_worst = 0;
    for (int i = 0; i < 300; i++) {
        double len = 10 + 800 * trng_uniform(&r), ang = (116 + 33 * trng_uniform(&r)) * 3.14159265358979323846 / 180;
        double xy[6] = {0, 0, 1, 0, 1 - len * cos(ang), len * sin(ang)}, v[3], gr[6] = {0};
        for (int k = 0; k < 3; k++) v[k] = trng_uniform(&r);
        int32_t tri[3] = {0, 1, 2};
        tc_mesh_desc d;
        memset(&d, 0, sizeof d);
        d.nverts = 3, d.xy = xy, d.ntris = 1, d.tris = tri, d.nchan = 1, d.values = v, d.gradients = gr;
        tc_mesh *m = NULL;
        CHECK(tc_mesh_new(&d, &m, NULL) == TC_OK);
        for (int range = 0; m && range < 2; range++) {
            tc_recon *rec = make(m, TC_METHOD_CLOUGH_TOCHER, TC_CROSS_NORMAL, TC_TANGENTS_GIVEN,
                                 range ? TC_RANGE_FREE : TC_RANGE_LOCAL, NULL);
            double out = rec ? worst_outside(rec, NULL) : INFINITY; /* flat planes: no bend */
            if (range) free_worst = fmax(free_worst, out);
            else local_worst = fmax(local_worst, out);
            tc_recon_free(rec);
        }
        tc_mesh_free(m);
    }
    CHECK_MSG(free_worst > 0.5, "free normal should overshoot long obtuse triangles (worst %.3g)", free_worst);
    CHECK_MSG(local_worst <= 1e-12, "local leaves the bound by %.3g", local_worst);
    fprintf(stderr, "  [range single obtuse] 300 triangles, flat planes: free net up to %.3g beyond, local %.2g\n",
            free_worst, local_worst);
}

/* Range "positive": data >= 0 never reconstructed below 0 (the net), and only
 * that: above, the free cubic's ordinates stay as they were. */
TEST(range_positive_keeps_nonnegative_data_nonnegative) {
    trng r;
    trng_seed(&r, tc_test_seed() + 903);
    double worst_neg = 0, free_neg = 0;
    for (int trial = 0; trial < 6; trial++) {
        tmesh g;
        obtuse_mesh(&g, &r, trial < 3 ? 1 : 100);
        double slope = 4;
        tmesh_sample(&g, 2, rough_f, &slope, 1, 0, 0.4);
        tc_mesh *m = tmesh_build(&g);
        for (int range = 0; m && range < 2; range++) {
            tc_recon *rec = make(m, TC_METHOD_CLOUGH_TOCHER, TC_CROSS_NORMAL, TC_TANGENTS_GIVEN,
                                 range ? TC_RANGE_FREE : TC_RANGE_POSITIVE, NULL);
            const double *c = rec ? tc_recon_coefs(rec) : NULL;
            double neg = 0;
            for (size_t i = 0; c && i < (size_t)tc_mesh_triangle_count(m) * 2 * TC_CT_ORDINATES; i++)
                neg = fmax(neg, -c[i]);
            if (range) free_neg = fmax(free_neg, neg);
            else worst_neg = fmax(worst_neg, neg);
            if (!range && rec) {
                cont_report rep;
                check_continuity(rec, &g, 1e-10, &rep);
            }
            tc_recon_free(rec);
        }
        tc_mesh_free(m);
        tmesh_free(&g);
    }
    CHECK_MSG(free_neg > 0.1, "free should go negative on this data (worst %.3g)", free_neg);
    CHECK_MSG(worst_neg <= 1e-12, "positive went below 0 by %.3g", worst_neg);
}

/* ---- what cannot be had: a dart ---- */

/* Edge a-b is shared by two needles that both reach far beyond b (a dart:
 * the segment between their centroids crosses the edge's line far outside
 * the edge). C1 across a-b ties their cross-boundary ordinates to the edge's
 * middle leg extended there, which with z_a = 0, z_b = 1 and the far corners
 * at 0.5 lies far outside [0, 1]: no C1 reconstruction inside the bound
 * exists. The limiter keeps the bound and joins that edge C0 with the
 * smallest kink, naming it; range "free" keeps C1 and overshoots. */
TEST(range_local_dart_joined_c0_and_named) {
    /* a = (0,0), b = (1,0), w = (100, 1), w' = (100, -1); the gap at b closed
     * by (b, w', w) and the far side by (w, w', f). */
    double xy[10] = {0, 0, 1, 0, 100, 1, 100, -1, 200, 0}, v[5] = {0, 1, 0.5, 0.5, 0.5}, gr[10] = {0};
    int32_t tri[12] = {0, 1, 2, 1, 0, 3, 1, 3, 2, 2, 3, 4};
    tc_mesh_desc d;
    memset(&d, 0, sizeof d);
    d.nverts = 5, d.xy = xy, d.ntris = 4, d.tris = tri, d.nchan = 1, d.values = v, d.gradients = gr;
    tc_mesh *m = NULL;
    CHECK(tc_mesh_new(&d, &m, NULL) == TC_OK);
    tc_diags dg;
    tc_diags_init(&dg);
    tc_recon *rec = m ? make(m, TC_METHOD_CLOUGH_TOCHER, TC_CROSS_NORMAL, TC_TANGENTS_GIVEN, TC_RANGE_LOCAL, &dg)
                      : NULL;
    tc_recon *fr = m ? make(m, TC_METHOD_CLOUGH_TOCHER, TC_CROSS_NORMAL, TC_TANGENTS_GIVEN, TC_RANGE_FREE, NULL)
                     : NULL;
    if (rec && fr) {
        CHECK_MSG(worst_outside(rec, NULL) <= 1e-12, "local leaves the bound by %.3g", worst_outside(rec, NULL));
        CHECK_MSG(worst_outside(fr, NULL) > 1, "free should overshoot the dart (%.3g)", worst_outside(fr, NULL));
        int named = 0;
        for (int i = 0; i < dg.count; i++)
            named |= strstr(dg.items[i].message, "joined C0") && (!strcmp(dg.items[i].path, "triangles[0]") ||
                                                                  !strcmp(dg.items[i].path, "triangles[1]"));
        CHECK_MSG(named, "no warning names the dart edge");
        /* Still continuous across it. */
        double va, vb;
        tc_eval_triangle(rec, 0, 0.5, 0, &va, NULL);
        tc_eval_triangle(rec, 1, 0.5, 0, &vb, NULL);
        CHECK_NEAR(va, vb, 1e-14);
    }
    tc_recon_free(rec);
    tc_recon_free(fr);
    tc_diags_free(&dg);
    tc_mesh_free(m);
}

/* ---- the other methods, and what it says ---- */

/* Powell-Sabin: its ordinates all come from the corner planes (range.h), so
 * limiting the planes bounds the net: its 19 ordinates inside the bound. */
TEST(range_local_bounds_powell_sabin) {
    trng r;
    trng_seed(&r, tc_test_seed() + 904);
    double free_worst = 0, local_worst = 0;
    for (int trial = 0; trial < 6; trial++) {
        tmesh g;
        obtuse_mesh(&g, &r, trial < 3 ? 1 : 60);
        double slope = 3;
        tmesh_sample(&g, 2, rough_f, &slope, 1, 0, 0.4);
        tc_mesh *m = tmesh_build(&g);
        tc_recon *fr = m ? make(m, TC_METHOD_POWELL_SABIN, TC_CROSS_NORMAL, TC_TANGENTS_GIVEN, TC_RANGE_FREE, NULL)
                         : NULL;
        tc_recon *rec = m ? make(m, TC_METHOD_POWELL_SABIN, TC_CROSS_NORMAL, TC_TANGENTS_GIVEN, TC_RANGE_LOCAL, NULL)
                          : NULL;
        evidence ev = {fr ? tc_recon_corner_gradients(fr) : NULL, 0, NULL};
        if (fr) free_worst = fmax(free_worst, worst_outside(fr, NULL));
        local_worst = fmax(local_worst, rec ? worst_outside(rec, &ev) : INFINITY);
        tc_recon_free(rec);
        tc_recon_free(fr);
        tc_mesh_free(m);
        tmesh_free(&g);
    }
    CHECK_MSG(free_worst > 0.1, "free powell-sabin should overshoot (worst %.3g)", free_worst);
    CHECK_MSG(local_worst <= 1e-12, "local powell-sabin leaves the bound by %.3g", local_worst);
}

/* Warnings: local names where it limited; free says how far it leaves the
 * data's range (at least the sampled excursion, at most the net's). */
TEST(range_warnings_say_what_and_where) {
    trng r;
    trng_seed(&r, tc_test_seed() + 905);
    tmesh g;
    obtuse_mesh(&g, &r, 100);
    double slope = 3;
    tmesh_sample(&g, 1, rough_f, &slope, 1, 0, 0);
    tc_mesh *m = tmesh_build(&g);
    tc_diags dl, df;
    tc_diags_init(&dl);
    tc_diags_init(&df);
    tc_recon *a = m ? make(m, TC_METHOD_CLOUGH_TOCHER, TC_CROSS_NORMAL, TC_TANGENTS_GIVEN, TC_RANGE_LOCAL, &dl) : NULL;
    tc_recon *b = m ? make(m, TC_METHOD_CLOUGH_TOCHER, TC_CROSS_NORMAL, TC_TANGENTS_GIVEN, TC_RANGE_FREE, &df) : NULL;
    int planes = 0, leaves = 0;
    for (int i = 0; i < dl.count; i++)
        planes += strstr(dl.items[i].message, "limited the slope at this vertex") && !strncmp(dl.items[i].path, "vertices[", 9);
    for (int i = 0; i < df.count; i++)
        leaves += strstr(df.items[i].message, "leaves its data's range") && !strncmp(df.items[i].path, "triangles[", 10);
    CHECK_MSG(planes >= 1 && planes <= TC_RANGE_NAMED, "local: %d plane warnings naming a vertex", planes);
    CHECK_MSG(leaves == 1, "free: %d warnings that it leaves the range", leaves);
    CHECK_MSG(count_warnings(&dl, "leaves its data's range") == 0, "local must not say it leaves the range");
    tc_recon_free(a);
    tc_recon_free(b);
    tc_diags_free(&dl);
    tc_diags_free(&df);
    tc_mesh_free(m);
    tmesh_free(&g);
}

/* Planes so steep that the free cubic overflows (and is refused) are simply
 * scaled into range by the limiter: accepted, finite, inside. */
TEST(range_local_tames_overflowing_planes) {
    const double xy[8] = {0, 0, 1, 0, 1, 1, 0, 1}, v[4] = {1, 2, 3, 4}, g[8] = {1.7e308, 1.7e308, 0, 0, 0, 0, 0, 0};
    const int32_t tri[6] = {0, 1, 2, 0, 2, 3};
    tc_mesh_desc d;
    memset(&d, 0, sizeof d);
    d.nverts = 4, d.xy = xy, d.ntris = 2, d.tris = tri, d.nchan = 1, d.values = v, d.gradients = g;
    tc_mesh *m = NULL;
    CHECK(tc_mesh_new(&d, &m, NULL) == TC_OK);
    tc_recon *rec = m ? make(m, TC_METHOD_CLOUGH_TOCHER, TC_CROSS_NORMAL, TC_TANGENTS_GIVEN, TC_RANGE_LOCAL, NULL)
                      : NULL;
    if (rec) CHECK_MSG(worst_outside(rec, NULL) <= 1e-12, "outside by %.3g", worst_outside(rec, NULL));
    tc_recon_free(rec);
    tc_mesh_free(m);
}
