/* test_scenes.c — the reference front-end: exact radiosity against closed forms,
 * Monte Carlo and brute-force visibility; its meshes, flags, samples and JSON. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "io/request.h"
#include "io/request_write.h"
#include "meshgen.h"
#include "scenes/meshing.h"
#include "scenes/scene.h"

static const double PI = 3.14159265358979323846;

static tc_scene scene(tc_scene_id id) {
    tc_scene s;
    CHECK(tc_scene_init(&s, id) == TC_OK);
    return s;
}

static tc_scene_mesh *mesh_of(const tc_scene *s, tc_scene_mesh_kind kind, int n, int gradients) {
    tc_scene_mesh_opts o;
    tc_scene_mesh_opts_default(&o);
    o.kind = kind, o.density = n, o.gradients = gradients;
    tc_scene_mesh *m = NULL;
    int st = tc_scene_mesh_new(s, &o, &m);
    CHECK_MSG(st == TC_OK && m, "%s %s N=%d: status %d", tc_scene_name(s->id), tc_scene_mesh_kind_name(kind), n, st);
    return m;
}

static tc_mesh *core_mesh(const tc_scene_mesh *m) {
    tc_mesh *cm = NULL;
    tc_diags dg;
    tc_diags_init(&dg);
    int st = tc_mesh_new(&m->desc, &cm, &dg);
    CHECK_MSG(st == TC_OK, "tc_mesh_new: %s: %s", dg.count ? dg.items[0].path : "",
              dg.count ? dg.items[0].message : "");
    tc_diags_free(&dg);
    return cm;
}

/* ---- names ------------------------------------------------------------------------ */

TEST(scenes_names_parse_back) {
    for (int i = 0; i < TC_SCENE_COUNT; i++) {
        tc_scene_id id;
        CHECK(tc_scene_name((tc_scene_id)i) && tc_scene_summary((tc_scene_id)i));
        CHECK(tc_scene_parse(tc_scene_name((tc_scene_id)i), &id) == 0 && id == (tc_scene_id)i);
    }
    tc_scene_id id;
    tc_scene_mesh_kind k;
    CHECK(tc_scene_parse("nope", &id) == -1 && tc_scene_parse(NULL, &id) == -1);
    CHECK(tc_scene_name(TC_SCENE_COUNT) == NULL);
    CHECK(tc_scene_mesh_kind_parse("adaptive", &k) == 0 && k == TC_SCENE_MESH_ADAPTIVE);
    CHECK(tc_scene_mesh_kind_parse("quad", &k) == -1);
    tc_scene s;
    CHECK(tc_scene_init(&s, TC_SCENE_COUNT) == TC_EINVAL);
}

TEST(scenes_bad_options_and_free_null) {
    tc_scene s = scene(TC_SCENE_PENUMBRA);
    tc_scene_mesh_opts o;
    tc_scene_mesh *m = (tc_scene_mesh *)&o;
    tc_scene_mesh_opts_default(&o);
    o.density = 0;
    CHECK(tc_scene_mesh_new(&s, &o, &m) == TC_EINVAL && m == NULL);
    tc_scene_mesh_opts_default(&o);
    o.kind = TC_SCENE_MESH_ADAPTIVE, o.max_depth = 13;
    CHECK(tc_scene_mesh_new(&s, &o, &m) == TC_EINVAL);
    o.max_depth = 4, o.threshold = -1;
    CHECK(tc_scene_mesh_new(&s, &o, &m) == TC_EINVAL && m == NULL);
    tc_scene_mesh_free(NULL);
}

/* ---- values against independent computations ------------------------------------------- */

/* Form factor from a point to the rectangle [0,X]x[0,Y] (in units of the height)
 * parallel to it with a corner straight above (the classic closed form), and its
 * derivative in X. Both are odd in each argument. */
static double rect_g(double X, double Y) {
    double a = sqrt(1 + X * X), b = sqrt(1 + Y * Y);
    return (X / a * atan(Y / a) + Y / b * atan(X / b)) / (2 * PI);
}

static double rect_dg(double X, double Y) {
    double a2 = 1 + X * X, a = sqrt(a2);
    return (Y / (a2 * (a2 + Y * Y)) + atan(Y / a) / (a2 * a)) / (2 * PI);
}

/* F and grad F at (x, y) of the axis-aligned rectangle r at height c, by superposition. */
static double rect_ff(const double r[4], double c, double x, double y, double grad[2]) {
    double f = 0;
    grad[0] = grad[1] = 0;
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++) {
            double sg = (i ? 1 : -1) * (j ? 1 : -1), X = (r[2 * i] - x) / c, Y = (r[2 * j + 1] - y) / c;
            f += sg * rect_g(X, Y);
            grad[0] -= sg * rect_dg(X, Y) / c;
            grad[1] -= sg * rect_dg(Y, X) / c;
        }
    return f;
}

TEST(scenes_square_light_matches_closed_form) {
    tc_scene s = scene(TC_SCENE_SQUARE_LIGHT);
    double worst = 0, g[2];
    for (int i = 0; i <= 20; i++)
        for (int j = 0; j <= 20; j++) {
            double x = -0.2 + 1.4 * i / 20, y = -0.1 + 1.2 * j / 20;
            double exact = s.rho * rect_ff(s.light, s.light_z, x, y, g);
            worst = fmax(worst, fabs(tc_scene_value(&s, x, y) - exact) / s.scale);
        }
    CHECK_MSG(worst < 1e-14, "worst relative difference %.3g", worst);
    /* The penumbra scene's light alone, seen from where nothing is in the way. */
    tc_scene p = scene(TC_SCENE_PENUMBRA);
    CHECK_NEAR(tc_scene_value(&p, 0.95, 0.05), p.rho * rect_ff(p.light, p.light_z, 0.95, 0.05, g), 1e-16);
}

/* Flat occluder, everything axis-aligned: the hidden part of the light is the
 * rectangle light ∩ (occluder projected from the point), so F_visible is the
 * difference of two closed forms — independent of the polygon clipping. */
static double separable_ff(const tc_scene *s, double x, double y) {
    double k = s->light_z / s->occ_z0, hid[4], g[2];
    double p[2] = {x, y};
    for (int a = 0; a < 2; a++) {
        hid[a] = fmax(s->light[a], p[a] + (s->occ[a] - p[a]) * k);
        hid[a + 2] = fmin(s->light[a + 2], p[a] + (s->occ[a + 2] - p[a]) * k);
    }
    double f = rect_ff(s->light, s->light_z, x, y, g);
    if (hid[0] < hid[2] && hid[1] < hid[3]) f -= rect_ff(hid, s->light_z, x, y, g);
    return f;
}

TEST(scenes_flat_occluders_match_closed_form) {
    const tc_scene_id ids[] = {TC_SCENE_PENUMBRA, TC_SCENE_STIFF};
    for (int i = 0; i < 2; i++) {
        tc_scene s = scene(ids[i]);
        trng r;
        trng_seed(&r, 11);
        double worst = 0;
        for (int j = 0; j < 20000; j++) {
            /* half the points uniform, half within 1e-4 of the stiff scene's slivers */
            double x = trng_uniform(&r), y = trng_uniform(&r);
            if (j % 2) x = (j % 4 == 1 ? 0.31998 : 0.62001) + 4e-5 * (trng_uniform(&r) - 0.5);
            worst = fmax(worst, fabs(tc_scene_visibility(&s, x, y) - separable_ff(&s, x, y)));
        }
        CHECK_MSG(worst < 1e-14, "%s: worst |F - closed form| %.3g", tc_scene_name(ids[i]), worst);
        printf("  [closed form] %-8s 20000 points: worst |F - closed form| %.2g\n", tc_scene_name(ids[i]), worst);
    }
}

/* Ray (x, y, 0) -> l hits the occluder: the flat square, or the solid box (slabs). */
static int blocked(const tc_scene *s, double x, double y, const double l[3]) {
    if (s->occluder == TC_OCCLUDER_SQUARE) {
        double t = s->occ_z0 / l[2], px = x + t * (l[0] - x), py = y + t * (l[1] - y);
        return px >= s->occ[0] && px <= s->occ[2] && py >= s->occ[1] && py <= s->occ[3];
    }
    if (s->occluder != TC_OCCLUDER_BOX) return 0;
    double t0 = 0, t1 = s->occ_z1 / l[2], p[2] = {x, y};
    for (int a = 0; a < 2; a++) {
        double d = l[a] - p[a];
        if (d == 0) {
            if (p[a] < s->occ[a] || p[a] > s->occ[a + 2]) return 0;
            continue;
        }
        double ta = (s->occ[a] - p[a]) / d, tb = (s->occ[a + 2] - p[a]) / d;
        t0 = fmax(t0, fmin(ta, tb)), t1 = fmin(t1, fmax(ta, tb));
    }
    return t0 <= t1;
}

/* F by Monte Carlo over the light: mean of A cos cos / (pi r^2) V for uniform
 * points (parallel planes: cos = H / r on both ends). */
static void monte_carlo(const tc_scene *s, double x, double y, int n, trng *r, double *mean, double *se) {
    double A = (s->light[2] - s->light[0]) * (s->light[3] - s->light[1]), sum = 0, sum2 = 0, H = s->light_z;
    for (int i = 0; i < n; i++) {
        double l[3] = {s->light[0] + (s->light[2] - s->light[0]) * trng_uniform(r),
                       s->light[1] + (s->light[3] - s->light[1]) * trng_uniform(r), H};
        double dx = l[0] - x, dy = l[1] - y, r2 = dx * dx + dy * dy + H * H;
        double f = blocked(s, x, y, l) ? 0 : A * H * H / (PI * r2 * r2);
        sum += f, sum2 += f * f;
    }
    *mean = sum / n;
    *se = sqrt(fmax(sum2 / n - *mean * *mean, 0) / (n - 1));
}

static void check_monte_carlo(tc_scene_id id, const double (*pts)[2], int npts) {
    tc_scene s = scene(id);
    trng r;
    trng_seed(&r, 1994 + (uint64_t)id); /* fixed: the bound is 4 standard errors */
    double worst_z = 0, worst_rel = 0, biggest_se = 0;
    for (int i = 0; i < npts; i++) {
        double mc, se, f = tc_scene_visibility(&s, pts[i][0], pts[i][1]);
        monte_carlo(&s, pts[i][0], pts[i][1], 100000, &r, &mc, &se);
        CHECK_MSG(fabs(f - mc) <= 4 * se + 1e-15, "%s at (%g, %g): F %.10g, Monte Carlo %.10g +- %.3g",
                  tc_scene_name(id), pts[i][0], pts[i][1], f, mc, se);
        if (se > 0) worst_z = fmax(worst_z, fabs(f - mc) / se);
        if (f > 0) worst_rel = fmax(worst_rel, fabs(f - mc) / f);
        biggest_se = fmax(biggest_se, se / (f > 0 ? f : 1));
    }
    printf("  [monte carlo] %-12s %d points x 1e5 samples: worst |F - MC| = %.2f SE, worst relative %.2g, "
           "largest relative SE %.2g\n", tc_scene_name(id), npts, worst_z, worst_rel, biggest_se);
}

TEST(scenes_area_lights_agree_with_monte_carlo) {
    static const double square[20][2] = {
        {0.05, 0.1}, {0.05, 0.3}, {0.05, 0.5}, {0.05, 0.7}, {0.05, 0.95}, {0.3, 0.1}, {0.3, 0.3},
        {0.3, 0.5},  {0.3, 0.7},  {0.3, 0.95}, {0.55, 0.1}, {0.55, 0.3}, {0.55, 0.5}, {0.55, 0.7},
        {0.55, 0.95}, {0.8, 0.1}, {0.8, 0.3},  {0.8, 0.5},  {0.8, 0.7}, {0.99, 0.99}};
    static const double penumbra[20][2] = { /* umbra [0.29,0.59]x[0.39,0.69] */
        {0.4, 0.5},  {0.5, 0.6},  {0.3, 0.4},   {0.1, 0.5},  {0.7, 0.5}, {0.5, 0.2},  {0.45, 0.8},
        {0.1, 0.1},  {0.8, 0.9},  {0.6, 0.7},   {0.285, 0.5}, {0.95, 0.5}, {0.5, 0.05}, {0.95, 0.95},
        {0.02, 0.02}, {0.2, 0.3}, {0.75, 0.6},  {0.35, 0.75}, {0.9, 0.2}, {0.595, 0.385}};
    static const double box[20][2] = { /* footprint [0.4,0.6]^2, shadow out to ~0.356 / 0.644 */
        {0.5, 0.5},  {0.45, 0.58}, {0.38, 0.5}, {0.39, 0.39}, {0.36, 0.6},  {0.62, 0.45}, {0.5, 0.63},
        {0.5, 0.37}, {0.61, 0.61}, {0.65, 0.5}, {0.3, 0.3},   {0.37, 0.37}, {0.63, 0.36}, {0.1, 0.1},
        {0.9, 0.5},  {0.5, 0.9},   {0.2, 0.7},  {0.399, 0.5}, {0.5, 0.399}, {0.6001, 0.41}};
    static const double stiff[20][2] = { /* penumbrae x in [0.319967,0.319997], [0.619997,0.620027] */
        {0.319982, 0.5},  {0.31999, 0.45},  {0.319975, 0.6},  {0.62001, 0.5},   {0.5, 0.369985},
        {0.45, 0.670015}, {0.31998, 0.369985}, {0.4, 0.5},    {0.6199, 0.6},    {0.3199, 0.5},
        {0.3, 0.3},       {0.7, 0.8},       {0.5, 0.36996},   {0.5, 0.67006},   {0.1, 0.9},
        {0.9, 0.1},       {0.62003, 0.4},   {0.45, 0.3699719}, {0.620025, 0.67003}, {0.32, 0.37}};
    check_monte_carlo(TC_SCENE_SQUARE_LIGHT, square, 20);
    check_monte_carlo(TC_SCENE_PENUMBRA, penumbra, 20);
    check_monte_carlo(TC_SCENE_BOX, box, 20);
    check_monte_carlo(TC_SCENE_STIFF, stiff, 20);
}

TEST(scenes_point_shadow_matches_brute_force_visibility) {
    tc_scene s = scene(TC_SCENE_POINT_SHADOW);
    trng r;
    trng_seed(&r, 7);
    double l[3] = {s.light[0], s.light[1], s.light_z};
    int bad = 0, lit = 0;
    for (int i = 0; i < 20000; i++) {
        int grid = i < 101 * 101; /* a grid through the edges' neighbourhood, then random points */
        double x = grid ? (i % 101) / 100.0 : trng_uniform(&r), y = grid ? (i / 101) / 100.0 : trng_uniform(&r);
        if (fabs(fabs(x - 0.5) - 0.3) < 1e-12 || fabs(fabs(y - 0.5) - 0.3) < 1e-12) continue; /* on the edge */
        int vis = !blocked(&s, x, y, l);
        bad += vis != (tc_scene_visibility(&s, x, y) == 1);
        lit += vis;
        double dx = l[0] - x, dy = l[1] - y, r2 = dx * dx + dy * dy + 1;
        double expect = vis ? s.rho * s.emit * (1 / sqrt(r2)) / (PI * r2) : 0;
        if (fabs(tc_scene_value(&s, x, y) - expect) > 1e-15) bad++;
    }
    CHECK_MSG(bad == 0, "%d disagreements", bad);
    CHECK(lit > 5000 && lit < 15000);
}

/* B is invariant under the symmetries of its geometry, to rounding. */
static double asymmetry(const tc_scene *s) {
    double worst = 0;
    for (int i = 0; i <= 40; i++)
        for (int j = 0; j <= 40; j++) {
            double x = (i + 0.37) / 41, y = (j + 0.11) / 41, b = tc_scene_value(s, x, y);
            double im[3] = {tc_scene_value(s, 1 - x, y), tc_scene_value(s, x, 1 - y), tc_scene_value(s, y, x)};
            for (int k = 0; k < 3; k++) worst = fmax(worst, fabs(im[k] - b) / s->scale);
        }
    return worst;
}

TEST(scenes_symmetric_scenes_are_symmetric) {
    const tc_scene_id ids[] = {TC_SCENE_SQUARE_LIGHT, TC_SCENE_POINT_SHADOW, TC_SCENE_BOX};
    for (int i = 0; i < 3; i++) {
        tc_scene s = scene(ids[i]);
        double a = asymmetry(&s);
        CHECK_MSG(a < 1e-13, "%s: asymmetry %.3g", tc_scene_name(ids[i]), a);
    }
    /* The penumbra scene's occluder is off-centre: its shadow is not symmetric. */
    tc_scene p = scene(TC_SCENE_PENUMBRA);
    CHECK(asymmetry(&p) > 1e-3);
}

TEST(scenes_limits_from_each_side) {
    tc_scene ps = scene(TC_SCENE_POINT_SHADOW), box = scene(TC_SCENE_BOX), pen = scene(TC_SCENE_PENUMBRA);
    /* point-shadow: the shadow's edge x = 0.2; lit side = the smooth factor at the point */
    double in = tc_scene_value_from(&ps, 0.2, 0.5, 1, 0), out = tc_scene_value_from(&ps, 0.2, 0.5, -1, 0.3);
    CHECK(in == 0 && out > 0.2);
    CHECK_NEAR(out, tc_scene_value(&ps, 0.2 - 1e-9, 0.5), 1e-9);
    /* box: 0 under the box; outside, the limit of B approaching the contact line */
    double under = tc_scene_value_from(&box, 0.4, 0.5, 1, 0), side = tc_scene_value_from(&box, 0.4, 0.5, -1, 0);
    CHECK(under == 0 && side > 0.001);
    for (double t = 1e-3; t >= 1e-7; t /= 10) CHECK_NEAR(tc_scene_value(&box, 0.4 - t, 0.5), side, 1.0 * t);
    CHECK(tc_scene_value(&box, 0.4, 0.5) == 0); /* the dark side on the line itself */
    /* a footprint corner: one value for every outside direction (the diagonal's limit) */
    double diag = tc_scene_value_from(&box, 0.4, 0.4, -1, -1);
    CHECK(tc_scene_value_from(&box, 0.4, 0.4, 1, -0.2) == diag);
    CHECK_NEAR(tc_scene_value(&box, 0.4 - 1e-7, 0.4 - 1e-7), diag, 1e-6);
    /* continuous scenes: the limit is the value */
    CHECK(tc_scene_value_from(&pen, 0.29, 0.5, 1, 0) == tc_scene_value(&pen, 0.29, 0.5));
    CHECK(tc_scene_value_from(&pen, 0.29, 0.5, 0, 0) == tc_scene_value(&pen, 0.29, 0.5));
}

/* ---- events ----------------------------------------------------------------------------- */

static int has_event(const tc_scene *s, tc_continuity kind, int axis, double at, double lo, double hi) {
    for (int i = 0; i < s->nevents; i++) {
        const tc_scene_event *e = &s->events[i];
        if (e->kind == kind && e->axis == axis && fabs(e->at - at) < 1e-12 && fabs(e->lo - lo) < 1e-12 &&
            fabs(e->hi - hi) < 1e-12)
            return 1;
    }
    return 0;
}

TEST(scenes_events_follow_the_geometry) {
    tc_scene p = scene(TC_SCENE_PENUMBRA), q = scene(TC_SCENE_POINT_SHADOW), b = scene(TC_SCENE_BOX);
    tc_scene st = scene(TC_SCENE_STIFF), sq = scene(TC_SCENE_SQUARE_LIGHT);
    /* penumbra: x = 2o - l (H = 1, h = 0.5); x = -0.01 falls off the domain */
    CHECK(p.nevents == 7);
    const double px[3] = {0.29, 0.59, 0.89}, py[4] = {0.09, 0.39, 0.69, 0.99};
    for (int i = 0; i < 3; i++) CHECK(has_event(&p, TC_C0, 0, px[i], 0.09, 0.99));
    for (int i = 0; i < 4; i++) CHECK(has_event(&p, TC_C0, 1, py[i], 0, 0.89));
    CHECK(q.nevents == 4 && has_event(&q, TC_CM1, 0, 0.2, 0.2, 0.8) && has_event(&q, TC_CM1, 1, 0.8, 0.2, 0.8));
    CHECK(sq.nevents == 0);
    /* box: 4 contact lines, 4 top-edge lines, 8 face-plane segments */
    double o = (0.4 - 0.65 * 0.15) / 0.85, f = (0.6 - 0.35 * 0.15) / 0.85;
    CHECK(b.nevents == 16);
    for (int a = 0; a < 2; a++) {
        CHECK(has_event(&b, TC_CM1, a, 0.4, 0.4, 0.6) && has_event(&b, TC_CM1, a, 0.6, 0.4, 0.6));
        CHECK(has_event(&b, TC_C0, a, o, o, f) && has_event(&b, TC_C0, a, f, o, f));
        CHECK(has_event(&b, TC_C0, a, 0.4, o, 0.4) && has_event(&b, TC_C0, a, 0.6, 0.6, f));
    }
    /* stiff: penumbrae light side * h / (H - h) wide */
    double w = 0.3 * 1e-4 / (1 - 1e-4);
    CHECK(st.nevents == 8);
    double k = 1e-4 / (1 - 1e-4); /* h / (H - h): x = o + (o - l) k */
    CHECK(has_event(&st, TC_C0, 0, 0.32 - 0.03 * k, 0.37 - 0.28 * k, 0.67 + 0.32 * k));
    CHECK_NEAR(st.events[0].at - st.events[1].at, w, 1e-15);
}

/* ---- meshes ------------------------------------------------------------------------------- */

static int count_flags(const tc_mesh *cm, tc_continuity want) {
    int n = 0;
    for (int32_t t = 0; t < tc_mesh_triangle_count(cm); t++)
        for (int k = 0; k < 3; k++) {
            int nk;
            int32_t t2 = tc_mesh_neighbor(cm, t, k, &nk);
            if (t2 > t && tc_mesh_edge_flag(cm, t, k) == want) n++;
        }
    return n;
}

/* Every scene x kind x density: tc_mesh_new accepts it with gradients and
 * midpoints, the core reconstructs it, and the flags are where they belong. */
TEST(scenes_every_mesh_is_accepted) {
    const int dens[] = {2, 4, 8, 16};
    for (int id = 0; id < TC_SCENE_COUNT; id++)
        for (int kind = 0; kind < 3; kind++)
            for (int d = 0; d < 4; d++) {
                tc_scene s = scene((tc_scene_id)id);
                int n = kind == TC_SCENE_MESH_ADAPTIVE ? dens[d] / 2 : dens[d];
                tc_scene_mesh *m = mesh_of(&s, (tc_scene_mesh_kind)kind, n, 1);
                if (!m) continue;
                tc_mesh *cm = core_mesh(m);
                if (cm) {
                    CHECK(count_flags(cm, TC_C0) == m->flagged_c0 && count_flags(cm, TC_CM1) == m->flagged_cm1);
                    tc_options op;
                    tc_options_default(&op);
                    tc_recon *r = NULL;
                    CHECK(tc_recon_new(cm, &op, &r, NULL) == TC_OK);
                    tc_recon_free(r);
                }
                if (kind != TC_SCENE_MESH_DISC) CHECK(m->flagged_c0 + m->flagged_cm1 == 0);
                if (kind == TC_SCENE_MESH_UNIFORM)
                    CHECK(m->desc.nverts == (n + 1) * (n + 1) && m->desc.ntris == 2 * n * n);
                tc_mesh_free(cm);
                tc_scene_mesh_free(m);
            }
}

TEST(scenes_disc_meshes_carry_their_flags) {
    tc_scene p = scene(TC_SCENE_PENUMBRA), q = scene(TC_SCENE_POINT_SHADOW), b = scene(TC_SCENE_BOX);
    tc_scene st = scene(TC_SCENE_STIFF), sq = scene(TC_SCENE_SQUARE_LIGHT);
    tc_scene_mesh *m = mesh_of(&p, TC_SCENE_MESH_DISC, 8, 0);
    CHECK(m && m->flagged_c0 > 0 && m->flagged_cm1 == 0 && m->desc.c0.count > 0 && m->desc.ncorner_values == 0);
    tc_scene_mesh_free(m);
    m = mesh_of(&q, TC_SCENE_MESH_DISC, 8, 0);
    CHECK(m && m->flagged_cm1 > 0 && m->flagged_c0 == 0 && m->desc.cm1.count > 0 && m->desc.ncorner_values > 0);
    tc_scene_mesh_free(m);
    m = mesh_of(&b, TC_SCENE_MESH_DISC, 8, 0);
    CHECK(m && m->flagged_cm1 > 0 && m->flagged_c0 > 0);
    tc_scene_mesh_free(m);
    m = mesh_of(&sq, TC_SCENE_MESH_DISC, 8, 0);
    CHECK(m && m->flagged_c0 + m->flagged_cm1 == 0);
    tc_scene_mesh_free(m);
    /* stiff: slivers 3e-5 wide whose length is capped at 1/N by the refinement */
    for (int n = 1; n <= 16; n *= 2) {
        m = mesh_of(&st, TC_SCENE_MESH_DISC, n, 0);
        if (!m) continue;
        double expect = n <= 2 ? 1e4 : 0.3 / n / 3.0003e-5; /* longest sliver cell >= 0.3/N */
        CHECK_MSG(m->worst_aspect >= expect, "stiff N=%d: worst aspect %.4g", n, m->worst_aspect);
        tc_scene_mesh_free(m);
    }
}

/* One-sided second-order normal derivative of B at edge midpoint mid, on the
 * side sg * n, step h. */
static double side_derivative(const tc_scene *s, const double mid[2], const double n[2], double h, double sg) {
    double f[3];
    for (int j = 0; j < 3; j++)
        f[j] = tc_scene_value(s, mid[0] + sg * (j + 1) * h * n[0], mid[1] + sg * (j + 1) * h * n[1]);
    return sg * (-5 * f[0] + 8 * f[1] - 3 * f[2]) / (2 * h);
}

static double altitude(const double *xy, const int32_t *v, double len) {
    const double *a = xy + 2 * v[0], *b = xy + 2 * v[1], *c = xy + 2 * v[2];
    return fabs((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])) / len;
}

typedef struct {
    double c0_min, c1_max, cm1_min; /* smallest kink on C0, largest on C1, smallest jump on C-1 (/scale) */
    int bad;
} jump_report;

/* Samples B across one interior edge (triangles t, t2) and checks that its
 * flag matches the function: a value jump across C-1, a gradient jump across
 * C0, neither across C1. The flag came from the events, not from sampling. */
static void check_edge(const tc_scene *s, const tc_scene_mesh *m, const tc_mesh *cm, int32_t t, int k, int32_t t2,
                       jump_report *rep) {
    const double *xy = m->desc.xy;
    int32_t a = m->desc.tris[3 * t + k], b = m->desc.tris[3 * t + (k + 1) % 3];
    double ex = xy[2 * b] - xy[2 * a], ey = xy[2 * b + 1] - xy[2 * a + 1], len = hypot(ex, ey);
    double mid[2] = {0.5 * (xy[2 * a] + xy[2 * b]), 0.5 * (xy[2 * a + 1] + xy[2 * b + 1])};
    double n[2] = {-ey / len, ex / len};
    double alt = fmin(altitude(xy, m->desc.tris + 3 * t, len), altitude(xy, m->desc.tris + 3 * t2, len));
    double h = 1e-3 * fmin(len, alt); /* the samples stay well inside both triangles */
    tc_continuity f = tc_mesh_edge_flag(cm, t, k);
    double G = s->scale;
    if (f == TC_CM1) {
        double jump = fabs(tc_scene_value_from(s, mid[0], mid[1], n[0], n[1]) -
                           tc_scene_value_from(s, mid[0], mid[1], -n[0], -n[1]));
        rep->cm1_min = fmin(rep->cm1_min, jump / G);
        rep->bad += jump < 0.01 * G;
        return;
    }
    double dp = side_derivative(s, mid, n, h, 1), dm = side_derivative(s, mid, n, h, -1), kink = fabs(dp - dm);
    if (f == TC_C0) {
        rep->c0_min = fmin(rep->c0_min, kink / G);
        rep->bad += kink < 0.01 * G;
    } else {
        rep->c1_max = fmax(rep->c1_max, kink / G);
        rep->bad += kink > 1e-4 * G + 1e-5 * (fabs(dp) + fabs(dm));
    }
}

TEST(scenes_disc_flags_match_the_function) {
    const tc_scene_id ids[] = {TC_SCENE_PENUMBRA, TC_SCENE_POINT_SHADOW, TC_SCENE_BOX, TC_SCENE_STIFF};
    for (int i = 0; i < 4; i++)
        for (int n = 4; n <= 16; n *= 2) {
            tc_scene s = scene(ids[i]);
            tc_scene_mesh *m = mesh_of(&s, TC_SCENE_MESH_DISC, n, 0);
            tc_mesh *cm = m ? core_mesh(m) : NULL;
            if (!cm) {
                tc_scene_mesh_free(m);
                continue;
            }
            jump_report rep = {INFINITY, 0, INFINITY, 0};
            for (int32_t t = 0; t < m->desc.ntris; t++)
                for (int k = 0; k < 3; k++) {
                    int nk;
                    int32_t t2 = tc_mesh_neighbor(cm, t, k, &nk);
                    if (t2 > t) check_edge(&s, m, cm, t, k, t2, &rep);
                }
            CHECK_MSG(rep.bad == 0, "%s N=%d: %d edges whose flag the function contradicts", tc_scene_name(ids[i]), n,
                      rep.bad);
            if (n == 8)
                printf("  [flags] %-12s N=8: smallest kink on C0 %.3g, largest on C1 %.2g, smallest jump on C-1 %.3g "
                       "(x scale)\n", tc_scene_name(ids[i]), rep.c0_min, rep.c1_max, rep.cm1_min);
            tc_mesh_free(cm);
            tc_scene_mesh_free(m);
        }
}

TEST(scenes_grid_has_no_t_vertices_and_adaptive_is_conforming) {
    const tc_scene_mesh_kind kinds[] = {TC_SCENE_MESH_DISC, TC_SCENE_MESH_ADAPTIVE};
    tc_scene s = scene(TC_SCENE_BOX);
    for (int i = 0; i < 2; i++) {
        tc_scene_mesh *m = mesh_of(&s, kinds[i], 4, 0);
        tc_mesh *cm = m ? core_mesh(m) : NULL;
        if (!cm) {
            tc_scene_mesh_free(m);
            continue;
        }
        /* conforming: every boundary edge is on the domain's boundary; areas sum to 1 */
        const double *xy = m->desc.xy;
        double area = 0;
        int stray = 0;
        for (int32_t t = 0; t < m->desc.ntris; t++) {
            const int32_t *v = m->desc.tris + 3 * t;
            area += 0.5 * ((xy[2 * v[1]] - xy[2 * v[0]]) * (xy[2 * v[2] + 1] - xy[2 * v[0] + 1]) -
                           (xy[2 * v[1] + 1] - xy[2 * v[0] + 1]) * (xy[2 * v[2]] - xy[2 * v[0]]));
            for (int k = 0; k < 3; k++) {
                int nk;
                if (tc_mesh_neighbor(cm, t, k, &nk) >= 0) continue;
                const double *p = xy + 2 * v[k], *q = xy + 2 * v[(k + 1) % 3];
                int on = (p[0] == q[0] && (p[0] == 0 || p[0] == 1)) || (p[1] == q[1] && (p[1] == 0 || p[1] == 1));
                stray += !on;
            }
        }
        CHECK_MSG(stray == 0, "%s: %d interior edges with one triangle (T-vertices)",
                  tc_scene_mesh_kind_name(kinds[i]), stray);
        CHECK_NEAR(area, 1, 1e-12); /* counter-clockwise and no overlaps */
        tc_mesh_free(cm);
        tc_scene_mesh_free(m);
    }
}

TEST(scenes_adaptive_refines_where_the_shadow_is) {
    tc_scene s = scene(TC_SCENE_POINT_SHADOW);
    tc_scene_mesh_opts o;
    tc_scene_mesh_opts_default(&o);
    o.kind = TC_SCENE_MESH_ADAPTIVE, o.density = 4, o.max_depth = 5;
    tc_scene_mesh *m = NULL;
    CHECK(tc_scene_mesh_new(&s, &o, &m) == TC_OK && m);
    if (!m) return;
    /* the smallest triangles hug the shadow's edge, the largest are away from it */
    double smallest = INFINITY, where = 0;
    for (int32_t t = 0; t < m->desc.ntris; t++) {
        const int32_t *v = m->desc.tris + 3 * t;
        const double *a = m->desc.xy + 2 * v[0];
        double len = hypot(m->desc.xy[2 * v[1]] - a[0], m->desc.xy[2 * v[1] + 1] - a[1]);
        if (len < smallest) smallest = len, where = fmin(fabs(fabs(a[0] - 0.5) - 0.3), fabs(fabs(a[1] - 0.5) - 0.3));
    }
    CHECK(smallest < 1.0 / (4 << 4) && where < 0.05);
    CHECK(m->samples >= m->desc.nverts);
    /* 2:1 balanced: triangles sharing an edge differ in area by at most 2x
     * (a fan over a side or half a side, leaves at most one level apart) */
    tc_mesh *cm = core_mesh(m);
    double worst = 1;
    for (int32_t t = 0; cm && t < m->desc.ntris; t++)
        for (int k = 0; k < 3; k++) {
            int nk;
            int32_t t2 = tc_mesh_neighbor(cm, t, k, &nk);
            if (t2 < 0) continue;
            const int32_t *v = m->desc.tris + 3 * t, *w = m->desc.tris + 3 * t2;
            double a = altitude(m->desc.xy, v, 1), b = altitude(m->desc.xy, w, 1);
            worst = fmax(worst, fmax(a / b, b / a));
        }
    CHECK_MSG(worst <= 2 + 1e-9, "neighbouring areas differ by %.3gx", worst);
    tc_mesh_free(cm);
    tc_scene_mesh_free(m);
    o.threshold = 0.5; /* fewer splits */
    tc_scene_mesh *coarse = NULL;
    CHECK(tc_scene_mesh_new(&s, &o, &coarse) == TC_OK && coarse);
    tc_scene_mesh_free(coarse);
}

/* ---- samples ------------------------------------------------------------------------------ */

static double centroid_dir(const tc_scene_mesh *m, int32_t t, const double p[2], int d) {
    const int32_t *v = m->desc.tris + 3 * t;
    return (m->desc.xy[2 * v[0] + d] + m->desc.xy[2 * v[1] + d] + m->desc.xy[2 * v[2] + d]) / 3 - p[d];
}

/* The value tc_mesh_new will use at corner k of triangle t: the override if any. */
static double corner_value(const tc_mesh_desc *d, int32_t t, int k) {
    for (int32_t j = 0; j < d->ncorner_values; j++)
        if (d->corner_values_tri[j] == t) return d->corner_values[3 * j + k];
    return d->values[d->tris[3 * t + k]];
}

/* 1 if p is a corner of the box's footprint (where the outside limit is a fan). */
static int footprint_corner(const tc_scene *s, const double p[2]) {
    return s->occluder == TC_OCCLUDER_BOX && (p[0] == s->occ[0] || p[0] == s->occ[2]) &&
           (p[1] == s->occ[1] || p[1] == s->occ[3]);
}

/* Every corner's value is the limit from its triangle's side (the override
 * where the vertex is on a C-1 line and the sides differ); every midpoint
 * sample on a C-1 edge is its side's limit. */
TEST(scenes_corner_values_and_midpoints_take_each_side) {
    const tc_scene_id ids[] = {TC_SCENE_POINT_SHADOW, TC_SCENE_BOX};
    for (int i = 0; i < 2; i++) {
        tc_scene s = scene(ids[i]);
        tc_scene_mesh *m = mesh_of(&s, TC_SCENE_MESH_DISC, 8, 0);
        if (!m) continue;
        const tc_mesh_desc *d = &m->desc;
        int bad = 0, overrides = 0;
        for (int32_t t = 0; t < d->ntris; t++)
            for (int k = 0; k < 3; k++) {
                const double *p = d->xy + 2 * d->tris[3 * t + k];
                double z = corner_value(d, t, k);
                double want = tc_scene_value_from(&s, p[0], p[1], centroid_dir(m, t, p, 0), centroid_dir(m, t, p, 1));
                bad += !footprint_corner(&s, p) && z != want; /* there: one value per sector, see sampling.c */
                overrides += z != d->values[d->tris[3 * t + k]];
            }
        CHECK_MSG(bad == 0 && overrides > 0, "%s: %d corner values from the wrong side", tc_scene_name(ids[i]), bad);
        int per_side = 0;
        for (int32_t j = 0; j < d->nmidpoints; j++) {
            const int32_t *e = d->midpoint_edge + 2 * j;
            double mid[2] = {0.5 * (d->xy[2 * e[0]] + d->xy[2 * e[1]]),
                             0.5 * (d->xy[2 * e[0] + 1] + d->xy[2 * e[1] + 1])};
            int32_t t = d->midpoint_tri[j];
            double want = t < 0 ? tc_scene_value(&s, mid[0], mid[1])
                                : tc_scene_value_from(&s, mid[0], mid[1], centroid_dir(m, t, mid, 0),
                                                      centroid_dir(m, t, mid, 1));
            CHECK(d->midpoint_values[j] == want);
            per_side += t >= 0;
        }
        CHECK(per_side == 2 * m->flagged_cm1);
        tc_scene_mesh_free(m);
    }
}

/* Corner gradients: against the closed-form gradient of the unoccluded light,
 * and, on the penumbra's disc mesh, against central differences taken just
 * inside each triangle (so on the triangle's side of every kink). */
TEST(scenes_corner_gradients_are_accurate) {
    tc_scene s = scene(TC_SCENE_SQUARE_LIGHT);
    tc_scene_mesh *m = mesh_of(&s, TC_SCENE_MESH_UNIFORM, 8, 1);
    double worst = 0, gmax = 0;
    for (int32_t t = 0; m && t < m->desc.ntris; t++)
        for (int k = 0; k < 3; k++) {
            const double *p = m->desc.xy + 2 * m->desc.tris[3 * t + k], *g = m->desc.corner_gradients + 6 * t + 2 * k;
            double ge[2];
            rect_ff(s.light, s.light_z, p[0], p[1], ge);
            worst = fmax(worst, hypot(g[0] - s.rho * ge[0], g[1] - s.rho * ge[1]));
            gmax = fmax(gmax, s.rho * hypot(ge[0], ge[1]));
        }
    CHECK_MSG(worst < 1e-9 * gmax, "square-light: worst gradient error %.3g (max |grad| %.3g)", worst, gmax);
    printf("  [gradients] square-light uniform N=8: worst error %.2g, relative to max |grad B| %.2g\n", worst,
           worst / gmax);
    tc_scene_mesh_free(m);

    tc_scene p = scene(TC_SCENE_PENUMBRA);
    m = mesh_of(&p, TC_SCENE_MESH_DISC, 8, 1);
    worst = 0;
    for (int32_t t = 0; m && t < m->desc.ntris; t++)
        for (int k = 0; k < 3; k++) {
            const double *v = m->desc.xy + 2 * m->desc.tris[3 * t + k], *g = m->desc.corner_gradients + 6 * t + 2 * k;
            double q[2] = {v[0] + 1e-6 * centroid_dir(m, t, v, 0), v[1] + 1e-6 * centroid_dir(m, t, v, 1)}, h = 1e-9;
            double gx = (tc_scene_value(&p, q[0] + h, q[1]) - tc_scene_value(&p, q[0] - h, q[1])) / (2 * h);
            double gy = (tc_scene_value(&p, q[0], q[1] + h) - tc_scene_value(&p, q[0], q[1] - h)) / (2 * h);
            worst = fmax(worst, hypot(g[0] - gx, g[1] - gy));
        }
    CHECK_MSG(worst < 1e-4 * p.scale, "penumbra: worst corner gradient error %.3g", worst);
    tc_scene_mesh_free(m);
}

/* ---- JSON ---------------------------------------------------------------------------------- */

static int same_doubles(const double *a, const double *b, size_t n) {
    return n == 0 || (a && b && memcmp(a, b, n * sizeof *a) == 0);
}
static int same_ints(const int32_t *a, const int32_t *b, size_t n) {
    return n == 0 || (a && b && memcmp(a, b, n * sizeof *a) == 0);
}

static int same_lines(const tc_polylines *a, const tc_polylines *b) {
    return a->count == b->count && (a->count == 0 || (same_ints(a->start, b->start, (size_t)a->count + 1) &&
                                                      same_ints(a->verts, b->verts, (size_t)a->start[a->count])));
}

static int same_mask(const uint8_t *a, const uint8_t *b, size_t n) {
    for (size_t i = 0; i < n; i++)
        if ((a ? a[i] != 0 : 1) != (b ? b[i] != 0 : 1)) return 0;
    return 1;
}

/* Writes d, reads it back and compares every array bit for bit. */
static void check_round_trip(const tc_mesh_desc *d, const tc_options *o) {
    tc_strbuf b;
    tc_strbuf_init(&b);
    tc_json_request(&b, d, o);
    CHECK(!b.oom && b.len > 2 && b.buf[b.len - 2] == '}' && b.buf[b.len - 1] == '\n');
    tc_request *r = NULL;
    tc_diags dg;
    tc_diags_init(&dg);
    int st = tc_request_parse(b.buf, b.len, TC_REQ_MESH, &r, &dg);
    CHECK_MSG(st == TC_REQ_OK && dg.count == 0, "parse: %s %s", dg.count ? dg.items[0].path : "",
              dg.count ? dg.items[0].message : "");
    if (r) {
        const tc_mesh_desc *e = &r->desc;
        size_t C = (size_t)d->nchan, nv = (size_t)d->nverts;
        CHECK(e->nverts == d->nverts && e->ntris == d->ntris && e->nchan == d->nchan && r->values_plain == (C == 1));
        CHECK(same_doubles(e->xy, d->xy, 2 * nv) && same_ints(e->tris, d->tris, 3 * (size_t)d->ntris));
        CHECK(same_doubles(e->values, d->values, nv * C));
        CHECK(e->ncorner_values == d->ncorner_values &&
              same_ints(e->corner_values_tri, d->corner_values_tri, (size_t)d->ncorner_values) &&
              same_doubles(e->corner_values, d->corner_values, 3 * C * (size_t)d->ncorner_values));
        CHECK(!d->gradients == !e->gradients && same_mask(e->gradients_mask, d->gradients_mask, nv));
        for (size_t v = 0; d->gradients && v < nv; v++)
            if (!d->gradients_mask || d->gradients_mask[v])
                CHECK(same_doubles(e->gradients + 2 * C * v, d->gradients + 2 * C * v, 2 * C));
        CHECK(!d->normals == !e->normals && same_mask(e->normals_mask, d->normals_mask, nv));
        CHECK(!d->normals || same_doubles(e->normals, d->normals, 3 * C * nv));
        size_t ncg = (size_t)d->ncorner_gradients;
        CHECK(e->ncorner_gradients == d->ncorner_gradients &&
              same_ints(e->corner_gradients_tri, d->corner_gradients_tri, ncg) &&
              same_mask(e->corner_gradients_mask, d->corner_gradients_mask, 3 * ncg));
        for (size_t c = 0; c < 3 * ncg; c++)
            if (!d->corner_gradients_mask || d->corner_gradients_mask[c])
                CHECK(same_doubles(e->corner_gradients + 2 * C * c, d->corner_gradients + 2 * C * c, 2 * C));
        CHECK(e->nmidpoints == d->nmidpoints &&
              same_ints(e->midpoint_edge, d->midpoint_edge, 2 * (size_t)d->nmidpoints) &&
              same_doubles(e->midpoint_values, d->midpoint_values, C * (size_t)d->nmidpoints));
        for (int32_t i = 0; i < d->nmidpoints; i++)
            CHECK(e->midpoint_tri[i] == (d->midpoint_tri ? d->midpoint_tri[i] : -1));
        CHECK(same_lines(&e->c0, &d->c0) && same_lines(&e->cm1, &d->cm1));
        if (o) CHECK(memcmp(&r->opt, o, sizeof *o) == 0);
    }
    tc_request_free(r);
    tc_diags_free(&dg);
    tc_strbuf_free(&b);
}

TEST(scenes_request_json_round_trips) {
    /* a scene mesh with everything a scene produces */
    tc_scene s = scene(TC_SCENE_BOX);
    tc_scene_mesh *m = mesh_of(&s, TC_SCENE_MESH_DISC, 4, 1);
    tc_options o;
    tc_options_default(&o);
    if (m) check_round_trip(&m->desc, &o);
    tc_scene_mesh_free(m);
    /* three channels, masks, awkward numbers, no options */
    const double xy[] = {0, 0, 1, 0, 1, 1, 0.1, 1.0 / 3};
    const int32_t tris[] = {0, 1, 2, 0, 2, 3};
    double vals[12], grads[24], cg[36], nrm[36], mv[6];
    for (int i = 0; i < 12; i++) vals[i] = i == 3 ? -0.0 : i == 5 ? 1e-300 : (i + 0.1) / 7;
    for (int i = 0; i < 24; i++) grads[i] = (i - 11) * 1.0e10 / 3;
    for (int i = 0; i < 36; i++) cg[i] = sqrt(i + 2.0), nrm[i] = i % 3 == 2 ? 1 + i : -i / 9.0;
    for (int i = 0; i < 6; i++) mv[i] = exp(i);
    const uint8_t gmask[] = {1, 0, 1, 1}, cgmask[] = {1, 1, 0};
    const int32_t cgt[] = {1}, cvt[] = {0}, me[] = {0, 2, 1, 2}, mt[] = {1, -1}, ls[] = {0, 2}, lv[] = {0, 2};
    double cv[9] = {1, 2, 3, 4, 5, 6, 7, 8, 9};
    tc_mesh_desc d = {0};
    d.nverts = 4, d.xy = xy, d.ntris = 2, d.tris = tris, d.nchan = 3, d.values = vals;
    d.ncorner_values = 1, d.corner_values_tri = cvt, d.corner_values = cv;
    d.gradients = grads, d.gradients_mask = gmask;
    d.ncorner_gradients = 1, d.corner_gradients_tri = cgt, d.corner_gradients = cg, d.corner_gradients_mask = cgmask;
    d.nmidpoints = 2, d.midpoint_edge = me, d.midpoint_tri = mt, d.midpoint_values = mv;
    d.c0 = (tc_polylines){1, ls, lv};
    check_round_trip(&d, NULL);
    d.gradients = NULL, d.gradients_mask = NULL, d.normals = nrm; /* normals instead */
    d.nchan = 1, d.ncorner_gradients = 0, d.c0.count = 0, d.cm1 = (tc_polylines){1, ls, lv};
    check_round_trip(&d, NULL);
}
