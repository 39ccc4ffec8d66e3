/* linear.h — the baselines (linear.c): constant, linear and linear4, as rows of the
 * method table read them (labels, build, evaluator). */
#ifndef TC_CORE_LINEAR_H
#define TC_CORE_LINEAR_H

#include "core/geom.h"

struct tc_recon;

extern const char *const tc__constant_labels[1];
extern const char *const tc__linear_labels[3];
extern const char *const tc__linear4_labels[6];
int tc__constant_build(struct tc_recon *r, tc_diags *dg);
int tc__linear_build(struct tc_recon *r, tc_diags *dg);
int tc__linear4_build(struct tc_recon *r, tc_diags *dg);
void tc__constant_eval(const double *coef, const tc__eval_point *at, double *value, double *grad);
void tc__linear_eval(const double *coef, const tc__eval_point *at, double *value, double *grad);
void tc__linear4_eval(const double *coef, const tc__eval_point *at, double *value, double *grad);

#endif
