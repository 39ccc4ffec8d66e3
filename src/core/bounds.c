/* bounds.c — how far each triangle of a range-restricted reconstruction may
 * reach: its corner values' range, widened only as far as the data show the function going. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/geom.h"
#include "core/minmax.h"
#include "core/parallel.h"
#include "core/range.h"

static void corner_range(const struct tc_mesh *m, const double *cz, int32_t t, int ch, double *lo, double *hi) {
    int nc = m->nc;
    *lo = INFINITY, *hi = -INFINITY;
    for (int k = 0; k < 3; k++) {
        double z = cz[tc__ix(3 * (long)t + k, nc, ch)];
        *lo = tc__fmin(*lo, z), *hi = tc__fmax(*hi, z);
    }
}

/* Per wedge and channel, the range of every corner value of its faces: the
 * values around a vertex on one side of its delimiters. */
static void wedge_ranges(const struct tc_mesh *m, const tc__wedge_set *ws, const double *cz, double *wr, int32_t w0,
                         int32_t w1) {
    int nc = m->nc;
    for (int32_t w = w0; w < w1; w++)
        for (int ch = 0; ch < nc; ch++) {
            double *r = wr + 2 * tc__ix(w, nc, ch);
            r[0] = INFINITY, r[1] = -INFINITY;
            for (int32_t i = 0; i < ws->w[w].count; i++) {
                double lo, hi;
                corner_range(m, cz, ws->corners[ws->w[w].first + i] / 3, ch, &lo, &hi);
                r[0] = tc__fmin(r[0], lo), r[1] = tc__fmax(r[1], hi);
            }
        }
}

/* What one triangle's bound is made of, per channel. */
typedef struct {
    double lo, hi;          /* its corner values' range (its quad's, for per_quad) */
    double around[2];       /* the range of the values around it: its corners' wedges */
    double data[2];         /* hump above hi and dip below lo that samples or data planes show */
    double est[2];          /* the same that estimated planes show */
} extent;

/* minmod: the smaller magnitude if a and b agree in sign, else 0. */
static double minmod(double a, double b) { return a > 0 && b > 0 ? tc__fmin(a, b) : a < 0 && b < 0 ? tc__fmax(a, b) : 0; }

/* How much a corner's plane is believed about the shape of the data. Given
 * planes and planes from the paper's midpoint samples are data. A plane
 * estimated from the neighbouring vertices is data too on a well-shaped
 * triangle (shaped: aspect <= TC_RANGE_SHAPED_ASPECT), whose neighbourhood is
 * about its own size; on a long or obtuse one it is fitted over a region far
 * wider than the triangle, and at a vertex on the mesh's boundary it is a
 * one-sided extrapolation there: none. */
enum { PLANE_DATA, PLANE_ESTIMATED, PLANE_NONE };

static int plane_kind(const struct tc_mesh *m, const tc__wedge_set *ws, tc_tangents mode, size_t c, int shaped) {
    int32_t t = (int32_t)(c / 3), k = (int32_t)(c % 3);
    int given = m->given_grad_has && m->given_grad_has[c];
    int mids = m->mid_has && m->mid_has[c] && m->mid_has[3 * t + (k + 2) % 3];
    if (given && (mode == TC_TANGENTS_AUTO || mode == TC_TANGENTS_GIVEN)) return PLANE_DATA;
    if (mids && (mode == TC_TANGENTS_AUTO || mode == TC_TANGENTS_MIDPOINTS)) return PLANE_DATA;
    if (shaped) return PLANE_DATA;
    const tc__wedge *w = &ws->w[ws->of_corner[c]];
    for (int side = 0; side < 2; side++)
        if (w->side_edge[side] >= 0 && m->nbr[w->side_edge[side]] < 0) return PLANE_NONE;
    return PLANE_ESTIMATED;
}

/* The humps and dips triangle t's edges show (i -> j). A midpoint sample above
 * both ends (below both) is an observed one: the parabola through the three
 * samples has a Bézier net that passes the ends by 4/3 of the sample's
 * excess. Corner planes whose slopes along the edge rise from one end and
 * fall to the other show one too (only then can a smooth function pass both
 * ends; a monotone edge shows nothing however steep its planes): the net of
 * such an edge passes the ends by about a third of the smaller slope. */
static void bends(const struct tc_mesh *m, const tc__wedge_set *ws, const double *cz, const double *planes,
                  tc_tangents mode, int32_t t, int ch, extent *ext) {
    int nc = m->nc, shaped = tc__face_aspect(m, t) <= TC_RANGE_SHAPED_ASPECT;
    for (int i = 0; i < 3; i++) {
        size_t ci = tc__ix(t, 3, i), cj = tc__ix(t, 3, (i + 1) % 3);
        if (m->mid_has && m->mid_has[ci]) {
            double zi = cz[tc__ix((long)ci, nc, ch)], zj = cz[tc__ix((long)cj, nc, ch)], mid = m->mid[tc__ix((long)ci, nc, ch)];
            ext->data[0] = tc__fmax(ext->data[0], 4.0 / 3 * (mid - tc__fmax(zi, zj)));
            ext->data[1] = tc__fmax(ext->data[1], 4.0 / 3 * (tc__fmin(zi, zj) - mid));
        }
        int ki = plane_kind(m, ws, mode, ci, shaped), kj = plane_kind(m, ws, mode, cj, shaped);
        if (!planes || ki == PLANE_NONE || kj == PLANE_NONE) continue;
        double e[2];
        tc__sub(e, tc__vxy(m, m->tri[cj]), tc__vxy(m, m->tri[ci]));
        double di = tc__dot(planes + 2 * tc__ix((long)ci, nc, ch), e), dj = tc__dot(planes + 2 * tc__ix((long)cj, nc, ch), e);
        double *to = ki == PLANE_DATA && kj == PLANE_DATA ? ext->data : ext->est;
        to[0] = tc__fmax(to[0], minmod(di, -dj) / 3), to[1] = tc__fmax(to[1], minmod(-di, dj) / 3);
    }
}

static void extent_of(const struct tc_mesh *m, const tc__wedge_set *ws, const double *cz, const double *planes,
                      const double *wr, tc_tangents mode, int per_quad, int32_t t, int ch, extent *ext) {
    int nc = m->nc;
    memset(ext, 0, sizeof *ext);
    ext->lo = ext->around[0] = INFINITY, ext->hi = ext->around[1] = -INFINITY;
    for (int half = 0; half <= (per_quad && m->nq); half++) {
        int32_t u = half ? t ^ 1 : t;
        double a, b;
        corner_range(m, cz, u, ch, &a, &b);
        ext->lo = tc__fmin(ext->lo, a), ext->hi = tc__fmax(ext->hi, b);
        for (int k = 0; k < 3; k++) {
            const double *r = wr + 2 * tc__ix(ws->of_corner[3 * u + k], nc, ch);
            ext->around[0] = tc__fmin(ext->around[0], r[0]), ext->around[1] = tc__fmax(ext->around[1], r[1]);
        }
        bends(m, ws, cz, planes, mode, u, ch, ext);
    }
}

/* The bound from the extent: the corners' range widened by TC_RANGE_MARGIN
 * of its spread, or by the bend the data show if more (an estimated plane's
 * only as far as the values around go), never below 0 where the corners are
 * >= 0; range "positive" keeps only that floor. */
static void bound_of(const extent *ext, tc_range mode, double *lo, double *hi) {
    double floor = ext->lo >= 0 ? 0 : -INFINITY, margin = TC_RANGE_MARGIN * (ext->hi - ext->lo);
    if (mode == TC_RANGE_POSITIVE) {
        *lo = floor, *hi = INFINITY;
        return;
    }
    double up = tc__fmax(ext->data[0], tc__fmin(ext->est[0], tc__fmax(0, ext->around[1] - ext->hi)));
    double down = tc__fmax(ext->data[1], tc__fmin(ext->est[1], tc__fmax(0, ext->lo - ext->around[0])));
    *lo = tc__fmax(ext->lo - tc__fmax(margin, down), floor);
    *hi = ext->hi + tc__fmax(margin, up);
}

/* The range of each channel's corner values, per part: min, max and largest
 * magnitude are exact whatever the order, so the parts' merge is the serial scan. */
typedef struct {
    const struct tc_mesh *m;
    const double *cz;
    double lo[TC_PARALLEL_MAX][TC_MAX_CHANNELS], hi[TC_PARALLEL_MAX][TC_MAX_CHANNELS],
        big[TC_PARALLEL_MAX][TC_MAX_CHANNELS];
} range_pass;

static void channel_part(void *ctx, int32_t lo, int32_t hi, int part) {
    range_pass *rp = ctx;
    int nc = rp->m->nc;
    for (int ch = 0; ch < nc; ch++) {
        double l = INFINITY, h = -INFINITY, big = 0;
        for (int32_t c = lo; c < hi; c++) {
            double z = rp->cz[tc__ix(c, nc, ch)];
            if (z < l) l = z; /* finite (a mesh invariant): plain compares */
            if (z > h) h = z;
            if (fabs(z) > big) big = fabs(z);
        }
        rp->lo[part][ch] = l, rp->hi[part][ch] = h, rp->big[part][ch] = big;
    }
}

void tc__channel_range(const struct tc_mesh *m, const double *cz, int threads, double *lo, double *hi, double *big) {
    if (cz == m->cz && m->cz_range_kept) { /* the mesh's own values: scanned once, by tc_mesh_new */
        for (int ch = 0; ch < m->nc; ch++) lo[ch] = m->cz_lo[ch], hi[ch] = m->cz_hi[ch], big[ch] = m->cz_big[ch];
        return;
    }
    range_pass *rp = malloc(sizeof *rp); /* 24 KiB: off the stack */
    int parts = tc__parallel_parts(threads, 3 * m->nt, 16384);
    for (int ch = 0; ch < m->nc; ch++) lo[ch] = INFINITY, hi[ch] = -INFINITY, big[ch] = 0;
    if (!rp) { /* the serial scan */
        for (int ch = 0; ch < m->nc; ch++)
            for (size_t c = 0; c < 3 * (size_t)m->nt; c++) {
                double z = cz[tc__ix((long)c, m->nc, ch)];
                if (z < lo[ch]) lo[ch] = z;
                if (z > hi[ch]) hi[ch] = z;
                if (fabs(z) > big[ch]) big[ch] = fabs(z);
            }
        return;
    }
    rp->m = m, rp->cz = cz;
    tc__parallel_for(threads, 3 * m->nt, 16384, channel_part, rp);
    for (int p = 0; p < parts; p++)
        for (int ch = 0; ch < m->nc; ch++) {
            if (rp->lo[p][ch] < lo[ch]) lo[ch] = rp->lo[p][ch];
            if (rp->hi[p][ch] > hi[ch]) hi[ch] = rp->hi[p][ch];
            if (rp->big[p][ch] > big[ch]) big[ch] = rp->big[p][ch];
        }
    tc__free(rp);
}

/* The per-wedge and per-triangle loops, in parts (each writes its own entries only). */
typedef struct {
    const struct tc_mesh *m;
    const tc__wedge_set *ws;
    const double *cz, *planes;
    double *wr;
    tc_tangents tangents;
    tc_range mode;
    int per_quad;
    tc__bounds *b;
} bounds_pass;

static void ranges_part(void *ctx, int32_t lo, int32_t hi, int part) {
    const bounds_pass *bp = ctx;
    (void)part;
    wedge_ranges(bp->m, bp->ws, bp->cz, bp->wr, lo, hi);
}

static void bounds_part(void *ctx, int32_t lo, int32_t hi, int part) {
    const bounds_pass *bp = ctx;
    int nc = bp->m->nc;
    (void)part;
    for (int32_t t = lo; t < hi; t++)
        for (int ch = 0; ch < nc; ch++) {
            extent ext;
            extent_of(bp->m, bp->ws, bp->cz, bp->planes, bp->wr, bp->tangents, bp->per_quad, t, ch, &ext);
            bound_of(&ext, bp->mode, &bp->b->lo[tc__ix(t, nc, ch)], &bp->b->hi[tc__ix(t, nc, ch)]);
        }
}

int tc__bounds_build(const struct tc_mesh *m, const tc__wedge_set *ws, const double *cz, const double *planes,
                     tc_tangents tangents, tc_range mode, int per_quad, tc__bounds *b) {
    int nc = m->nc;
    memset(b, 0, sizeof *b);
    b->nc = nc;
    b->lo = tc__malloc(tc__ix(m->nt, nc, 0), sizeof *b->lo);
    b->hi = tc__malloc(tc__ix(m->nt, nc, 0), sizeof *b->hi);
    double *wr = tc__malloc(tc__ix(ws->nw, nc, 0), 2 * sizeof *wr);
    if (!b->lo || !b->hi || !wr) {
        tc__free(wr);
        return TC_ENOMEM;
    }
    bounds_pass bp = {m, ws, cz, planes, wr, tangents, mode, per_quad, b};
    tc__parallel_for(ws->threads, ws->nw, 4096, ranges_part, &bp);
    double clo[TC_MAX_CHANNELS], chi[TC_MAX_CHANNELS], cbig[TC_MAX_CHANNELS];
    tc__channel_range(m, cz, ws->threads, clo, chi, cbig);
    for (int ch = 0; ch < nc; ch++) {
        double big = cbig[ch], lo = clo[ch], hi = chi[ch];
        b->tol[ch] = TC_RANGE_SLACK * big;
        b->span[ch] = hi > lo ? hi - lo : tc__fmax(big, 1e-300);
    }
    tc__parallel_for(ws->threads, m->nt, 2048, bounds_part, &bp);
    tc__free(wr);
    return TC_OK;
}

void tc__bounds_free(tc__bounds *b) {
    tc__free(b->lo);
    tc__free(b->hi);
    b->lo = b->hi = NULL;
}
