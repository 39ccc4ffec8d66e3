/* test_locate.c — unit tests of the point locator (src/core/locate.c).
 * Meshes are built by hand; the reference is a brute-force scan in exact integer arithmetic. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "core/locate.h"
#include "core/mesh.h"
#include "tocher.h"

/* ---- random numbers (splitmix64, seeded from the harness) ----------------- */

static uint64_t rng_state;

static void rng_seed(uint64_t salt) { rng_state = (uint64_t)tc_test_seed() * 0x9E3779B97F4A7C15ull + salt; }

static uint64_t rnd64(void) {
    uint64_t z = (rng_state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* Uniform integer in [lo, hi]. */
static int64_t rnd_int(int64_t lo, int64_t hi) { return lo + (int64_t)(rnd64() % (uint64_t)(hi - lo + 1)); }

/* A random multiple of 2^-bits in [lo, hi] (lo, hi multiples of it): exact. */
static double rnd_dyadic(double lo, double hi, int bits) {
    int64_t a = (int64_t)ldexp(lo, bits), b = (int64_t)ldexp(hi, bits);
    return ldexp((double)rnd_int(a, b), -bits);
}

/* ---- exact reference arithmetic ---------------------------------------------
 * Test coordinates are multiples of 2^-53 below 256 in magnitude, so they are
 * integers below 2^61 once scaled, and a 2x2 determinant of differences fits
 * in 128 bits. Anything else is reported as a test failure, not mis-computed. */

__extension__ typedef __int128 i128;

static i128 to_fixed(double v) {
    double s = ldexp(v, 53);
    CHECK_MSG(fabs(v) < 256 && s == floor(s), "coordinate %.17g is not exact in the reference", v);
    return (i128)s;
}

/* The exact sign of cross(e - s, p - s). */
static int ref_orient(const double s[2], const double e[2], double px, double py) {
    i128 sx = to_fixed(s[0]), sy = to_fixed(s[1]);
    i128 d = (to_fixed(e[0]) - sx) * (to_fixed(py) - sy) - (to_fixed(e[1]) - sy) * (to_fixed(px) - sx);
    return (d > 0) - (d < 0);
}

/* ---- hand-built meshes ------------------------------------------------------ */

typedef struct {
    struct tc_mesh m; /* only nv, nt, xy, tri, orient are filled */
    int32_t capv, capt;
} tmesh;

static void tm_init(tmesh *tm) { memset(tm, 0, sizeof *tm); }

static void tm_free(tmesh *tm) {
    free(tm->m.xy);
    free(tm->m.tri);
    free(tm->m.orient);
    tm_init(tm);
}

static int32_t tm_vertex(tmesh *tm, double x, double y) {
    if (tm->m.nv == tm->capv) {
        tm->capv = tm->capv ? 2 * tm->capv : 64;
        tm->m.xy = realloc(tm->m.xy, 2 * (size_t)tm->capv * sizeof *tm->m.xy);
        if (!tm->m.xy) abort();
    }
    tm->m.xy[2 * (size_t)tm->m.nv] = x;
    tm->m.xy[2 * (size_t)tm->m.nv + 1] = y;
    return tm->m.nv++;
}

static const double *tm_xy(const tmesh *tm, int32_t v) { return tm->m.xy + 2 * (size_t)v; }

/* Signed doubled area of (a, b, c), from differences. */
static double area2(const double *a, const double *b, const double *c) {
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/* Adds triangle (a, b, c) in the given order; orient from its signed area. */
static void tm_tri(tmesh *tm, int32_t a, int32_t b, int32_t c) {
    if (tm->m.nt == tm->capt) {
        tm->capt = tm->capt ? 2 * tm->capt : 64;
        tm->m.tri = realloc(tm->m.tri, 3 * (size_t)tm->capt * sizeof *tm->m.tri);
        tm->m.orient = realloc(tm->m.orient, (size_t)tm->capt * sizeof *tm->m.orient);
        if (!tm->m.tri || !tm->m.orient) abort();
    }
    double ar = area2(tm_xy(tm, a), tm_xy(tm, b), tm_xy(tm, c));
    CHECK_MSG(ar != 0, "degenerate test triangle %d", tm->m.nt);
    int32_t *t = tm->m.tri + 3 * (size_t)tm->m.nt;
    t[0] = a;
    t[1] = b;
    t[2] = c;
    tm->m.orient[tm->m.nt++] = ar > 0 ? 1 : -1;
}

/* Adds (a, b, c), reversed half of the time when flip is set. */
static void tm_tri_maybe_flipped(tmesh *tm, int32_t a, int32_t b, int32_t c, int flip) {
    if (flip && (rnd64() & 1)) tm_tri(tm, a, c, b);
    else tm_tri(tm, a, b, c);
}

static double tm_total_area(const tmesh *tm) {
    double sum = 0;
    for (int32_t t = 0; t < tm->m.nt; t++) {
        const int32_t *v = tm->m.tri + 3 * (size_t)t;
        sum += fabs(area2(tm_xy(tm, v[0]), tm_xy(tm, v[1]), tm_xy(tm, v[2]))) / 2;
    }
    return sum;
}

static tc_locator *tm_locator(const tmesh *tm) {
    tc_locator *L = NULL;
    int rc = tc_locator_new(&tm->m, &L);
    CHECK_MSG(rc == TC_OK && L, "tc_locator_new failed: %d", rc);
    tc__locator_grid_now(L); /* tc_locate through the grid (test_points: the same as the tree) */
    return L;
}

/* A grid of n x n square cells of side h from (ox, oy), each split into two
 * triangles. Interior vertices are jittered by up to 0.2 h in multiples of
 * 2^-jitter_bits (0 = no jitter), so boundary and domain stay the square. */
typedef struct {
    int n;
    double h, ox, oy;
    int jitter_bits;
    int diag;  /* 0: all cells split '/', 1: all '\', 2: random */
    int flip;  /* reverse the vertex order of random triangles */
    int (*skip)(int i, int j); /* leaves cell (i, j) out, or NULL */
} grid_opt;

static void tm_grid(tmesh *tm, const grid_opt *o) {
    int n = o->n;
    tm_init(tm);
    for (int j = 0; j <= n; j++)
        for (int i = 0; i <= n; i++) {
            double x = o->ox + i * o->h, y = o->oy + j * o->h;
            if (o->jitter_bits && i > 0 && i < n && j > 0 && j < n) {
                double a = ldexp(floor(ldexp(0.2 * o->h, o->jitter_bits)), -o->jitter_bits);
                x += rnd_dyadic(-a, a, o->jitter_bits);
                y += rnd_dyadic(-a, a, o->jitter_bits);
            }
            tm_vertex(tm, x, y);
        }
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            if (o->skip && o->skip(i, j)) continue;
            int32_t v00 = j * (n + 1) + i, v10 = v00 + 1, v01 = v00 + n + 1, v11 = v01 + 1;
            int d = o->diag == 2 ? (int)(rnd64() & 1) : o->diag;
            if (d == 0) {
                tm_tri_maybe_flipped(tm, v00, v10, v11, o->flip);
                tm_tri_maybe_flipped(tm, v00, v11, v01, o->flip);
            } else {
                tm_tri_maybe_flipped(tm, v00, v10, v01, o->flip);
                tm_tri_maybe_flipped(tm, v10, v11, v01, o->flip);
            }
        }
}

/* ---- the reference rule (a brute-force reimplementation) -------------------- */

enum { REF_OUT = 0, REF_TOUCH = 1, REF_OWN = 2 };

/* Edge a -> b of a counter-clockwise triangle: REF_OWN if P is on the
 * triangle's side of it or on it with the tie going to this triangle,
 * REF_TOUCH if on it with the tie going to the other side, else REF_OUT. */
static int ref_edge(const double *a, const double *b, double x, double y) {
    int a_first = a[0] < b[0] || (a[0] == b[0] && a[1] < b[1]); /* canonical s = a */
    int sg = a_first ? ref_orient(a, b, x, y) : -ref_orient(b, a, x, y); /* > 0: interior side */
    if (sg != 0) return sg > 0 ? REF_OWN : REF_OUT;
    return a_first ? REF_OWN : REF_TOUCH; /* the tie goes to the left of s -> e */
}

static int ref_classify(const tmesh *tm, int32_t t, double x, double y) {
    const int32_t *v = tm->m.tri + 3 * (size_t)t;
    const double *p[3] = {tm_xy(tm, v[0]), tm_xy(tm, v[1]), tm_xy(tm, v[2])};
    if (tm->m.orient[t] < 0) {
        const double *q = p[1];
        p[1] = p[2];
        p[2] = q;
    }
    /* Cheap exact rejection first: outside the box means outside the triangle. */
    for (int a = 0; a < 2; a++) {
        double z = a ? y : x;
        if (z < fmin(fmin(p[0][a], p[1][a]), p[2][a]) || z > fmax(fmax(p[0][a], p[1][a]), p[2][a]))
            return REF_OUT;
    }
    int r = REF_OWN;
    for (int k = 0; k < 3; k++) {
        int e = ref_edge(p[k], p[(k + 1) % 3], x, y);
        if (e < r) r = e;
    }
    return r;
}

/* Scans every triangle: *nown = number of strict owners; returns what
 * tc_locate must return (the strict owner, else the lowest closed container, else -1). */
static int32_t ref_owner(const tmesh *tm, double x, double y, int *nown) {
    int32_t own = -1, touch = -1;
    *nown = 0;
    for (int32_t t = 0; t < tm->m.nt; t++) {
        int c = ref_classify(tm, t, x, y);
        if (c == REF_OWN && (*nown)++ == 0) own = t;
        if (c == REF_TOUCH && touch < 0) touch = t;
    }
    return own >= 0 ? own : touch;
}

/* Checks one query against the reference; interior says P is inside the
 * domain (not on its outer boundary), closed says P is in the closed domain. */
static void check_point(const tmesh *tm, const tc_locator *L, double x, double y, int interior, int closed) {
    int nown;
    int32_t want = ref_owner(tm, x, y, &nown), got = tc_locate(L, x, y);
    CHECK_MSG(got == want, "(%.17g, %.17g): tc_locate %d, reference %d", x, y, (int)got, (int)want);
    CHECK_MSG(nown <= 1, "(%.17g, %.17g): %d strict owners", x, y, nown);
    if (interior) CHECK_MSG(nown == 1, "(%.17g, %.17g): interior point with %d strict owners", x, y, nown);
    if (closed) CHECK_MSG(got >= 0, "(%.17g, %.17g): point of the closed domain not located", x, y);
}

/* ---- tests -------------------------------------------------------------------- */

TEST(locate_lifecycle) {
    tc_locator_free(NULL);
    tc_locator *const junk = (tc_locator *)(uintptr_t)16; /* any non-NULL: a failure must clear *out */
    tc_locator *L = junk;
    CHECK(tc_locator_new(NULL, &L) == TC_EINVAL && L == NULL);
    tmesh tm;
    tm_init(&tm);
    CHECK(tc_locator_new(&tm.m, NULL) == TC_EINVAL);
    /* No triangles: a valid, empty index. */
    CHECK(tc_locator_new(&tm.m, &L) == TC_OK && L);
    CHECK(tc_locate(L, 0, 0) == -1);
    tc_locator_free(L);
    CHECK(tc_locate(NULL, 0, 0) == -1);

    /* One clockwise triangle: interior, corners, edges in; outside, NaN, inf out. */
    tm_tri(&tm, tm_vertex(&tm, 0, 0), tm_vertex(&tm, 0, 1), tm_vertex(&tm, 1, 0));
    L = tm_locator(&tm);
    CHECK(tc_locate(L, 0.25, 0.25) == 0);
    CHECK(tc_locate(L, 0, 0) == 0 && tc_locate(L, 1, 0) == 0 && tc_locate(L, 0, 1) == 0);
    CHECK(tc_locate(L, 0.5, 0.5) == 0 && tc_locate(L, 0, 0.5) == 0 && tc_locate(L, 0.5, 0) == 0);
    CHECK(tc_locate(L, 0.5, 0.5 + 0x1p-52) == -1);
    CHECK(tc_locate(L, -0x1p-1074, 0.5) == -1);
    CHECK(tc_locate(L, NAN, 0.1) == -1 && tc_locate(L, 0.1, NAN) == -1);
    CHECK(tc_locate(L, INFINITY, 0) == -1 && tc_locate(L, -INFINITY, 0) == -1);
    tc_locator_free(L);

    /* A bad vertex index is refused, not read. */
    tm.m.tri[2] = 7;
    L = junk;
    CHECK(tc_locator_new(&tm.m, &L) == TC_EINVAL && L == NULL);
    tm_free(&tm);
}

/* Double-precision barycentrics of P in triangle t, minimum of the three. */
static double min_bary(const tmesh *tm, int32_t t, double x, double y) {
    const int32_t *v = tm->m.tri + 3 * (size_t)t;
    const double *a = tm_xy(tm, v[0]), *b = tm_xy(tm, v[1]), *c = tm_xy(tm, v[2]);
    double p[2] = {x, y}, d = area2(a, b, c);
    double la = area2(p, b, c) / d, lb = area2(a, p, c) / d, lc = area2(a, b, p) / d;
    return fmin(fmin(la, lb), lc);
}

/* 1. Random points in jittered grids with both diagonal directions and mixed
 *    triangle orientations land in a triangle that contains them. */
TEST(locate_grid_random_points) {
    rng_seed(1);
    for (int variant = 0; variant < 4; variant++) {
        grid_opt o = {16, 1.0 / 16, 0, 0, variant & 1 ? 20 : 0, variant < 2 ? 2 : variant - 2, 1, NULL};
        tmesh tm;
        tm_grid(&tm, &o);
        CHECK_NEAR(tm_total_area(&tm), 1.0, 1e-12);
        tc_locator *L = tm_locator(&tm);
        int inside = 0;
        for (int q = 0; q < 20000; q++) {
            double x = -0.25 + 1.5 * ((double)(rnd64() >> 11) * 0x1p-53);
            double y = -0.25 + 1.5 * ((double)(rnd64() >> 11) * 0x1p-53);
            int32_t t = tc_locate(L, x, y);
            if (x >= 0 && x <= 1 && y >= 0 && y <= 1) {
                inside++;
                CHECK_MSG(t >= 0 && t < tm.m.nt, "(%.17g, %.17g) in the domain: got %d", x, y, (int)t);
                if (t >= 0 && t < tm.m.nt)
                    CHECK_MSG(min_bary(&tm, t, x, y) >= -1e-12, "(%.17g, %.17g) not in triangle %d (%g)", x, y,
                              (int)t, min_bary(&tm, t, x, y));
            } else {
                CHECK_MSG(t == -1, "(%.17g, %.17g) outside the domain: got %d", x, y, (int)t);
            }
        }
        CHECK(inside > 8000 && inside < 20000);
        tc_locator_free(L);
        tm_free(&tm);
    }
}

static int on_unit_boundary(double x, double y) { return x == 0 || x == 1 || y == 0 || y == 1; }

/* 2. Every vertex, every point at k/8 of every edge, and points a hair off each
 *    edge: exactly one strict owner inside, and the locator returns it; on the
 *    outer boundary the locator still answers. */
TEST(locate_one_owner_edges_vertices) {
    rng_seed(2);
    for (int variant = 0; variant < 6; variant++) {
        grid_opt o = {8, 1.0 / 8, 0, 0, variant >= 3 ? 12 : 0, variant % 3, 1, NULL};
        tmesh tm;
        tm_grid(&tm, &o);
        CHECK_NEAR(tm_total_area(&tm), 1.0, 1e-12);
        tc_locator *L = tm_locator(&tm);
        for (int32_t v = 0; v < tm.m.nv; v++) {
            const double *p = tm_xy(&tm, v);
            check_point(&tm, L, p[0], p[1], !on_unit_boundary(p[0], p[1]), 1);
        }
        for (int32_t t = 0; t < tm.m.nt; t++)
            for (int k = 0; k < 3; k++) {
                const double *a = tm_xy(&tm, tm.m.tri[3 * t + k]), *b = tm_xy(&tm, tm.m.tri[3 * t + (k + 1) % 3]);
                for (int i = 1; i < 8; i++) {
                    double x = a[0] + (b[0] - a[0]) * i / 8, y = a[1] + (b[1] - a[1]) * i / 8;
                    int bnd = on_unit_boundary(x, y);
                    check_point(&tm, L, x, y, !bnd, 1);
                    /* A hair to either side (2^-40: exact, far below the edge lengths). */
                    for (int s = -1; s <= 1; s += 2) {
                        double dx = s * 0x1p-40, dy = s * 0x1p-40;
                        int in = x + dx > 0 && x + dx < 1 && y - dy > 0 && y - dy < 1;
                        check_point(&tm, L, x + dx, y - dy, in, in);
                    }
                }
            }
        tc_locator_free(L);
        tm_free(&tm);
    }
}

/* Fans around one vertex with rays in many directions (axis directions, the
 * edges of the half-open arcs, included): the centre and the points on the rays
 * have exactly one strict owner. */
TEST(locate_vertex_fans) {
    static const int dir[16][2] = {{1, 0},  {2, 1},   {1, 1},   {1, 2},  {0, 1},  {-1, 2}, {-1, 1}, {-2, 1},
                                   {-1, 0}, {-2, -1}, {-1, -1}, {-1, -2}, {0, -1}, {1, -2}, {1, -1}, {2, -1}};
    rng_seed(3);
    int fans = 0;
    for (int trial = 0; trial < 400; trial++) {
        int pick[16], k = 0;
        for (int i = 0; i < 16; i++)
            if (rnd64() % 3) pick[k++] = i;
        if (k < 3) continue;
        /* Consecutive rays (cyclically) must turn left by less than 180 degrees. */
        int ok = 1;
        for (int i = 0; i < k; i++) {
            const int *a = dir[pick[i]], *b = dir[pick[(i + 1) % k]];
            ok &= a[0] * b[1] - a[1] * b[0] > 0;
        }
        if (!ok) continue;
        fans++;
        tmesh tm;
        tm_init(&tm);
        double cx = rnd_dyadic(-4, 4, 8), cy = rnd_dyadic(-4, 4, 8);
        int32_t c = tm_vertex(&tm, cx, cy), r0 = tm.m.nv;
        for (int i = 0; i < k; i++) {
            double len = (double)rnd_int(1, 4) * 0.5; /* ragged outline, still star-shaped */
            tm_vertex(&tm, cx + dir[pick[i]][0] * len, cy + dir[pick[i]][1] * len);
        }
        for (int i = 0; i < k; i++) tm_tri_maybe_flipped(&tm, c, r0 + i, r0 + (i + 1) % k, 1);
        tc_locator *L = tm_locator(&tm);
        check_point(&tm, L, cx, cy, 1, 1);
        for (int i = 0; i < k; i++) {
            const double *w = tm_xy(&tm, r0 + i);
            for (int j = 1; j < 16; j++)
                check_point(&tm, L, cx + (w[0] - cx) * j / 16, cy + (w[1] - cy) * j / 16, 1, 1);
            check_point(&tm, L, w[0], w[1], 0, 1);
        }
        tc_locator_free(L);
        tm_free(&tm);
    }
    CHECK(fans > 50);
}

/* A crack: the grid's vertices on a line are duplicated, one copy per side,
 * numbered in opposite directions so that no order by index could agree.
 * diagonal: the crack is y = x (cells on it split along it); else x = 1/2. */
static void tm_crack_grid(tmesh *tm, int n, int diagonal) {
    double h = 1.0 / n;
    tm_init(tm);
    int32_t *copy_b = malloc((size_t)(n + 1) * sizeof *copy_b);
    if (!copy_b) abort();
    for (int j = 0; j <= n; j++)
        for (int i = 0; i <= n; i++) tm_vertex(tm, i * h, j * h);
    for (int k = n; k >= 0; k--) { /* the second copies, in reverse order */
        int i = diagonal ? k : n / 2, j = k;
        copy_b[k] = tm_vertex(tm, i * h, j * h);
    }
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            int32_t v[4] = {j * (n + 1) + i, j * (n + 1) + i + 1, (j + 1) * (n + 1) + i, (j + 1) * (n + 1) + i + 1};
            int32_t tri[2][3];
            int along = diagonal ? i == j : (int)(rnd64() & 1);
            if (along) { /* split along '/' */
                int32_t a[3] = {v[0], v[1], v[3]}, b[3] = {v[0], v[3], v[2]};
                memcpy(tri[0], a, sizeof a);
                memcpy(tri[1], b, sizeof b);
            } else {
                int32_t a[3] = {v[0], v[1], v[2]}, b[3] = {v[1], v[3], v[2]};
                memcpy(tri[0], a, sizeof a);
                memcpy(tri[1], b, sizeof b);
            }
            for (int s = 0; s < 2; s++) {
                /* Side B: below the diagonal / right of x = 1/2 (by the centroid). */
                double cx = 0, cy = 0;
                for (int k = 0; k < 3; k++) {
                    cx += tm_xy(tm, tri[s][k])[0];
                    cy += tm_xy(tm, tri[s][k])[1];
                }
                int side_b = diagonal ? cy < cx : cx > 3 * (n / 2) * h;
                for (int k = 0; k < 3 && side_b; k++) {
                    int vi = tri[s][k] % (n + 1), vj = tri[s][k] / (n + 1);
                    if (diagonal ? vi == vj : vi == n / 2) tri[s][k] = copy_b[vj];
                }
                tm_tri_maybe_flipped(tm, tri[s][0], tri[s][1], tri[s][2], 1);
            }
        }
    free(copy_b);
}

/* 3. Points on a crack made of duplicated vertices have exactly one owner. */
TEST(locate_crack_duplicated_vertices) {
    rng_seed(4);
    for (int diagonal = 0; diagonal < 2; diagonal++) {
        int n = 8;
        tmesh tm;
        tm_crack_grid(&tm, n, diagonal);
        CHECK_NEAR(tm_total_area(&tm), 1.0, 1e-12);
        CHECK(tm.m.nv == (n + 1) * (n + 1) + n + 1);
        tc_locator *L = tm_locator(&tm);
        for (int k = 0; k <= 64; k++) { /* every 1/64 along the crack */
            double s = k / 64.0, x = diagonal ? s : 0.5, y = s;
            check_point(&tm, L, x, y, !on_unit_boundary(x, y), 1);
        }
        for (int q = 0; q < 2000; q++) { /* random exact points on the crack */
            double s = rnd_dyadic(0, 1, 30);
            double x = diagonal ? s : 0.5;
            check_point(&tm, L, x, s, !on_unit_boundary(x, s), 1);
        }
        for (int q = 0; q < 2000; q++) { /* and anywhere */
            double x = rnd_dyadic(-0.125, 1.125, 20), y = rnd_dyadic(-0.125, 1.125, 20);
            int in = x > 0 && x < 1 && y > 0 && y < 1;
            check_point(&tm, L, x, y, in, in || (x >= 0 && x <= 1 && y >= 0 && y <= 1));
        }
        tc_locator_free(L);
        tm_free(&tm);
    }
}

/* 4. The same mesh translated by 1e9 (exactly: vertices are multiples of 2^-16,
 *    queries of 2^-20, and 1e9 + x then still fits in a double) gives the same
 *    owners. */
TEST(locate_translation_invariance) {
    rng_seed(5);
    const double T[2] = {1e9, -3e8};
    uint64_t seed = rng_state;
    grid_opt o = {16, 1.0 / 16, 0, 0, 16, 2, 1, NULL};
    tmesh a, b;
    tm_grid(&a, &o);
    rng_state = seed; /* same jitter, diagonals and flips */
    o.ox = T[0];
    o.oy = T[1];
    tm_grid(&b, &o);
    for (int32_t v = 0; v < a.m.nv; v++)
        for (int c = 0; c < 2; c++) {
            double x = a.m.xy[2 * v + c], y = b.m.xy[2 * v + c];
            CHECK_MSG(y - T[c] == x, "vertex %d not translated exactly", (int)v);
        }
    CHECK(memcmp(a.m.tri, b.m.tri, 3 * (size_t)a.m.nt * sizeof *a.m.tri) == 0);
    tc_locator *La = tm_locator(&a), *Lb = tm_locator(&b);
    int located = 0, mism = 0;
    for (int q = 0; q < 30000 + a.m.nv; q++) {
        double x, y;
        if (q < a.m.nv) {
            x = a.m.xy[2 * q];
            y = a.m.xy[2 * q + 1];
        } else if (q % 3 == 0) { /* on an edge: vertex plus a dyadic fraction of the edge */
            int32_t t = (int32_t)rnd_int(0, a.m.nt - 1);
            int k = (int)rnd_int(0, 2);
            const double *p = tm_xy(&a, a.m.tri[3 * t + k]), *r = tm_xy(&a, a.m.tri[3 * t + (k + 1) % 3]);
            double f = rnd_dyadic(0, 1, 4);
            x = p[0] + (r[0] - p[0]) * f;
            y = p[1] + (r[1] - p[1]) * f;
        } else {
            x = rnd_dyadic(-0.125, 1.125, 20);
            y = rnd_dyadic(-0.125, 1.125, 20);
        }
        int32_t ta = tc_locate(La, x, y), tb = tc_locate(Lb, x + T[0], y + T[1]);
        CHECK_MSG((x + T[0]) - T[0] == x && (y + T[1]) - T[1] == y, "query (%.17g, %.17g) not exact", x, y);
        if (ta != tb && ++mism <= 5) CHECK_MSG(0, "(%.17g, %.17g): owner %d, translated %d", x, y, (int)ta, (int)tb);
        located += ta >= 0;
        /* The untranslated answers are the reference's. */
        if (q % 8 == 0) check_point(&a, La, x, y, 0, 0);
    }
    CHECK(mism == 0);
    CHECK(located > 20000);
    tc_locator_free(La);
    tc_locator_free(Lb);
    tm_free(&a);
    tm_free(&b);
}

static int skip_notch(int i, int j) { return i >= 4 && j >= 4; }
static int skip_hole(int i, int j) { return i >= 3 && i <= 4 && j >= 3 && j <= 4; }

/* 5. An L-shape and a square with a square hole: points in the notch or hole
 *    are outside, points on their rims are not. */
TEST(locate_nonconvex_and_hole) {
    rng_seed(6);
    for (int shape = 0; shape < 2; shape++) {
        grid_opt o = {8, 1.0 / 8, 0, 0, 0, 2, 1, shape ? skip_hole : skip_notch};
        tmesh tm;
        tm_grid(&tm, &o);
        /* The removed region, open and closed. */
        double lo = shape ? 3.0 / 8 : 0.5, hi = shape ? 5.0 / 8 : 1.0;
        CHECK_NEAR(tm_total_area(&tm), 1.0 - (hi - lo) * (hi - lo), 1e-12);
        tc_locator *L = tm_locator(&tm);
        int in_gap = 0;
        for (int q = 0; q < 20000; q++) {
            double x = rnd_dyadic(-0.125, 1.125, 6), y = rnd_dyadic(-0.125, 1.125, 6);
            int in_square = x >= 0 && x <= 1 && y >= 0 && y <= 1;
            /* The notch runs out to the square's edge: its rim there is not in the domain. */
            int gap_open = x > lo && y > lo && (shape ? x < hi && y < hi : 1);
            int gap_closed = x >= lo && x <= hi && y >= lo && y <= hi;
            int interior = x > 0 && x < 1 && y > 0 && y < 1 && !gap_closed;
            check_point(&tm, L, x, y, interior, in_square && !gap_open);
            if (gap_open && in_square) {
                in_gap++;
                CHECK_MSG(tc_locate(L, x, y) == -1, "(%g, %g) in the gap located", x, y);
            }
        }
        CHECK(in_gap > 300);
        /* The unused vertex in the middle of the hole, the notch's inner corner. */
        if (shape) CHECK(tc_locate(L, 0.5, 0.5) == -1);
        else CHECK(tc_locate(L, 0.5, 0.5) >= 0 && tc_locate(L, 0.75, 0.75) == -1);
        tc_locator_free(L);
        tm_free(&tm);
    }
}

/* 6. Strips of slivers (width 2^-27 for length 1: aspect ratio 1.3e8), along x
 *    and along the diagonal, against the exact reference. */
TEST(locate_slivers) {
    rng_seed(7);
    const double h = 0x1p-27;
    for (int rotated = 0; rotated < 2; rotated++) {
        tmesh tm;
        tm_init(&tm);
        /* (x, y) -> (x - y, x + y) keeps the coordinates dyadic. */
#define SLIVER_V(x, y) (rotated ? tm_vertex(&tm, (x) - (y), (x) + (y)) : tm_vertex(&tm, (x), (y)))
        int32_t bot[9], top[8];
        for (int i = 0; i <= 8; i++) bot[i] = SLIVER_V((double)i, 0.0);
        for (int i = 0; i < 8; i++) top[i] = SLIVER_V(i + 0.5, h);
#undef SLIVER_V
        for (int i = 0; i < 8; i++) tm_tri_maybe_flipped(&tm, bot[i], bot[i + 1], top[i], 1);
        for (int i = 0; i < 7; i++) tm_tri_maybe_flipped(&tm, top[i], bot[i + 1], top[i + 1], 1);
        CHECK_NEAR(tm_total_area(&tm) / (rotated ? 2 : 1), 7.5 * h, 1e-20);
        tc_locator *L = tm_locator(&tm);
        int located = 0;
        for (int q = 0; q < 20000; q++) {
            double u = rnd_dyadic(-0.5, 8.5, 20), v = rnd_dyadic(-h / 2, 1.5 * h, 40);
            if (q % 4 == 0) v = h * (double)rnd_int(0, 8) / 8; /* on a strip boundary or a ninth of the way */
            double x = rotated ? u - v : u, y = rotated ? u + v : v;
            int32_t t = tc_locate(L, x, y);
            check_point(&tm, L, x, y, 0, 0);
            if (t >= 0) {
                located++;
                CHECK(ref_classify(&tm, t, x, y) != REF_OUT);
            }
        }
        CHECK(located > 4000);
        /* Every vertex and a point strictly inside every sliver. */
        for (int32_t v = 0; v < tm.m.nv; v++) CHECK(tc_locate(L, tm_xy(&tm, v)[0], tm_xy(&tm, v)[1]) >= 0);
        for (int32_t t = 0; t < tm.m.nt; t++) {
            const int32_t *w = tm.m.tri + 3 * t;
            double x = 0, y = 0;
            for (int k = 0; k < 3; k++) { /* weights 1/4, 1/4, 1/2: exact */
                x += tm_xy(&tm, w[k])[0] * (k == 2 ? 0.5 : 0.25);
                y += tm_xy(&tm, w[k])[1] * (k == 2 ? 0.5 : 0.25);
            }
            CHECK_MSG(tc_locate(L, x, y) == t, "inside sliver %d: got %d", (int)t, (int)tc_locate(L, x, y));
        }
        tc_locator_free(L);
        tm_free(&tm);
    }
}

/* Two triangles (s, e, a) and (e, s, b), in either vertex order, share the
 * edge s-e; every point of pts (inside the quad) must get the exact owner.
 * Returns how many points lie exactly on the line s-e. */
static int near_edge_case(const double s[2], const double e[2], const double a[2], const double b[2], int order,
                          const double *pts, int np) {
    tmesh tm;
    tm_init(&tm);
    int32_t vs = tm_vertex(&tm, s[0], s[1]), ve = tm_vertex(&tm, e[0], e[1]);
    int32_t va = tm_vertex(&tm, a[0], a[1]), vb = tm_vertex(&tm, b[0], b[1]);
    if (order) {
        tm_tri(&tm, vb, vs, ve);
        tm_tri(&tm, va, ve, vs);
    } else {
        tm_tri(&tm, vs, ve, va);
        tm_tri(&tm, ve, vs, vb);
    }
    tc_locator *L = tm_locator(&tm);
    int on_line = 0;
    for (int i = 0; i < np; i++) {
        on_line += ref_orient(s, e, pts[2 * i], pts[2 * i + 1]) == 0;
        check_point(&tm, L, pts[2 * i], pts[2 * i + 1], 1, 1);
    }
    tc_locator_free(L);
    tm_free(&tm);
    return on_line;
}

/* Up to 25 points: (x, y) moved by -2 .. 2 ulps in each coordinate. */
static int ulp_cloud(double x, double y, double *pts) {
    int n = 0;
    for (int dx = -2; dx <= 2; dx++)
        for (int dy = -2; dy <= 2; dy++) {
            double px = x, py = y;
            for (int k = 0; k < abs(dx); k++) px = nextafter(px, (float)dx * INFINITY);
            for (int k = 0; k < abs(dy); k++) py = nextafter(py, (float)dy * INFINITY);
            pts[2 * n] = px;
            pts[2 * n + 1] = py;
            n++;
        }
    return n;
}

static double round_to(double v, int bits) { return ldexp(nearbyint(ldexp(v, bits)), -bits); }

/* Points within a few ulps of a shared edge, with full-precision coordinates
 * and differences that round, where a plain floating-point cross product gets
 * the side wrong: the owner must be the exact one. */
TEST(locate_exact_near_edge) {
    rng_seed(8);
    double pts[2 * 1024];
    int on_line = 0;
    /* Direction (3, 2) / 4: points s + k (3, 2) 2^-14 lie exactly on the line. */
    for (int m = 0; m < 100; m++) {
        double s[2] = {1 + rnd_dyadic(0, 0.0625, 52), 1 + rnd_dyadic(0, 0.0625, 52)};
        double e[2] = {s[0] + 0.75, s[1] + 0.5}, a[2] = {1.0, 1.9375}, b[2] = {1.9375, 1.0};
        for (int q = 0; q < 40; q++) {
            int64_t k = rnd_int(1, 4095);
            int np = ulp_cloud(s[0] + (double)(3 * k) * 0x1p-14, s[1] + (double)(2 * k) * 0x1p-14, pts);
            on_line += near_edge_case(s, e, a, b, m & 1, pts, np);
        }
    }
    /* Random edges across binades (s below 1, e in [2, 4)), points interpolated. */
    for (int m = 0; m < 100; m++) {
        double s[2] = {rnd_dyadic(0.5, 1, 53), rnd_dyadic(0.5, 1, 53)};
        double e[2] = {rnd_dyadic(2, 4, 51), rnd_dyadic(2, 4, 51)};
        double mid[2] = {(s[0] + e[0]) / 2, (s[1] + e[1]) / 2}, nrm[2] = {s[1] - e[1], e[0] - s[0]};
        double a[2] = {round_to(mid[0] + nrm[0], 20), round_to(mid[1] + nrm[1], 20)};
        double b[2] = {round_to(mid[0] - nrm[0], 20), round_to(mid[1] - nrm[1], 20)};
        for (int q = 0; q < 40; q++) {
            double f = 0.05 + 0.9 * ((double)(rnd64() >> 11) * 0x1p-53);
            int np = ulp_cloud(s[0] + f * (e[0] - s[0]), s[1] + f * (e[1] - s[1]), pts);
            near_edge_case(s, e, a, b, m & 1, pts, np);
        }
    }
    /* Shewchuk's example: a 32 x 32 grid of ulps at (c, c) against the line
     * y = x through (-t, -t) and (u, u), where P - s rounds. */
    static const double cfg[4][3] = {{0.5, 12, 24}, {0.5, 12.25, 100.5}, {0.75, 3.5, 7}, {1.5, 200, 6}};
    for (int v = 0; v < 4; v++) {
        double c = cfg[v][0], t = cfg[v][1], u = cfg[v][2];
        double s[2] = {-t, -t}, e[2] = {u, u}, a[2] = {-t, u}, b[2] = {u, -t};
        int np = 0;
        for (int i = 0; i < 32; i++)
            for (int j = 0; j < 32; j++, np++) {
                pts[2 * np] = c + i * ldexp(0x1p-52, ilogb(c));
                pts[2 * np + 1] = c + j * ldexp(0x1p-52, ilogb(c));
            }
        int exact = near_edge_case(s, e, a, b, v & 1, pts, np);
        CHECK(exact == 32);
        on_line += exact;
    }
    CHECK(on_line > 1000);
}

static double now_seconds(void) { return tc_now_ms() * 1e-3; }

/* Locates the n points xy into ans; returns the seconds it took. */
static double time_queries(const tc_locator *L, const double *xy, int32_t *ans, int n) {
    double t0 = now_seconds();
    for (int q = 0; q < n; q++) ans[q] = tc_locate(L, xy[2 * q], xy[2 * q + 1]);
    return now_seconds() - t0;
}

/* Every answer contains its point, and -1 comes exactly outside the square [0, D]^2. */
static void check_answers(const tmesh *tm, const double *xy, const int32_t *ans, int n, double D) {
    int bad = 0;
    for (int q = 0; q < n && bad < 5; q++) {
        double x = xy[2 * q], y = xy[2 * q + 1];
        int in = x >= 0 && x <= D && y >= 0 && y <= D;
        int ok = in ? ans[q] >= 0 && ans[q] < tm->m.nt && ref_classify(tm, ans[q], x, y) != REF_OUT : ans[q] == -1;
        if (!ok) {
            bad++;
            CHECK_MSG(0, "(%.17g, %.17g): got %d (in the square: %d)", x, y, (int)ans[q], in);
        }
    }
}

/* 7. A jittered 200 x 200 grid (80 000 triangles), 200 000 random queries: each
 *    answer contains its point, -1 exactly outside the square, and a subsample
 *    matches a full brute-force scan. Reports the throughput on stderr, also
 *    for the same number of queries in raster order (coherent, cache-friendly). */
TEST(locate_large_mesh) {
    rng_seed(9);
    const int n = 200;
    const double h = 1.0 / 256, D = n * h;
    grid_opt o = {n, h, 0, 0, 20, 2, 1, NULL};
    tmesh tm;
    tm_grid(&tm, &o);
    CHECK(tm.m.nt == 2 * n * n);
    CHECK_NEAR(tm_total_area(&tm), D * D, 1e-12);
    double t0 = now_seconds();
    tc_locator *L = tm_locator(&tm);
    double t_build = now_seconds() - t0;
    enum { NQ = 200000, RW = 500 }; /* raster: NQ / RW rows of RW points */
    double *qxy = malloc(2 * NQ * sizeof *qxy);
    int32_t *ans = malloc(NQ * sizeof *ans);
    if (!qxy || !ans) abort();
    for (int q = 0; q < NQ; q++) {
        qxy[2 * q] = rnd_dyadic(-0.015625, D + 0.015625, 30);
        qxy[2 * q + 1] = rnd_dyadic(-0.015625, D + 0.015625, 30);
    }
    double t_rand = time_queries(L, qxy, ans, NQ);
    check_answers(&tm, qxy, ans, NQ, D);
    for (int q = 0; q < NQ; q += NQ / 2000) check_point(&tm, L, qxy[2 * q], qxy[2 * q + 1], 0, 0);
    for (int q = 0; q < NQ; q++) { /* pixel centres over [-1/64, D + 1/64]^2 */
        double px = (q % RW + 0.5) / RW, py = (q / RW + 0.5) / (NQ / RW);
        qxy[2 * q] = round_to(-0.015625 + px * (D + 0.03125), 30);
        qxy[2 * q + 1] = round_to(-0.015625 + py * (D + 0.03125), 30);
    }
    double t_raster = time_queries(L, qxy, ans, NQ);
    check_answers(&tm, qxy, ans, NQ, D);
    fprintf(stderr,
            "  [locate_large_mesh] %d triangles: build %.1f ms; %d random queries %.1f ms = %.2f M/s; "
            "raster order %.1f ms = %.2f M/s\n",
            (int)tm.m.nt, 1e3 * t_build, NQ, 1e3 * t_rand, NQ / t_rand / 1e6, 1e3 * t_raster, NQ / t_raster / 1e6);
    free(qxy);
    free(ans);
    tc_locator_free(L);
    tm_free(&tm);
}

/* The bounds tc_locator_new checks before it reads anything: a vertex index equal to the vertex
 * count (one past the last, the classic off-by-one) or negative is refused as TC_EINVAL, not
 * read from beyond the coordinate array, and a negative triangle count is TC_EINVAL too (not
 * TC_ELIMIT, which a negative count cast to size_t would otherwise give). */
TEST(locate_rejects_bad_counts_and_indices) {
    tmesh tm;
    tm_init(&tm);
    tm_tri(&tm, tm_vertex(&tm, 0, 0), tm_vertex(&tm, 1, 0), tm_vertex(&tm, 0, 1));
    tc_locator *const junk = (tc_locator *)(uintptr_t)16;
    tc_locator *L = junk;
    for (int k = 0; k < 3; k++) {
        int32_t keep = tm.m.tri[k];
        tm.m.tri[k] = tm.m.nv; /* within the capacity of 64 vertices: a wrong bound reads no foreign memory */
        L = junk;
        CHECK_MSG(tc_locator_new(&tm.m, &L) == TC_EINVAL && L == NULL, "corner %d = nv accepted", k);
        tm.m.tri[k] = -1;
        L = junk;
        CHECK_MSG(tc_locator_new(&tm.m, &L) == TC_EINVAL && L == NULL, "corner %d = -1 accepted", k);
        tm.m.tri[k] = keep;
    }
    CHECK(tc_locator_new(&tm.m, &L) == TC_OK && L);
    tc_locator_free(L);
    int32_t nt = tm.m.nt;
    tm.m.nt = -1;
    L = junk;
    CHECK(tc_locator_new(&tm.m, &L) == TC_EINVAL && L == NULL);
    tm.m.nt = nt;
    tm_free(&tm);
}
