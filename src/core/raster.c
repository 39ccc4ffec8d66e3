/* raster.c — rendering a reconstruction over a tile of pixels: every pixel centre
 * owned by exactly the triangle tc_locate names (shared exact test), evaluated
 * exactly as tc_eval_triangle does, rows split into bands across threads. */
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/ct.h"
#include "core/geom.h"
#include "core/locate.h"
#include "core/mesh.h"
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
    const tc_render_options *ropt;
    float *values;
    int32_t *owner;
    const double *xs; /* [width] pixel-centre x of each column, as tc_viewport_pixel_center gives it */
    int32_t row0, rows; /* the rows rendered: [row0, row0 + rows) of vp, stored from values/owner's row 0 */
    int32_t nbands;
    atomic_int next_band;
    atomic_int timed_out;
} job;

/* The band being rasterized: rows [j0, j1). */
typedef struct {
    const job *jb;
    int32_t j0, j1;
} band;

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
 * index wins, as in tc_locate). Returns the test's result. */
static int claim(const band *bd, const struct tc__slot *s, int32_t i, int32_t j, double y) {
    const tc_viewport *vp = bd->jb->vp;
    int hit = tc__slot_test(s, bd->jb->xs[i], y);
    if (hit == TC_SLOT_OUT) return hit;
    int32_t *slot = &bd->jb->owner[tc__ix(j - bd->jb->row0, vp->width, i)];
    if (hit == TC_SLOT_OWN) *slot = s->t;
    else if (*slot == -1 || (*slot <= -2 && -2 - *slot > s->t)) *slot = -2 - s->t;
    return hit;
}

/* Where row y crosses the triangle, approximately: [*xl, *xr], or 0 if it
 * misses it. Only a starting guess; claim() decides every pixel it touches. */
static int row_hull(const struct tc__slot *s, double y, double *xl, double *xr) {
    int any = 0;
    *xl = INFINITY, *xr = -INFINITY;
    for (int k = 0; k < 3; k++) {
        int n = k == 2 ? 0 : k + 1;
        double py = s->y[k], qy = s->y[n];
        if ((py - y) * (qy - y) > 0) continue;
        double x = py == qy ? s->x[k] : s->x[k] + (y - py) * (s->x[n] - s->x[k]) / (qy - py);
        if (py == qy) *xl = fmin(*xl, s->x[n]), *xr = fmax(*xr, s->x[n]);
        *xl = fmin(*xl, x), *xr = fmax(*xr, x);
        any = 1;
    }
    return any;
}

/* The pixels of row j (within [i0, i1]) the triangle contains, each owned
 * exactly as tc_locate would own its centre. Pixel centres along a row are
 * non-decreasing in x (each step of tc_viewport_pixel_center rounds
 * monotonically) and the triangle's closed set and its strict-ownership set are
 * both convex, so the contained pixels form one run: exact tests at its two
 * ends, outward until the first pixel out, and — when both ends are strictly
 * owned — everything between is strictly owned without a test. */
static void cover_row(const band *bd, const struct tc__slot *s, int32_t j, int32_t i0, int32_t i1) {
    const tc_viewport *vp = bd->jb->vp;
    double x, y, xl, xr, step = (vp->x1 - vp->x0) / vp->width;
    tc_viewport_pixel_center(vp, 0, j, &x, &y);
    if (!row_hull(s, y, &xl, &xr)) return;
    double fa = ceil((xl - vp->x0) / step - 0.5), fb = floor((xr - vp->x0) / step - 0.5);
    int32_t a = fa < i0 ? i0 : fa > i1 ? i1 : (int32_t)fa, b = fb > i1 ? i1 : fb < i0 ? i0 : (int32_t)fb;
    if (b < a) { /* a thin crossing between two centres: test the few around it */
        int32_t lo = b - 1 < i0 ? i0 : b - 1, hi = a + 1 > i1 ? i1 : a + 1;
        for (int32_t i = lo; i <= hi; i++) claim(bd, s, i, j, y);
        return;
    }
    int ha = TC_SLOT_OUT, hb = TC_SLOT_OUT;
    int32_t a0 = a, b0 = b;
    while (a <= b && (ha = claim(bd, s, a, j, y)) == TC_SLOT_OUT) a++;
    if (a > b) { /* nothing inside the guess: the run, if any, lies just beside it */
        for (int32_t i = a0 - 1; i >= i0 && claim(bd, s, i, j, y) != TC_SLOT_OUT; i--) {}
        for (int32_t i = b0 + 1; i <= i1 && claim(bd, s, i, j, y) != TC_SLOT_OUT; i++) {}
        return;
    }
    while (b > a && (hb = claim(bd, s, b, j, y)) == TC_SLOT_OUT) b--;
    if (b == a) hb = ha;
    for (int32_t i = a - 1; i >= i0 && claim(bd, s, i, j, y) != TC_SLOT_OUT; i--) {}
    for (int32_t i = b + 1; i <= i1 && claim(bd, s, i, j, y) != TC_SLOT_OUT; i++) {}
    int32_t *row = bd->jb->owner + (size_t)(j - bd->jb->row0) * (size_t)vp->width;
    for (int32_t i = a + 1; i < b; i++) {
        if (ha == TC_SLOT_OWN && hb == TC_SLOT_OWN) row[i] = s->t;
        else claim(bd, s, i, j, y);
    }
}

/* A double as the tile's float: rounded once, and beyond the float range the
 * largest float of its sign, never an infinity (the doubles are finite: the
 * ordinates are bounded, recon.c). */
static inline float tile_float(double v) {
    float f = (float)v;
    return isinf(f) ? copysignf(FLT_MAX, f) : f;
}

static void cover(void *ctx, const struct tc__slot *s) {
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
    if (i0 > i1) return;
    for (int32_t j = j0; j <= j1; j++) cover_row(bd, s, j, i0, i1);
}

/* The owner of pixel p, turning a closed-only candidate (-2 - t) into t. */
static int32_t settle(int32_t *owner, size_t p) {
    int32_t t = owner[p];
    if (t <= -2) t = owner[p] = -2 - t;
    return t;
}

/* Pixels [i, i + n) of a row, owned by t whose frame is f: each pixel as
 * tc_eval_triangle evaluates it (tc__frame, tc__frame_at, the method's eval).
 * The cubic methods go through tc__ct_span, which does that same arithmetic
 * four pixels at a time. */
static void shade_run(const job *jb, const tc__eval_frame *f, int32_t t, const double *xs, double y, int32_t n,
                      float *out) {
    const tc_recon *r = jb->r;
    int nc = r->m->nc;
    const double *coef = r->coef + (size_t)t * (size_t)nc * (size_t)r->ncoef;
    if (r->eval == tc__ct_eval) {
        tc__ct_span(f, coef, nc, xs, y, n, out, NULL);
        for (size_t i = 0; i < (size_t)n * (size_t)nc; i++) /* as tile_float */
            if (isinf(out[i])) out[i] = copysignf(FLT_MAX, out[i]);
        for (int ch = 0; ch < nc; ch++) /* as tc__floored: (float) keeps the sign */
            for (int32_t i = 0; r->floor0[ch] && i < n; i++)
                if (out[tc__ix(i, nc, ch)] < 0) out[tc__ix(i, nc, ch)] = 0;
        return;
    }
    double v[TC_MAX_CHANNELS];
    for (int32_t i = 0; i < n; i++) {
        tc__eval_point at;
        tc__frame_at(f, xs[i], y, &at);
        for (int ch = 0; ch < nc; ch++) r->eval(coef + (size_t)ch * (size_t)r->ncoef, &at, &v[ch], NULL);
        for (int ch = 0; ch < nc; ch++) out[tc__ix(i, nc, ch)] = tile_float(tc__floored(r, ch, v[ch]));
    }
}

/* Each row split into runs of one owner; the frame set up once per triangle. */
static void shade_band(const band *bd) {
    const job *jb = bd->jb;
    const tc_viewport *vp = jb->vp;
    int nc = jb->r->m->nc;
    tc__eval_frame f;
    memset(&f, 0, sizeof f); /* set before use (cur == -1); this quiets -Wmaybe-uninitialized */
    int32_t cur = -1;
    for (int32_t j = bd->j0; j < bd->j1; j++) {
        double x, y;
        tc_viewport_pixel_center(vp, 0, j, &x, &y);
        size_t row = (size_t)(j - jb->row0) * (size_t)vp->width;
        for (int32_t i = 0; i < vp->width;) {
            int32_t t = settle(jb->owner, row + (size_t)i), e = i + 1;
            while (e < vp->width && settle(jb->owner, row + (size_t)e) == t) e++;
            float *out = jb->values + (row + (size_t)i) * (size_t)nc;
            if (t < 0) {
                for (int32_t p = 0; p < e - i; p++)
                    for (int ch = 0; ch < nc; ch++)
                        out[tc__ix(p, nc, ch)] = jb->ropt->background ? tile_float(jb->ropt->background[ch]) : 0.0f;
            } else {
                if (t != cur) tc__frame(jb->r->m, t, &f), cur = t;
                shade_run(jb, &f, t, jb->xs + i, y, e - i, out);
            }
            i = e;
        }
    }
}

static void render_band(job *jb, int32_t b) {
    const tc_viewport *vp = jb->vp;
    band bd = {jb, jb->row0 + b * BAND_ROWS, jb->row0 + (b + 1) * BAND_ROWS};
    if (bd.j1 > jb->row0 + jb->rows) bd.j1 = jb->row0 + jb->rows;
    for (size_t p = (size_t)(bd.j0 - jb->row0) * (size_t)vp->width; p < (size_t)(bd.j1 - jb->row0) * (size_t)vp->width;
         p++)
        jb->owner[p] = -1;
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
        if (jb->ropt->deadline_ms > 0 && tc_now_ms() > jb->ropt->deadline_ms) {
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

int tc_render(const tc_recon *r, const tc_locator *L, const tc_viewport *vp, const tc_render_options *ropt,
              float *values, int32_t *owner) {
    static const tc_render_options defaults = {NULL, 1, 0, 0, 0};
    if (!ropt) ropt = &defaults;
    if (!valid_viewport(vp) || ropt->row0 < 0 || ropt->rows < 0 || ropt->row0 >= vp->height ||
        ropt->rows > vp->height - ropt->row0)
        return TC_EINVAL;
    int32_t rows = ropt->rows ? ropt->rows : vp->height - ropt->row0;
    int32_t *own = owner ? owner : tc__malloc((size_t)vp->width * (size_t)rows, sizeof *own);
    double *xs = tc__malloc((size_t)vp->width, sizeof *xs);
    if (!own || !xs) {
        if (!owner) free(own);
        free(xs);
        return TC_ENOMEM;
    }
    for (int32_t i = 0; i < vp->width; i++) {
        double unused;
        tc_viewport_pixel_center(vp, i, 0, &xs[i], &unused);
    }
    job jb = {r, L, vp, ropt, values, own, xs, ropt->row0, rows, (rows + BAND_ROWS - 1) / BAND_ROWS, 0, 0};
    run_threads(&jb, jb.ropt->threads > 1 ? jb.ropt->threads : 1);
    if (!owner) free(own);
    free(xs);
    return atomic_load(&jb.timed_out) ? TC_ETIMEOUT : TC_OK;
}

/* ---- mesh overlay ---- */

static void overlay_colour(tc_continuity kind, int boundary, int nc, double scale, float *c) {
    static const float rgb[4][3] = {{0.35f, 0.35f, 0.35f}, {1, 0.8f, 0}, {1, 0.1f, 0.1f}, {1, 1, 1}};
    static const float grey[4] = {0.35f, 0.7f, 1, 1};
    int k = boundary ? 3 : kind == TC_C1 ? 0 : kind == TC_C0 ? 1 : 2;
    for (int ch = 0; ch < nc; ch++) c[ch] = (float)(scale * (nc == 3 ? rgb[k][ch] : grey[k]));
}

/* A one-pixel line between two points in pixel coordinates (DDA), clipped to
 * the rows [row0, row0 + rows) that values holds from its row 0. Each pixel is
 * the same whichever rows are drawn: a band's line is the whole tile's line. */
static void draw_line(const tc_viewport *vp, int32_t row0, int32_t rows, int nc, const float *c, double ax,
                      double ay, double bx, double by, float *values) {
    if (floor(fmax(ay, by) + 0.5) < row0 || floor(fmin(ay, by) + 0.5) >= row0 + rows) return; /* not in the band */
    double n = ceil(fmax(fabs(bx - ax), fabs(by - ay)));
    if (!(n < 1e7)) return; /* an edge far outside the tile: skip rather than walk it */
    for (double k = 0; k <= n; k++) {
        double f = n > 0 ? k / n : 0;
        double px = floor(ax + f * (bx - ax) + 0.5), py = floor(ay + f * (by - ay) + 0.5);
        if (px < 0 || py < row0 || px >= vp->width || py >= row0 + rows) continue;
        memcpy(values + ((size_t)(py - row0) * (size_t)vp->width + (size_t)px) * (size_t)nc, c,
               (size_t)nc * sizeof *c);
    }
}

void tc_render_overlay(const tc_recon *r, const tc_viewport *vp, double scale, float *values) {
    tc_render_overlay_rows(r, vp, scale, 0, vp->height, values);
}

void tc_render_overlay_rows(const tc_recon *r, const tc_viewport *vp, double scale, int32_t row0, int32_t rows,
                            float *values) {
    const struct tc_mesh *m = r->m;
    const tc__method *mt = r->method;
    float c[TC_MAX_CHANNELS];
    double sx = vp->width / (vp->x1 - vp->x0), sy = vp->height / (vp->y1 - vp->y0);
    for (int32_t e = 0; e < 3 * m->nt; e++) {
        if (m->nbr[e] >= 0 && m->nbr[e] < e / 3) continue;       /* each edge once */
        if (mt->quads_only && tc__is_diagonal(m, e)) continue; /* inside a patch: not an edge of it */
        const double *a = tc__vxy(m, m->tri[e]), *b = tc__vxy(m, m->tri[3 * (e / 3) + (e % 3 + 1) % 3]);
        overlay_colour((tc_continuity)tc__method_edge(mt, m, e), m->nbr[e] < 0, m->nc, scale, c);
        draw_line(vp, row0, rows, m->nc, c, (a[0] - vp->x0) * sx - 0.5, (vp->y1 - a[1]) * sy - 0.5, (b[0] - vp->x0) * sx - 0.5,
                  (vp->y1 - b[1]) * sy - 0.5, values);
    }
}
