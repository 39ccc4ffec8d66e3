/* raster.c — rendering a reconstruction over a tile of pixels: every pixel centre
 * owned by exactly the triangle tc_locate names (shared exact test), evaluated
 * exactly as tc_eval_triangle does, rows split into bands across threads. */
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/internal.h"
#include "core/locate.h"
#include "core/recon.h"

#define BAND_ROWS 16 /* rows per unit of work: small enough to balance threads */

void tc_viewport_pixel_center(const tc_viewport *vp, int32_t i, int32_t j, double *x, double *y) {
    *x = vp->x0 + (vp->x1 - vp->x0) * ((i + 0.5) / vp->width);
    *y = vp->y1 - (vp->y1 - vp->y0) * ((j + 0.5) / vp->height);
}

typedef struct {
    const tc_recon *r;
    const tc_locator *L;
    const tc_viewport *vp;
    const tc_render_options *o;
    float *values;
    int32_t *owner;
    int32_t nbands;
    atomic_int next_band;
    atomic_int timed_out;
} job;

/* The band being rasterized: rows [j0, j1). */
typedef struct {
    const job *jb;
    int32_t j0, j1;
} band;

static double now_ms(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

/* Pixel index range [lo, hi] whose centres may fall in [a, b] along an axis of
 * n pixels starting at origin with the given step (widened by one pixel on each
 * side: the exact test below decides, this only has to be a superset). */
static void pixel_range(double a, double b, double origin, double step, int32_t n, int32_t *lo, int32_t *hi) {
    double fa = (a - origin) / step - 0.5, fb = (b - origin) / step - 0.5;
    double l = floor(fmin(fa, fb)) - 1, h = ceil(fmax(fa, fb)) + 1;
    *lo = l < 0 ? 0 : l >= n ? n : (int32_t)l;
    *hi = h < 0 ? -1 : h >= n ? n - 1 : (int32_t)h;
}

/* Owner encoding while a band is rasterized: -1 none, t >= 0 strict owner,
 * -2 - t a closed-only candidate (points on the outer boundary; the lowest
 * index wins, as in tc_locate). */
static void cover(void *ctx, const struct tc_slot *s) {
    const band *bd = ctx;
    const tc_viewport *vp = bd->jb->vp;
    double xmin = fmin(s->x[0], fmin(s->x[1], s->x[2])), xmax = fmax(s->x[0], fmax(s->x[1], s->x[2]));
    double ymin = fmin(s->y[0], fmin(s->y[1], s->y[2])), ymax = fmax(s->y[0], fmax(s->y[1], s->y[2]));
    int32_t i0, i1, j0, j1;
    pixel_range(xmin, xmax, vp->x0, (vp->x1 - vp->x0) / vp->width, vp->width, &i0, &i1);
    /* Rows count downwards from y1. */
    pixel_range(-ymax, -ymin, -vp->y1, (vp->y1 - vp->y0) / vp->height, vp->height, &j0, &j1);
    if (j0 < bd->j0) j0 = bd->j0;
    if (j1 > bd->j1 - 1) j1 = bd->j1 - 1;
    for (int32_t j = j0; j <= j1; j++)
        for (int32_t i = i0; i <= i1; i++) {
            double x, y;
            tc_viewport_pixel_center(vp, i, j, &x, &y);
            int hit = tc__slot_test(s, x, y);
            if (hit == TC_SLOT_OUT) continue;
            int32_t *o = &bd->jb->owner[(size_t)j * vp->width + i];
            if (hit == TC_SLOT_OWN) *o = s->t;
            else if (*o == -1 || (*o <= -2 && -2 - *o > s->t)) *o = -2 - s->t;
        }
}

static void shade_band(const band *bd) {
    const job *jb = bd->jb;
    const tc_viewport *vp = jb->vp;
    int nc = jb->r->m->nc;
    double v[TC_MAX_CHANNELS];
    for (int32_t j = bd->j0; j < bd->j1; j++)
        for (int32_t i = 0; i < vp->width; i++) {
            size_t p = (size_t)j * vp->width + i;
            int32_t t = jb->owner[p];
            if (t <= -2) t = jb->owner[p] = -2 - t;
            float *out = jb->values + p * nc;
            if (t < 0) {
                for (int ch = 0; ch < nc; ch++) out[ch] = jb->o->background ? (float)jb->o->background[ch] : 0.0f;
                continue;
            }
            double x, y;
            tc_viewport_pixel_center(vp, i, j, &x, &y);
            tc_eval_triangle(jb->r, t, x, y, v, NULL);
            for (int ch = 0; ch < nc; ch++) out[ch] = (float)v[ch];
        }
}

static void render_band(job *jb, int32_t b) {
    const tc_viewport *vp = jb->vp;
    band bd = {jb, b * BAND_ROWS, (b + 1) * BAND_ROWS};
    if (bd.j1 > vp->height) bd.j1 = vp->height;
    for (size_t p = (size_t)bd.j0 * vp->width; p < (size_t)bd.j1 * vp->width; p++) jb->owner[p] = -1;
    double xa, ya, xb, yb, lo[2], hi[2];
    tc_viewport_pixel_center(vp, 0, bd.j1 - 1, &xa, &ya);
    tc_viewport_pixel_center(vp, vp->width - 1, bd.j0, &xb, &yb);
    lo[0] = fmin(xa, xb), hi[0] = fmax(xa, xb), lo[1] = fmin(ya, yb), hi[1] = fmax(ya, yb);
    tc__locator_query_box(jb->L, lo, hi, cover, &bd);
    shade_band(&bd);
}

static void *worker(void *arg) {
    job *jb = arg;
    for (;;) {
        int32_t b = atomic_fetch_add(&jb->next_band, 1);
        if (b >= jb->nbands || atomic_load(&jb->timed_out)) return NULL;
        if (jb->o->deadline_ms > 0 && now_ms() > jb->o->deadline_ms) {
            atomic_store(&jb->timed_out, 1);
            return NULL;
        }
        render_band(jb, b);
    }
}

static int valid_viewport(const tc_viewport *vp) {
    return vp->width >= 1 && vp->height >= 1 && isfinite(vp->x0) && isfinite(vp->x1) && isfinite(vp->y0) &&
           isfinite(vp->y1) && vp->x1 > vp->x0 && vp->y1 > vp->y0 &&
           (size_t)vp->width * (size_t)vp->height <= SIZE_MAX / (sizeof(float) * TC_MAX_CHANNELS);
}

static void run_threads(job *jb, int n) {
    pthread_t tid[64];
    int started = 0;
    if (n > 64) n = 64;
    if (n > jb->nbands) n = jb->nbands;
    for (; started < n - 1; started++) /* the caller is worker number n */
        if (pthread_create(&tid[started], NULL, worker, jb) != 0) break;
    worker(jb);
    for (int k = 0; k < started; k++) pthread_join(tid[k], NULL);
}

int tc_render(const tc_recon *r, const tc_locator *L, const tc_viewport *vp, const tc_render_options *o,
              float *values, int32_t *owner) {
    static const tc_render_options defaults = {NULL, 1, 0};
    if (!valid_viewport(vp)) return TC_EINVAL;
    int32_t *own = owner ? owner : tc__malloc((size_t)vp->width * vp->height, sizeof *own);
    if (!own) return TC_ENOMEM;
    job jb = {r, L, vp, o ? o : &defaults, values, own, (vp->height + BAND_ROWS - 1) / BAND_ROWS, 0, 0};
    run_threads(&jb, jb.o->threads > 1 ? jb.o->threads : 1);
    if (!owner) free(own);
    return atomic_load(&jb.timed_out) ? TC_ETIMEOUT : TC_OK;
}

/* ---- mesh overlay ---- */

static void overlay_colour(tc_continuity kind, int boundary, int nc, double scale, float *c) {
    static const float rgb[4][3] = {{0.35f, 0.35f, 0.35f}, {1, 0.8f, 0}, {1, 0.1f, 0.1f}, {1, 1, 1}};
    static const float grey[4] = {0.35f, 0.7f, 1, 1};
    int k = boundary ? 3 : kind == TC_C1 ? 0 : kind == TC_C0 ? 1 : 2;
    for (int ch = 0; ch < nc; ch++) c[ch] = (float)(scale * (nc == 3 ? rgb[k][ch] : grey[k]));
}

/* A one-pixel line between two points in pixel coordinates (DDA), clipped. */
static void draw_line(const tc_viewport *vp, int nc, const float *c, double ax, double ay, double bx, double by,
                      float *values) {
    double n = ceil(fmax(fabs(bx - ax), fabs(by - ay)));
    if (!(n < 1e7)) return; /* an edge far outside the tile: skip rather than walk it */
    for (double k = 0; k <= n; k++) {
        double f = n > 0 ? k / n : 0;
        double px = floor(ax + f * (bx - ax) + 0.5), py = floor(ay + f * (by - ay) + 0.5);
        if (px < 0 || py < 0 || px >= vp->width || py >= vp->height) continue;
        memcpy(values + ((size_t)py * vp->width + (size_t)px) * nc, c, (size_t)nc * sizeof *c);
    }
}

void tc_render_overlay(const tc_recon *r, const tc_viewport *vp, double scale, float *values) {
    const struct tc_mesh *m = r->m;
    int hermite = r->opt.method == TC_METHOD_HERMITE;
    int honor = r->opt.method == TC_METHOD_CLOUGH_TOCHER || hermite;
    float c[TC_MAX_CHANNELS];
    double sx = vp->width / (vp->x1 - vp->x0), sy = vp->height / (vp->y1 - vp->y0);
    for (int32_t e = 0; e < 3 * m->nt; e++) {
        if (m->nbr[e] >= 0 && m->nbr[e] < e / 3) continue; /* each edge once */
        if (hermite && tc__is_diagonal(m, e)) continue;     /* inside a patch: not an edge of it */
        const double *a = tc__vxy(m, m->tri[e]), *b = tc__vxy(m, m->tri[3 * (e / 3) + (e % 3 + 1) % 3]);
        int boundary = m->nbr[e] < 0;
        overlay_colour(honor ? (tc_continuity)m->flag[e] : TC_C1, boundary, m->nc, scale, c);
        draw_line(vp, m->nc, c, (a[0] - vp->x0) * sx - 0.5, (vp->y1 - a[1]) * sy - 0.5, (b[0] - vp->x0) * sx - 0.5,
                  (vp->y1 - b[1]) * sy - 0.5, values);
    }
}
