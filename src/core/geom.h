/* geom.h — small planar geometry helpers shared by the core modules.
 * Everything works on differences of points, never on raw world coordinates. */
#ifndef TC_CORE_GEOM_H
#define TC_CORE_GEOM_H

#include <float.h>
#include <math.h>

#include "core/mesh.h"

/* Relative tolerance below which two edge directions count as collinear
 * (|sin| of the angle between them). Far below any meaningful mesh angle, far
 * above the rounding of points placed on a line by interpolation (~1e-16). */
#define TC_COLLINEAR_TOL 1e-12

static inline double tc__cross(const double a[2], const double b[2]) {
    return a[0] * b[1] - a[1] * b[0];
}
static inline double tc__dot(const double a[2], const double b[2]) {
    return a[0] * b[0] + a[1] * b[1];
}
static inline void tc__sub(double out[2], const double a[2], const double b[2]) {
    out[0] = a[0] - b[0];
    out[1] = a[1] - b[1];
}

/* Triangle (p0, p1, p2) has non-zero area: |(p1-p0) x (p2-p0)| above
 * 16 eps |p1-p0| |p2-p0|, i.e. relative to the two edges from p0, so slivers of
 * any aspect ratio pass while the sign of their area is above rounding. */
static inline int tc__nonzero_area(const double p0[2], const double p1[2], const double p2[2]) {
    double e1[2] = {p1[0] - p0[0], p1[1] - p0[1]}, e2[2] = {p2[0] - p0[0], p2[1] - p0[1]};
    return fabs(e1[0] * e2[1] - e1[1] * e2[0]) > 16 * DBL_EPSILON * hypot(e1[0], e1[1]) * hypot(e2[0], e2[1]);
}

/* Directions a and b (from a common vertex) point in opposite directions on
 * one line: the two sides of a 180 degree wedge. */
static inline int tc__antiparallel_within(const double a[2], const double b[2], double tol) {
    return fabs(tc__cross(a, b)) <= tol * hypot(a[0], a[1]) * hypot(b[0], b[1]) && tc__dot(a, b) < 0;
}
static inline int tc__antiparallel(const double a[2], const double b[2]) {
    return tc__antiparallel_within(a, b, TC_COLLINEAR_TOL);
}

/* A C0 line through a vertex this close to straight (|sin| of the bend) keeps a
 * fading kink there (wedgeplane.c): the vertex is classed C0, not C1, so the
 * reconstruction changes continuously as a line is bent through straight. */
#define TC_STRAIGHT_BAND 1e-9

/* Barycentric coordinates of (x, y) in triangle t (in the given vertex order)
 * and the constant gradients of lam[1] and lam[2]; grad lam[0] = -(dl1 + dl2).
 * Each lam[i] is the signed area over the point and the edge opposite corner i,
 * measured from that edge's end nearer the point and divided by the area seen
 * from the same end: small for points near the edge whatever the far corner's distance
 * (needles), and exactly 1 and 0 at the corners. The three need not sum to 1
 * in the last bit; the evaluators work in difference form and do not care. */
static inline void tc__bary(const struct tc_mesh *m, int32_t t, double x, double y,
                            double lam[3], double dl1[2], double dl2[2]) {
    const int32_t *v = m->tri + 3 * (size_t)t;
    const double *p[3] = {tc__vxy(m, v[0]), tc__vxy(m, v[1]), tc__vxy(m, v[2])};
    for (int i = 0; i < 3; i++) {
        const double *a = p[(i + 1) % 3], *b = p[(i + 2) % 3];
        double da = (x - a[0]) * (x - a[0]) + (y - a[1]) * (y - a[1]);
        double db = (x - b[0]) * (x - b[0]) + (y - b[1]) * (y - b[1]);
        const double *o = db < da ? b : a; /* the end nearer the point: short d, little cancellation */
        double e[2], d[2] = {x - o[0], y - o[1]}, c[2];
        tc__sub(e, b, a);
        tc__sub(c, p[i], o);
        lam[i] = tc__cross(e, d) / tc__cross(e, c);
    }
    double e1[2], e2[2];
    tc__sub(e1, p[1], p[0]);
    tc__sub(e2, p[2], p[0]);
    double det = tc__cross(e1, e2);
    dl1[0] = e2[1] / det;
    dl1[1] = -e2[0] / det;
    dl2[0] = -e1[1] / det;
    dl2[1] = e1[0] / det;
}

/* Where a triangle's piece is evaluated: barycentric coordinates in the
 * triangle (given vertex order), the gradients of lam[1] and lam[2], and the
 * point relative to the triangle's first corner (for pieces that need the
 * position itself, such as a bilinear map's inverse). */
typedef struct {
    double lam[3];
    double dl1[2], dl2[2];
    double d[2];
} tc_at;

static inline void tc__at(const struct tc_mesh *m, int32_t t, double x, double y, tc_at *at) {
    const double *p0 = tc__vxy(m, m->tri[3 * (size_t)t]);
    tc__bary(m, t, x, y, at->lam, at->dl1, at->dl2);
    at->d[0] = x - p0[0];
    at->d[1] = y - p0[1];
}

#endif
