/* test_methods.c — the method table (src/core/method.c) against what the
 * methods do: names both ways, coefficient labels, and the options each reads. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "props.h"
#include "quadgen.h"

TEST(methods_table_names_round_trip) {
    int n = tc_method_count();
    CHECK(n >= 7);
    for (int i = 0; i < n; i++) {
        const char *name = tc_method_name((tc_method)i);
        tc_method back = (tc_method)-1;
        CHECK_MSG(name && tc_method_parse(name, &back) == 0 && back == (tc_method)i, "method %d (%s)", i,
                  name ? name : "no name");
    }
    tc_method x;
    CHECK(tc_method_name((tc_method)n) == NULL && tc_method_name((tc_method)-1) == NULL);
    CHECK(tc_method_parse("clough_tocher", &x) == -1 && tc_method_parse(NULL, &x) == -1);
    CHECK(tc_method_reads((tc_method)n) == 0 && tc_method_quads_only(TC_METHOD_HERMITE));
    CHECK(!tc_method_quads_only(TC_METHOD_CLOUGH_TOCHER));
}

/* The options table: one row per field of tc_options but the method (the
 * core asserts the count at compile time), names both ways, value 0 the
 * default, distinct TC_READS_* bits; the request's table has them all. */
TEST(methods_option_table) {
    tc_options def, o;
    tc_options_default(&def);
    unsigned seen = 0;
    for (int i = 0; i < tc_option_count(); i++) {
        const char *name = tc_option_name(i);
        CHECK_MSG(name && tc_option_bit(i) && !(seen & tc_option_bit(i)), "option %d (%s): bit %#x", i,
                  name ? name : "?", tc_option_bit(i));
        seen |= tc_option_bit(i);
        CHECK(tc_option_get(&def, i) == 0 && tc_option_value_name(i, 0) && tc_option_value_name(i, 1));
        for (int v = 0; tc_option_value_name(i, v); v++) {
            o = def;
            tc_option_set(&o, i, v);
            CHECK(tc_option_get(&o, i) == v);
        }
    }
    CHECK(tc_option_name(tc_option_count()) == NULL && tc_option_value_name(0, 99) == NULL);
}

static void wavy(const void *ctx, double x, double y, int ch, double *v, double g[2], double h[3]) {
    (void)ctx;
    double a = 1 + 0.5 * ch;
    *v = sin(2 * a * x) * cos(1.3 * y) + x * y;
    g[0] = 2 * a * cos(2 * a * x) * cos(1.3 * y) + y;
    g[1] = -1.3 * sin(2 * a * x) * sin(1.3 * y) + x;
    h[0] = -4 * a * a * sin(2 * a * x) * cos(1.3 * y);
    h[1] = -2.6 * a * cos(2 * a * x) * sin(1.3 * y) + 1;
    h[2] = -1.69 * sin(2 * a * x) * cos(1.3 * y);
}

/* Each coefficient of r equals that of base, bit for bit. */
static int same_coefs(const tc_recon *r, const tc_recon *base) {
    const tc_mesh *m = tc_recon_mesh(base);
    size_t n = (size_t)tc_mesh_triangle_count(m) * (size_t)tc_mesh_channel_count(m) * (size_t)tc_recon_coef_count(base);
    return tc_recon_coef_count(r) == tc_recon_coef_count(base) && !memcmp(tc_recon_coefs(r), tc_recon_coefs(base),
                                                                          n * sizeof(double));
}

/* Method i on m: its labels are as many as its coefficients, and every value
 * of every option it does not read (tc_method_reads; the options of the core's
 * table, tc_option_*) leaves every coefficient the same. */
static void check_reads(const tc_mesh *m, tc_method method) {
    tc_options o;
    tc_options_default(&o);
    o.method = method;
    tc_recon *base = NULL;
    if (tc_recon_new(m, &o, &base, NULL) != TC_OK) {
        tc_test_fail(__FILE__, __LINE__, "%s does not build", tc_method_name(method));
        return;
    }
    int nk = tc_recon_coef_count(base);
    for (int k = 0; k < nk; k++) CHECK(tc_recon_coef_label(base, k) != NULL);
    CHECK(tc_recon_coef_label(base, nk) == NULL);
    for (int i = 0; i < tc_option_count(); i++) {
        if (tc_method_reads(method) & tc_option_bit(i)) continue;
        for (int v = 1; tc_option_value_name(i, v); v++) {
            tc_options o2 = o;
            tc_option_set(&o2, i, v);
            tc_recon *r = NULL;
            CHECK(tc_recon_new(m, &o2, &r, NULL) == TC_OK);
            CHECK_MSG(r && same_coefs(r, base), "%s changes with %s \"%s\", which it does not read",
                      tc_method_name(method), tc_option_name(i), tc_option_value_name(i, v));
            tc_recon_free(r);
        }
    }
    tc_recon_free(base);
}

/* fn on every method: the triangle methods on a flagged mesh with C-1 jumps and
 * midpoint samples (so every face has its own plane and the averaging and wedge
 * rules matter); the quad methods on a jittered quad grid. */
static void each_method(uint64_t seed, void (*fn)(const tc_mesh *m, tc_method method)) {
    trng rng;
    trng_seed(&rng, seed);
    tmesh g;
    random_flagged_mesh(&g, &rng, 0, 12);
    tmesh_sample(&g, 2, smooth_f, NULL, 0, 1, 0.3);
    tc_mesh *m = tmesh_build(&g);
    for (int i = 0; m && i < tc_method_count(); i++)
        if (!tc_method_quads_only((tc_method)i)) fn(m, (tc_method)i);
    tc_mesh_free(m);
    tmesh_free(&g);
    qmesh q;
    qgrid_opts go = {0.2, 1, {0}, {0}};
    qmesh_grid(&q, 5, 4, &go, &rng);
    qmesh_sample(&q, 2, wavy, NULL);
    tc_mesh_desc d;
    qmesh_desc(&q, 0, 0, &d);
    m = NULL;
    CHECK(tc_mesh_new(&d, &m, NULL) == TC_OK);
    for (int i = 0; m && i < tc_method_count(); i++)
        if (tc_method_quads_only((tc_method)i)) fn(m, (tc_method)i);
    tc_mesh_free(m);
    qmesh_free(&q);
}

TEST(methods_ignore_the_options_they_do_not_read) { each_method(tc_test_seed() + 71, check_reads); }

/* Method i on m with a deadline: long past, it stops with TC_ETIMEOUT, no
 * reconstruction and no finding: it stopped at the first check, after the wedges
 * for the tangent-plane methods, before the stages whose warnings these meshes
 * raise (steep midpoint planes, range limits, C0 flags read as C1); far ahead,
 * the same coefficients as without. (The later checks only matter for a deadline
 * that passes mid-build: test_daemon_load's deadline check sees them.) */
static void check_deadline(const tc_mesh *m, tc_method method) {
    tc_options o;
    tc_options_default(&o);
    o.method = method;
    tc_recon *base = NULL;
    CHECK(tc_recon_new(m, &o, &base, NULL) == TC_OK);
    tc_recon *r = base; /* not NULL: the failed build must clear it */
    o.deadline_ms = 1.0; /* tc_now_ms() counts from boot: long past */
    tc_diags dg;
    tc_diags_init(&dg);
    CHECK_MSG(tc_recon_new(m, &o, &r, &dg) == TC_ETIMEOUT && r == NULL && dg.count == 0,
              "%s: past its deadline (%d findings: %s)", tc_method_name(method), dg.count,
              dg.count ? dg.items[0].message : "");
    tc_diags_free(&dg);
    o.deadline_ms = tc_now_ms() + 3.6e6;
    r = NULL;
    CHECK(tc_recon_new(m, &o, &r, NULL) == TC_OK);
    CHECK_MSG(r && base && same_coefs(r, base), "%s: a deadline ahead changed the coefficients",
              tc_method_name(method));
    tc_recon_free(r);
    tc_recon_free(base);
}

TEST(methods_stop_at_the_deadline) { each_method(tc_test_seed() + 73, check_deadline); }
