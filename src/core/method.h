/* method.h — one row per reconstruction method: everything the core knows about
 * a method (src/core/method.c). recon, the overlay and the names all read it. */
#ifndef TC_CORE_METHOD_H
#define TC_CORE_METHOD_H

#include "core/geom.h"
#include "core/wedge.h"

struct tc_recon;

/* Value (and gradient if grad != NULL) of one channel of one triangle's piece
 * from its coefficients, at the point described by `at`. */
typedef void (*tc__piece_eval)(const double *coef, const tc__eval_point *at, double *value, double *grad);

/* Fills r->coef ([nt][nc][ncoef], allocated by tc_recon_new) and, for a method
 * with tangent planes, r->planes. r->method is this row. */
typedef int (*tc__method_build)(struct tc_recon *r, tc_diags *dg);

/* Invariants: methods[m] describes tc_method m; labels has ncoef entries;
 * `smooth` is TC_C1, TC_C0 or TC_CM1 and `honour` a TC_HONOR_* of wedge.h. */
typedef struct {
    const char *name;           /* as in requests ("clough-tocher") */
    int ncoef;                  /* coefficients per triangle and channel */
    const char *const *labels;  /* [ncoef], as in /v1/ordinates */
    tc__method_build build;
    tc__piece_eval eval;
    int honour;                 /* which interior flags cut it (its wedges, its jumps) */
    int8_t smooth;              /* the most continuity it has across an interior edge it
                                 * does not cut: TC_C1, TC_C0 (linear) or TC_CM1 (constant) */
    unsigned uses;              /* TC__USES_* (option_table.h): what it is built with, which
                                 * decides the options it reads (tc_method_reads) */
    int quads_only;             /* needs a mesh given as quads (and patches span both halves) */
    int ordinates;              /* its first `ordinates` coefficients are Bézier ordinates that
                                 * bound its pieces (range.h); 0: it cannot leave its data's range */
} tc__method;

/* The row of method m, or NULL if m is not a method. */
const tc__method *tc__method_of(tc_method m);

/* The continuity the reconstruction has across edge id e (3t+k): the edge's
 * flag as the method honours it, capped by what the method reaches anywhere. */
static inline int tc__method_edge(const tc__method *mt, const struct tc_mesh *m, int32_t e) {
    int f = tc__eff_flag(m, mt->honour, e);
    return f < mt->smooth ? f : mt->smooth;
}

#endif
