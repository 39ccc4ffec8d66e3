/* formfactor.h — the geometry behind the analytic scenes: Lambert's point-to-polygon
 * form factor, central projection onto the light's plane, convex hulls and clipping. */
#ifndef TC_SCENES_FORMFACTOR_H
#define TC_SCENES_FORMFACTOR_H

/* A convex polygon in a horizontal plane, vertices counter-clockwise seen from
 * above (+z). The scenes need at most 4 (light) + 8 (box hull) vertices after
 * clipping; the bound leaves room and is checked on every append. */
#define TC__POLY_MAX 24
typedef struct {
    int n;
    double v[TC__POLY_MAX][2];
} tc__poly;

/* Form factor from the receiver point (x, y, 0), normal +z, to the polygon p lying
 * in the plane z = height > 0 (Lambert's formula, exact):
 *     F = 1/(2 pi) |sum_i angle(R_i, R_i+1) * (unit(R_i x R_i+1) . z)|,
 * R_i = vertex i - point. Coincident consecutive vertices contribute nothing. */
double tc__form_factor(const tc__poly *p, double height, double x, double y);

/* Central projection of q (0 < q[2] < height) from the receiver point (x, y, 0)
 * onto the plane z = height. */
void tc__project(double x, double y, const double q[3], double height, double out[2]);

/* 2 * signed area of triangle abc (> 0 counter-clockwise), computed about the
 * vertex opposite the longest side: the rounding error is then eps times the
 * product of the two shorter sides, so points 1e9 away (the clipped box's
 * projection) do not swamp the orientation of points near the light. */
double tc__orient(const double a[2], const double b[2], const double c[2]);

/* Convex hull of n <= TC__POLY_MAX points, counter-clockwise, collinear points
 * dropped (Andrew's monotone chain). Fewer than 3 output vertices: degenerate. */
void tc__hull(const double (*pts)[2], int n, tc__poly *out);

/* subject ∩ clip for convex counter-clockwise polygons (Sutherland-Hodgman:
 * the subject clipped by each edge's half-plane in turn). out->n < 3 when the
 * intersection has no area. out may not alias the inputs. */
void tc__clip(const tc__poly *subject, const tc__poly *clip, tc__poly *out);

/* 1 if (x, y) lies in the closed convex polygon p (boundary included). */
int tc__inside(const tc__poly *p, double x, double y);

#endif
