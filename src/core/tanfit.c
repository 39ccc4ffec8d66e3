/* tanfit.c — the estimated tangent plane of a wedge (tangents "estimate", or
 * "auto" without gradients or midpoints): a weighted least-squares fit to the
 * samples around the wedge's vertex, never across a delimiter.
 *
 * Three choices, each measured on the report's scenes (docs/design-notes.md,
 * "Tangent planes", with the alternatives that lost):
 *  - Sectors. A C1 vertex where two flagged edges meet at an angle (a penumbra's
 *    corner: the paper makes it C1) has one wedge spanning regions in which the
 *    function is smooth only piecewise. Each sector between flagged edges is
 *    fitted on its own and the planes are averaged by the sectors' areas, so a
 *    tiny corner cell cannot tilt the plane of the lit region around it.
 *  - Neighbourhood. Vertex rings grown from the sector's faces across C1 edges
 *    only: two rings always, up to four while fewer than CUBIC_MIN sample
 *    positions are distinct (coarse meshes, narrow wedges, and the near
 *    coincident pairs a sliver strip puts on both sides of a grid line).
 *  - Model. z - z_v = g.d + (quadratic) + (cubic), rows weighted 1/|d|^2 with
 *    |d| at least NEAR_CAP times the median distance of the first ring:
 *    cubic from CUBIC_MIN distinct positions, quadratic from QUAD_MIN, else a
 *    plane; an order whose terms the samples do not determine independently
 *    (tc__lsq_solve_indep) falls back to the next lower one.
 * Invariants: linear data gives its exact gradient (every model contains the
 * plane); quadratic data too wherever the quadratic or cubic fit runs; the
 * plane is linear in the values (channels are independent right-hand sides)
 * and invariant under translating or scaling the coordinates (offsets from the
 * vertex, scaled by the farthest sample). */
#include <math.h>
#include <string.h>

#include "core/alloc.h"
#include "core/fhypot.h"
#include "core/geom.h"
#include "core/lsq.h"
#include "core/mesh.h"
#include "core/minmax.h"
#include "core/tanfit.h"

/* Two vertex rings give a cubic 18 samples on a regular mesh; narrow wedges and
 * coarse meshes grow to four while fewer than CUBIC_MIN positions are distinct. */
#define RINGS_ALWAYS 2
#define RINGS_MAX 4
/* Distinct positions for a cubic (9 terms) and a quadratic (5): a third more
 * than the terms, so one bad sample cannot be interpolated exactly. */
#define CUBIC_MIN 12
#define QUAD_MIN 6
/* Two samples closer than this fraction of their distance from the vertex count
 * as one position (a sliver's two long sides seen from afar). */
#define SAME_POSITION 0.05
/* A fitted term needs this much of its column outside the span of the lower
 * terms (the sine of the angle); below, the order drops. Samples on three lines
 * make the cubic terms dependent up to the lines' 1e-4 offsets: refused. */
#define TERM_INDEP 1e-2
/* Relative rank tolerance of the fit (tc__lsq_solve_indep's rtol): a column
 * below 1e-9 of the largest, after the rows' unit scaling, is not determined by
 * the samples (they lie on a line through v): the fit fails rather than
 * return a slope of size 1/1e-9 made of rounding. */
#define FIT_RTOL 1e-9
/* A sample much nearer than its ring's others mostly measures the function
 * across one thin element — where an unflagged kink hides (a penumbra strip
 * next to a flat region) — so its weight is that of a sample at this fraction of
 * the median first-ring distance at most (unflagged stiff scene: 10x lower error). */
#define NEAR_CAP 0.3
/* Faces one sector's neighbourhood may hold; beyond, it stops growing. */
#define MAX_FACES 512

int tc__fit_space_init(const struct tc_mesh *m, tc__fit_space *fs) {
    fs->tmark = tc__calloc((size_t)m->nt, sizeof *fs->tmark);
    fs->vmark = tc__calloc((size_t)m->nv, sizeof *fs->vmark);
    fs->vsample = tc__calloc((size_t)m->nv, sizeof *fs->vsample);
    fs->gen = 0; /* one per sector fit, < 3 nt < 2^31: never wraps onto a stale mark */
    if (!fs->tmark || !fs->vmark || !fs->vsample) {
        tc__fit_space_free(fs);
        return TC_ENOMEM;
    }
    return TC_OK;
}

void tc__fit_space_free(tc__fit_space *fs) {
    tc__free(fs->tmark), tc__free(fs->vmark), tc__free(fs->vsample);
    memset(fs, 0, sizeof *fs);
}

/* ---- the neighbourhood of one sector ---- */

typedef struct {
    int32_t v;                      /* the wedge's vertex */
    int n, ndup;                    /* samples, and those at an earlier one's position */
    double d[TC_LSQ_MAXROWS][2];    /* offset from v */
    const double *z[TC_LSQ_MAXROWS];
    int64_t key[TC_LSQ_MAXROWS];    /* vertex id, or -1 - edge id for a midpoint */
    int8_t ring[TC_LSQ_MAXROWS];    /* vertex ring the sample was reached in */
    uint8_t dup[TC_LSQ_MAXROWS];
    int nf;
    int32_t face[MAX_FACES];        /* faces gathered, ring by ring */
} hood;

static void add_midpoint(const struct tc_mesh *m, hood *h, int32_t e, int ring) {
    if (!m->mid_has || !m->mid_has[e] || h->n == TC_LSQ_MAXROWS) return;
    int32_t t = e / 3, k = e % 3, other = m->nbr[e] >= 0 ? 3 * m->nbr[e] + m->nbr_k[e] : e;
    int64_t key = -1 - (int64_t)(e < other ? e : other); /* one sample per edge side pair */
    for (int i = 0; i < h->n; i++)
        if (h->key[i] == key) return;
    const double *a = tc__vxy(m, m->tri[e]), *b = tc__vxy(m, m->tri[3 * t + (k + 1) % 3]), *p = tc__vxy(m, h->v);
    int i = h->n++;
    h->d[i][0] = 0.5 * ((a[0] - p[0]) + (b[0] - p[0]));
    h->d[i][1] = 0.5 * ((a[1] - p[1]) + (b[1] - p[1]));
    h->z[i] = m->mid + (size_t)e * (size_t)m->nc;
    h->key[i] = key, h->ring[i] = (int8_t)ring, h->dup[i] = 0;
}

/* Corner c's vertex as a sample (its value on c's side of any C-1 edge). A
 * vertex at v's own position (the twin of a crack) carries no slope: skipped. */
static void add_vertex(const struct tc_mesh *m, const double *cz, tc__fit_space *fs, hood *h, int32_t c, int ring) {
    int32_t u = m->tri[c];
    if (u == h->v || fs->vmark[u] == fs->gen || h->n == TC_LSQ_MAXROWS) return;
    double d[2];
    tc__sub(d, tc__vxy(m, u), tc__vxy(m, h->v));
    if (d[0] == 0 && d[1] == 0) return;
    fs->vmark[u] = fs->gen;
    int i = fs->vsample[u] = h->n++;
    h->d[i][0] = d[0], h->d[i][1] = d[1];
    h->z[i] = cz + (size_t)c * (size_t)m->nc;
    h->key[i] = u, h->ring[i] = (int8_t)ring, h->dup[i] = 0;
}

static int is_sample(const tc__fit_space *fs, int32_t u) { return fs->vmark[u] == fs->gen; }

/* An edge of f much shorter than its ends' distance from v joins two samples
 * at nearly one position: the later counts as a duplicate. */
static void note_duplicates(const struct tc_mesh *m, const tc__fit_space *fs, hood *h, int32_t f) {
    for (int k = 0; k < 3; k++) {
        int32_t a = m->tri[3 * (size_t)f + (size_t)k], b = m->tri[3 * (size_t)f + (size_t)(k + 1) % 3];
        if (a == h->v || b == h->v || !is_sample(fs, a) || !is_sample(fs, b)) continue;
        int ia = fs->vsample[a], ib = fs->vsample[b], late = ia > ib ? ia : ib;
        if (h->dup[ia] || h->dup[ib]) continue;
        double ab[2] = {h->d[ia][0] - h->d[ib][0], h->d[ia][1] - h->d[ib][1]};
        double near2 = tc__fmin(tc__dot(h->d[ia], h->d[ia]), tc__dot(h->d[ib], h->d[ib]));
        if (tc__dot(ab, ab) < SAME_POSITION * SAME_POSITION * near2) h->dup[late] = 1, h->ndup++;
    }
}

static void add_face(const struct tc_mesh *m, const double *cz, tc__fit_space *fs, hood *h, int32_t f, int ring) {
    if (h->nf == MAX_FACES) return;
    fs->tmark[f] = fs->gen;
    h->face[h->nf++] = f;
    for (int k = 0; k < 3; k++) add_vertex(m, cz, fs, h, 3 * f + k, ring);
    for (int k = 0; k < 3; k++) add_midpoint(m, h, 3 * f + k, ring);
    note_duplicates(m, fs, h, f);
}

/* Some vertex of f was first reached in ring `ring`. */
static int touches_ring(const struct tc_mesh *m, const tc__fit_space *fs, const hood *h, int32_t f, int ring) {
    for (int k = 0; k < 3; k++) {
        int32_t u = m->tri[3 * (size_t)f + (size_t)k];
        if (is_sample(fs, u) && h->ring[fs->vsample[u]] == ring) return 1;
    }
    return 0;
}

/* Ring L: the faces that touch a ring L-1 vertex and are reached from the
 * faces gathered so far across C1 edges only (never a delimiter, never a face
 * at v: those belong to other sectors or wedges). */
static int grow_ring(const struct tc_mesh *m, int honor, const double *cz, tc__fit_space *fs, hood *h, int L) {
    int before = h->nf;
    for (int i = 0; i < h->nf; i++)
        for (int k = 0; k < 3; k++) {
            int32_t e = 3 * h->face[i] + k, nb = m->nbr[e];
            if (nb < 0 || fs->tmark[nb] == fs->gen || tc__eff_flag(m, honor, e) != TC_C1) continue;
            if (tc__corner_of(m, nb, h->v) >= 0 || !touches_ring(m, fs, h, nb, L - 1)) continue;
            add_face(m, cz, fs, h, nb, L);
        }
    return h->nf > before;
}

/* ---- the fit ---- */

/* The median distance of the first-ring samples (there is one at least). */
static double ring1_median(const hood *h) {
    double r[TC_LSQ_MAXROWS];
    int n = 0;
    for (int i = 0; i < h->n; i++) {
        if (h->ring[i] != 1) continue;
        double x = tc__hypot(h->d[i][0], h->d[i][1]);
        int j = n++;
        for (; j > 0 && r[j - 1] > x; j--) r[j] = r[j - 1]; /* insertion: a handful of samples */
        r[j] = x;
    }
    return n ? r[n / 2] : 0;
}

/* Weighted least squares for g in z - z_v = g.d + ... in coordinates scaled
 * by the farthest sample; the highest order the samples determine. */
static void fit(const hood *h, const double *zv, int nc, double *g) {
    static const int terms[3] = {9, 5, 2};
    double s = 0;
    for (int i = 0; i < h->n; i++) s = tc__fmax(s, tc__hypot(h->d[i][0], h->d[i][1])); /* > 0: no sample sits on v */
    double near = NEAR_CAP * ring1_median(h) / s;
    int distinct = h->n - h->ndup, order = distinct >= CUBIC_MIN ? 0 : distinct >= QUAD_MIN ? 1 : 2;
    for (; order < 3; order++) {
        int cols = terms[order];
        double A[TC_LSQ_MAXROWS][TC_LSQ_MAXCOLS], B[TC_LSQ_MAXROWS][TC_LSQ_MAXRHS], X[TC_LSQ_MAXCOLS][TC_LSQ_MAXRHS];
        for (int i = 0; i < h->n; i++) {
            /* w = 1/r applied twice, never 1/r^2: no overflow for any r a double holds */
            double x = h->d[i][0] / s, y = h->d[i][1] / s, w = 1 / tc__fmax(near, tc__hypot(x, y));
            double row[9] = {x, y, 0.5 * x * x, x * y, 0.5 * y * y, x * x * x / 6, 0.5 * x * x * y, 0.5 * x * y * y,
                             y * y * y / 6};
            for (int j = 0; j < cols; j++) A[i][j] = row[j] * w * w;
            for (int ch = 0; ch < nc; ch++) B[i][ch] = (h->z[i][ch] - zv[ch]) * w * w;
        }
        if (tc__lsq_solve_indep(A, h->n, cols, B, nc, FIT_RTOL, cols > 2 ? TERM_INDEP : 0, X) == 0) {
            for (int ch = 0; ch < nc; ch++) g[2 * ch] = X[0][ch] / s, g[2 * ch + 1] = X[1][ch] / s;
            return;
        }
    }
    memset(g, 0, 2 * (size_t)nc * sizeof *g); /* unreachable: a face's two edges at v are independent */
}

/* ---- sectors ---- */

/* The edge at v between the faces of consecutive corners a and b. */
static int32_t between(const struct tc_mesh *m, int32_t a, int32_t b) {
    int32_t t = a / 3, k = a % 3, tb = b / 3;
    return m->nbr[a] == tb ? a : 3 * t + (k + 2) % 3;
}

/* A flagged edge inside a wedge: only at a C1 vertex, between sectors. */
static int splits(const struct tc_mesh *m, const tc__wedge_set *ws, int32_t a, int32_t b) {
    return tc__eff_flag(m, ws->honor_flags, between(m, a, b)) != TC_C1;
}

/* The plane of the sector made of corners cs[(s0 + i) % cnt], i < len; *area
 * receives the area of its faces. */
static void fit_sector(const struct tc_mesh *m, const tc__wedge_set *ws, const tc__wedge *w, const double *cz,
                       tc__fit_space *fs, int s0, int len, double *g, double *area) {
    const int32_t *cs = ws->corners + w->first;
    hood h;
    h.v = w->v, h.n = h.ndup = h.nf = 0;
    fs->gen++;
    *area = 0;
    for (int i = 0; i < len; i++) {
        int32_t t = cs[(s0 + i) % w->count] / 3;
        add_face(m, cz, fs, &h, t, 1);
        *area += tc__face_area(m, t);
    }
    for (int L = 2; L <= RINGS_MAX; L++) {
        if (L > RINGS_ALWAYS && h.n - h.ndup >= CUBIC_MIN) break;
        if (!grow_ring(m, ws->honor_flags, cz, fs, &h, L)) break;
    }
    fit(&h, cz + (size_t)cs[s0] * (size_t)m->nc, m->nc, g);
}

void tc__fit_wedge(const struct tc_mesh *m, const tc__wedge_set *ws, const tc__wedge *w, const double *cz,
                   tc__fit_space *fs, double *g) {
    const int32_t *cs = ws->corners + w->first;
    int cnt = w->count, nc = m->nc, full = w->side_edge[0] < 0, s0 = -1;
    /* A full turn is cyclic: its sectors start after its first flagged edge. */
    for (int i = 0; full && i < cnt && s0 < 0 && cnt > 1; i++)
        if (splits(m, ws, cs[i], cs[(i + 1) % cnt])) s0 = (i + 1) % cnt;
    if (s0 < 0) s0 = 0;
    double sum[2 * TC_MAX_CHANNELS] = {0}, total = 0, gs[2 * TC_MAX_CHANNELS], area;
    for (int begin = 0, i = 0; i < cnt; i++) {
        int last = i == cnt - 1;
        if (!last && !splits(m, ws, cs[(s0 + i) % cnt], cs[(s0 + i + 1) % cnt])) continue;
        fit_sector(m, ws, w, cz, fs, (s0 + begin) % cnt, i + 1 - begin, gs, &area);
        if (begin == 0 && last) { /* one sector: its plane as fitted, bit for bit */
            memcpy(g, gs, 2 * (size_t)nc * sizeof *g);
            return;
        }
        for (int k = 0; k < 2 * nc; k++) sum[k] += area * gs[k];
        total += area;
        begin = i + 1;
    }
    for (int k = 0; k < 2 * nc; k++) g[k] = sum[k] / total;
}
