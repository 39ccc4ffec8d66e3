/* ct_span.c — the Clough-Tocher value over a run of pixels of one row, four at a time: the
 * arithmetic of tc__frame_at + tc__ct_eval (geom.h, ct.c) lane for lane, so a rendered pixel is
 * bit for bit the value /v1/evaluate gives at its centre.
 *
 * Invariant: every lane performs exactly the IEEE operations the scalar path performs, in the
 * same order on the same operands. Branches of the scalar code become computing every
 * alternative and selecting bitwise (an exact operation); nothing is reassociated, nothing is
 * fused (-std=c11 keeps -ffp-contract=off, and no FMA target is enabled). If the scalar code
 * changes, this file must change with it: tests/unit/test_raster.c compares every pixel, with
 * the AVX2 build and with the portable one. Vectors pass only between always-inline functions
 * of this file, never across an ABI boundary (the Makefile silences GCC's -Wpsabi note). */
#include <stdint.h>
#include <string.h>

#include "core/alloc.h"
#include "core/cpu.h"
#include "core/ct.h"
#include "core/ct_lanes.h"
#include "core/vec4.h"

typedef float v4f __attribute__((vector_size(16)));

#define INLINE TC__V4_INLINE

/* tc__frame_at's lam[q], lane by lane. */
INLINE tc__v4d lam_of(const tc__eval_frame *f, int q, tc__v4d x, double y) {
    const double *a = f->p[(q + 1) % 3], *b = f->p[(q + 2) % 3];
    tc__v4d dax = x - tc__splat(a[0]), dbx = x - tc__splat(b[0]);
    double day = y - a[1], dby = y - b[1];
    tc__v4i near_b = (dbx * dbx + tc__splat(dby * dby)) < (dax * dax + tc__splat(day * day));
    tc__v4d dx = tc__sel(near_b, dbx, dax), dy = tc__sel(near_b, tc__splat(dby), tc__splat(day));
    tc__v4d cross = tc__splat(f->e[q][0]) * dy - tc__splat(f->e[q][1]) * dx;
    return cross * tc__sel(near_b, tc__splat(f->inv_b[q]), tc__splat(f->inv_a[q]));
}

/* tc__ct_eval_sub's value for one channel's ordinates o, the subtriangle
 * chosen per lane by the masks is0 / is1 (else 2), the reference ordinate by
 * r0 / r1 (else the third). */
INLINE tc__v4d cubic(const double *o, tc__v4i is0, tc__v4i is1, tc__v4i r0, tc__v4i r1, tc__v4d A, tc__v4d B, tc__v4d C) {
    tc__v4d g[10];
    for (int k = 0; k < 10; k++)
        g[k] = tc__sel(is0, tc__splat(o[tc__ct_sub[0][k]]), tc__sel(is1, tc__splat(o[tc__ct_sub[1][k]]), tc__splat(o[tc__ct_sub[2][k]])));
    tc__v4d q[3];
    return tc__ct_lanes_cubic(g, r0, r1, A, B, C, q);
}

INLINE void span_body(const tc__eval_frame *f, const double *coef, int nc, const double *xs, double y, int32_t n,
                      float *out, double *dout) {
    for (int32_t i = 0; i < n; i += 4) {
        int32_t k = n - i < 4 ? n - i : 4;
        double xl[4];
        for (int l = 0; l < 4; l++) xl[l] = xs[i + (l < k ? l : 0)]; /* tail lanes repeat a real pixel */
        tc__v4d x = {xl[0], xl[1], xl[2], xl[3]};
        tc__v4d l0 = lam_of(f, 0, x, y), l1 = lam_of(f, 1, x, y), l2 = lam_of(f, 2, x, y);
        /* tc__ct_eval: sub = l0 <= l1 ? (l0 <= l2 ? 0 : 2) : (l1 <= l2 ? 1 : 2) */
        tc__v4i m01 = l0 <= l1, m02 = l0 <= l2, m12 = l1 <= l2;
        tc__v4i is0 = m01 & m02, is1 = ~m01 & m12;
        /* A = lam[a] - lam[sub], B = lam[b] - lam[sub], C = 3 lam[sub], a = sub+1, b = sub+2 */
        tc__v4d A = tc__sel(is0, l1 - l0, tc__sel(is1, l2 - l1, l0 - l2));
        tc__v4d B = tc__sel(is0, l2 - l0, tc__sel(is1, l0 - l1, l1 - l2));
        tc__v4d C = 3 * tc__sel(is0, l0, tc__sel(is1, l1, l2));
        /* ref = A >= B ? (A >= C ? b300 : b003) : (B >= C ? b030 : b003) */
        tc__v4i mAB = A >= B, mAC = A >= C, mBC = B >= C;
        tc__v4i r0 = mAB & mAC, r1 = ~mAB & mBC;
        for (int ch = 0; ch < nc; ch++) {
            tc__v4d v = cubic(coef + (size_t)ch * TC_CT_ORDINATES, is0, is1, r0, r1, A, B, C);
            v4f fv = __builtin_convertvector(v, v4f);
            for (int l = 0; l < k; l++) out[tc__ix(i + l, nc, ch)] = fv[l];
            if (dout)
                for (int l = 0; l < k; l++) dout[tc__ix(i + l, nc, ch)] = v[l];
        }
    }
}

static void span_generic(const tc__eval_frame *f, const double *coef, int nc, const double *xs, double y, int32_t n,
                         float *out, double *dout) {
    span_body(f, coef, nc, xs, y, n, out, dout);
}

#if TC__X86
__attribute__((target("avx2"))) static void span_avx2(const tc__eval_frame *f, const double *coef, int nc,
                                                       const double *xs, double y, int32_t n, float *out,
                                                       double *dout) {
    span_body(f, coef, nc, xs, y, n, out, dout);
}
#endif

static int force_generic;

void tc__ct_span_force_generic(int on) {
    force_generic = on;
}

void tc__ct_span(const tc__eval_frame *f, const double *coef, int nc, const double *xs, double y, int32_t n, float *out,
                 double *dout) {
#if TC__X86
    if (!force_generic && tc__cpu_avx2()) {
        span_avx2(f, coef, nc, xs, y, n, out, dout);
        return;
    }
#endif
    span_generic(f, coef, nc, xs, y, n, out, dout);
}
