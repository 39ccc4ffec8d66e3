/* raster.c — rendering a reconstruction over a tile of pixels: the rows split into bands across
 * threads, each band's triangles covered by raster_cover.c (every pixel centre owned by exactly
 * the triangle tc_locate names, valued by the fast cubic or exactly), its samples limited. */
#include <math.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/cpu.h"
#include "core/ct_fast.h"
#include "core/mesh.h"
#include "core/minmax.h"
#include "core/parallel.h"
#include "core/raster_band.h"
#include "core/recon.h"

/* Rows per unit of work (tocher.h): few enough parts per tile to waste little on their
 * boundaries (each a locator query, and a second set-up of the triangles that cross it: 32 rows
 * render a 1024² tile 5-7% faster per thread than 16 did), enough to balance threads (128 parts
 * in a 4096² tile). The bands shrink to BAND_MIN_ROWS towards the tile's end (band_size). */
#define BAND_ROWS TC_RENDER_BAND_ROWS
#define BAND_MIN_ROWS 8

void tc_viewport_pixel_center(const tc_viewport *vp, int32_t i, int32_t j, double *x, double *y) {
    *x = vp->x0 + (vp->x1 - vp->x0) * ((i + 0.5) / vp->width);
    *y = vp->y1 - (vp->y1 - vp->y0) * ((j + 0.5) / vp->height);
}

/* How far, in pixels, raster_cover.c's pixel_range widens a triangle's range of columns (or
 * rows) along an axis [lo, hi] of n pixels: one pixel, for the rounding of its own index, and
 * where the pixels are not many ulps wide also the rounding of the centres. A centre
 * (tc_viewport_pixel_center) lies within a few ulps of |lo| + |hi| of where it would be
 * exactly, and pixel_range's index of a coordinate a centre could equal is as close: together
 * under 2^-48 (|lo| + |hi|) units, n (|lo| + |hi|) / (hi - lo) 2^-48 pixels, and the index's
 * own rounding under (n + 2) 2^-48. Below 2^-8 of a pixel (a pixel wider than ~2^12 of the
 * coordinates' ulps: every usual tile) it is left out, so their ranges are as they were; a
 * tile zoomed deeper (several centres of a row the same double) got too narrow a range with
 * the one pixel alone, and pixels on a triangle's edge went to its neighbour. Overflow: a NaN
 * keeps one pixel (pixels ~1e300 wide), an infinity widens to the whole axis. */
static double range_margin(double lo, double hi, int32_t n) {
    double slack = (n * ((fabs(lo) + fabs(hi)) / (hi - lo)) + n + 2) * 0x1p-48;
    return slack > 0x1p-8 ? 1 + slack : 1;
}

static int force_generic; /* tests (tc__raster_force_generic): 1 the portable covering, 2 no fast form */
static atomic_long fast_setups; /* tests: triangles set up in the fast form while force_generic is set */

/* The band's covering: tc__cover_band_avx2 where it was built (x86) and the CPU has its
 * instructions (AVX2, and FMA for ct_fast.h's fused multiply-adds), unless a test forces the
 * portable one; both give the same bytes. */
static void (*cover_band_here(void))(band *) {
#if TC__X86
    if (!force_generic && tc__cpu_avx2_fma()) return tc__cover_band_avx2;
#endif
    return tc__cover_band_portable;
}

/* Whether triangles may take the fast form (ct_fast.h) here: only where its fused multiply-adds
 * are instructions in the row loop, i.e. the AVX2 build on a CPU with FMA, or a target whose
 * compiler inlines fma (__FP_FAST_FMA: aarch64). Elsewhere each is a call of libm's fma, and on
 * an x86 CPU without FMA libm's software one (~1 us a call): a 1024² grid64 tile ran at 0.3
 * Mpixel/s in the fast form's portable build with it (GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA
 * here), 15 with calls of the hardware fma, and 30 on the exact path, which every triangle then
 * takes (its pixels /v1/evaluate's doubles, rounded to float, bit for bit). */
static int fast_form_here(void) {
    if (force_generic) return force_generic == 1; /* 1: the portable build's fast form, for its tests */
#ifdef __FP_FAST_FMA
    return 1;
#else
    return tc__cpu_avx2_fma();
#endif
}

void tc__raster_force_generic(int on) {
    force_generic = on;
    atomic_store(&fast_setups, 0);
}

long tc__raster_fast_setups(void) {
    return atomic_load(&fast_setups);
}

/* Whether some |v[i]| >= b, four at a time without a branch: the common answer, no, costs
 * ~1% of a band's render here, where the band is still in cache (the daemon's scan of a whole
 * 4096² tile after it was rendered took 9 ms on two threads, from memory). */
static int any_at_least(const float *v, size_t n, float b) {
    const v4si magnitude = {0x7fffffff, 0x7fffffff, 0x7fffffff, 0x7fffffff};
    const v4f bound = {b, b, b, b};
    v4si hit = {0, 0, 0, 0};
    size_t i = 0;
    for (; i + 4 <= n; i += 4) {
        v4si x;
        memcpy(&x, v + i, sizeof x);
        v4f mag;
        x &= magnitude;
        memcpy(&mag, &x, sizeof mag);
        hit |= mag >= bound;
    }
    int any = (hit[0] | hit[1] | hit[2] | hit[3]) != 0;
    for (; i < n; i++) any |= fabsf(v[i]) >= b;
    return any;
}

/* Rows [j0, j1)'s samples limited to +-jb->limit (tc_render_options.limit) and counted: a
 * pixel's own operation, so the tile's bytes still do not depend on the bands. */
static void limit_band(job *jb, int32_t j0, int32_t j1) {
    float b = jb->limit;
    if (!(b > 0)) return;
    size_t n = (size_t)(j1 - j0) * (size_t)jb->vp->width * (size_t)jb->nc;
    float *v = jb->values + (size_t)(j0 - jb->row0) * (size_t)jb->vp->width * (size_t)jb->nc;
    if (!any_at_least(v, n, b)) return;
    long long count = 0;
    for (size_t i = 0; i < n; i++) {
        if (!(fabsf(v[i]) >= b)) continue; /* the tile holds no NaN */
        count++;
        v[i] = copysignf(b, v[i]);
    }
    atomic_fetch_add(&jb->limited, count);
}

/* The band of rows [j0, j1) (take_band's), its owners in the caller's array or in scratch
 * (BAND_ROWS rows of the worker's: a tile's owners need never exist at once, nor touch
 * memory outside the cache, when the caller does not want them). */
static void render_band(job *jb, int32_t j0, int32_t j1, int32_t *scratch) {
    const tc_viewport *vp = jb->vp;
    shade_queue q; /* ~12 KB of stack: no thread here is started with less than the default */
    q.n = 0;
    band bd = {jb, j0, j1, scratch, {NULL}, 0, 0, tc__recon_is_ct(jb->r) ? &q : NULL};
    if (jb->owner) bd.own = jb->owner + (size_t)(bd.j0 - jb->row0) * (size_t)vp->width;
    memset(bd.own, 0xff, (size_t)(bd.j1 - bd.j0) * (size_t)vp->width * sizeof *bd.own); /* all -1 */
    jb->cover_band(&bd);
    limit_band(jb, j0, j1); /* while the band is in cache */
}

/* Rows in the next band when `left` rows are left for `threads` workers (guided
 * self-scheduling): BAND_ROWS while there is plenty, then smaller, down to BAND_MIN_ROWS, so
 * that the workers end together. With bands of BAND_ROWS to the end, the first worker done
 * waited 0.7-0.9 ms for the last of a 6-7 ms 4096² tile on 16 threads of the lent Xeon (the
 * workers busy 91% of the wall; 96% with a tail of small bands); guided, that tile went from
 * 3187 to 3346 Mpixel/s and the 1024² from 1224 to 1337 (medians of 4 rounds in turns,
 * bench/perf/device/ab_bands.txt). It also gives a band of few rows (the daemon renders
 * 4096-wide tiles ~96 rows a call) to more than three threads. One thread always takes
 * BAND_ROWS. A pixel does not depend on where bands begin, so neither do the tile's bytes. */
static int32_t band_size(int32_t left, int threads) {
    int32_t share = left / threads / BAND_MIN_ROWS * BAND_MIN_ROWS;
    return share > BAND_ROWS ? BAND_ROWS : share < BAND_MIN_ROWS ? BAND_MIN_ROWS : share;
}

/* Takes the next band, rows [*j0, *j1) of the viewport; 0 when no rows are left. */
static int take_band(job *jb, int32_t *j0, int32_t *j1) {
    int32_t at = atomic_load(&jb->next_row);
    do {
        if (at >= jb->rows) return 0;
        *j1 = at + band_size(jb->rows - at, jb->threads);
    } while (!atomic_compare_exchange_weak(&jb->next_row, &at, *j1));
    *j0 = jb->row0 + at;
    *j1 = jb->row0 + (*j1 < jb->rows ? *j1 : jb->rows);
    return 1;
}

static void *worker(void *arg) {
    job *jb = arg;
    int32_t *scratch = jb->owner ? NULL : tc__malloc((size_t)BAND_ROWS * (size_t)jb->vp->width, sizeof *scratch);
    if (!jb->owner && !scratch) {
        atomic_store(&jb->no_memory, 1);
        return NULL;
    }
    for (int32_t j0, j1; take_band(jb, &j0, &j1);) {
        if (atomic_load(&jb->timed_out) || atomic_load(&jb->no_memory)) break;
        if (jb->ropt->deadline_ms > 0 && tc_now_ms() > jb->ropt->deadline_ms) {
            atomic_store(&jb->timed_out, 1);
            break;
        }
        render_band(jb, j0, j1, scratch);
    }
    tc__free(scratch);
    return NULL;
}

static int valid_viewport(const tc_viewport *vp) {
    return vp->width >= 1 && vp->height >= 1 && isfinite(vp->x0) && isfinite(vp->x1) && isfinite(vp->y0) &&
           isfinite(vp->y1) && vp->x1 > vp->x0 && vp->y1 > vp->y0 &&
           (size_t)vp->width * (size_t)vp->height <= SIZE_MAX / (sizeof(float) * TC_MAX_CHANNELS);
}

/* One worker as a part of a tc__parallel_for_threads loop whose parts are the workers. */
static void worker_part(void *ctx, int32_t lo, int32_t hi, int part) {
    (void)lo, (void)hi, (void)part;
    worker(ctx);
}

/* n workers, the caller one of them, on the core's thread pool (parallel.c): starting
 * fifteen threads per tile cost ~0.5 ms, a twentieth of a 4096² tile's time on 16 cores
 * and more than a small tile's. The bands go to whichever worker asks next, so a part that
 * starts late (or after another on the same thread) only finds fewer bands left. */
static void run_threads(job *jb, int n) {
    int most = (jb->rows + BAND_MIN_ROWS - 1) / BAND_MIN_ROWS; /* bands of the least size */
    if (n > TC_PARALLEL_MAX) n = TC_PARALLEL_MAX;
    if (n > most) n = most;
    jb->threads = n > 1 ? n : 1;
    if (n <= 1) worker(jb);
    else tc__parallel_for_threads(n, n, 1, worker_part, jb);
}

int tc_render(const tc_recon *r, const tc_locator *L, const tc_viewport *vp, const tc_render_options *ropt,
              float *values, int32_t *owner) {
    static const tc_render_options defaults = {.threads = 1};
    if (!ropt) ropt = &defaults;
    if (!valid_viewport(vp) || ropt->row0 < 0 || ropt->rows < 0 || ropt->row0 >= vp->height ||
        ropt->rows > vp->height - ropt->row0)
        return TC_EINVAL;
    int32_t rows = ropt->rows ? ropt->rows : vp->height - ropt->row0;
    double *xs = tc__malloc((size_t)vp->width, sizeof *xs), *ys = tc__malloc((size_t)rows, sizeof *ys);
    if (!xs || !ys) {
        tc__free(xs), tc__free(ys);
        return TC_ENOMEM;
    }
    double unused;
    for (int32_t i = 0; i < vp->width; i++) tc_viewport_pixel_center(vp, i, 0, &xs[i], &unused);
    for (int32_t j = 0; j < rows; j++) tc_viewport_pixel_center(vp, 0, ropt->row0 + j, &unused, &ys[j]);
    int grain_lo = INT32_MAX / 2, grain_hi = INT32_MIN / 2;
    for (int32_t i = 0; i < vp->width; i++) widen_grain(xs[i], &grain_lo, &grain_hi);
    for (int32_t j = 0; j < rows; j++) widen_grain(ys[j], &grain_lo, &grain_hi);
    /* beyond FLT_MAX: infinity, which no sample reaches (the tile stops at +-FLT_MAX); NaN: none */
    float limit = ropt->limit > FLT_MAX ? INFINITY : ropt->limit > 0 ? (float)ropt->limit : 0;
    job jb = {.r = r, .L = L, .vp = vp, .ropt = ropt, .values = values, .owner = owner, .xs = xs, .ys = ys,
              .row0 = ropt->row0, .rows = rows, .grain_lo = grain_lo, .grain_hi = grain_hi, .nc = r->m->nc,
              .per_x = vp->width / (vp->x1 - vp->x0), .per_y = vp->height / (vp->y1 - vp->y0),
              .margin_x = range_margin(vp->x0, vp->x1, vp->width), .margin_y = range_margin(vp->y0, vp->y1, vp->height),
              .fast_form = fast_form_here(), .threads = 1, .limit = limit,
              .cover_band = cover_band_here(),
              .fast_setups = force_generic ? &fast_setups : NULL};
    run_threads(&jb, jb.ropt->threads > 1 ? jb.ropt->threads : 1);
    if (ropt->limited) *ropt->limited += atomic_load(&jb.limited);
    tc__free(xs), tc__free(ys);
    return atomic_load(&jb.no_memory) ? TC_ENOMEM : atomic_load(&jb.timed_out) ? TC_ETIMEOUT : TC_OK;
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
    if (floor(tc__fmax(ay, by) + 0.5) < row0 || floor(tc__fmin(ay, by) + 0.5) >= row0 + rows) return; /* not in the band */
    double n = ceil(tc__fmax(fabs(bx - ax), fabs(by - ay)));
    if (!(n < 1e7)) return; /* an edge far outside the tile: skip rather than walk it */
    for (double k = 0; k <= n; k++) {
        double f = n > 0 ? k / n : 0;
        double px = floor(ax + f * (bx - ax) + 0.5), py = floor(ay + f * (by - ay) + 0.5);
        /* written so that NaN fails it: a vertex on x0 of a viewport whose pixels per unit
         * overflow to infinity is at 0 * infinity */
        if (!(px >= 0 && py >= row0 && px < vp->width && py < row0 + rows)) continue;
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
