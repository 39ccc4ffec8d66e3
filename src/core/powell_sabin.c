/* powell_sabin.c — the C1 quadratic Powell-Sabin 6-split reconstruction.
 * (Placeholder until the method lands: refuses with a clear message.) */
#include "core/recon.h"

int tc__ps_build(struct tc_recon *r, tc_diags *dg) {
    (void)r;
    return tc_diags_add(dg, TC_SEV_ERROR, "method", "powell-sabin is not available yet");
}
