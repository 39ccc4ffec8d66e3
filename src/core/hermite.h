/* hermite.h — bicubic Hermite patches over quads: the coefficient layout and
 * the pieces tests reach into (the bilinear map's inverse, one patch's evaluation). */
#ifndef TC_CORE_HERMITE_H
#define TC_CORE_HERMITE_H

#include "core/geom.h"

/* Per split triangle and channel: the 16 bicubic Bézier ordinates b_ij at
 * 4i + j (i along s from a to b, j along t from a to d), then the quad's
 * corners b, c, d relative to a (the triangle's first corner) at
 * TC_HERMITE_GEOM: xb yb xc yc xd yd. Both halves of a quad hold the same. */
enum { TC_HERMITE_GEOM = 16, TC_HERMITE_COEFS = 22 };
extern const char *const tc__hermite_labels[TC_HERMITE_COEFS];

/* The parameters par = (s, t) with x(s, t) = d for the bilinear map of the convex
 * quad P[0..3] (P[0] = 0: corners relative to the first), x(s, t) =
 * s P1 + t P3 + st (P2 - P1 - P3). Exact at the four corners; inside the quad
 * the root in [0,1]^2 (a value within 1e-10, SQUARE_SNAP, outside is clamped onto it); outside,
 * the nearest real solution, or the nearest point of the map's fold when
 * there is none. Always finite. */
void tc__bilinear_inverse(const double P[4][2], const double d[2], double par[2]);

struct tc_recon;

/* The method row's build: tangent planes (pipeline.h), twists, patches. */
int tc__hermite_build(struct tc_recon *r, tc_diags *dg);

/* Value and gradient (grad may be NULL) of one channel's patch at `at`. */
void tc__hermite_eval(const double *coef, const tc__eval_point *at, double *value, double *grad);

#endif
