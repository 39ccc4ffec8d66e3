/* eval.c — evaluating a reconstruction: one triangle's piece at a point, or
 * many points located through a tc_locator (outside points: 0 and tri -1). */
#include <string.h>

#include "core/geom.h"
#include "core/recon.h"

void tc_eval_triangle(const tc_recon *r, int32_t t, double x, double y, double *value, double *grad) {
    tc_at at;
    int nc = r->m->nc;
    tc__at(r->m, t, x, y, &at);
    const double *coef = r->coef + (size_t)t * nc * r->ncoef;
    for (int ch = 0; ch < nc; ch++)
        r->eval(coef + (size_t)ch * r->ncoef, &at, &value[ch], grad ? grad + 2 * ch : NULL);
}

void tc_eval_points(const tc_recon *r, const tc_locator *L, size_t n, const double *xy, double *values,
                    double *grads, int32_t *tri) {
    int nc = r->m->nc;
    for (size_t i = 0; i < n; i++) {
        double *v = values + i * nc, *g = grads ? grads + 2 * i * nc : NULL;
        int32_t t = tc_locate(L, xy[2 * i], xy[2 * i + 1]);
        if (tri) tri[i] = t;
        if (t >= 0) {
            tc_eval_triangle(r, t, xy[2 * i], xy[2 * i + 1], v, g);
        } else {
            memset(v, 0, (size_t)nc * sizeof *v);
            if (g) memset(g, 0, 2 * (size_t)nc * sizeof *g);
        }
    }
}
