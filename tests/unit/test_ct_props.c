/* test_ct_props.c — the continuity properties of clough-tocher on randomized
 * meshes: interpolation, C0 across C0/C1 edges, C1 across C1 edges, at C1
 * vertices and inside each triangle, for every cross_boundary rule. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "core/ct.h"
#include "core/geom.h"
#include "meshgen.h"
#include "props.h"


TEST(ct_continuity_randomized_meshes) {
    trng r;
    trng_seed(&r, tc_test_seed());
    const tc_cross crosses[] = {TC_CROSS_NORMAL, TC_CROSS_SALESIN, TC_CROSS_AFFINE};
    const tc_tangents sources[] = {TC_TANGENTS_GIVEN, TC_TANGENTS_MIDPOINTS, TC_TANGENTS_ESTIMATE, TC_TANGENTS_AUTO};
    cont_report worst = {0};
    for (int trial = 0; trial < 16; trial++) {
        tmesh g;
        random_flagged_mesh(&g, &r, trial % 2, 12 + 4 * trng_int(&r, 2));
        tc_tangents src = sources[trial % 4];
        tmesh_sample(&g, 1 + trng_int(&r, 3), smooth_f, NULL, src == TC_TANGENTS_GIVEN, src != TC_TANGENTS_GIVEN, 0.3);
        tc_mesh *m = tmesh_build(&g);
        for (int ci = 0; m && ci < 4; ci++) {
            tc_options o;
            tc_options_default(&o);
            o.cross_boundary = crosses[ci % 3];
            if (ci == 3) o.method = TC_METHOD_CLOUGH_TOCHER_C1; /* flags ignored: C1 across every edge */
            o.tangents = src;
            tc_recon *rec = NULL;
            CHECK(tc_recon_new(m, &o, &rec, NULL) == TC_OK);
            if (!rec) continue;
            cont_report rep;
            check_continuity(rec, &g, 1e-10, &rep);
            worst.c0 = fmax(worst.c0, rep.c0), worst.c1 = fmax(worst.c1, rep.c1);
            worst.vertex = fmax(worst.vertex, rep.vertex), worst.internal = fmax(worst.internal, rep.internal);
            worst.corner = fmax(worst.corner, rep.corner);
            tc_recon_free(rec);
        }
        tc_mesh_free(m);
        tmesh_free(&g);
    }
    fprintf(stderr, "  [continuity] worst relative residuals: corner %.2g, C0 %.2g, C1 edge %.2g, C1 vertex %.2g, "
                    "internal %.2g\n", worst.corner, worst.c0, worst.c1, worst.vertex, worst.internal);
}

/* wedges "literal" with cross_boundary "salesin" on random flagged meshes
 * with per-corner data (issue 14: all six of an outside test were refused as
 * "singular" where Project's normal only pointed down). Every one builds, and
 * continuity holds as for the other rules. */
TEST(ct_literal_salesin_random_meshes_build) {
    trng r;
    trng_seed(&r, tc_test_seed() + 14);
    int refused = 0;
    cont_report worst = {0};
    for (int trial = 0; trial < 6; trial++) {
        tmesh g;
        random_flagged_mesh(&g, &r, trial % 2, 12 + 4 * (trial / 2 % 2));
        tmesh_sample(&g, 1 + trial % 3, smooth_f, NULL, 1, 0, 0.3);
        tc_mesh *m = tmesh_build(&g);
        tc_options o;
        tc_options_default(&o);
        o.cross_boundary = TC_CROSS_SALESIN, o.wedges = TC_WEDGES_LITERAL, o.tangents = TC_TANGENTS_GIVEN;
        o.range = TC_RANGE_FREE;
        tc_diags dg;
        tc_diags_init(&dg);
        tc_recon *rec = NULL;
        int st = m ? tc_recon_new(m, &o, &rec, &dg) : TC_EINVAL;
        if (st != TC_OK) {
            refused++;
            tc_test_fail(__FILE__, __LINE__, "trial %d refused: %s", trial, dg.count ? dg.items[0].message : "-");
        }
        if (rec) {
            cont_report rep;
            check_continuity(rec, &g, 1e-10, &rep);
            worst.c0 = fmax(worst.c0, rep.c0), worst.c1 = fmax(worst.c1, rep.c1);
        }
        tc_recon_free(rec);
        tc_diags_free(&dg);
        tc_mesh_free(m);
        tmesh_free(&g);
    }
    fprintf(stderr, "  [literal salesin] 6 random flagged meshes: %d refused; C0 %.2g, C1 %.2g\n", refused, worst.c0,
            worst.c1);
}
