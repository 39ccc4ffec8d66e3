/* props.c — shared pieces of the convergence tests: the smooth test function
 * and the max error over a fixed point cloud on a structured grid. */
#include <math.h>

#include "props.h"

void wave_f(const void *ctx, double x, double y, int ch, double *v, double g[2]) {
    (void)ctx, (void)ch;
    *v = exp(0.7 * x) * sin(2.5 * y + 0.3) + cos(1.7 * x * y);
    g[0] = 0.7 * exp(0.7 * x) * sin(2.5 * y + 0.3) - 1.7 * y * sin(1.7 * x * y);
    g[1] = 2.5 * exp(0.7 * x) * cos(2.5 * y + 0.3) - 1.7 * x * sin(1.7 * x * y);
}

double grid_max_error(const tc_recon *rec, int n) {
    double worst = 0;
    trng r;
    trng_seed(&r, 99);
    for (int i = 0; i < 4000; i++) {
        double x = trng_uniform(&r), y = trng_uniform(&r), v, fv, fg[2];
        int ci = (int)(x * n), cj = (int)(y * n);
        double fx = x * n - ci, fy = y * n - cj;
        int32_t t = 2 * (cj * n + ci) + (fy > fx); /* diag 0: (a,b,c) below the diagonal, (a,c,d) above */
        tc_eval_triangle(rec, t, x, y, &v, NULL);
        wave_f(NULL, x, y, 0, &fv, fg);
        worst = fmax(worst, fabs(v - fv));
    }
    return worst;
}
