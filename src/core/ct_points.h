/* ct_points.h — the Clough-Tocher value and gradient at four scattered points at once, each in
 * its own triangle: tc__frame_at + tc__ct_eval + tc__floored, lane for lane (ct_points.c). */
#ifndef TC_CORE_CT_POINTS_H
#define TC_CORE_CT_POINTS_H

#include <stdint.h>

#include "core/geom.h"

/* One point: its triangle's frame and ordinates [nc][19], where it is, and
 * where its values [nc] and (if g) gradients [nc][2] go. */
typedef struct {
    const tc__eval_frame *f;
    const double *coef;
    double x, y;
    double *v, *g;
} tc__ct_lane;

/* Evaluates four lanes (a lane may repeat another: same results, written
 * twice). Every double is the one tc_eval_triangle gives for that point and
 * triangle: the same IEEE operations in the same order, branches turned into
 * exact selections. floor0[ch]: clamp negative values of channel ch to 0. */
void tc__ct_points4(const tc__ct_lane lane[4], int nc, const uint8_t *floor0);

/* Tests: 1 forces the portable build, 0 lets the CPU choose (AVX2 when present). */
void tc__ct_points_force_generic(int on);

#endif
