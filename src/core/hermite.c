/* hermite.c — bicubic Hermite patches over quads through the bilinear map.
 * (Placeholder until the method lands: refuses with a clear message.) */
#include "core/recon.h"

int tc__hermite_build(struct tc_recon *r, tc_diags *dg) {
    (void)r;
    return tc_diags_add(dg, TC_SEV_ERROR, "method", "hermite is not available yet");
}
