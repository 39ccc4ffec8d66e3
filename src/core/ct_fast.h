/* ct_fast.h — the Clough-Tocher cubic of one triangle made ready for rendering: four pixel
 * centres of a row at a time, within 1e-12 of the data scale of tc__ct_eval (not bit for bit).
 *
 * Why it is close: a barycentric is computed from one fixed corner of its edge, so its error
 * is a few ulps times the triangle's aspect (longest edge squared over twice the area);
 * raster.c sends only triangles of aspect <= TC__CT_FAST_ASPECT here, which bounds the
 * value's error by about 9 * 3 * eps * 64 ~ 4e-13 of the ordinates' spread (tests/unit/
 * test_raster.c measures it). The subtriangle is chosen by tc__ct_eval's rule on these
 * barycentrics; where rounding picks the neighbour, the two cubics agree to C1 there.
 * Why it is fast: the ten ordinates of a subtriangle are taken relative to the centroid's
 * (exact for constant data) and turned into the nine coefficients of the cubic's monomials in
 * A, B, C once per triangle; four pixels that share a subtriangle (nearly always) then cost the
 * ten monomials plus one multiply-add per coefficient and channel, with no per-lane gathers.
 * Nothing is fused or reassociated (-ffp-contract=off), so the AVX2 and the portable builds
 * give the same bits, and a pixel's value depends only on the triangle, its row and its x. */
#ifndef TC_CORE_CT_FAST_H
#define TC_CORE_CT_FAST_H

#include <stdint.h>
#include <string.h>

#include "core/ct.h"
#include "core/vec4.h"

#define TC__CT_FAST_ASPECT 64.0

/* The monomials of A, B, C, in the order of tc__ct_fast's coefficients. */
/* (C^3 has none: its ordinate is the centroid's, the base the others are taken from.) */
enum { TC__M_AAA, TC__M_BBB, TC__M_AAB, TC__M_ABB, TC__M_AAC, TC__M_BBC, TC__M_ACC, TC__M_BCC, TC__M_ABC, TC__NMONO };

typedef struct {
    int nc;
    double ax[3], ay[3], ex[3], ey[3], inv[3]; /* lam[q] = cross(e[q], p - a[q]) * inv[q] */
    double base[TC_MAX_CHANNELS];              /* the centroid's ordinate */
    double c[TC_MAX_CHANNELS][3][TC__NMONO];   /* per subtriangle, the monomials' coefficients */
} tc__ct_fast;

void tc__ct_fast_prepare(const tc__eval_frame *f, const double *coef, int nc, tc__ct_fast *ff);

/* Tests: 1 makes tc_render use the portable build of its row loop (raster.c), 0 lets the CPU choose. */
void tc__raster_force_generic(int on);

TC__V4_INLINE void tc__ct_fast_monomials(int s, const tc__v4d l[3], tc__v4d mono[TC__NMONO]) {
    tc__v4d ls = l[s], A = l[(s + 1) % 3] - ls, B = l[(s + 2) % 3] - ls, C = tc__splat(3) * ls;
    tc__v4d AA = A * A, BB = B * B, CC = C * C;
    mono[TC__M_AAA] = AA * A, mono[TC__M_BBB] = BB * B;
    mono[TC__M_AAB] = AA * B, mono[TC__M_ABB] = A * BB, mono[TC__M_AAC] = AA * C;
    mono[TC__M_BBC] = BB * C, mono[TC__M_ACC] = A * CC, mono[TC__M_BCC] = B * CC, mono[TC__M_ABC] = A * B * C;
}

/* A sum in a tree, not a chain: the additions' latency, not their count, bounds a chain. */
TC__V4_INLINE tc__v4d tc__ct_fast_cubic(const double *c, double base, const tc__v4d m[TC__NMONO]) {
    tc__v4d p0 = tc__splat(c[0]) * m[0] + tc__splat(c[1]) * m[1], p1 = tc__splat(c[2]) * m[2] + tc__splat(c[3]) * m[3];
    tc__v4d p2 = tc__splat(c[4]) * m[4] + tc__splat(c[5]) * m[5], p3 = tc__splat(c[6]) * m[6] + tc__splat(c[7]) * m[7];
    return tc__splat(base) + (((p0 + p1) + (p2 + p3)) + tc__splat(c[8]) * m[8]);
}

/* The row's constants: K[q] = e[q].x (y - a[q].y). */
TC__V4_INLINE void tc__ct_fast_row(const tc__ct_fast *ff, double y, double K[3]) {
    for (int q = 0; q < 3; q++) K[q] = ff->ex[q] * (y - ff->ay[q]);
}

/* Values v[ch] at the four centres (x[l], y) of the row whose constants K gives. */
TC__V4_INLINE void tc__ct_fast_lanes(const tc__ct_fast *ff, const double K[3], tc__v4d x, tc__v4d *v) {
    tc__v4d lam[3];
    for (int q = 0; q < 3; q++)
        lam[q] = (tc__splat(K[q]) - tc__splat(ff->ey[q]) * (x - tc__splat(ff->ax[q]))) * tc__splat(ff->inv[q]);
    /* tc__ct_eval's choice: sub = l0 <= l1 ? (l0 <= l2 ? 0 : 2) : (l1 <= l2 ? 1 : 2) */
    tc__v4i m01 = lam[0] <= lam[1], m02 = lam[0] <= lam[2], m12 = lam[1] <= lam[2];
    tc__v4i is0 = m01 & m02, is1 = ~m01 & m12;
    unsigned b0 = tc__mask4(is0), b1 = tc__mask4(is1);
    int s = b0 == 15 ? 0 : b1 == 15 ? 1 : (b0 | b1) == 0 ? 2 : -1;
    if (s >= 0) {
        tc__v4d mono[TC__NMONO];
        tc__ct_fast_monomials(s, lam, mono);
        for (int ch = 0; ch < ff->nc; ch++) v[ch] = tc__ct_fast_cubic(ff->c[ch][s], ff->base[ch], mono);
        return;
    }
    /* Lanes on both sides of an inner edge: each lane's own subtriangle's barycentrics and
     * coefficients selected (exact), then the operations tc__ct_fast_monomials and
     * tc__ct_fast_cubic perform for it, in their order: the same bits as a lane of a
     * group that shares one subtriangle, for one evaluation instead of three. */
    tc__v4d ls = tc__sel(is0, lam[0], tc__sel(is1, lam[1], lam[2]));
    tc__v4d la = tc__sel(is0, lam[1], tc__sel(is1, lam[2], lam[0]));
    tc__v4d lb = tc__sel(is0, lam[2], tc__sel(is1, lam[0], lam[1]));
    tc__v4d A = la - ls, B = lb - ls, C = tc__splat(3) * ls;
    tc__v4d AA = A * A, BB = B * B, CC = C * C, m[TC__NMONO];
    m[TC__M_AAA] = AA * A, m[TC__M_BBB] = BB * B;
    m[TC__M_AAB] = AA * B, m[TC__M_ABB] = A * BB, m[TC__M_AAC] = AA * C;
    m[TC__M_BBC] = BB * C, m[TC__M_ACC] = A * CC, m[TC__M_BCC] = B * CC, m[TC__M_ABC] = A * B * C;
    for (int ch = 0; ch < ff->nc; ch++) {
        tc__v4d c[TC__NMONO];
        for (int k = 0; k < TC__NMONO; k++)
            c[k] = tc__sel(is0, tc__splat(ff->c[ch][0][k]), tc__sel(is1, tc__splat(ff->c[ch][1][k]), tc__splat(ff->c[ch][2][k])));
        tc__v4d p0 = c[0] * m[0] + c[1] * m[1], p1 = c[2] * m[2] + c[3] * m[3];
        tc__v4d p2 = c[4] * m[4] + c[5] * m[5], p3 = c[6] * m[6] + c[7] * m[7];
        v[ch] = tc__splat(ff->base[ch]) + (((p0 + p1) + (p2 + p3)) + c[8] * m[8]);
    }
}

#endif
