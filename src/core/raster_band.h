/* raster_band.h — what a tile's rendering (raster.c) hands the covering of a band's triangles
 * (raster_cover.c, built twice: portable and AVX2): the job, the band, and their small helpers. */
#ifndef TC_CORE_RASTER_BAND_H
#define TC_CORE_RASTER_BAND_H

#include <math.h>
#include <stdatomic.h>
#include <float.h>
#include <stdint.h>
#include <string.h>

#include "core/ct.h"
#include "core/ct_points.h"
#include "core/locate.h"
#include "core/recon.h"

struct band;

typedef struct {
    const tc_recon *r;
    const tc_locator *L;
    const tc_viewport *vp;
    const tc_render_options *ropt;
    float *values;
    int32_t *owner; /* the caller's owners of rows [row0, row0 + rows), or NULL: each band its own */
    const double *xs; /* [width] pixel-centre x of each column, as tc_viewport_pixel_center gives it */
    const double *ys; /* [rows] pixel-centre y of each row rendered (from row0), likewise */
    int32_t row0, rows; /* the rows rendered: [row0, row0 + rows) of vp, stored from values/owner's row 0 */
    int grain_lo, grain_hi; /* every centre of xs and ys a multiple of 2^grain_lo, below 2^grain_hi in magnitude */
    int nc;              /* r->m->nc: read once, not behind two pointers in every four pixels */
    double per_x;        /* vp->width / (vp->x1 - vp->x0): pixels per unit along a row (guesses only) */
    double per_y;        /* vp->height / (vp->y1 - vp->y0): pixels per unit down a column (likewise) */
    double margin_x, margin_y; /* pixel_range's widening along a row and down a column (range_margin) */
    int fast_form;       /* fast_form_here(), read once */
    void (*cover_band)(struct band *bd); /* tc__cover_band_avx2 or _portable, as the CPU allows */
    atomic_long *fast_setups; /* tests: where tri_setup counts its fast forms, or NULL */
    int threads;            /* the workers taking bands (band_size) */
    atomic_int next_row;    /* the first row no worker has taken, from row0 */
    float limit;            /* ropt->limit as a float, or 0 */
    atomic_llong limited;   /* samples limit_band stored as +-limit */
    atomic_int timed_out;
    atomic_int no_memory;
} job;

/* How many triangles the band holds back before covering them: the first read of a
 * triangle's ordinates is a cache miss (a 1024² tile of 8192 triangles spent 8% of its time
 * waiting on it), so each is prefetched PREFETCH_AHEAD triangles before its turn. */
#define PREFETCH_AHEAD 4

/* Pixels that triangles with few centres own (cover_few), waiting to be shaded exactly four at
 * a time, each lane its own triangle (tc__ct_points4: tc_eval_triangle's arithmetic lane for
 * lane): a tile denser than its pixels has about one such pixel per triangle, which alone would
 * fill one lane of four. Entry k: its lane (frame in f[k] or an earlier entry's of the same
 * triangle, values into v) and where its floats go. */
#define QUEUE 32
typedef struct {
    tc__eval_frame f[QUEUE];
    tc__ct_lane lane[QUEUE];
    float *out[QUEUE];
    double v[QUEUE * TC_MAX_CHANNELS];
    int n;
} shade_queue;

/* The band being rasterized: rows [j0, j1), their owners from own (row j0); the triangles
 * the locator gave and cover has not yet taken, in order (held[(first + k) % AHEAD]); the
 * pixels waiting for their values (q: NULL unless the method is the cubic). */
typedef struct band {
    const job *jb;
    int32_t j0, j1;
    int32_t *own;
    const struct tc__slot *held[PREFETCH_AHEAD];
    int first, nheld;
    shade_queue *q;
} band;

static inline int32_t *own_row(const band *bd, int32_t j) {
    return bd->own + (size_t)(j - bd->j0) * (size_t)bd->jb->vp->width;
}

/* A double as the tile's float: rounded once, and beyond the float range the
 * largest float of its sign, never an infinity (the doubles are finite: the
 * ordinates are bounded, recon.c). */
static inline float tile_float(double v) {
    float f = (float)v;
    return isinf(f) ? copysignf(FLT_MAX, f) : f;
}

typedef float v4f __attribute__((vector_size(16)));
typedef int32_t v4si __attribute__((vector_size(16)));

/* Widens [*lo, *hi] so that v is a multiple of 2^*lo and |v| < 2^*hi; a subnormal
 * (or non-finite) v makes the range hopeless (lattice_exact then says no). */
static inline void widen_grain(double v, int *lo, int *hi) {
    if (v == 0) return;
    uint64_t u;
    memcpy(&u, &v, sizeof u);
    int ex = (int)(u >> 52 & 0x7ff);
    if (ex == 0 || ex == 0x7ff) {
        *lo = INT32_MIN / 2;
        return;
    }
    uint64_t m = (u & ((UINT64_C(1) << 52) - 1)) | UINT64_C(1) << 52;
    int g = ex - 1075 + __builtin_ctzll(m), e = ex - 1022; /* |v| < 2^e */
    if (g < *lo) *lo = g;
    if (e > *hi) *hi = e;
}

/* The band's rows covered: every triangle the locator gives for them claims its pixels and shades
 * those it owns strictly, then the closed-only candidates are settled and the rest gets the
 * background; the band's owners must be all -1 before. One function, built twice from
 * raster_cover.c: tc__cover_band_avx2 with AVX2 and FMA instructions throughout (for a CPU that
 * has both; raster.c chooses), tc__cover_band_portable with the baseline's. Same bytes. */
void tc__cover_band_portable(band *bd);
void tc__cover_band_avx2(band *bd);

#endif
