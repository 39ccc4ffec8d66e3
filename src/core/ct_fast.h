/* ct_fast.h — the Clough-Tocher cubic of one triangle made ready for rendering: four pixel
 * centres of a row at a time, within 1e-12 of the data scale of tc__ct_eval (not bit for bit).
 *
 * The form: on subtriangle s (the one whose corner i = s has the least barycentric), with
 * A = l[s+1] - l[s], B = l[s+2] - l[s] and C = 3 l[s] = 1 - A - B, the cubic is a polynomial
 * of degree 3 in A and B alone, ten coefficients (tc__ct_fast_prepare expands tc__ct_eval's
 * Bernstein form into them once per triangle). A and B are, up to sign, two of the three
 * differences D01 = l0 - l1, D02 = l0 - l2, D12 = l1 - l2, which are affine in (x, y) and
 * taken from corner 0 (where they are exactly 1, 1, 0): D = R + gx (x - x0), R = d0 + gy
 * (y - y0) once per row. Their signs choose the subtriangle by tc__ct_eval's rule. So four
 * pixels cost one subtraction, three multiply-adds, the comparisons and one bivariate Horner
 * scheme (nine multiply-adds) per channel; no barycentrics, no monomials.
 * Why it is close: D's error is a few ulps times the triangle's aspect (longest edge squared
 * over twice the area), and raster_cover.c sends only triangles of aspect <= TC__CT_FAST_ASPECT
 * here; the cubic's gradient in (A, B) is at most 3 times its ordinates' spread whatever
 * the form, and the Horner scheme's rounding is at most ~7 ulps of the sum of its terms'
 * magnitudes, each coefficient a sum of at most nine Bernstein weights times ordinate
 * differences (|A|, |B| <= 1 on the subtriangle): a few 1e-13 of the ordinates' largest
 * magnitude at worst, 3.9e-16 measured (tests/unit/test_raster.c). Where rounding picks the
 * neighbouring subtriangle, the two cubics agree to C1 there.
 * The multiply-adds are fused explicitly (tc__fma4: one rounding each, on every build: the
 * FMA instruction where raster_cover.c's AVX2 build runs, libm's correctly rounded fma in the portable
 * one); nothing else is fused or reassociated (-std=c11: no contraction). So the two builds give
 * the same bits, and a pixel's value depends only on the triangle, its row and its x. Fused, a
 * 1024² grid64 tile renders ~8% faster than with a multiply and an add (one rounding fewer per
 * step, and half the chain's latency). */
#ifndef TC_CORE_CT_FAST_H
#define TC_CORE_CT_FAST_H

#include <stdint.h>
#include <string.h>

#include "core/ct.h"
#include "core/vec4.h"

#define TC__CT_FAST_ASPECT 64.0

/* The ten coefficients of a subtriangle's cubic in (a, b), the two D's it reads (signs folded in). */
enum { TC__H00, TC__H10, TC__H20, TC__H30, TC__H01, TC__H02, TC__H03, TC__H11, TC__H21, TC__H12, TC__NH };

typedef struct {
    int nc;
    double x0, y0;                          /* corner 0: where the D's are 1, 1, 0 */
    double gx[3], gy[3];                    /* the gradients of D01, D02, D12 */
    tc__v4d h[TC_MAX_CHANNELS][TC__NH];     /* lane s: subtriangle s's cubic in (a, b); lane 3 = lane 2 */
} tc__ct_fast;

void tc__ct_fast_prepare(const tc__eval_frame *f, const double *coef, int nc, tc__ct_fast *ff);

/* Tests: 1 makes tc_render use the portable build of raster_cover.c with the fast form, 2
 * no fast form (the exact path for every triangle, as where fma is not an instruction), 0 lets
 * the CPU choose. */
void tc__raster_force_generic(int on);
/* Tests: triangles set up in the fast form since tc__raster_force_generic last set a mode (counted
 * only while one is set). */
long tc__raster_fast_setups(void);

/* a * b + c, lane by lane, rounded once: lane-wise fma, which GCC turns into one vfmadd in a
 * file built for FMA (raster_cover_avx2.o) and into calls of libm's fma elsewhere. */
TC__V4_INLINE tc__v4d tc__fma4(tc__v4d a, tc__v4d b, tc__v4d c) {
    return (tc__v4d){__builtin_fma(a[0], b[0], c[0]), __builtin_fma(a[1], b[1], c[1]), __builtin_fma(a[2], b[2], c[2]),
                     __builtin_fma(a[3], b[3], c[3])};
}

/* c00 + a (c10 + a (c20 + a c30)) + b ((c01 + b (c02 + b c03)) + a ((c11 + a c21) + b c12)),
 * each step one fused multiply-add: two chains of about equal depth, so their latencies overlap. */
TC__V4_INLINE tc__v4d tc__ct_fast_horner(const tc__v4d h[TC__NH], tc__v4d a, tc__v4d b) {
    tc__v4d pa = tc__fma4(a, tc__fma4(a, h[TC__H30], h[TC__H20]), h[TC__H10]);
    tc__v4d pb = tc__fma4(b, tc__fma4(b, h[TC__H03], h[TC__H02]), h[TC__H01]);
    tc__v4d pab = tc__fma4(b, h[TC__H12], tc__fma4(a, h[TC__H21], h[TC__H11]));
    return tc__fma4(a, pa, tc__fma4(b, tc__fma4(a, pab, pb), h[TC__H00]));
}

/* The row's constants: R[k] = d0[k] + gy[k] (y - y0), d0 = (1, 1, 0). */
TC__V4_INLINE void tc__ct_fast_row(const tc__ct_fast *ff, double y, double R[3]) {
    double dy = y - ff->y0;
    R[0] = __builtin_fma(ff->gy[0], dy, 1), R[1] = __builtin_fma(ff->gy[1], dy, 1), R[2] = ff->gy[2] * dy;
}

/* Lane l of the result: lane s of h, s lane l's subtriangle (0 where is0, 1 where is1, else 2).
 * A permutation of the 32-bit halves (AVX2's vpermd; loop-invariant index, computed once where
 * inlined); clang, the fuzzing build, has no __builtin_shuffle and selects instead. Exact. */
TC__V4_INLINE tc__v4d tc__ct_fast_own(tc__v4d h, tc__v4i is0, tc__v4i is1) {
#ifdef __clang__
    return tc__sel(is0, tc__splat(h[0]), tc__sel(is1, tc__splat(h[1]), tc__splat(h[2])));
#else
    typedef int32_t v8si __attribute__((vector_size(32)));
    tc__v4i sub = tc__splat_i(2) + is0 + is0 + is1; /* the masks are -1 or 0 */
    tc__v4i pair = sub * tc__splat_i(INT64_C(0x200000002)) + tc__splat_i(INT64_C(1) << 32);
    v8si idx, w; /* lane l: halves 2 sub[l] and 2 sub[l] + 1 */
    memcpy(&idx, &pair, sizeof idx);
    memcpy(&w, &h, sizeof w);
    w = __builtin_shuffle(w, idx);
    memcpy(&h, &w, sizeof h);
    return h;
#endif
}

/* Values v[ch] (ch < nc, nc <= ff->nc) at the four centres (x[l], y) of the row whose constants R
 * gives. A caller that passes a constant nc gets the channel loops unrolled and v kept in
 * registers (one channel: a 1024² grid64 tile ~4% faster). mix (a constant where inlined): every
 * group through the permutation below, without the branch that picks one subtriangle's cubic for
 * four lanes that share it; the same bits either way. */
TC__V4_INLINE void tc__ct_fast_lanes_mix(const tc__ct_fast *ff, int nc, const double R[3], tc__v4d x, tc__v4d *v,
                                          int mix) {
    tc__v4d t = x - tc__splat(ff->x0);
    tc__v4d d01 = tc__fma4(tc__splat(ff->gx[0]), t, tc__splat(R[0]));
    tc__v4d d02 = tc__fma4(tc__splat(ff->gx[1]), t, tc__splat(R[1]));
    tc__v4d d12 = tc__fma4(tc__splat(ff->gx[2]), t, tc__splat(R[2]));
    /* tc__ct_eval's choice: sub = l0 <= l1 ? (l0 <= l2 ? 0 : 2) : (l1 <= l2 ? 1 : 2) */
    tc__v4i m01 = d01 <= tc__splat(0), m02 = d02 <= tc__splat(0), m12 = d12 <= tc__splat(0);
    tc__v4i is0 = m01 & m02, is1 = ~m01 & m12;
    unsigned b0 = tc__mask4(is0), b1 = tc__mask4(is1);
    int s = mix ? -1 : b0 == 15 ? 0 : b1 == 15 ? 1 : (b0 | b1) == 0 ? 2 : -1;
    tc__v4d a, b, h[TC__NH];
    if (s >= 0) {
        a = s == 0 ? d01 : s == 1 ? d12 : d02;
        b = s == 0 ? d02 : s == 1 ? d01 : d12;
        for (int ch = 0; ch < nc; ch++) {
            for (int k = 0; k < TC__NH; k++) h[k] = tc__splat(ff->h[ch][k][s]);
            v[ch] = tc__ct_fast_horner(h, a, b);
        }
        return;
    }
    /* Lanes on both sides of an inner edge: each lane's own subtriangle's D's and coefficients
     * (tc__ct_fast_own), then tc__ct_fast_horner's operations: the same bits as a lane of a group
     * that shares one subtriangle, for one evaluation instead of three. */
    a = tc__sel(is0, d01, tc__sel(is1, d12, d02));
    b = tc__sel(is0, d02, tc__sel(is1, d01, d12));
    for (int ch = 0; ch < nc; ch++) {
        for (int k = 0; k < TC__NH; k++) h[k] = tc__ct_fast_own(ff->h[ch][k], is0, is1);
        v[ch] = tc__ct_fast_horner(h, a, b);
    }
}

/* tc__ct_fast_lanes_mix with the branch: one subtriangle's cubic for a group that lies in it. */
TC__V4_INLINE void tc__ct_fast_lanes_nc(const tc__ct_fast *ff, int nc, const double R[3], tc__v4d x, tc__v4d *v) {
    tc__ct_fast_lanes_mix(ff, nc, R, x, v, 0);
}

/* Every channel's values: tc__ct_fast_lanes_nc with ff->nc. */
TC__V4_INLINE void tc__ct_fast_lanes(const tc__ct_fast *ff, const double R[3], tc__v4d x, tc__v4d *v) {
    tc__ct_fast_lanes_nc(ff, ff->nc, R, x, v);
}

#endif
