/* recon.h — struct tc_recon and the per-method pieces it dispatches to.
 * A method is its coefficient layout plus an evaluator of one triangle's piece. */
#ifndef TC_CORE_RECON_H
#define TC_CORE_RECON_H

#include "core/geom.h"

/* Value (and gradient if grad != NULL) of one channel of one triangle's piece
 * from its coefficients, at the point described by `at`. */
typedef void (*tc_piece_eval)(const double *coef, const tc_at *at, double *value, double *grad);

struct tc_recon {
    const struct tc_mesh *m;
    tc_options opt;
    int ncoef;
    const char *const *labels; /* [ncoef] */
    tc_piece_eval eval;
    double *coef;              /* [nt][nc][ncoef] */
    double *cgrad;             /* [3nt][nc][2] corner planes used, or NULL */
};

/* linear.c: the baselines. Each fills r->coef (allocated by the caller). */
extern const char *const tc__constant_labels[1];
extern const char *const tc__linear_labels[3];
extern const char *const tc__linear4_labels[6];
void tc__constant_build(const struct tc_mesh *m, double *coef);
void tc__linear_build(const struct tc_mesh *m, double *coef);
void tc__linear4_build(const struct tc_mesh *m, double *coef, tc_diags *dg);
void tc__constant_eval(const double *o, const tc_at *at, double *value, double *grad);
void tc__linear_eval(const double *o, const tc_at *at, double *value, double *grad);
void tc__linear4_eval(const double *o, const tc_at *at, double *value, double *grad);

/* powell_sabin.c and hermite.c: each fills r->ncoef, r->labels, r->eval and
 * r->coef (allocating it) for its method. */
int tc__ps_build(struct tc_recon *r, tc_diags *dg);
int tc__hermite_build(struct tc_recon *r, tc_diags *dg);

#endif
