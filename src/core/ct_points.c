/* ct_points.c — the Clough-Tocher value and gradient at four scattered points at once, each lane
 * with its own triangle: the arithmetic of tc__frame_at + tc__ct_eval (geom.h, ct.c) lane for lane.
 *
 * Invariant: every lane performs exactly the IEEE operations the scalar path performs, in the
 * same order on the same operands. Branches of the scalar code (the nearer edge end, the
 * subtriangle, the reference ordinate) become computing every alternative and selecting
 * bitwise (an exact operation); nothing is reassociated, nothing is fused (-std=c11 keeps
 * -ffp-contract=off, and no FMA target is enabled). If the scalar code changes, this file must
 * change with it: tests/unit/test_points.c compares every double, with the AVX2 build and with
 * the portable one. Vectors pass only between always-inline functions of this file, never
 * across an ABI boundary (the Makefile silences GCC's -Wpsabi note). */
#include <string.h>

#include "core/cpu.h"
#include "core/ct.h"
#include "core/ct_lanes.h"
#include "core/vec4.h"
#include "core/ct_points.h"


#define INLINE TC__V4_INLINE

/* Field `expr` (of frame f) of the four lanes. */
#define GATHER(L, expr) ((tc__v4d){(L)[0].f->expr, (L)[1].f->expr, (L)[2].f->expr, (L)[3].f->expr})

/* tc__frame_at's lam[q], lane by lane. */
INLINE tc__v4d lam_of(const tc__ct_lane *L, int q, tc__v4d x, tc__v4d y) {
    int a = (q + 1) % 3, b = (q + 2) % 3;
    tc__v4d dax = x - GATHER(L, p[a][0]), day = y - GATHER(L, p[a][1]);
    tc__v4d dbx = x - GATHER(L, p[b][0]), dby = y - GATHER(L, p[b][1]);
    tc__v4i near_b = (dbx * dbx + dby * dby) < (dax * dax + day * day);
    tc__v4d dx = tc__sel(near_b, dbx, dax), dy = tc__sel(near_b, dby, day);
    tc__v4d cross = GATHER(L, e[q][0]) * dy - GATHER(L, e[q][1]) * dx;
    return cross * tc__sel(near_b, GATHER(L, inv_b[q]), GATHER(L, inv_a[q]));
}

INLINE void points_body(const tc__ct_lane *L, int nc, const uint8_t *floor0) {
    tc__v4d x = {L[0].x, L[1].x, L[2].x, L[3].x}, y = {L[0].y, L[1].y, L[2].y, L[3].y};
    tc__v4d l0 = lam_of(L, 0, x, y), l1 = lam_of(L, 1, x, y), l2 = lam_of(L, 2, x, y);
    /* tc__ct_eval: sub = l0 <= l1 ? (l0 <= l2 ? 0 : 2) : (l1 <= l2 ? 1 : 2) */
    tc__v4i m01 = l0 <= l1, m02 = l0 <= l2, m12 = l1 <= l2;
    tc__v4i is0 = m01 & m02, is1 = ~m01 & m12;
    int sub[4];
    for (int k = 0; k < 4; k++) sub[k] = is0[k] ? 0 : is1[k] ? 1 : 2;
    /* A = lam[a] - lam[sub], B = lam[b] - lam[sub], C = 3 lam[sub], a = sub+1, b = sub+2 */
    tc__v4d A = tc__sel(is0, l1 - l0, tc__sel(is1, l2 - l1, l0 - l2));
    tc__v4d B = tc__sel(is0, l2 - l0, tc__sel(is1, l0 - l1, l1 - l2));
    tc__v4d C = 3 * tc__sel(is0, l0, tc__sel(is1, l1, l2));
    /* ref = A >= B ? (A >= C ? b300 : b003) : (B >= C ? b030 : b003) */
    tc__v4i mAB = A >= B, mAC = A >= C, mBC = B >= C;
    tc__v4i r0 = mAB & mAC, r1 = ~mAB & mBC;
    int grads = L[0].g != NULL;
    for (int ch = 0; ch < nc; ch++) {
        const double *o[4];
        for (int k = 0; k < 4; k++) o[k] = L[k].coef + (size_t)ch * TC_CT_ORDINATES;
        tc__v4d g[10];
        for (int j = 0; j < 10; j++)
            g[j] = (tc__v4d){o[0][tc__ct_sub[sub[0]][j]], o[1][tc__ct_sub[sub[1]][j]], o[2][tc__ct_sub[sub[2]][j]],
                         o[3][tc__ct_sub[sub[3]][j]]};
        tc__v4d q[3];
        tc__v4d v = tc__ct_lanes_cubic(g, r0, r1, A, B, C, q);
        if (floor0[ch]) v = tc__sel(v < 0, (tc__v4d){0, 0, 0, 0}, v); /* tc__floored */
        for (int k = 0; k < 4; k++) L[k].v[ch] = v[k];
        if (!grads) continue;
        /* D[a] = 3 qa, D[b] = 3 qb, D[sub] = 3 (3 qc - qa - qb); lane by lane per sub:
         * sub 0: D = (Ds, Da, Db); sub 1: (Db, Ds, Da); sub 2: (Da, Db, Ds). */
        tc__v4d Da = 3 * q[0], Db = 3 * q[1], Ds = 3 * (3 * q[2] - q[0] - q[1]);
        tc__v4d D0 = tc__sel(is0, Ds, tc__sel(is1, Db, Da)), D1 = tc__sel(is0, Da, tc__sel(is1, Ds, Db));
        tc__v4d D2 = tc__sel(is0, Db, tc__sel(is1, Da, Ds));
        tc__v4d dl10 = GATHER(L, dl1[0]), dl11 = GATHER(L, dl1[1]), dl20 = GATHER(L, dl2[0]), dl21 = GATHER(L, dl2[1]);
        tc__v4d gx = (D1 - D0) * dl10 + (D2 - D0) * dl20, gy = (D1 - D0) * dl11 + (D2 - D0) * dl21;
        for (int k = 0; k < 4; k++) L[k].g[2 * ch] = gx[k], L[k].g[2 * ch + 1] = gy[k];
    }
}

static void points_generic(const tc__ct_lane lane[4], int nc, const uint8_t *floor0) {
    points_body(lane, nc, floor0);
}

#if TC__X86
__attribute__((target("avx2"))) static void points_avx2(const tc__ct_lane lane[4], int nc, const uint8_t *floor0) {
    points_body(lane, nc, floor0);
}
#endif

static int force_generic;

void tc__ct_points_force_generic(int on) {
    force_generic = on;
}

void tc__ct_points4(const tc__ct_lane lane[4], int nc, const uint8_t *floor0) {
#if TC__X86
    if (!force_generic && tc__cpu_avx2()) {
        points_avx2(lane, nc, floor0);
        return;
    }
#endif
    points_generic(lane, nc, floor0);
}
