/* ct_fast.c — turning a triangle's 19 Clough-Tocher ordinates into the form ct_fast.h
 * renders from: per subtriangle, the coefficients of the cubic's monomials in A, B, C. */
#include "core/ct_fast.h"

void tc__ct_fast_prepare(const tc__eval_frame *f, const double *coef, int nc, tc__ct_fast *ff) {
    ff->nc = nc;
    for (int q = 0; q < 3; q++) {
        const double *a = f->p[(q + 1) % 3];
        ff->ax[q] = a[0], ff->ay[q] = a[1];
        ff->ex[q] = f->e[q][0], ff->ey[q] = f->e[q][1];
        ff->inv[q] = f->inv_a[q];
    }
    /* b300 b030 b003 b210 b120 b201 b021 b102 b012 b111 (tc__ct_sub's order) weigh
     * A^3 B^3 C^3 3A^2B 3AB^2 3A^2C 3B^2C 3AC^2 3BC^2 6ABC; b003 is the centroid's (CCC),
     * so its coefficient is 0 and constant data give exactly the constant. */
    static const int mono_of[10] = {TC__M_AAA, TC__M_BBB, -1, TC__M_AAB, TC__M_ABB,
                                    TC__M_AAC, TC__M_BBC, TC__M_ACC, TC__M_BCC, TC__M_ABC};
    static const double weight[10] = {1, 1, 1, 3, 3, 3, 3, 3, 3, 6};
    for (int ch = 0; ch < nc; ch++) {
        const double *o = coef + (size_t)ch * TC_CT_ORDINATES;
        ff->base[ch] = o[CT_CCC];
        for (int s = 0; s < 3; s++)
            for (int k = 0; k < 10; k++)
                if (mono_of[k] >= 0) ff->c[ch][s][mono_of[k]] = weight[k] * (o[tc__ct_sub[s][k]] - o[CT_CCC]);
    }
}
