/* geom.h — small planar geometry helpers shared by the core modules.
 * Everything works on differences of points, never on raw world coordinates. */
#ifndef TC_CORE_GEOM_H
#define TC_CORE_GEOM_H

#include <float.h>
#include <math.h>
#include <string.h>

#include "core/fhypot.h"
#include "core/mesh.h"
#include "core/minmax.h"

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
    return fabs(e1[0] * e2[1] - e1[1] * e2[0]) > 16 * DBL_EPSILON * tc__hypot(e1[0], e1[1]) * tc__hypot(e2[0], e2[1]);
}

/* Directions a and b (from a common vertex) point in opposite directions on
 * one line: the two sides of a 180 degree wedge. */
static inline int tc__antiparallel_within(const double a[2], const double b[2], double tol) {
    return fabs(tc__cross(a, b)) <= tol * tc__hypot(a[0], a[1]) * tc__hypot(b[0], b[1]) && tc__dot(a, b) < 0;
}
static inline int tc__antiparallel(const double a[2], const double b[2]) {
    return tc__antiparallel_within(a, b, TC_COLLINEAR_TOL);
}

/* A C0 line through a vertex this close to straight (|sin| of the bend) keeps a
 * fading kink there (wedgeplane.c): the vertex is classed C0, not C1, so the
 * reconstruction changes continuously as a line is bent through straight. */
#define TC_STRAIGHT_BAND 1e-9

/* Where a triangle's piece is evaluated: barycentric coordinates in the
 * triangle (given vertex order), the gradients of lam[1] and lam[2], and the
 * point relative to the triangle's first corner (for pieces that need the
 * position itself, such as a bilinear map's inverse). */
typedef struct {
    double lam[3];
    double dl1[2], dl2[2];
    double d[2];
} tc__eval_point;

/* What evaluating at many points of one triangle shares: its corners, each
 * edge opposite corner i (e = b - a with a = corner i+1, b = corner i+2), the
 * reciprocals of the areas corner i sees from a and from b, and the constant
 * gradients of lam[1] and lam[2] (grad lam[0] = -(dl1 + dl2)). Every
 * evaluation — a point, a pixel, a span of pixels — goes through tc__frame and
 * tc__frame_at, so the same point gives the same bits whichever path asked. */
typedef struct {
    double p[3][2];
    double e[3][2];
    double inv_a[3], inv_b[3];
    double dl1[2], dl2[2];
} tc__eval_frame;

/* The frame's edges and inv_a from its corners f->p: all the renderer's fast cubic reads
 * (ct_fast.h), with the corners from the locator's slot (raster_cover.c). */
static inline void tc__frame_edges(tc__eval_frame *f) {
    for (int i = 0; i < 3; i++) {
        const double *a = f->p[(i + 1) % 3], *b = f->p[(i + 2) % 3];
        double ca[2];
        tc__sub(f->e[i], b, a);
        tc__sub(ca, f->p[i], a);
        f->inv_a[i] = 1 / tc__cross(f->e[i], ca);
    }
}

/* The rest of the frame (inv_b, the gradients) once tc__frame_edges has run. */
static inline void tc__frame_rest(tc__eval_frame *f) {
    for (int i = 0; i < 3; i++) {
        double cb[2];
        tc__sub(cb, f->p[i], f->p[(i + 2) % 3]);
        f->inv_b[i] = 1 / tc__cross(f->e[i], cb);
    }
    double e1[2], e2[2];
    tc__sub(e1, f->p[1], f->p[0]);
    tc__sub(e2, f->p[2], f->p[0]);
    double inv = 1 / tc__cross(e1, e2);
    f->dl1[0] = e2[1] * inv, f->dl1[1] = -e2[0] * inv;
    f->dl2[0] = -e1[1] * inv, f->dl2[1] = e1[0] * inv;
}

static inline void tc__frame(const struct tc_mesh *m, int32_t t, tc__eval_frame *f) {
    TC_ASSERT(t >= 0 && t < m->nt && f);
    const int32_t *v = m->tri + 3 * (size_t)t;
    for (int i = 0; i < 3; i++) {
        const double *q = tc__vxy(m, v[i]);
        f->p[i][0] = q[0], f->p[i][1] = q[1];
    }
    tc__frame_edges(f);
    tc__frame_rest(f);
}

/* Each lam[i] is the signed area over the point and the edge opposite corner
 * i, measured from that edge's end nearer the point, over the area seen from
 * the same end: small for points near the edge whatever the far corner's
 * distance (needles), exactly 0 at the edge's two corners and within an ulp
 * of 1 at corner i (a product with a reciprocal, not a quotient: one division
 * per triangle instead of three per point; the evaluators' difference form
 * makes the corners exact). The three need not sum to 1 in the last bit. */
static inline void tc__frame_at(const tc__eval_frame *f, double x, double y, tc__eval_point *at) {
    for (int i = 0; i < 3; i++) {
        const double *a = f->p[(i + 1) % 3], *b = f->p[(i + 2) % 3];
        double dax = x - a[0], day = y - a[1], dbx = x - b[0], dby = y - b[1];
        int near_b = dbx * dbx + dby * dby < dax * dax + day * day; /* short d: little cancellation */
        double d[2] = {near_b ? dbx : dax, near_b ? dby : day};
        at->lam[i] = tc__cross(f->e[i], d) * (near_b ? f->inv_b[i] : f->inv_a[i]);
    }
    at->dl1[0] = f->dl1[0], at->dl1[1] = f->dl1[1];
    at->dl2[0] = f->dl2[0], at->dl2[1] = f->dl2[1];
    at->d[0] = x - f->p[0][0];
    at->d[1] = y - f->p[0][1];
}

static inline void tc__at(const struct tc_mesh *m, int32_t t, double x, double y, tc__eval_point *at) {
    tc__eval_frame f;
    tc__frame(m, t, &f);
    tc__frame_at(&f, x, y, at);
}

/* Triangle t's area (>= 0). */
static inline double tc__face_area(const struct tc_mesh *m, int32_t t) {
    const int32_t *v = m->tri + 3 * (size_t)t;
    double e1[2], e2[2];
    tc__sub(e1, tc__vxy(m, v[1]), tc__vxy(m, v[0]));
    tc__sub(e2, tc__vxy(m, v[2]), tc__vxy(m, v[0]));
    return 0.5 * fabs(tc__cross(e1, e2));
}

/* Triangle t's longest edge over its shortest altitude (2/sqrt(3) when
 * equilateral, 2 for a grid's right triangle); infinite when degenerate. */
static inline double tc__face_aspect(const struct tc_mesh *m, int32_t t) {
    const int32_t *v = m->tri + 3 * (size_t)t;
    double e[3][2], longest = 0;
    for (int k = 0; k < 3; k++) {
        tc__sub(e[k], tc__vxy(m, v[(k + 1) % 3]), tc__vxy(m, v[k]));
        longest = tc__fmax(longest, tc__hypot(e[k][0], e[k][1]));
    }
    double twice_area = fabs(tc__cross(e[0], e[2]));
    return twice_area > 0 ? longest * longest / twice_area : INFINITY;
}

/* Barycentric coordinates of (x, y) in triangle t and the gradients of lam[1]
 * and lam[2], as tc__frame_at computes them. */
static inline void tc__bary(const struct tc_mesh *m, int32_t t, double x, double y,
                            double lam[3], double dl1[2], double dl2[2]) {
    tc__eval_point at;
    tc__at(m, t, x, y, &at);
    memcpy(lam, at.lam, sizeof at.lam);
    memcpy(dl1, at.dl1, sizeof at.dl1);
    memcpy(dl2, at.dl2, sizeof at.dl2);
}

#endif
