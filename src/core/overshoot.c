/* overshoot.c — how far a rendered tile leaves the data it was built from: per pixel,
 * the excursion beyond its own triangle's corner values, in units of the data range. */
#include <math.h>
#include <string.h>

#include "tocher.h"

#include "core/minmax.h"

/* Lives in the core, next to tc_compare, because it needs nothing but the
 * mesh and a tile: no exact function, no scene. Tests, the report, the CLI and
 * the daemon all link the core, and a range limiter in the core can be
 * checked against the same definition. */

/* The channel's smallest and largest corner value over the mesh. */
static void data_range(const tc_mesh *m, int ch, double *lo, double *hi) {
    *lo = INFINITY, *hi = -INFINITY;
    for (int32_t t = 0, nt = tc_mesh_triangle_count(m); t < nt; t++)
        for (int k = 0; k < 3; k++) {
            double z = tc_mesh_corner_value(m, t, k)[ch];
            *lo = tc__fmin(*lo, z), *hi = tc__fmax(*hi, z);
        }
}

static void start(const tc_mesh *m, int ch, tc_overshoot_stats *s) {
    memset(s, 0, sizeof *s);
    data_range(m, ch, &s->lo, &s->hi);
    double r = s->hi - s->lo, mag = tc__fmax(fabs(s->lo), fabs(s->hi));
    s->unit = r > 0 ? r : mag > 0 ? mag : 1;
    s->worst_tri = s->worst_i = s->worst_j = -1;
}

/* e of value v in triangle t (see tc_overshoot_stats): the corners' bounds are
 * rounded to float like v, and rounding is monotone, so a value that lay
 * between the corners before rounding still does. */
static double excursion(const tc_mesh *m, int32_t t, int ch, float v, double unit) {
    if (!isfinite(v)) return INFINITY;
    float lo = INFINITY, hi = -INFINITY;
    for (int k = 0; k < 3; k++) {
        float z = (float)tc_mesh_corner_value(m, t, k)[ch];
        lo = fminf(lo, z), hi = fmaxf(hi, z);
    }
    double over = tc__fmax(0, tc__fmax((double)v - hi, lo - (double)v));
    return over / unit;
}

static void count(tc_overshoot_stats *s, double e, float v, double threshold, int32_t t, int32_t i, int32_t j) {
    s->min_value = s->pixels ? tc__fmin(s->min_value, v) : v;
    s->max_value = s->pixels ? tc__fmax(s->max_value, v) : v;
    s->pixels++;
    s->negative += s->lo >= 0 && v < 0;
    s->beyond += e > threshold;
    if (!(e > s->worst)) return;
    s->worst = e, s->worst_value = v;
    s->worst_tri = t, s->worst_i = i, s->worst_j = j;
}

int tc_overshoot(const tc_mesh *m, const float *values, const int32_t *owner, int32_t width, int32_t height,
                 double threshold, tc_overshoot_stats *out) {
    int nc = tc_mesh_channel_count(m);
    int32_t nt = tc_mesh_triangle_count(m);
    if (width < 0 || height < 0) return TC_EINVAL;
    size_t npix = (size_t)width * (size_t)height;
    for (size_t p = 0; p < npix; p++)
        if (owner[p] < -1 || owner[p] >= nt) return TC_EINVAL;
    for (int ch = 0; ch < nc; ch++) {
        tc_overshoot_stats *s = &out[ch];
        start(m, ch, s);
        for (size_t p = 0; p < npix; p++) {
            if (owner[p] < 0) continue;
            float v = values[p * (size_t)nc + (size_t)ch];
            double e = excursion(m, owner[p], ch, v, s->unit);
            count(s, e, v, threshold, owner[p], (int32_t)(p % (size_t)width), (int32_t)(p / (size_t)width));
        }
        s->beyond_fraction = s->pixels ? (double)s->beyond / (double)s->pixels : 0;
    }
    return TC_OK;
}
