/* tangent.h — each corner's input tangent plane and the wedge planes built
 * from them (FindOrdinates' WedgeNormal, paper Figure 6). */
#ifndef TC_CORE_TANGENT_H
#define TC_CORE_TANGENT_H

#include "core/wedge.h"

/* inputs[3nt][nc][2]: the plane each corner brings, per the `tangents` option;
 * cz[3nt][nc] are the corner values the reconstruction uses. */
int tc__corner_inputs(const struct tc_mesh *m, const tc__wedge_set *ws, const double *cz, tc_tangents mode,
                      double *inputs, tc_diags *dg);

/* out[nw][nc][2]: one plane per wedge from the corners' inputs — the average,
 * then for wedges with C0 sides the adjustment of Figure 6 steps 3-4, either
 * corrected or literal. Fails only for `literal` when its Project is singular. */
int tc__wedge_planes(const struct tc_mesh *m, const tc__wedge_set *ws, const double *inputs, tc_wedges mode,
                     tc_average average, double *out, tc_diags *dg);

#endif
