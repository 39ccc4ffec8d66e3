/* range.h — range-restricted reconstruction: per-triangle bounds from the data
 * (bounds.c), and the limiter of the wedge tangent planes every method shares (range.c).
 *
 * The bound of triangle T (range "local"), per channel, is [min, max] of T's
 * own three corner values (a C-1 edge's side's own values), widened on each
 * side by the larger of
 *   - TC_RANGE_MARGIN (5 %) of that spread (a flat triangle stays flat), and
 *   - the hump (dip) T's data show along one of its edges: a midpoint sample
 *     above (below) both ends, 4/3 of its excess (what the parabola through
 *     the three samples puts in the net); or corner planes that rise from one
 *     end of an edge and fall to the other, a third of the smaller of the two
 *     slopes along the edge (what such a bend puts in the net). Planes given
 *     or built from midpoint samples count as data, and so do planes
 *     estimated from the neighbouring vertices where T is well shaped
 *     (aspect <= TC_RANGE_SHAPED_ASPECT); on a longer or more obtuse T an
 *     estimated plane counts only as far as the values around T go (the
 *     range over the faces of the wedges at T's corners), and not at all at a
 *     vertex on the mesh's boundary (a one-sided fit);
 * and never below 0 where T's corner values are all >= 0. So a triangle of
 * flat data next to a thin strip cannot sink or swell, while a smooth peak or
 * ridge that passes between samples keeps its shape. What the limiter costs
 * against "free" is measured in docs/report.md "Range": within 1.1x on the
 * discontinuity meshes with midpoint planes, more (in RMS mostly) on meshes
 * whose cells unflagged jumps and kinks cross. Range
 * "positive" keeps only the floor at 0.
 *
 * A piece is a Bézier patch, so it lies inside the convex hull of its
 * ordinates: keeping every ordinate inside the bound bounds the function. The
 * ordinates a wedge's tangent plane sets (z + g.d for the directions d a
 * method names per corner) are kept inside by projecting the plane onto the
 * set of admissible planes (g = 0 is always admissible, since every corner
 * value lies in its own triangle's bound); what each method builds from them
 * is its own affair (ct_range.c, powell_sabin.c, hermite.c). */
#ifndef TC_CORE_RANGE_H
#define TC_CORE_RANGE_H

#include "core/wedge.h"

/* The local bound's least margin, as a fraction of the triangle's own spread
 * of corner values: room for rounding of the data and for the small second-
 * order rise of smooth data between samples; 0 for flat data. */
#define TC_RANGE_MARGIN 0.05

/* Above this aspect (longest edge / shortest altitude; 2 for a grid's right
 * triangle) a triangle's estimated corner planes are fitted over a region
 * much wider than the triangle and say little about a bend inside it: the
 * long, obtuse fans of discontinuity meshers (aspect 40 to 800). Measured:
 * the realistic surfaces keep their overshoot bounds up to about 16, and the
 * reference disc meshes need about 5 (tests/unit/test_overshoot.c, docs/report.md). */
#define TC_RANGE_SHAPED_ASPECT 8.0

/* Ordinates within this much of the bound, relative to the channel's largest
 * |value|, count as inside: rounding, not overshoot. */
#define TC_RANGE_SLACK 1e-12

/* What the limiter changes by less than this fraction of a channel's data
 * range (about a quarter of an 8-bit grey level) is not reported: flat data
 * with printing noise are limited silently. */
#define TC_RANGE_MATERIAL 1e-3

typedef struct {
    int nc;
    double *lo, *hi;                 /* [nt][nc]; -INFINITY / INFINITY where unbounded */
    double tol[TC_MAX_CHANNELS];     /* TC_RANGE_SLACK x the channel's largest |value| */
    double span[TC_MAX_CHANNELS];    /* the channel's data range (max - min of its corner values) */
} tc__bounds;

/* The bounds (as above) from the corner values cz [3nt][nc] the reconstruction
 * interpolates and its corner planes [3nt][nc][2] before any limiting, ws
 * the wedges they were built on, `tangents` where they came from. per_quad:
 * both triangles of a split quad get their quad's bound (hermite's patch). */
int tc__bounds_build(const struct tc_mesh *m, const tc__wedge_set *ws, const double *cz, const double *planes,
                     tc_tangents tangents, tc_range mode, int per_quad, tc__bounds *b);
void tc__bounds_free(tc__bounds *b);

/* How far ordinate z lies outside [lo, hi] (0 inside, or within tol). */
static inline double tc__outside(double z, double lo, double hi, double tol) {
    return z < lo - tol ? lo - z : z > hi + tol ? z - hi : 0;
}

/* What the limiters did materially (TC_RANGE_MATERIAL), for the answer's
 * warnings: counts, and the few places where each did the most (so a warning
 * can name them). */
enum { TC_RANGE_NAMED = 4 };
typedef struct {
    int32_t count;                  /* how many (per element and channel) */
    int32_t where[TC_RANGE_NAMED];  /* vertex (planes) or triangle (edges, kinks), most first */
    int edge[TC_RANGE_NAMED];       /* the triangle's edge (edges, kinks) */
    double size[TC_RANGE_NAMED];    /* the measure (see tc__range_stats), worst first */
    int named;
} tc__range_tally;

typedef struct {
    tc__range_tally planes; /* size: 1 - |g limited| / |g| (in the metric of its ordinates) */
    tc__range_tally edges;  /* size: how far the cross-boundary ordinate moved / the channel's range */
    tc__range_tally kinks;  /* size: the C1 mismatch left / the channel's range */
    tc__range_tally twists; /* hermite: size: 1 - the factor the cross derivative's second-order part kept */
    int32_t flattened;     /* wedge planes scaled down further so a C1 edge could stay in range */
} tc__range_stats;

/* Counts one event and keeps it if it is among the TC_RANGE_NAMED largest. */
void tc__range_note(tc__range_tally *t, double size, int32_t where, int edge);
void tc__range_stats_init(tc__range_stats *s);
/* Per channel, the smallest, largest and largest |.| corner value cz[3nt][nc]
 * (on up to `threads` threads; the values are finite, a mesh invariant). For
 * the mesh's own cz, the values tc_mesh_new kept (m->cz_lo ...): no scan. */
void tc__channel_range(const struct tc_mesh *m, const double *cz, int threads, double *lo, double *hi, double *big);
/* Adds the tally of a later part of a loop to `into`: the same as if its
 * events had been noted after into's (the named ones are the largest, ties
 * kept in the order noted, so merging parts in order gives the serial tally). */
void tc__range_tally_merge(tc__range_tally *into, const tc__range_tally *part);
/* The warnings that say what the limiter changed (none if nothing). */
void tc__range_warn(const struct tc_mesh *m, const tc__range_stats *s, tc_range mode, tc_diags *dg);

/* Range "free": one warning when the reconstruction leaves its data's range
 * (per channel, [min, max] of all corner values), saying by how much: at
 * least the largest excursion sampled inside the pieces, at most that of the
 * Bézier net (its first `nord` coefficients per triangle and channel). */
void tc__range_report_free(const struct tc_recon *r, int nord, tc_diags *dg);

/* The directions whose ordinates corner `corner`'s plane sets: a method's
 * ordinate z_corner + g . d[i] for i < the count returned (at most
 * TC_PLANE_DIRS_MAX), each of which must stay inside the corner's triangle's bound. */
enum { TC_PLANE_DIRS_MAX = 3 };
typedef int (*tc__plane_dirs_fn)(const void *ctx, int32_t corner, double d[TC_PLANE_DIRS_MAX][2]);

/* Projects every wedge plane in planes [3nt][nc][2] (equal on the corners of a
 * wedge) onto its admissible set, in the metric of the ordinates it moves;
 * wedges coupled across C0 sides are projected together, keeping their common
 * slope along each C0 side. cz [3nt][nc] are the corner values. */
int tc__range_planes(const struct tc_mesh *m, const tc__wedge_set *ws, const double *cz, const tc__bounds *b,
                     tc__plane_dirs_fn dirs, const void *ctx, double *planes, tc__range_stats *stats);

/* Scales the plane of wedge w, and of every wedge coupled to it across C0
 * sides, by lambda in [0, 1] (channel ch) in planes: admissible planes stay admissible. */
void tc__range_scale_group(const tc__wedge_set *ws, int nc, int32_t w, int ch, double lambda, double *planes);

#endif
