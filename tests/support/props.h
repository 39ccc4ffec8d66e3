/* props.h — shared checks of reconstruction properties used by several test
 * files: continuity residuals, scales, the standard smooth test function
 * (continuity.c), convergence and reproduction errors (props.c). */
#ifndef TC_TEST_PROPS_H
#define TC_TEST_PROPS_H

#include "meshgen.h"
#include "tocher.h"

typedef struct { double corner, c0, c1, vertex, internal; } cont_report;

void smooth_f(const void *ctx, double x, double y, int ch, double *v, double g[2]);
void recon_scales(const tc_recon *r, double *vs, double *gs);
/* Checks (CHECK) interpolation and every continuity the flags promise, each
 * relative residual <= tol; fills rep with the worst residuals. */
void check_continuity(const tc_recon *r, const tmesh *g, double tol, cont_report *rep);
void random_flagged_mesh(tmesh *g, trng *r, int delaunay, int n);
/* Worst mismatch of value (over vs) and gradient (over gs) between the pieces of
 * t and its neighbour along their shared edge k, at five points along it. */
void edge_residual(const tc_recon *r, int32_t t, int k, double vs, double gs, double *rv, double *rg);

/* The smooth function the convergence tests refine on, with its gradient. */
void wave_f(const void *ctx, double x, double y, int ch, double *v, double g[2]);
/* Max |rec - wave_f| over a fixed cloud of 4000 points, located on an n x n
 * grid split along diagonal 0 (tmesh_grid(.., diag 0)): cell, then side. */
double grid_max_error(const tc_recon *rec, int n);

/* Exact data for reproduction tests: linear and quadratic, per channel. */
void linear_data(const void *ctx, double x, double y, int ch, double *v, double g[2]);
void quadratic_data(const void *ctx, double x, double y, int ch, double *v, double g[2]);
/* Worst relative error of value (and gradient when check_grad) against f at
 * npts random points inside random triangles (barycentric sampling). */
double tri_reproduction_error(const tc_recon *rec, tfunc f, int npts, trng *r, int check_grad);

/* Removes the warnings of range "free" (how far the unlimited reconstruction
 * leaves its data's range) from d, so a test can assert "no other finding". */
void drop_range_free_warnings(tc_diags *d);

#endif
