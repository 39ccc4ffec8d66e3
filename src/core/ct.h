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

/* tc__ct_iij[i][j]: the edge ordinate next to corner i towards corner j;
 * tc__ct_cij[k]: the cross-boundary ordinate of edge k (corners k, k+1). */
extern const int tc__ct_iij[3][3];
extern const int tc__ct_cij[3];

/* Recomputes the ordinates the cross-boundary ones determine (ccu ccv ccw
 * ccc: the C1 conditions across the internal edges) after they changed. */
void tc__ct_close(double *o);

typedef struct {
    const struct tc_mesh *m;
    const tc__wedge_set *ws;
    const double *cz;   /* [3nt][nc] corner values used */
    const double *planes; /* [3nt][nc][2] each corner's wedge plane (after WedgeNormal, and
                           * range-limited): what the edge ordinates are built from */
    const double *inputs; /* [3nt][nc][2] each corner's input plane, before its wedge's
                           * were reconciled (the paper's N_u; salesin reads them) */
    tc_cross cross;
    tc_tangents tangents; /* where the corner planes came from (the range limiter trusts given ones) */
    tc_wedges wedges;   /* literal: salesin uses the paper's 3D Project */
    int by_area;        /* average "area" with corrected wedges: salesin's Avg is a plain mean */
    int threads;        /* for the per-triangle loop (tc_options.threads); no effect on the result */
} tc__ct_input;

/* Fills coef[nt][nc][19]. Fails only for salesin+literal where Project is singular. */
int tc__ct_ordinates(const tc__ct_input *ci, double *coef, tc_diags *dg);

/* ct_range.c: as tc__ct_ordinates, but first the wedge planes in `planes`
 * (the array ci->planes points to) are limited and afterwards the cross-boundary
 * ordinates, so every ordinate stays inside the bound of `mode` (range.h). */
int tc__ct_ordinates_ranged(const tc__ct_input *ci, tc_range mode, double *planes, double *coef, tc_diags *dg);

struct tc_recon;

/* The method row's build of the cubics (clough-tocher, clough-tocher-c1;
 * pipeline.c): the tangent-plane pipeline, then the ordinates (limited unless
 * range is free). */
int tc__ct_build(struct tc_recon *r, tc_diags *dg);

/* Value and gradient of the piece with ordinates o at `at`. grad may be NULL. */
void tc__ct_eval(const double *o, const tc__eval_point *at, double *value, double *grad);

/* The ten ordinates of the subtriangle opposite corner m, as b300 b030 b003
 * b210 b120 b201 b021 b102 b012 b111 with a = m+1, b = m+2 and c the centroid. */
extern const int tc__ct_sub[3][10];

/* Values (no gradients) of n pixel centres (xs[i], y) of one row, all owned by
 * the triangle with frame f and ordinates coef[nc][19]: out[i * nc + ch] is
 * (float) of exactly the double tc__frame_at + tc__ct_eval give there — the
 * same operations lane for lane, four pixels at a time (ct_span.c). dout, if
 * not NULL, gets the doubles themselves (tests: a float hides most last-bit slips). */
void tc__ct_span(const tc__eval_frame *f, const double *coef, int nc, const double *xs, double y, int32_t n,
                 float *out, double *dout);
/* Tests: 1 forces the portable (SSE2) build of tc__ct_span, 0 lets the CPU choose. */
void tc__ct_span_force_generic(int on);

/* Same, on the subtriangle opposite corner `sub` (0..2) whatever lam says:
 * the subtriangle pieces extended, for testing continuity across their edges. */
void tc__ct_eval_sub(const double o[TC_CT_ORDINATES], int sub, const double lam[3], const double dl1[2],
                     const double dl2[2], double *value, double *grad);

#endif
