/* props.c — shared pieces of the convergence and reproduction tests: the test
 * functions, the max error over a fixed point cloud, the reproduction error. */
#include <math.h>
#include <string.h>

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

/* Exact linear data (per channel), for reproduction tests. */
void linear_data(const void *ctx, double x, double y, int ch, double *v, double g[2]) {
    (void)ctx;
    g[0] = 0.7 - 0.2 * ch;
    g[1] = -1.3 + 0.5 * ch;
    *v = 2.0 + ch + g[0] * x + g[1] * y;
}

/* A full quadratic (per channel) with its exact gradient. */
void quadratic_data(const void *ctx, double x, double y, int ch, double *v, double g[2]) {
    (void)ctx;
    double a = 0.9 + 0.3 * ch;
    *v = 1.0 + 0.4 * x - 0.3 * y + a * x * x - 1.1 * x * y + 0.6 * y * y;
    g[0] = 0.4 + 2 * a * x - 1.1 * y;
    g[1] = -0.3 - 1.1 * x + 1.2 * y;
}

/* Worst relative error of value and gradient against f at `npts` random
 * points inside random triangles (barycentric sampling, no point location). */
double tri_reproduction_error(const tc_recon *rec, tfunc f, int npts, trng *r, int check_grad) {
    const tc_mesh *m = tc_recon_mesh(rec);
    const double *xy = tc_mesh_xy(m);
    const int32_t *tri = tc_mesh_triangles(m);
    int nc = tc_mesh_channel_count(m);
    double worst = 0, vs, gs;
    recon_scales(rec, &vs, &gs);
    for (int i = 0; i < npts; i++) {
        int32_t t = trng_int(r, tc_mesh_triangle_count(m));
        double a = trng_uniform(r), b = trng_uniform(r);
        if (a + b > 1) a = 1 - a, b = 1 - b;
        const double *p0 = xy + 2 * tri[3 * t], *p1 = xy + 2 * tri[3 * t + 1], *p2 = xy + 2 * tri[3 * t + 2];
        double x = p0[0] + a * (p1[0] - p0[0]) + b * (p2[0] - p0[0]);
        double y = p0[1] + a * (p1[1] - p0[1]) + b * (p2[1] - p0[1]);
        double val[TC_MAX_CHANNELS], grad[2 * TC_MAX_CHANNELS];
        tc_eval_triangle(rec, t, x, y, val, grad);
        for (int ch = 0; ch < nc; ch++) {
            double fv, fg[2];
            f(NULL, x, y, ch, &fv, fg);
            worst = fmax(worst, fabs(val[ch] - fv) / vs);
            if (check_grad) worst = fmax(worst, hypot(grad[2 * ch] - fg[0], grad[2 * ch + 1] - fg[1]) / gs);
        }
    }
    return worst;
}

void drop_range_free_warnings(tc_diags *d) {
    int kept = 0;
    for (int i = 0; i < d->count; i++) {
        if (d->items[i].severity == TC_SEV_WARNING && !strncmp(d->items[i].message, "range \"free\"", 12)) {
            d->warnings--;
            continue;
        }
        d->items[kept++] = d->items[i];
    }
    d->count = kept;
}
