/* plane.h — tangent planes through a known point, held as gradients (dz/dx, dz/dy).
 * The paper averages unit normals; these helpers do that in gradient form. */
#ifndef TC_CORE_PLANE_H
#define TC_CORE_PLANE_H

#include <math.h>

#include "core/assert.h"
#include "core/fhypot.h"

/* Adds the unit upward normal of the plane with gradient g to the sum S.
 * The normal of z = g.x is (-g, 1) / |(-g, 1)|; S[2] stays positive. */
static inline void tc__normal_acc(double S[3], const double g[2]) {
    double inv = 1.0 / tc__hypot(1.0, tc__hypot(g[0], g[1]));
    S[0] -= g[0] * inv;
    S[1] -= g[1] * inv;
    S[2] += inv;
}

/* The gradient of the plane whose (unnormalized, upward) normal is S. */
static inline void tc__normal_to_grad(const double S[3], double g[2]) {
    g[0] = -S[0] / S[2];
    g[1] = -S[1] / S[2];
}

/* The paper's Avg(N, N') for two planes given by gradients; symmetric in its
 * arguments bit for bit, so both wedges at an edge compute the same plane. */
static inline void tc__avg2(const double a[2], const double b[2], double out[2]) {
    double S[3] = {0, 0, 0};
    tc__normal_acc(S, a);
    tc__normal_acc(S, b);
    tc__normal_to_grad(S, out);
}

/* Solves g.a = ra, g.b = rb for g (a, b not parallel). */
static inline void tc__solve2(const double a[2], const double b[2], double ra, double rb, double g[2]) {
    double det = a[0] * b[1] - a[1] * b[0];
    g[0] = (ra * b[1] - rb * a[1]) / det;
    g[1] = (a[0] * rb - b[0] * ra) / det;
}

/* Replaces the slope of g along direction d by that of target, keeping g's
 * slope across d: the gradient form of the paper's Project, which never divides
 * by anything but |d|^2. */
static inline void tc__match_along(const double g[2], const double target[2], const double d[2], double out[2]) {
    TC_ASSERT(d[0] != 0 || d[1] != 0);
    double s = ((target[0] - g[0]) * d[0] + (target[1] - g[1]) * d[1]) / (d[0] * d[0] + d[1] * d[1]);
    out[0] = g[0] + s * d[0];
    out[1] = g[1] + s * d[1];
}

#endif
