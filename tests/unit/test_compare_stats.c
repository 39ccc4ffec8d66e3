/* test_compare_stats.c — error statistics against a reference: each figure computed by
 * hand on a case small enough to check, and points outside the mesh left out. */
#include <math.h>

#include "check.h"
#include "tocher.h"

TEST(error_stats_by_hand) {
    /* Unit square, linear data z = x: linear reconstructs it exactly, so the
     * error at each point is exactly the offset put into the reference. */
    static const double xy[] = {0, 0, 1, 0, 1, 1, 0, 1};
    static const int32_t tri[] = {0, 1, 2, 0, 2, 3};
    static const double z[] = {0, 1, 1, 0};
    tc_mesh_desc d = {0};
    d.nverts = 4, d.xy = xy, d.ntris = 2, d.tris = tri, d.nchan = 1, d.values = z;
    tc_mesh *m = NULL;
    tc_recon *r = NULL;
    tc_locator *L = NULL;
    CHECK(tc_mesh_new(&d, &m, NULL) == TC_OK);
    tc_options o;
    tc_options_default(&o);
    o.method = TC_METHOD_LINEAR;
    if (m) CHECK(tc_recon_new(m, &o, &r, NULL) == TC_OK);
    if (m) CHECK(tc_locator_new(m, &L) == TC_OK);
    if (!r || !L) return;
    const double pts[] = {0.25, 0.5, 0.5, 0.5, 0.75, 0.25, 2.0, 2.0}; /* the last is outside */
    const double ref[] = {0.25 + 0.1, 0.5 - 0.3, 0.75, 123};
    tc_error_stats e;
    CHECK(tc_compare(r, L, 4, pts, ref, 2.0, &e) == TC_OK);
    CHECK(e.n == 3 && e.outside == 1);
    CHECK_NEAR(e.max_abs, 0.3, 1e-15);
    CHECK_NEAR(e.rms, sqrt((0.01 + 0.09) / 3), 1e-15);
    CHECK_NEAR(e.mean_rel, (0.1 + 0.3) / 3 / 2.0, 1e-15);
    CHECK(e.scale == 2.0);
    CHECK(tc_compare(r, L, 3, pts, ref, 0, &e) == TC_OK); /* default scale: max |ref| */
    CHECK_NEAR(e.scale, 0.75, 0);
    CHECK_NEAR(e.mean_rel, (0.1 + 0.3) / 3 / 0.75, 1e-15);
    tc_locator_free(L);
    tc_recon_free(r);
    tc_mesh_free(m);
}
