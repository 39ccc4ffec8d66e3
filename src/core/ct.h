/* ct.h — Clough-Tocher cubic pieces: the 19 Bézier ordinates of a triangle's three
 * subtriangles (paper Figure 5) and their evaluation. */
#ifndef TC_CORE_CT_H
#define TC_CORE_CT_H

#include "core/geom.h"
#include "core/wedge.h"

/* Ordinate indices in the paper's order. u, v, w are the triangle's vertices
 * as given; c is its centroid. */
enum {
    CT_UUU, CT_VVV, CT_WWW, CT_UUV, CT_UUW, CT_UVV, CT_UWW, CT_VVW, CT_VWW,
    CT_CUU, CT_CVV, CT_CWW, CT_CCU, CT_CCV, CT_CCW, CT_CUV, CT_CUW, CT_CVW, CT_CCC
};

extern const char *const tc__ct_labels[TC_CT_ORDINATES];

typedef struct {
    const struct tc_mesh *m;
    const tc_wedge_set *ws;
    const double *cz;   /* [3nt][nc] corner values used */
    const double *cg;   /* [3nt][nc][2] corner planes after WedgeNormal */
    const double *in;   /* [3nt][nc][2] corner input planes (the paper's N_u; salesin) */
    tc_cross cross;
    tc_wedges wedges;   /* literal: salesin uses the paper's 3D Project */
    int by_area;        /* average "area" with corrected wedges: salesin's Avg is a plain mean */
} tc_ct_input;

/* Fills coef[nt][nc][19]. Fails only for salesin+literal where Project is singular. */
int tc__ct_ordinates(const tc_ct_input *in, double *coef, tc_diags *dg);

/* Value and gradient of the piece with ordinates o at `at`. grad may be NULL. */
void tc__ct_eval(const double *o, const tc_at *at, double *value, double *grad);

/* Same, on the subtriangle opposite corner `sub` (0..2) whatever lam says:
 * the subtriangle pieces extended, for testing continuity across their edges. */
void tc__ct_eval_sub(const double o[TC_CT_ORDINATES], int sub, const double lam[3], const double dl1[2],
                     const double dl2[2], double *value, double *grad);

#endif
