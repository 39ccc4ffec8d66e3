/* ct_fast.c — turning a triangle's 19 Clough-Tocher ordinates into the form ct_fast.h
 * renders from: per subtriangle, the ten coefficients of its cubic in two differences D. */
#include "core/ct_fast.h"

void tc__ct_fast_prepare(const tc__eval_frame *f, const double *coef, int nc, tc__ct_fast *ff) {
    /* l[q] = cross(e[q], p - a[q]) * inv_a[q], a[q] = corner q + 1: its gradient is
     * (-e[q].y, e[q].x) * inv_a[q]; the D's are l0 - l1, l0 - l2, l1 - l2. */
    double gx[3], gy[3];
    for (int q = 0; q < 3; q++) gx[q] = -f->e[q][1] * f->inv_a[q], gy[q] = f->e[q][0] * f->inv_a[q];
    ff->nc = nc;
    ff->x0 = f->p[0][0], ff->y0 = f->p[0][1];
    ff->gx[0] = gx[0] - gx[1], ff->gx[1] = gx[0] - gx[2], ff->gx[2] = gx[1] - gx[2];
    ff->gy[0] = gy[0] - gy[1], ff->gy[1] = gy[0] - gy[2], ff->gy[2] = gy[1] - gy[2];
    /* Subtriangle s's cubic in Bernstein form, b300 b030 b003 b210 b120 b201 b021 b102 b012
     * b111 (tc__ct_sub[s]'s order) weighing A^3 B^3 C^3 3A^2B 3AB^2 3A^2C 3B^2C 3AC^2 3BC^2
     * 6ABC, taken relative to the centroid's ordinate b003 (constant data then give exactly
     * the constant), C = 1 - A - B expanded into powers of A and B, then A = sa a, B = sb b
     * for the D's (a, b) it reads: subtriangle 0 (D01, D02) with A = -a, B = -b; 1 (D12, D01)
     * with A = -a, B = b; 2 (D02, D12) with A = a, B = b (tc__ct_fast_lanes). The three
     * subtriangles side by side, one per lane (lane 3 repeats lane 2: finite, never read). */
    const tc__v4d sa = {-1, -1, 1, 1}, sb = {-1, 1, 1, 1}, three = tc__splat(3);
    for (int ch = 0; ch < nc; ch++) {
        const double *o = coef + (size_t)ch * TC_CT_ORDINATES;
        tc__v4d b[10];
        for (int k = 0; k < 10; k++)
            b[k] = (tc__v4d){o[tc__ct_sub[0][k]], o[tc__ct_sub[1][k]], o[tc__ct_sub[2][k]], o[tc__ct_sub[2][k]]};
        tc__v4d c = b[2], aaa = b[0] - c, bbb = b[1] - c, aab = three * (b[3] - c), abb = three * (b[4] - c);
        tc__v4d aac = three * (b[5] - c), bbc = three * (b[6] - c), acc = three * (b[7] - c);
        tc__v4d bcc = three * (b[8] - c), abc = tc__splat(6) * (b[9] - c), two = tc__splat(2);
        tc__v4d *h = ff->h[ch];
        h[TC__H00] = c;
        h[TC__H10] = sa * acc;
        h[TC__H01] = sb * bcc;
        h[TC__H20] = aac - two * acc;
        h[TC__H02] = bbc - two * bcc;
        h[TC__H11] = sa * sb * (abc - two * acc - two * bcc);
        h[TC__H30] = sa * (aaa - aac + acc);
        h[TC__H03] = sb * (bbb - bbc + bcc);
        h[TC__H21] = sb * (aab - aac + two * acc + bcc - abc);
        h[TC__H12] = sa * (abb - bbc + acc + two * bcc - abc);
    }
}
