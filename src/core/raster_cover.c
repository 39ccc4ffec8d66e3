/* raster_cover.c — covering one band's triangles: each pixel centre owned exactly as tc_locate
 * owns it, valued by the fast cubic (ct_fast.h) or exactly as tc_eval_triangle values it.
 *
 * Built twice (Makefile): portable, and with -mavx2 -mfma and TC_COVER_AVX2, so that every
 * function here, not only the row loop, runs AVX2 and FMA instructions (and vec4.h's masks one
 * instruction) where raster.c finds the CPU has them. Nothing is contracted or reassociated
 * (-std=c11) and every fma is explicit, so both give the same bytes (tests/unit/test_raster.c). */
#include <math.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/cpu.h"
#include "core/ct.h"
#include "core/ct_fast.h"
#include "core/ct_points.h"
#include "core/geom.h"
#include "core/locate.h"
#include "core/mesh.h"
#include "core/minmax.h"
#include "core/raster_band.h"
#include "core/recon.h"

#ifdef TC_COVER_AVX2
#define COVER_BAND tc__cover_band_avx2
#else
#define COVER_BAND tc__cover_band_portable
#endif

/* Pixel index range [lo, hi] whose centres may fall in [a, b] along an axis of
 * n pixels starting at origin with the given step, widened by m pixels on each side
 * (the job's margin_x or margin_y: the rounding of the centres and of these indices, at
 * least a pixel): the exact test below decides, this only has to be a superset. */
static void pixel_range(double a, double b, double origin, double step, double per, int32_t n, double m,
                        int32_t *lo, int32_t *hi) {
    /* Multiplied by the pixels per unit where that is finite (a division costs several
     * multiplications, and a tile of small triangles does this for every one), else divided:
     * per overflows for a subnormal step. */
    double fa, fb;
    if (per < INFINITY) fa = (a - origin) * per - 0.5, fb = (b - origin) * per - 0.5;
    else fa = (a - origin) / step - 0.5, fb = (b - origin) / step - 0.5;
    /* floor(least - 1) and ceil(most + 1), clamped, by the conversion's truncation (floor's and
     * ceil's inline code, with the divisions, made this function 14% of a dense tile's time): l
     * is converted only when >= 0, where truncation is floor, and h only above -1, where
     * c + (c < h) is ceil. Adding or taking m rounds by at most half an ulp of a number
     * below 2^31 where it is converted, so each side keeps its margin but ~2^-22 of a pixel. */
    double l = (fa < fb ? fa : fb) - m, h = (fa > fb ? fa : fb) + m; /* fmin, fmax: calls */
    *lo = !(l >= 0) ? 0 : l >= n ? n : (int32_t)l; /* NaN (never from finite input): the whole range */
    if (!(h <= n - 1)) {
        *hi = n - 1;
    } else if (h <= -1) {
        *hi = -1;
    } else {
        int32_t c = (int32_t)h;
        *hi = c + (c < h);
    }
}

/* Owner encoding while a band is rasterized: -1 none, t >= 0 strict owner,
 * -2 - t a closed-only candidate (points on the outer boundary; the lowest
 * index wins, as in tc_locate). */

/* Triangle t's claim as a closed-only candidate of the pixel whose owner is *slot: it replaces
 * none (-1) and a candidate of a higher index (-2 - u < -2 - t when u > t); an owner stays.
 * (Written without a branch, a cmov and a store every time: 1-2% faster on a 1024² grid64
 * tile, 2-4% slower on the dense 256² and 512² grid256 tiles, 10 rounds in turns.) */
static inline void candidate(int32_t *slot, int32_t t) {
    int32_t c = -2 - t;
    if (*slot == -1 || *slot < c) *slot = c;
}

/* Claims the pixel (i, j) for s by the exact test; returns the test's result. */
static int claim(const band *bd, const struct tc__slot *s, int32_t i, int32_t j, double y) {
    int hit = tc__slot_test(s, bd->jb->xs[i], y);
    if (hit == TC_SLOT_OUT) return hit;
    int32_t *slot = &own_row(bd, j)[i];
    if (hit == TC_SLOT_OWN) *slot = s->t;
    else candidate(slot, s->t);
    return hit;
}


/* A triangle as one band meets it: its slot (the exact ownership tests), its
 * evaluation frame, and for the cubic of a well-shaped triangle its fast form. */
typedef struct {
    const struct tc__slot *s;
    tc__eval_frame f;
    double slope[3]; /* not fast: dx/dy of edge k -> k+1 (row_hull's guess) */
    double dy[3];    /* y[k+1] - y[k], as orient_sign computes it */
    int exact;       /* every orientation at a centre of the tile is computed exactly (lattice) */
    double inside[3]; /* exact: an orientation d is inside edge k when d > inside[k]: 0, or for an edge
                       * whose points the triangle owns, -2^-1010 (d >= 0: on the lattice a nonzero d
                       * is a multiple of 2^-1000 or coarser, lattice_exact; no subnormal involved) */
    v4f low[TC_MAX_CHANNELS]; /* store_lanes' lower clamp: 0 where the recon floors channel ch, else -FLT_MAX */
    int fast;        /* the cubic, and aspect <= TC__CT_FAST_ASPECT: ff and the hull below are set */
    double hx[3], hy[3]; /* fast: the corners from the top (largest y) down */
    double hs[3];        /* fast: dx/dy of top -> bottom, top -> middle, middle -> bottom */
    tc__ct_fast ff;
} tri;

/* Where row y crosses the triangle, approximately: [*xl, *xr], or 0 if it
 * misses it. Only a starting guess (slopes rounded once per triangle);
 * the exact tests (classify_one, claim) decide every pixel it touches. */
static inline void widen(double x, double *xl, double *xr) {
    *xl = x < *xl ? x : *xl; /* fmin/fmax are calls at -O2 */
    *xr = x > *xr ? x : *xr;
}

static inline int row_hull(const tri *tr, double y, double *xl, double *xr) {
    if (tr->fast) { /* a triangle of area > 0: the long edge and one of the two others, no loop */
        if (!(y <= tr->hy[0] && y >= tr->hy[2])) return 0; /* as below: no edge's span holds y */
        double xlong = tr->hx[0] + (y - tr->hy[0]) * tr->hs[0];
        /* each slope read only where its edge spans rows (not horizontal): finite */
        double xs = y > tr->hy[1]   ? tr->hx[0] + (y - tr->hy[0]) * tr->hs[1]
                    : y < tr->hy[1] ? tr->hx[1] + (y - tr->hy[1]) * tr->hs[2]
                                    : tr->hx[1];
        *xl = xlong < xs ? xlong : xs, *xr = xlong > xs ? xlong : xs;
        return 1;
    }
    const struct tc__slot *s = tr->s;
    int any = 0;
    *xl = INFINITY, *xr = -INFINITY;
    for (int k = 0; k < 3; k++) {
        int n = k == 2 ? 0 : k + 1;
        double py = s->y[k], qy = s->y[n];
        if ((py - y) * (qy - y) > 0) continue;
        double x = py == qy ? s->x[k] : s->x[k] + (y - py) * tr->slope[k];
        if (py == qy) widen(s->x[n], xl, xr); /* the row runs along the edge */
        widen(x, xl, xr);
        any = 1;
    }
    return any;
}

/* The same bound orient_sign (locate.c) certifies a floating-point sign with. */
#define ORIENT_ERRBOUND ((3.0 + 16.0 * 0x1p-53) * 0x1p-53)

/* Pixels [i, i + n) of a row, owned by t whose frame tr holds: each pixel as
 * tc_eval_triangle evaluates it (tc__frame_at and the method's eval;
 * tc__ct_span for the cubic, which does that same arithmetic four pixels at a
 * time), or the fast cubic (ct_fast.h) where tr->fast. Then as tile_float and
 * tc__floored make every value of a tile. */
static void shade_run(const job *jb, const tri *tr, int32_t t, const double *xs, double y, int32_t n, float *out) {
    const tc_recon *r = jb->r;
    int nc = r->m->nc;
    const double *coef = r->coef + (size_t)t * (size_t)nc * (size_t)r->ncoef;
    if (tc__recon_is_ct(r)) {
        if (tr->fast) {
            double K[3];
            tc__ct_fast_row(&tr->ff, y, K);
            for (int32_t i = 0; i < n; i++) {
                tc__v4d v[TC_MAX_CHANNELS];
                tc__ct_fast_lanes(&tr->ff, K, tc__splat(xs[i]), v);
                for (int ch = 0; ch < nc; ch++) out[tc__ix(i, nc, ch)] = (float)v[ch][0];
            }
        } else {
            tc__ct_span(&tr->f, coef, nc, xs, y, n, out, NULL);
        }
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
        tc__frame_at(&tr->f, xs[i], y, &at);
        for (int ch = 0; ch < nc; ch++) r->eval(coef + (size_t)ch * (size_t)r->ncoef, &at, &v[ch], NULL);
        for (int ch = 0; ch < nc; ch++) out[tc__ix(i, nc, ch)] = tile_float(tc__floored(r, ch, v[ch]));
    }
}

/* The pixels of row j in [lo, hi] that tr strictly owns (one run, or none) shaded. */
static void shade_pixels(const band *bd, const tri *tr, int32_t j, double y, int32_t lo, int32_t hi) {
    const job *jb = bd->jb;
    int32_t *row = own_row(bd, j), t = tr->s->t;
    while (lo <= hi && row[lo] != t) lo++;
    while (hi >= lo && row[hi] != t) hi--;
    if (lo <= hi)
        shade_run(jb, tr, t, jb->xs + lo, y, hi - lo + 1,
                  jb->values + ((size_t)(j - jb->row0) * (size_t)jb->vp->width + (size_t)lo) * (size_t)jb->nc);
}

/* m ? a : b, lane by lane, for floats. */
TC__V4_INLINE v4f fsel(v4si m, v4f a, v4f b) {
    v4si ia, ib, r;
    memcpy(&ia, &a, sizeof ia);
    memcpy(&ib, &b, sizeof ib);
    r = (ia & m) | (ib & ~m);
    v4f out;
    memcpy(&out, &r, sizeof out);
    return out;
}

/* SSE's maxps and minps, exactly: max(a, b) = a > b ? a : b and min(a, b) = a < b ? a : b, lane
 * by lane, so a NaN or a -0 in b comes through (store_lanes_nc relies on it). One instruction
 * on x86; elsewhere the same selection by comparison. */
TC__V4_INLINE v4f sse_max(v4f a, v4f b) {
#if TC__X86
    return __builtin_ia32_maxps(a, b);
#else
    return fsel(a > b, a, b);
#endif
}

TC__V4_INLINE v4f sse_min(v4f a, v4f b) {
#if TC__X86
    return __builtin_ia32_minps(a, b);
#else
    return fsel(a < b, a, b);
#endif
}

TC__V4_INLINE tc__v4d vabs(tc__v4d a) {
    return tc__sel((tc__v4i){INT64_MAX, INT64_MAX, INT64_MAX, INT64_MAX}, a, tc__splat(0));
}

/* Four fast values as the tile stores them (tile_float, tc__floored), lanes
 * in `mask` only; out is the first lane's pixel, full says all four lanes are
 * pixels of the row (the others, read and written back unchanged, belong to
 * this band's thread alone). */
TC__V4_INLINE void store_lanes_nc(const tri *tr, int nc, const double K[3], tc__v4d x, unsigned mask, int full,
                                   float *out, int mix) {
    tc__v4d v[TC_MAX_CHANNELS];
    tc__ct_fast_lanes_mix(&tr->ff, nc, K, x, v, mix);
    for (int ch = 0; ch < nc; ch++) {
        v4f f = __builtin_convertvector(v[ch], v4f), big = {FLT_MAX, FLT_MAX, FLT_MAX, FLT_MAX}, low;
        /* as tile_float, then tc__floored: a NaN or a -0 f comes through sse_max(c, f) and
         * sse_min(c, f); low is -FLT_MAX, or 0 for a floored channel */
        memcpy(&low, &tr->low[ch], sizeof low);
        f = sse_min(big, sse_max(low, f));
        if (nc == 1 && mask == 15) { /* one channel, four pixels of the row, all stored */
            memcpy(out, &f, sizeof f);
            continue;
        }
        if (nc == 1 && full) { /* one channel, four pixels of the row: blend in place */
            static const v4si lane[16] = {{0, 0, 0, 0},   {-1, 0, 0, 0},   {0, -1, 0, 0},   {-1, -1, 0, 0},
                                          {0, 0, -1, 0},  {-1, 0, -1, 0},  {0, -1, -1, 0},  {-1, -1, -1, 0},
                                          {0, 0, 0, -1},  {-1, 0, 0, -1},  {0, -1, 0, -1},  {-1, -1, 0, -1},
                                          {0, 0, -1, -1}, {-1, 0, -1, -1}, {0, -1, -1, -1}, {-1, -1, -1, -1}};
            v4f old;
            memcpy(&old, out, sizeof old);
            f = fsel(lane[mask], f, old);
            memcpy(out, &f, sizeof f);
            continue;
        }
        for (int l = 0; l < 4; l++)
            if (mask >> l & 1u) out[tc__ix(l, nc, ch)] = f[l];
    }
}

/* store_lanes_nc for the job's channels, the common single channel with its loops unrolled. mix:
 * every lane through tc__ct_fast_lanes_mix's permutation, whatever the subtriangles (the same
 * bits). A run of one to three pixels (a triangle's first and last rows) takes it: on an irregular
 * mesh whether such a group lies in one subtriangle is a branch that mispredicts, and a 512²
 * tile of del1e4 rendered 1.045x as fast (1024² 1.028x, del1e3 1.014x, grids 0.996-1.007x: 10
 * rounds in turns). Longer runs keep the branch: on a grid, whose identical triangles make it
 * predictable, every group through the permutation was 6-24% slower (bench/perf/notes.md). */
TC__V4_INLINE void store_lanes(const job *jb, const tri *tr, const double K[3], tc__v4d x, unsigned mask,
                                 int full, float *out, int mix) {
    if (jb->nc == 1) store_lanes_nc(tr, 1, K, x, mask, full, out, mix);
    else store_lanes_nc(tr, jb->nc, K, x, mask, full, out, mix);
}

/* Whether d = a - b is exact: Knuth's TwoSum error of a + (-b) is 0. */
static inline int diff_exact(double a, double b, double d) {
    double bb = d - a;
    return (a - (d - bb)) + (-b - bb) == 0;
}

/* Operands whose products neither underflow nor overflow: 0, or 2^-400 <= |v| <= 2^400. */
static inline int tame(double v) {
    double a = fabs(v);
    return a == 0 || (a >= 0x1p-400 && a <= 0x1p400);
}


/* Whether every orientation l - r = (x[k+1] - x[k]) (y - y[k]) - (y[k+1] - y[k]) (x - x[k])
 * of the triangle at a centre of the tile is computed exactly: all its operands are
 * integer multiples of 2^g below 2^E in magnitude (the corners' and the centres' range
 * together), so each difference is a multiple of 2^g below 2^(E+1), each product a
 * multiple of 2^2g below 2^(2E+2), l - r one below 2^(2E+3): an integer below 2^53
 * times 2^2g when E - g <= 25, exact, and no product underflows while 2g >= -1022.
 * A lattice of centres on a mesh of dyadic vertices (a grid) is the common case. */
static int lattice_exact(const job *jb, const struct tc__slot *s) {
    int lo = jb->grain_lo, hi = jb->grain_hi;
    for (int k = 0; k < 3; k++) widen_grain(s->x[k], &lo, &hi), widen_grain(s->y[k], &lo, &hi);
    return lo >= -500 && hi <= 500 && hi - lo <= 25;
}

/* The row's half of each edge's orientation at row y, as orient_sign computes it:
 * l[k] = (x[k+1] - x[k]) (y - y[k]), what edge_sign and the lanes take from the row. */
static inline void row_terms(const struct tc__slot *s, double y, double l[3]) {
    for (int k = 0; k < 3; k++) l[k] = (s->x[k == 2 ? 0 : k + 1] - s->x[k]) * (y - s->y[k]);
}

/* The sign (-1, 0, 1) of edge k's orientation at (x, y), computed as orient_sign
 * computes it: certified by its bound, or else exact because nothing rounded
 * (each difference checked by TwoSum, each product by fma, the difference of
 * the products by TwoSum: a centre exactly on a grid's diagonal). 2: neither,
 * only the exact test can say. */
static int edge_sign(const struct tc__slot *s, const double l[3], int k, double x, double y) {
    int n = k == 2 ? 0 : k + 1;
    double a = s->x[n] - s->x[k], b = y - s->y[k], c = s->y[n] - s->y[k], d = x - s->x[k];
    double r = c * d, det = l[k] - r;
    if (fabs(det) >= ORIENT_ERRBOUND * (fabs(l[k]) + fabs(r))) return (det > 0) - (det < 0);
    if (!tame(a) || !tame(b) || !tame(c) || !tame(d) || !diff_exact(s->x[n], s->x[k], a) ||
        !diff_exact(y, s->y[k], b) || !diff_exact(s->y[n], s->y[k], c) || !diff_exact(x, s->x[k], d) ||
        fma(a, b, -l[k]) != 0 || fma(c, d, -r) != 0 || !diff_exact(l[k], r, det))
        return 2;
    return (det > 0) - (det < 0);
}

/* One pixel's owner by the strict rule (a lane classify_lanes could not certify, or
 * a pixel beyond the guess): tc__slot_test's answer from the
 * edges' exact signs where edge_sign knows them (zero: inside for an edge the
 * triangle lies left of, touching otherwise), claim() where it does not; the
 * claim made as claim() makes it. */
static int classify_one(const band *bd, const struct tc__slot *s, const double l[3], int32_t i, int32_t j, double y) {
    int hit = TC_SLOT_OWN;
    for (int k = 0; k < 3; k++) {
        int sg = edge_sign(s, l, k, bd->jb->xs[i], y);
        if (sg == 2) return claim(bd, s, i, j, y);
        if (sg < 0) return TC_SLOT_OUT;
        if (sg == 0 && !(s->left >> k & 1u)) hit = TC_SLOT_TOUCH;
    }
    int32_t *slot = &own_row(bd, j)[i];
    if (hit == TC_SLOT_OWN) *slot = s->t;
    else candidate(slot, s->t);
    return hit;
}

/* The lane versions of tame and diff_exact, and whether the product p = a * b
 * rounded nothing: Dekker's exact product (Veltkamp's split), exact without an FMA
 * when neither factor's magnitude leaves [2^-400, 2^400] (tame: no overflow, no
 * subnormal part), so the portable and AVX2 builds agree. */
TC__V4_INLINE tc__v4i tame4(tc__v4d v) {
    tc__v4d a = vabs(v);
    return (a == tc__splat(0)) | ((a >= tc__splat(0x1p-400)) & (a <= tc__splat(0x1p400)));
}

TC__V4_INLINE tc__v4i diff_exact4(tc__v4d a, tc__v4d b, tc__v4d d) {
    tc__v4d bb = d - a;
    return (a - (d - bb)) + (-b - bb) == tc__splat(0);
}

TC__V4_INLINE tc__v4i prod_exact4(double a, tc__v4d b, tc__v4d p) {
    const double split = 134217729.0; /* 2^27 + 1 */
    double ta = a * split, ah = ta - (ta - a), alo = a - ah;
    tc__v4d tb = b * tc__splat(split), bh = tb - (tb - b), blo = b - bh;
    tc__v4d e = ((tc__splat(ah) * bh - p) + tc__splat(ah) * blo + tc__splat(alo) * bh) + tc__splat(alo) * blo;
    return e == tc__splat(0);
}

/* Edge e's orientation at the four centres x of the row whose terms l are (row_terms): exact,
 * where tr->exact (lattice_exact). */
TC__V4_INLINE tc__v4d exact_orient(const tri *tr, const double l[3], int e, tc__v4d x) {
    return tc__splat(l[e]) - tc__splat(tr->dy[e]) * (x - tc__splat(tr->s->x[e]));
}

/* The lanes strictly inside an edge whose points the neighbour across it owns (the slot's
 * across bits), tr->exact: orientation 0 on that edge, > 0 on the other two. The neighbour's
 * signs there are exact too (its corners tame, locate.c; the centres on tr's lattice), so it owns
 * them strictly and settles them: no closed-only claim is needed. A grid's diagonal through pixel
 * centres (a 1024² grid64 tile, every 16th centre of a row) made one in every other row of its
 * triangles, about 5% of that tile's time. Recomputed here, where a lane touches, not kept from
 * the classification: the common path stays as small. */
TC__V4_INLINE unsigned across_lanes(const tri *tr, const double l[3], tc__v4d x) {
    tc__v4d d[3];
    tc__v4i z = {0, 0, 0, 0}, p[3];
    for (int e = 0; e < 3; e++) d[e] = exact_orient(tr, l, e, x), p[e] = d[e] > tc__splat(0);
    for (int e = 0; e < 3; e++)
        if (tr->s->across >> e & 1u) z |= (d[e] == tc__splat(0)) & p[e == 2 ? 0 : e + 1] & p[e == 0 ? 2 : e - 1];
    return tc__mask4(z);
}

/* Four pixels of row j, lane q the pixel idx[q] at centre x[q] (lanes not in `valid`
 * ignored): each edge's orientation computed as orient_sign computes it (from corner
 * k: l - r, l = (x[k+1] - x[k]) (y - y[k]), r = (y[k+1] - y[k]) (x - x[k])) and its
 * sign certified by the same bound, so a lane certified inside (all three positive)
 * or outside (one negative) gets the exact answer without the exact test. A lane not
 * certified on some edge (a centre on an edge: a grid's diagonal) gets edge_sign's
 * second answer, four lanes at a time: the computed sign is exact when nothing
 * rounded (every difference checked by TwoSum, every product by Dekker's). Lanes
 * still unknown go to classify_one. Every lane owned or touching is claimed as
 * claim() claims it. *inb / *outb: the lanes strictly owned / outside the closed
 * triangle (a lane in neither is a closed-only candidate). */
TC__V4_INLINE void classify_at(const band *bd, const tri *tr, int32_t j, double y, const double l[3],
                                 const double al[3], const int32_t idx[4], tc__v4d x, unsigned valid,
                                 unsigned *inb, unsigned *outb) {
    const struct tc__slot *s = tr->s;
    tc__v4i in = {-1, -1, -1, -1}, out = {0, 0, 0, 0}, cert[3];
    tc__v4d det[3], r[3];
    if (tr->exact) { /* lattice_exact: each computed sign is the exact one */
        for (int e = 0; e < 3; e++) {
            tc__v4d d = exact_orient(tr, l, e, x);
            in &= d > tc__splat(tr->inside[e]);
            out |= d < tc__splat(0);
        }
        *inb = tc__mask4(in) & valid, *outb = tc__mask4(out) & valid;
        unsigned touch = valid & ~(*inb | *outb);
        if (touch && s->across) touch &= ~across_lanes(tr, l, x);
        for (; touch; touch &= touch - 1) /* claimed as claim() does */
            candidate(&own_row(bd, j)[idx[__builtin_ctz(touch)]], s->t);
        return;
    }
    for (int e = 0; e < 3; e++) {
        r[e] = tc__splat(tr->dy[e]) * (x - tc__splat(s->x[e])), det[e] = tc__splat(l[e]) - r[e];
        cert[e] = vabs(det[e]) >= tc__splat(ORIENT_ERRBOUND) * (tc__splat(al[e]) + vabs(r[e]));
        in &= cert[e] & (det[e] > tc__splat(0));
        out |= cert[e] & (det[e] < tc__splat(0));
    }
    *inb = tc__mask4(in) & valid, *outb = tc__mask4(out) & valid;
    unsigned unsure = valid & ~(*inb | *outb);
    if (!unsure) return;
    tc__v4i known = {-1, -1, -1, -1}, neg = {0, 0, 0, 0}, touch = {0, 0, 0, 0}, none = {0, 0, 0, 0};
    for (int e = 0; e < 3; e++) {
        neg |= det[e] < tc__splat(0);
        if (!(s->left >> e & 1u)) touch |= det[e] == tc__splat(0);
        if ((tc__mask4(cert[e]) & unsure) == unsure) continue; /* known on this edge */
        int n = e == 2 ? 0 : e + 1;
        double a = s->x[n] - s->x[e], b = y - s->y[e], c = tr->dy[e];
        int rows_ok = tame(a) && tame(b) && tame(c) && diff_exact(s->x[n], s->x[e], a) &&
                      diff_exact(y, s->y[e], b) && diff_exact(s->y[n], s->y[e], c) &&
                      (prod_exact4(a, tc__splat(b), tc__splat(l[e]))[0] != 0);
        tc__v4i ok = none;
        if (rows_ok) {
            tc__v4d xk = tc__splat(s->x[e]), d = x - xk;
            ok = tame4(d) & diff_exact4(x, xk, d) & prod_exact4(c, d, r[e]) &
                 diff_exact4(tc__splat(l[e]), r[e], det[e]);
        }
        known &= cert[e] | ok;
    }
    unsigned kn = tc__mask4(known) & unsure, ng = tc__mask4(neg), tc = tc__mask4(touch);
    for (int q = 0; unsure; q++, unsure >>= 1) {
        if (!(unsure & 1u)) continue;
        int h;
        if (kn >> q & 1u) {
            h = ng >> q & 1u ? TC_SLOT_OUT : tc >> q & 1u ? TC_SLOT_TOUCH : TC_SLOT_OWN;
            int32_t *slot = &own_row(bd, j)[idx[q]];
            if (h == TC_SLOT_OWN) *slot = s->t;
            else if (h == TC_SLOT_TOUCH) candidate(slot, s->t);
        } else {
            h = classify_one(bd, s, l, idx[q], j, y);
        }
        if (h == TC_SLOT_OWN) *inb |= 1u << q;
        else if (h == TC_SLOT_OUT) *outb |= 1u << q;
    }
}

/* Pixels i .. i + k - 1 of row j (k <= 4), their centres x: classify_at's answer. */
TC__V4_INLINE void classify_lanes(const band *bd, const tri *tr, int32_t j, double y, const double l[3],
                                    const double al[3], int32_t i, int32_t k, tc__v4d x, unsigned *inb,
                                    unsigned *outb) {
    const int32_t idx[4] = {i, i + 1, i + 2, i + 3};
    classify_at(bd, tr, j, y, l, al, idx, x, (1u << k) - 1, inb, outb);
}

/* Pixel centres i .. i + k - 1 of the row (1 <= k <= 4); lanes beyond repeat the first or
 * the last (every caller masks them out). No loop: GCC made the loop over k a call of
 * memcpy, with a vzeroupper before it, in every short run of the AVX2 rows. */
TC__V4_INLINE tc__v4d lanes_x(const double *xs, int32_t i, int32_t k) {
    tc__v4d x;
    if (k == 4) {
        memcpy(&x, xs + i, sizeof x);
        return x;
    }
    int32_t last = k - 1; /* 0 .. 2 */
    return (tc__v4d){xs[i], xs[i + (last < 1 ? last : 1)], xs[i + last], xs[i]};
}

TC__V4_INLINE void row_lanes(const band *bd, const tri *tr, int32_t j, double y, const double l[3], int32_t lo,
                               int32_t hi, int *first_out, int *last_out) {
    const job *jb = bd->jb;
    const struct tc__slot *s = tr->s;
    int nc = jb->nc;
    size_t row = (size_t)(j - jb->row0) * (size_t)jb->vp->width;
    int32_t *orow = own_row(bd, j);
    float *vrow = jb->values + row * (size_t)nc;
    double K[3] = {0, 0, 0}, al[3];
    if (tr->fast) tc__ct_fast_row(&tr->ff, y, K);
    for (int e = 0; e < 3; e++) al[e] = fabs(l[e]);
    /* The last four first: with an owned pixel there (b) and one in an earlier
     * four (a), every pixel between is owned (convexity) and needs no test. */
    int32_t ilast = lo + (hi - lo) / 4 * 4, klast = hi - ilast + 1, a = -1, b = -1;
    unsigned lin, lout;
    classify_lanes(bd, tr, j, y, l, al, ilast, klast, lanes_x(jb->xs, ilast, klast), &lin, &lout);
    for (int q = klast - 1; q >= 0 && b < 0; q--)
        if (lin >> q & 1u) b = ilast + q;
    for (int32_t i = lo; i <= hi; i += 4) {
        int32_t k = hi - i + 1 < 4 ? hi - i + 1 : 4;
        tc__v4d x = lanes_x(jb->xs, i, k);
        unsigned inb, outb;
        if (i == ilast) inb = lin, outb = lout;
        else if (a >= 0 && b >= i + 3) inb = 15, outb = 0;
        else classify_lanes(bd, tr, j, y, l, al, i, k, x, &inb, &outb);
        if (a < 0 && inb) a = i + __builtin_ctz(inb);
        if (inb == 15) {
            v4si t = {s->t, s->t, s->t, s->t};
            memcpy(orow + i, &t, sizeof t);
        } else {
            for (int q = 0; q < k; q++)
                if (inb >> q & 1u) orow[i + q] = s->t;
        }
        if (inb && tr->fast) store_lanes(jb, tr, K, x, inb, k == 4, vrow + (size_t)i * (size_t)nc, 0);
        if (i == lo) *first_out = outb & 1u;
        if (i + k - 1 == hi) *last_out = outb >> (k - 1) & 1u;
    }
}

/* Pixels [a, b] of row j, all strictly owned by the fast triangle tr: owners set and
 * values stored, four at a time. A run that is not a multiple of four ends with the
 * four pixels b - 3 .. b, recomputing some: a pixel's value depends only on the
 * triangle, its row and its x (ct_fast.h), not on its lane. */
TC__V4_INLINE void fill_run(const band *bd, const tri *tr, int32_t j, double y, int32_t a, int32_t b) {
    const job *jb = bd->jb;
    int nc = jb->nc;
    int32_t *orow = own_row(bd, j), n = b - a + 1, t = tr->s->t;
    float *vrow = jb->values + (size_t)(j - jb->row0) * (size_t)jb->vp->width * (size_t)nc;
    double K[3];
    tc__ct_fast_row(&tr->ff, y, K);
    if (n < 4) { /* the row's one group: through the permutation, no branch on its subtriangles (mix) */
        for (int32_t i = a; i <= b; i++) orow[i] = t;
        int full = a + 4 <= jb->vp->width;
        store_lanes(jb, tr, K, lanes_x(jb->xs, a, n), (1u << n) - 1, full, vrow + (size_t)a * (size_t)nc, 1);
        return;
    }
    v4si tv = {t, t, t, t};
    for (int32_t i = a;; i += 4) {
        if (i > b - 3) i = b - 3;
        memcpy(orow + i, &tv, sizeof tv);
        tc__v4d x;
        memcpy(&x, jb->xs + i, sizeof x);
        store_lanes(jb, tr, K, x, 15, 1, vrow + (size_t)i * (size_t)nc, 0);
        if (i == b - 3) break;
    }
}

/* Row j of a fast triangle tr from the guess [lo, hi] (hi - lo >= 2), settled by one
 * four-lane classification of P0..P3 = lo, lo + 1, hi - 1, hi when the guess is right
 * to a pixel. Each lane is owned (strictly), out (of the closed triangle) or touching
 * (in the closed triangle, not owned: classify_one claimed it as a candidate). Facts:
 * (1) the owned set and the closed triangle are convex (intersections of half-planes,
 *     open or closed), and a row's centres are non-decreasing in x;
 * (2) a point strictly between a closed point c and an owned point w is owned: each
 *     edge's orientation is affine along the row, >= 0 at c, and > 0 at w, or 0 at w
 *     (then the edge owns its points, and the orientation is >= 0 between, 0 only where
 *     it owns them too).
 * The run [a, b] (everything in it owned, by (1) or (2)):
 *   left:  P0 out and P1 owned: a = lo + 1; P0 out, P1 touching, P2 owned and
 *          x(P1) < x(lo + 2): a = lo + 2, by (2); lo = i0 (no column further left is
 *          the triangle's) and P0 owned: a = lo, or P0 touching and P1 owned: a = lo + 1;
 *   right: the mirror image (P3 out and P2 owned: b = hi - 1, ...).
 * Nothing outside [a, b] in [i0, i1] is owned or touching but the lanes classify_one
 * claimed: a closed pixel left of P0 out would put P0 between it and the closed P1.
 * Returns 0 when the lanes fit none of these (the caller then classifies lane by lane). */
TC__V4_INLINE int guessed_run(const band *bd, const tri *tr, int32_t j, double y, const double l[3], int32_t lo,
                                int32_t hi, int32_t i0, int32_t i1) {
    const double *xs = bd->jb->xs;
    const int32_t idx[4] = {lo, lo + 1, hi - 1, hi};
    tc__v4d x = {xs[lo], xs[lo + 1], xs[hi - 1], xs[hi]};
    double al[3] = {fabs(l[0]), fabs(l[1]), fabs(l[2])};
    unsigned in, out;
    classify_at(bd, tr, j, y, l, al, idx, x, 15, &in, &out);
    unsigned touch = 15u & ~(in | out);
    int32_t a = -1, b = -1;
    if (out & 1u) {
        if (in & 2u) a = lo + 1;
        else if ((touch & 2u) && (in & 4u) && lo + 2 <= hi - 1 && xs[lo + 1] < xs[lo + 2]) a = lo + 2;
    } else if (lo == i0) {
        if (in & 1u) a = lo;
        else if ((touch & 1u) && (in & 2u)) a = lo + 1;
    }
    if (out & 8u) {
        if (in & 4u) b = hi - 1;
        else if ((touch & 4u) && (in & 2u) && hi - 2 >= lo + 1 && xs[hi - 2] < xs[hi - 1]) b = hi - 2;
    } else if (hi == i1) {
        if (in & 8u) b = hi;
        else if ((touch & 8u) && (in & 4u)) b = hi - 1;
    }
    if (a < 0 || b < a) return 0;
    fill_run(bd, tr, j, y, a, b);
    return 1;
}

/* Row j of triangle tr within columns [i0, i1]: the pixels it contains, each
 * owned exactly as tc_locate would own its centre, and those it strictly owns
 * shaded. The guess from row_hull, widened by a pixel, is classified lane by
 * lane; pixel centres along a row are non-decreasing in x and the triangle's
 * closed set is convex, so its pixels form one run, and where an end of the
 * guess is still in, the run goes on outward until a pixel is out. Closed-only
 * candidates are left to settle_band. */
TC__V4_INLINE void cover_row_body(const band *bd, const tri *tr, int32_t j, int32_t i0, int32_t i1) {
    const job *jb = bd->jb;
    const tc_viewport *vp = jb->vp;
    const struct tc__slot *s = tr->s;
    double y = jb->ys[j - jb->row0], xl, xr, per_x = jb->per_x, l[3];
    if (!row_hull(tr, y, &xl, &xr)) return;
    row_terms(s, y, l);
    /* A guess, biased a little outward: a centre the edge runs through (a grid's
     * diagonal) falls inside [lo, hi], the pixel beyond it outside, as guessed_run wants. */
    double fa = floor((xl - vp->x0) * per_x - (0.5 + 0x1p-8)), fb = ceil((xr - vp->x0) * per_x - (0.5 - 0x1p-8));
    /* A NaN guess (a viewport so narrow that per_x overflows: 0 * inf) guesses the whole
     * span [i0, i1]: the comparisons are written so that NaN fails them. */
    int32_t lo = !(fa >= i0) ? i0 : fa > i1 ? i1 : (int32_t)fa, hi = !(fb <= i1) ? i1 : fb < i0 ? i0 : (int32_t)fb;
    if (tr->fast && hi - lo >= 2 && guessed_run(bd, tr, j, y, l, lo, hi, i0, i1)) return;
    int first_out = 1, last_out = 1;
    row_lanes(bd, tr, j, y, l, lo, hi, &first_out, &last_out);
    int32_t a = lo, b = hi;
    if (!first_out)
        while (a > i0 && classify_one(bd, s, l, a - 1, j, y) != TC_SLOT_OUT) a--;
    if (!last_out)
        while (b < i1 && classify_one(bd, s, l, b + 1, j, y) != TC_SLOT_OUT) b++;
    if (!tr->fast) shade_pixels(bd, tr, j, y, a, b);
    else {
        if (a < lo) shade_pixels(bd, tr, j, y, a, lo - 1);
        if (b > hi) shade_pixels(bd, tr, j, y, hi + 1, b);
    }
}


static void cover_rows(const band *bd, const tri *tr, int32_t j0, int32_t j1, int32_t i0, int32_t i1) {
    for (int32_t j = j0; j <= j1; j++) cover_row_body(bd, tr, j, i0, i1);
}

/* tc__frame's corners and edges, the corners taken from the slot (the locator's copy, in cache)
 * instead of the mesh's vertex array, back in the mesh's order. */
static void frame_from_slot(const tc_mesh *m, const struct tc__slot *s, tc__eval_frame *f) {
    for (int i = 0; i < 3; i++) {
        int k = tc__slot_corner(m->orient[s->t] < 0, i);
        f->p[i][0] = s->x[k], f->p[i][1] = s->y[k];
    }
    tc__frame_edges(f);
}

/* tc__frame's whole frame (the exact evaluation's), the corners from the slot. */
static void exact_frame(const tc_mesh *m, const struct tc__slot *s, tc__eval_frame *f) {
    frame_from_slot(m, s, f);
    tc__frame_rest(f);
}

/* Aspect <= TC__CT_FAST_ASPECT (ct_fast.h's premise): the longest edge squared at most that
 * many times twice the area, from the frame's edges, without a square root. */
static int fast_shape(const tc__eval_frame *f) {
    double longest = 0;
    for (int q = 0; q < 3; q++) {
        double sq = f->e[q][0] * f->e[q][0] + f->e[q][1] * f->e[q][1];
        longest = sq > longest ? sq : longest; /* fmax is a call at -O2 */
    }
    return longest <= TC__CT_FAST_ASPECT * fabs(tc__cross(f->e[0], f->e[1]));
}


/* A fast triangle's corners from the top down and the slopes of its edges (row_hull's). */
static void sort_hull(tri *tr) {
    const struct tc__slot *s = tr->s;
    int top = 0, bot = 0; /* the first corner of largest y, the first of least, the third between */
    for (int k = 1; k < 3; k++) {
        if (s->y[k] > s->y[top]) top = k;
        if (s->y[k] < s->y[bot]) bot = k;
    }
    const int order[3] = {top, 3 - top - bot, bot}; /* top != bot: the area is > 0 */
    for (int q = 0; q < 3; q++) tr->hx[q] = s->x[order[q]], tr->hy[q] = s->y[order[q]];
    tr->hs[0] = (tr->hx[2] - tr->hx[0]) / (tr->hy[2] - tr->hy[0]);
    tr->hs[1] = (tr->hx[1] - tr->hx[0]) / (tr->hy[1] - tr->hy[0]);
    tr->hs[2] = (tr->hx[2] - tr->hx[1]) / (tr->hy[2] - tr->hy[1]);
}

/* Everything the rows of triangle s read, set once per triangle and band (a triangle with
 * few centres takes cover_few instead). */
static void tri_setup(const job *jb, const struct tc__slot *s, tri *tr) {
    tr->s = s;
    for (int k = 0; k < 3; k++) {
        tr->dy[k] = s->y[k == 2 ? 0 : k + 1] - s->y[k];
        tr->inside[k] = s->left >> k & 1u ? -0x1p-1010 : 0;
    }
    tr->exact = lattice_exact(jb, s);
    for (int ch = 0; ch < jb->nc; ch++) {
        float lo = jb->r->floor0[ch] ? 0.0f : -FLT_MAX;
        tr->low[ch] = (v4f){lo, lo, lo, lo};
    }
    frame_from_slot(jb->r->m, s, &tr->f);
    tr->fast = jb->fast_form && tc__recon_is_ct(jb->r) && fast_shape(&tr->f);
    if (jb->fast_setups && tr->fast) atomic_fetch_add(jb->fast_setups, 1);
    if (!tr->fast) {
        tc__frame_rest(&tr->f); /* the exact evaluation's whole frame, tc__frame's */
        for (int k = 0; k < 3; k++) tr->slope[k] = (s->x[k == 2 ? 0 : k + 1] - s->x[k]) / tr->dy[k];
        return;
    }
    sort_hull(tr);
    tc__ct_fast_prepare(&tr->f, jb->r->coef + (size_t)s->t * (size_t)jb->nc * (size_t)jb->r->ncoef, jb->nc, &tr->ff);
}

/* A triangle takes cover_few when its box covers fewer than FEW_BOX pixels of the tile, or its
 * area is under FEW_AREA pixels and its box under FEW_AREA_BOX (a long sliver's box can be large
 * and nearly empty: its rows go through the hull's guess). The fast form costs ~30 operations
 * per channel to set up and each row's guess and runs more: a 256² tile of 131k triangles
 * (grid256, half a pixel each) rendered 1.5x as fast this way, of 200k (del1e5) 1.6x (eleventh
 * round of bench/perf/notes.md). Since the owned centres are shaded four at a time
 * (shade_queue), triangles of 2 pixels go faster this way too (1.14-1.17x; twelfth round);
 * areas of 3 or 4 pixels as the bound were alike, 6 and 8 slower. */
#define FEW_BOX 16
#define FEW_AREA 4.0
#define FEW_AREA_BOX 64

/* Whether the triangle goes through cover_few: box is its pixel box on the tile (not the
 * band: a pixel must not depend on how the tile is cut into bands). */
static int few_centres(const job *jb, const struct tc__slot *s, int64_t box) {
    if (box < FEW_BOX) return 1;
    if (box >= FEW_AREA_BOX) return 0;
    const double a[2] = {s->x[1] - s->x[0], s->y[1] - s->y[0]}, b[2] = {s->x[2] - s->x[0], s->y[2] - s->y[0]};
    return 0.5 * fabs(tc__cross(a, b)) * jb->per_x * jb->per_y < FEW_AREA; /* NaN or inf: no */
}

/* The queued pixels' values, as shade_run stores the exact path's (tile_float, then tc__floored
 * on the float: floor0 is not passed to tc__ct_points4, whose doubles would be floored first). */
static void flush_queue(const job *jb, shade_queue *q) {
    static const uint8_t no_floor[TC_MAX_CHANNELS];
    int nc = jb->nc;
    for (int k = 0; k < q->n; k += 4) {
        tc__ct_lane lane[4];
        for (int l = 0; l < 4; l++) lane[l] = q->lane[k + l < q->n ? k + l : q->n - 1]; /* repeats: the same values */
        tc__ct_points4(lane, nc, no_floor);
    }
    for (int k = 0; k < q->n; k++)
        for (int ch = 0; ch < nc; ch++) {
            float f = tile_float(q->v[k * nc + ch]);
            q->out[k][ch] = jb->r->floor0[ch] && f < 0 ? 0 : f;
        }
    q->n = 0;
}

/* The pixel centred at (x, y) that s owns, its floats at out: queued for flush_queue. *fk is the
 * entry holding s's frame, or -1 when none does yet (a flush empties the queue, frames with it). */
static void queue_pixel(const band *bd, const struct tc__slot *s, double x, double y, float *out, int *fk) {
    const job *jb = bd->jb;
    shade_queue *q = bd->q;
    if (q->n == QUEUE) flush_queue(jb, q), *fk = -1;
    int k = q->n++;
    if (*fk < 0) *fk = k, exact_frame(jb->r->m, s, &q->f[k]);
    q->lane[k] = (tc__ct_lane){&q->f[*fk], jb->r->coef + (size_t)s->t * (size_t)jb->nc * TC_CT_ORDINATES, x, y,
                               q->v + (size_t)k * (size_t)jb->nc, NULL};
    q->out[k] = out;
}

/* Rows [j0, j1] and columns [i0, i1] of a triangle with few centres: each centre within
 * the closed box [xmin, xmax] x [ymin, ymax] (no other can be in the closed triangle)
 * classified exactly, as classify_one does for the rows, and each owned one shaded exactly
 * (tc_eval_points' bits): queued for four lanes across triangles (the cubic), or at once
 * (shade_run: the other methods), the frame made at the first. Most triangles of a tile denser
 * than its pixels own no centre and cost no more than the tests. */
static void cover_few(const band *bd, const struct tc__slot *s, const double box[4], int32_t i0, int32_t i1,
                      int32_t j0, int32_t j1) {
    const job *jb = bd->jb;
    while (i0 <= i1 && !(jb->xs[i0] >= box[0])) i0++; /* centres non-decreasing along a row */
    while (i1 >= i0 && !(jb->xs[i1] <= box[1])) i1--;
    if (i0 > i1) return;
    tri tr; /* shade_run reads only f and fast; not zeroed whole: the fast form is ~1 KB */
    tr.s = s, tr.fast = 0;
    int framed = 0, fk = -1;
    for (int32_t j = j0; j <= j1; j++) {
        double y = jb->ys[j - jb->row0], l[3];
        if (!(y >= box[2] && y <= box[3])) continue;
        row_terms(s, y, l);
        float *row = jb->values + (size_t)(j - jb->row0) * (size_t)jb->vp->width * (size_t)jb->nc;
        for (int32_t i = i0; i <= i1; i++) {
            if (classify_one(bd, s, l, i, j, y) != TC_SLOT_OWN) continue;
            if (bd->q) {
                queue_pixel(bd, s, jb->xs[i], y, row + (size_t)i * (size_t)jb->nc, &fk);
                continue;
            }
            if (!framed) exact_frame(jb->r->m, s, &tr.f), framed = 1;
            shade_run(jb, &tr, s->t, jb->xs + i, y, 1, row + (size_t)i * (size_t)jb->nc);
        }
    }
}

static void cover(void *ctx, const struct tc__slot *s) {
    const band *bd = ctx;
    const job *jb = bd->jb;
    const tc_viewport *vp = jb->vp;
    double xmin = INFINITY, xmax = -INFINITY, ymin = INFINITY, ymax = -INFINITY;
    for (int k = 0; k < 3; k++) widen(s->x[k], &xmin, &xmax), widen(s->y[k], &ymin, &ymax);
    /* Centres go down the band's rows (ys non-increasing): none between ymin and ymax when the
     * top one is below ymin or the bottom one above ymax, the common case of a triangle the
     * locator gives this band only for its neighbour's rows (the test below, made early). */
    if (jb->ys[bd->j0 - jb->row0] < ymin || jb->ys[bd->j1 - 1 - jb->row0] > ymax) return;
    int32_t i0, i1, j0, j1;
    pixel_range(xmin, xmax, vp->x0, (vp->x1 - vp->x0) / vp->width, jb->per_x, vp->width, jb->margin_x, &i0, &i1);
    /* Rows count downwards from y1. */
    pixel_range(-ymax, -ymin, -vp->y1, (vp->y1 - vp->y0) / vp->height, jb->per_y, vp->height, jb->margin_y, &j0,
                &j1);
    /* The box that decides the path (few_centres, and with it the fast form), judged on the
     * tile's rows, not the band's: a pixel must not depend on how the tile is cut into bands
     * (tc_render_options.row0/rows, BAND_ROWS). */
    int64_t box = (int64_t)(i1 - i0 + 1) * (int64_t)(j1 - j0 + 1);
    if (j0 < bd->j0) j0 = bd->j0;
    if (j1 > bd->j1 - 1) j1 = bd->j1 - 1;
    if (i0 > i1 || j0 > j1) return;
    if (few_centres(jb, s, box)) {
        cover_few(bd, s, (const double[4]){xmin, xmax, ymin, ymax}, i0, i1, j0, j1);
        return;
    }
    /* The rows are widened by a pixel for rounding: a band often gets a triangle that
     * only its neighbour's rows cross. No centre y within [ymin, ymax] (exact
     * comparisons): no row of this band meets the closed triangle, so nothing to set up. */
    int32_t jm = j0;
    while (jm <= j1 && !(jb->ys[jm - jb->row0] >= ymin && jb->ys[jm - jb->row0] <= ymax)) jm++;
    if (jm > j1) return;
    tri tr;
    tri_setup(jb, s, &tr);
    cover_rows(bd, &tr, j0, j1, i0, i1);
}

/* The locator's callback: the triangle's ordinates prefetched, it is held, and the one held
 * longest (when PREFETCH_AHEAD are) covered: the order is the locator's, only later. */
static void cover_later(void *ctx, const struct tc__slot *s) {
    band *bd = ctx;
    const tc_recon *r = bd->jb->r;
    const char *c = (const char *)(r->coef + (size_t)s->t * (size_t)bd->jb->nc * (size_t)r->ncoef);
    for (size_t off = 0; off < (size_t)bd->jb->nc * (size_t)r->ncoef * sizeof(double); off += 64)
        __builtin_prefetch(c + off);
    __builtin_prefetch(&r->m->orient[s->t]); /* frame_from_slot's */
    if (bd->nheld == PREFETCH_AHEAD) {
        cover(bd, bd->held[bd->first]);
        bd->held[bd->first] = s;
        bd->first = (bd->first + 1) % PREFETCH_AHEAD;
        return;
    }
    bd->held[(bd->first + bd->nheld++) % PREFETCH_AHEAD] = s;
}

/* After every triangle of the band: the pixels no triangle owns strictly get the
 * background, and closed-only candidates (points on the outer boundary: the
 * lowest index wins, as in tc_locate) become owned and are shaded exactly. */
/* The first pixel from i on of a row of n whose owner is not settled (negative: none, or a
 * closed-only candidate), or n: on x86 eight owners at a time by their sign bits, one movmskps per
 * four (most of a tile is owned; the scan was 3-4% of a 1024² grid64 tile an owner at a time),
 * elsewhere (and for the last few) one at a time. */
static inline int32_t first_unsettled(const int32_t *row, int32_t i, int32_t n) {
#if TC__X86
    for (; i + 8 <= n; i += 8) {
        v4f a, b;
        memcpy(&a, row + i, sizeof a);
        memcpy(&b, row + i + 4, sizeof b);
        unsigned m = (unsigned)__builtin_ia32_movmskps(a) | (unsigned)__builtin_ia32_movmskps(b) << 4;
        if (m) return i + __builtin_ctz(m);
    }
#endif
    while (i < n && row[i] >= 0) i++;
    return i;
}

static void settle_band(const band *bd) {
    const job *jb = bd->jb;
    const tc_viewport *vp = jb->vp;
    int nc = jb->nc;
    for (int32_t j = bd->j0; j < bd->j1; j++) {
        double y = jb->ys[j - jb->row0];
        size_t row = (size_t)(j - jb->row0) * (size_t)vp->width;
        int32_t *orow = own_row(bd, j);
        for (int32_t i = first_unsettled(orow, 0, vp->width); i < vp->width;
             i = first_unsettled(orow, i + 1, vp->width)) {
            int32_t t = orow[i];
            float *out = jb->values + (row + (size_t)i) * (size_t)nc;
            if (t == -1) {
                for (int ch = 0; ch < nc; ch++)
                    out[ch] = jb->ropt->background ? tile_float(jb->ropt->background[ch]) : 0.0f;
                continue;
            }
            tri tr; /* shade_run reads only f and fast; not zeroed whole: the fast form is ~1 KB */
            tr.s = NULL, tr.fast = 0;
            t = orow[i] = -2 - t;
            tc__frame(jb->r->m, t, &tr.f);
            shade_run(jb, &tr, t, jb->xs + i, y, 1, out);
        }
    }
}


/* raster_band.h: the band's triangles from the locator, each covered (held PREFETCH_AHEAD behind),
 * the queue's last pixels shaded, then the band settled. */
void COVER_BAND(band *bd) {
    const job *jb = bd->jb;
    const tc_viewport *vp = jb->vp;
    double xa, ya, xb, yb, lo[2], hi[2];
    tc_viewport_pixel_center(vp, 0, bd->j1 - 1, &xa, &ya);
    tc_viewport_pixel_center(vp, vp->width - 1, bd->j0, &xb, &yb);
    lo[0] = tc__fmin(xa, xb), hi[0] = tc__fmax(xa, xb), lo[1] = tc__fmin(ya, yb), hi[1] = tc__fmax(ya, yb);
    tc__locator_query_box(jb->L, lo, hi, cover_later, bd);
    for (; bd->nheld > 0; bd->nheld--, bd->first = (bd->first + 1) % PREFETCH_AHEAD) cover(bd, bd->held[bd->first]);
    if (bd->q) flush_queue(jb, bd->q);
    settle_band(bd);
}
