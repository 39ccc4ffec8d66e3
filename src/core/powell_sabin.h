/* powell_sabin.h — the C1 quadratic Powell-Sabin 6-split (powell_sabin.c): its
 * coefficient layout, its row's build and evaluator, and one piece for tests. */
#ifndef TC_CORE_POWELL_SABIN_H
#define TC_CORE_POWELL_SABIN_H

#include "core/geom.h"

struct tc_recon;

/* TC_PS_COEFS coefficients per triangle and channel (layout in tocher.h at
 * tc_recon_coefs): the first TC_PS_ORDINATES are Bézier ordinates, the rest
 * the split geometry. */
enum { TC_PS_COEFS = 25, TC_PS_ORDINATES = 19 };
extern const char *const tc__ps_labels[TC_PS_COEFS];
int tc__ps_build(struct tc_recon *r, tc_diags *dg);
void tc__ps_eval(const double *coef, const tc__eval_point *at, double *value, double *grad);

/* Piece p (0..5) of the 6-split extended to any point, for tests: piece 2k + h
 * lies on edge k, next to its corner k (h = 0) or k+1 (h = 1). */
void tc__ps_eval_piece(const double *coef, int piece, const double lam[3], const double dl1[2], const double dl2[2],
                       double *value, double *grad);

#endif
