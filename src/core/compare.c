/* compare.c — how far a reconstruction is from reference values: max abs, RMS and
 * Bastos & Oliveira's mean relative error (|ref - rec| / full scale, averaged). */
#include <math.h>

#include "core/minmax.h"
#include "core/recon.h"

/* Largest |ref| over the points: the default full scale. */
static double max_abs_ref(size_t n, int nc, const double *ref) {
    double m = 0;
    for (size_t i = 0; i < n * (size_t)nc; i++) m = tc__fmax(m, fabs(ref[i]));
    return m;
}

int tc_compare(const tc_recon *r, const tc_locator *L, size_t n, const double *xy, const double *ref, double scale,
               tc_error_stats *out) {
    int nc = r->m->nc;
    double sum2 = 0, sum_abs = 0, v[TC_MAX_CHANNELS];
    *out = (tc_error_stats){0};
    out->scale = scale > 0 ? scale : max_abs_ref(n, nc, ref);
    for (size_t i = 0; i < n; i++) {
        int32_t t;
        tc_eval_points(r, L, 1, xy + 2 * i, v, NULL, &t);
        if (t < 0) {
            out->outside++;
            continue;
        }
        for (int ch = 0; ch < nc; ch++) {
            double e = fabs(ref[i * (size_t)nc + (size_t)ch] - v[ch]);
            out->max_abs = tc__fmax(out->max_abs, e);
            sum2 += e * e;
            sum_abs += e;
        }
        out->n++;
    }
    double count = (double)out->n * nc;
    if (out->n) {
        out->rms = sqrt(sum2 / count);
        out->mean_rel = out->scale > 0 ? sum_abs / count / out->scale : 0;
    }
    return TC_OK;
}
