/* locate.c — point location: which triangle of a mesh owns a point (x, y).
 * A static bounding-volume hierarchy over triangle boxes plus an exact top-left ownership rule. */
#include <math.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include "core/alloc.h"
#include "core/locate.h"
#include "core/locgrid.h"
#include "core/mesh.h"
#include "core/minmax.h"

/* ==== The ownership rule =====================================================
 *
 * Every edge is tested in a canonical frame: its endpoints sorted by
 * coordinates (x, then y), s < e. The coordinates decide, never the vertex
 * indices, so two coincident copies of a vertex (a crack made by a front-end)
 * give the same frame. The test is the sign of
 *     val = cross(e - s, P - s) = (e.x - s.x)(P.y - s.y) - (e.y - s.y)(P.x - s.x),
 * always evaluated as this one expression of (s, e, P), and its sign is exact:
 * the floating-point value is used when a forward error bound certifies its
 * sign, otherwise the same determinant is evaluated in exact expansion
 * arithmetic (see orient_sign). So the two triangles of an edge get the same
 * answer, and so do two collinear edges of one line (their canonical directions
 * agree and an exact sign depends only on the side of the line). Exactness,
 * not only bit-identical doubles, is what the fan argument below needs: with
 * rounded signs, the three or more edges meeting near a vertex could disagree
 * and leave a tiny region with zero or two owners. Only differences relative
 * to s are ever multiplied, so a mesh translated by an exactly representable
 * offset gives the same doubles and, in any case, the same exact signs.
 *
 * A triangle, walked counter-clockwise, has its interior to the left of each
 * directed edge p -> q. If p < q the canonical frame runs the same way and the
 * triangle is LEFT of s -> e; otherwise it is RIGHT of it. Ties (val == 0) go
 * to the left triangle, i.e. the edge's own half-plane is val >= 0 for the left
 * triangle and val < 0 for the right one. A triangle strictly owns P when P is
 * in all three of its half-planes. Left of a canonical direction means above a
 * non-vertical edge and to the -x side of a vertical one: a top-left fill rule.
 *
 * Why every point of the interior of a (conforming, non-overlapping) mesh has
 * exactly one strict owner:
 *  - P inside a triangle: that triangle only, all its tests are strict.
 *  - P inside a shared edge E (not at an endpoint): only the two triangles of E
 *    contain P, and P lies strictly inside their other two half-planes. On E,
 *    val == 0, which puts P in the left triangle's half-plane and out of the
 *    right one's: exactly one owner.
 *  - P at an interior vertex v: the triangles around v form a full fan between
 *    rays r_1 .. r_k in counter-clockwise order, t_i between r_i and r_(i+1).
 *    At P = v both fan edges of t_i give val == 0 and the opposite edge is
 *    strict, so t_i owns v iff it is the left triangle of both its fan edges.
 *    Call a ray OUTgoing if its far end w > v (then s = v and the canonical
 *    direction points away from v, whose left is the counter-clockwise side),
 *    INcoming otherwise (canonical direction points at v, left = clockwise
 *    side). t_i lies counter-clockwise of r_i and clockwise of r_(i+1), so it
 *    owns v iff r_i is OUT and r_(i+1) is IN. OUT rays are those with angle in
 *    the half-open half-circle (-90, 90] degrees, IN rays the other half. Every
 *    triangle angle is below 180 degrees, so the rays of a full fan cannot all
 *    lie in one half-circle: both kinds occur, each kind is contiguous in the
 *    cyclic order, hence there is exactly one OUT -> IN step: one owner.
 *    (For a partial fan at a boundary vertex the same count gives at most one.)
 * Points on the outer boundary may have no strict owner (the left triangle of a
 * boundary edge may be missing). The fallback then takes the triangle that
 * contains P in the closed sense (every canonical test >= 0 after orientation),
 * the lowest index if several do; points of no closed triangle are outside.
 */

/* ==== Exact orientation sign ================================================
 * Assumes IEEE double arithmetic without excess precision (FLT_EVAL_METHOD 0,
 * as on x86-64 and AArch64) and no overflow or underflow of the products
 * (coordinate differences between about 1e-150 and 1e150). */

/* Shewchuk's bound for the relative error of the floating-point determinant
 * (3 + 16 eps) eps, eps = 2^-53: beyond it the computed sign is the true one. */
#define ORIENT_ERRBOUND ((3.0 + 16.0 * 0x1p-53) * 0x1p-53)

static int sign_of(double v) { return (v > 0) - (v < 0); }

/* a - b == *hi + *lo exactly. */
static void two_diff(double a, double b, double *hi, double *lo) {
    double x = a - b, bv = a - x, av = x + bv;
    *hi = x;
    *lo = (a - av) + (bv - b);
}

/* a + b == *hi + *lo exactly. */
static void two_sum(double a, double b, double *hi, double *lo) {
    double x = a + b, bv = x - a, av = x - bv;
    *hi = x;
    *lo = (a - av) + (b - bv);
}

/* a == *hi + *lo with each half of 26 significant bits (Veltkamp's split). */
static void split(double a, double *hi, double *lo) {
    double c = 134217729.0 * a, big = c - a; /* 2^27 + 1 */
    *hi = c - big;
    *lo = a - *hi;
}

/* a * b == *hi + *lo exactly (Dekker's product: the halves' products are exact,
 * so no fma is needed — without a hardware fma, libm's is a slow software call;
 * -std=c11 keeps the compiler from contracting these lines into one). */
static void two_prod(double a, double b, double *hi, double *lo) {
    double ah, al, bh, bl;
    *hi = a * b;
    split(a, &ah, &al);
    split(b, &bh, &bl);
    double e1 = *hi - ah * bh, e2 = e1 - al * bh, e3 = e2 - ah * bl;
    *lo = al * bl - e3;
}

/* Adds b to the expansion h[0 .. *n) (non-overlapping, increasing magnitude),
 * keeping that invariant (Shewchuk's Grow-Expansion). */
static void grow_expansion(double *h, int *n, double b) {
    double q = b;
    for (int i = 0; i < *n; i++) two_sum(q, h[i], &q, &h[i]);
    h[(*n)++] = q;
}

/* The exact sign of (a0 + a1)(b0 + b1) - (c0 + c1)(d0 + d1): sixteen exact
 * partial products summed into one expansion, whose sign is that of its most
 * significant non-zero component. */
static __attribute__((noinline)) int exact_det_sign(const double a[2], const double b[2], const double c[2], const double d[2]) {
    double h[16];
    int n = 0;
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++) { /* zero parts (exact differences, the common case) add nothing */
            double hi, lo;
            if (a[i] != 0 && b[j] != 0) {
                two_prod(a[i], b[j], &hi, &lo);
                if (lo != 0) grow_expansion(h, &n, lo);
                grow_expansion(h, &n, hi);
            }
            if (c[i] != 0 && d[j] != 0) {
                two_prod(c[i], d[j], &hi, &lo);
                if (lo != 0) grow_expansion(h, &n, -lo);
                grow_expansion(h, &n, -hi);
            }
        }
    for (int i = n - 1; i >= 0; i--)
        if (h[i] != 0) return sign_of(h[i]);
    return 0;
}

/* The exact sign of cross(e - s, p - s). The fast path evaluates exactly the
 * expression of the rule; only when its sign is not certified are the four
 * differences split into exact pairs and the determinant summed exactly. */
static inline __attribute__((always_inline)) int orient_sign(double sx, double sy, double ex, double ey, double px, double py) {
    double l = (ex - sx) * (py - sy), r = (ey - sy) * (px - sx), det = l - r, sum;
    /* Opposite-signed (or zero) products: no cancellation, the sign is exact. */
    if (l > 0) {
        if (r <= 0) return sign_of(det);
        sum = l + r;
    } else if (l < 0) {
        if (r >= 0) return sign_of(det);
        sum = -l - r;
    } else {
        return sign_of(det);
    }
    if (det >= ORIENT_ERRBOUND * sum || -det >= ORIENT_ERRBOUND * sum) return sign_of(det);
    double a[2], b[2], c[2], d[2];
    two_diff(ex, sx, &a[0], &a[1]);
    two_diff(py, sy, &b[0], &b[1]);
    two_diff(ey, sy, &c[0], &c[1]);
    two_diff(px, sx, &d[0], &d[1]);
    return exact_det_sign(a, b, c, d);
}

/* ==== The index ==============================================================
 * Triangles live in `slots`, permuted so that each leaf's triangles are
 * contiguous, each with its corners in counter-clockwise order and one bit per
 * edge saying whether its corners are already in canonical order.
 * Nodes form a flat array in depth-first order: an internal node's left child
 * is the next node, its right child is `first`. Leaves have count >= 1. */

#define LEAF_MAX 4
/* Depth bound: splits are exact medians by count, so a node at depth k holds at
 * most ceil(T / 2^k) triangles; with T < 2^31, depth 29 holds at most 4 and is a
 * leaf. The traversal keeps at most one pending sibling per level. */
#define STACK_MAX 64

struct node {
    double lo[2], hi[2]; /* box of every triangle below */
    int32_t first;       /* leaf: first slot; internal: right child */
    int32_t count;       /* leaf: slots [first, first + count); internal: 0 */
};

#define slot tc__slot /* declared in locate.h, shared with the rasterizer */

struct tc_locator {
    int32_t nnodes;
    int depth; /* of the deepest leaf, root = 0; < STACK_MAX */
    struct node *nodes;
    struct slot *slots;
    int32_t nt;
    /* The grid is a cache in front of the tree (it changes no answer), built
     * once enough points have been asked for to pay for it (locator_note).
     * Queries read it with acquire; one thread builds it and publishes it
     * with release, the others keep walking the tree meanwhile. */
    _Atomic(tc__locgrid *) grid;  /* NULL: queries walk the tree */
    atomic_int grid_done;         /* 1 once a build was started (built or refused) */
    atomic_llong queries;         /* points asked for through tc__locator_note */
    long long grid_after;         /* queries that pay for building the grid */
};

/* Queries before the grid is built; -1: the cost estimate (tests set 0). */
static long long grid_after_override = -1;

void tc__locator_grid_after(long long queries) {
    grid_after_override = queries;
}

/* ---- building ---- */

struct builder {
    const double *box;   /* [T][4] per triangle: xmin, ymin, xmax, ymax */
    const double *cen;   /* [T][2] box centres, the split keys */
    int32_t *perm;       /* slot -> triangle */
    struct node *nodes;
    int32_t nnodes, cap;
    int depth;
    uint64_t rng;        /* fixed seed: the build is deterministic */
};

/* Total order of triangles along an axis: box centre, then index. Ties by
 * index keep the median split exact however many centres coincide. */
static int key_less(const struct builder *b, int axis, int32_t i, int32_t j) {
    double ci = b->cen[2 * (size_t)i + (size_t)axis], cj = b->cen[2 * (size_t)j + (size_t)axis];
    return ci < cj || (ci == cj && i < j);
}

static uint32_t next_rand(struct builder *b) {
    b->rng ^= b->rng << 13;
    b->rng ^= b->rng >> 7;
    b->rng ^= b->rng << 17;
    return (uint32_t)(b->rng >> 32);
}

static void swap_i32(int32_t *a, int32_t *c) {
    int32_t t = *a;
    *a = *c;
    *c = t;
}

/* Reorders perm[lo, hi) so that perm[k] has rank k - lo, smaller keys before,
 * larger after (quickselect, random pivot, Lomuto partition: always ends). */
static void select_kth(struct builder *b, int axis, int32_t lo, int32_t hi, int32_t k) {
    int32_t *p = b->perm;
    while (hi - lo > 1) {
        swap_i32(&p[lo + (int32_t)(next_rand(b) % (uint32_t)(hi - lo))], &p[hi - 1]);
        int32_t pivot = p[hi - 1], store = lo;
        for (int32_t i = lo; i < hi - 1; i++)
            if (key_less(b, axis, p[i], pivot)) swap_i32(&p[i], &p[store++]);
        swap_i32(&p[store], &p[hi - 1]);
        if (k == store) return;
        if (k < store) hi = store;
        else lo = store + 1;
    }
}

/* Grows the box (lo, hi) to cover the box (alo, ahi). */
static void box_union(double lo[2], double hi[2], const double alo[2], const double ahi[2]) {
    for (int a = 0; a < 2; a++) {
        lo[a] = tc__fmin(lo[a], alo[a]);
        hi[a] = tc__fmax(hi[a], ahi[a]);
    }
}

/* The axis along which the centres of perm[lo, hi) spread most. */
static int split_axis(const struct builder *b, int32_t lo, int32_t hi) {
    double mn[2] = {INFINITY, INFINITY}, mx[2] = {-INFINITY, -INFINITY};
    for (int32_t i = lo; i < hi; i++) {
        const double *c = b->cen + 2 * (size_t)b->perm[i];
        for (int a = 0; a < 2; a++) {
            mn[a] = tc__fmin(mn[a], c[a]);
            mx[a] = tc__fmax(mx[a], c[a]);
        }
    }
    return mx[1] - mn[1] > mx[0] - mn[0];
}

/* Builds the subtree over perm[lo, hi) (non-empty) at the given depth and
 * returns its node index, or -1 if the node array is full (impossible by the
 * node-count bound, but never written past). Recursion depth is the tree's. */
static int32_t build_node(struct builder *b, int32_t lo, int32_t hi, int depth) {
    if (b->nnodes >= b->cap) return -1;
    int32_t id = b->nnodes++;
    struct node *nd = &b->nodes[id];
    if (depth > b->depth) b->depth = depth;
    if (hi - lo <= LEAF_MAX) {
        *nd = (struct node){{INFINITY, INFINITY}, {-INFINITY, -INFINITY}, lo, hi - lo};
        for (int32_t i = lo; i < hi; i++) {
            const double *bx = b->box + 4 * (size_t)b->perm[i];
            box_union(nd->lo, nd->hi, bx, bx + 2);
        }
        return id;
    }
    int32_t mid = lo + (hi - lo) / 2;
    select_kth(b, split_axis(b, lo, hi), lo, hi, mid);
    int32_t left = build_node(b, lo, mid, depth + 1); /* == id + 1: depth-first order */
    int32_t right = left < 0 ? -1 : build_node(b, mid, hi, depth + 1);
    if (right < 0) return -1;
    *nd = (struct node){{INFINITY, INFINITY}, {-INFINITY, -INFINITY}, right, 0};
    box_union(nd->lo, nd->hi, b->nodes[left].lo, b->nodes[left].hi);
    box_union(nd->lo, nd->hi, b->nodes[right].lo, b->nodes[right].hi);
    return id;
}

/* Lexicographic (x, then y) order of points: the canonical edge order. */
static int point_less(double ax, double ay, double bx, double by) {
    return ax < bx || (ax == bx && ay < by);
}

/* Fills a slot with triangle t, corners turned counter-clockwise; no across bits yet
 * (fill_across, once every slot is filled). */
static void fill_slot(struct slot *s, const struct tc_mesh *m, int32_t t) {
    const int32_t *v = m->tri + 3 * (size_t)t;
    for (int k = 0; k < 3; k++) {
        int32_t c = v[tc__slot_corner(m->orient[t] < 0, k)];
        s->x[k] = m->xy[2 * (size_t)c];
        s->y[k] = m->xy[2 * (size_t)c + 1];
    }
    s->t = t;
    s->left = s->across = 0;
    for (int k = 0; k < 3; k++) {
        int j = k == 2 ? 0 : k + 1;
        if (point_less(s->x[k], s->y[k], s->x[j], s->y[j])) s->left |= 1u << k;
    }
}

/* Coordinates whose differences and products orient_sign takes exactly, together with centres
 * of a tile's lattice (raster_cover.c's lattice_exact: multiples of 2^-500 below 2^500): 0, or
 * 2^-250 <= |v| <= 2^250 (a difference is then 0 or at least 2^-500, a product of two at least
 * 2^-1000 and below 2^1002, Dekker's parts of it normal). */
static int tame_coordinate(double v) {
    double a = fabs(v);
    return a == 0 || (a >= 0x1p-250 && a <= 0x1p250);
}

/* Whether su, the slot of the triangle across edge k (corners a -> b) of slot s, owns every
 * point strictly between a and b: su runs b -> a as a left edge with its third corner strictly
 * left of it (exact signs), so at such a point that edge's sign is 0, which su's rule admits, and
 * the other two are > 0 (the shared-edge case of the argument above), whatever m->orient says. */
static int owned_across(const struct slot *s, int k, const struct slot *su) {
    int j = k == 2 ? 0 : k + 1;
    for (int q = 0; q < 3; q++) {
        int n = q == 2 ? 0 : q + 1, w = n == 2 ? 0 : n + 1;
        if (su->x[q] != s->x[j] || su->y[q] != s->y[j] || su->x[n] != s->x[k] || su->y[n] != s->y[k]) continue;
        for (int c = 0; c < 3; c++)
            if (!tame_coordinate(su->x[c]) || !tame_coordinate(su->y[c])) return 0;
        return (su->left >> q & 1u) && orient_sign(su->x[q], su->y[q], su->x[n], su->y[n], su->x[w], su->y[w]) > 0;
    }
    return 0;
}

/* Every slot's across bits: for each edge that is not left, whether the mesh's neighbour across
 * it (topology.c's nbr, by shared vertices) owns the points strictly inside it. slot_of: scratch
 * for nt entries, triangle -> slot. */
static void fill_across(struct tc_locator *L, const struct tc_mesh *m, int32_t *slot_of) {
    for (int32_t i = 0; i < m->nt; i++) slot_of[L->slots[i].t] = i;
    for (int32_t i = 0; i < m->nt; i++) {
        struct slot *s = &L->slots[i];
        int cw = m->orient[s->t] < 0;
        for (int k = 0; k < 3; k++) {
            if (s->left >> k & 1u) continue;
            int a = tc__slot_corner(cw, k), b = tc__slot_corner(cw, k == 2 ? 0 : k + 1);
            int me = b == (a + 1) % 3 ? a : b; /* the mesh's edge e joins its corners e and e + 1 */
            int32_t u = m->nbr[3 * (size_t)s->t + (size_t)me];
            if (u >= 0 && owned_across(s, k, &L->slots[slot_of[u]])) s->across |= 1u << k;
        }
    }
}

/* Per-triangle boxes and centres (exact: min / max of the corners, so a point
 * of the closed triangle is always inside its box). Returns TC_EINVAL on a bad
 * vertex index. */
static int triangle_boxes(const struct tc_mesh *m, double *box, double *cen) {
    for (int32_t t = 0; t < m->nt; t++) {
        const int32_t *v = m->tri + 3 * (size_t)t;
        double *bx = box + 4 * (size_t)t;
        bx[0] = bx[1] = INFINITY;
        bx[2] = bx[3] = -INFINITY;
        for (int k = 0; k < 3; k++) {
            if (v[k] < 0 || v[k] >= m->nv) return TC_EINVAL;
            const double *p = m->xy + 2 * (size_t)v[k];
            box_union(bx, bx + 2, p, p);
        }
        cen[2 * (size_t)t] = 0.5 * bx[0] + 0.5 * bx[2];
        cen[2 * (size_t)t + 1] = 0.5 * bx[1] + 0.5 * bx[3];
    }
    return TC_OK;
}

/* Builds nodes and slots of L for mesh m (nt >= 1). */
static int build_index(struct tc_locator *L, const struct tc_mesh *m) {
    size_t T = (size_t)m->nt;
    double *box = malloc(T * 4 * sizeof *box), *cen = malloc(T * 2 * sizeof *cen);
    int32_t *perm = malloc(T * sizeof *perm);
    /* A split node holds > LEAF_MAX triangles, so its halves hold >= 2 each:
     * unless the root is the only node, every leaf holds >= 2 triangles, so
     * there are <= T / 2 leaves and < T nodes in all. */
    L->nodes = malloc(T * sizeof *L->nodes);
    L->slots = malloc(T * sizeof *L->slots);
    int rc = TC_ENOMEM;
    if (box && cen && perm && L->nodes && L->slots) rc = triangle_boxes(m, box, cen);
    if (rc == TC_OK) {
        for (int32_t t = 0; t < m->nt; t++) perm[t] = t;
        struct builder b = {box, cen, perm, L->nodes, 0, m->nt, 0, 0x9E3779B97F4A7C15ull};
        int32_t root = build_node(&b, 0, m->nt, 0);
        L->nnodes = b.nnodes;
        L->depth = b.depth;
        /* Unreachable by the median and node-count arguments; checked so that
         * neither the node array nor the fixed query stack is trusted blindly. */
        if (root != 0 || L->depth >= STACK_MAX) rc = TC_ELIMIT;
        /* Give back the unused tail of the node array (keep it if realloc fails). */
        struct node *fit = rc == TC_OK ? realloc(L->nodes, (size_t)b.nnodes * sizeof *fit) : NULL;
        if (fit) L->nodes = fit;
        for (int32_t i = 0; i < m->nt; i++) fill_slot(&L->slots[i], m, perm[i]);
        /* perm is done with: it becomes fill_across's triangle -> slot map (a mesh made without
         * topology, as some tests make one, has no neighbours and no across bits) */
        if (m->nbr) fill_across(L, m, perm);
    }
    tc__free(box);
    tc__free(cen);
    tc__free(perm);
    return rc;
}

/* Builds and publishes the grid unless a build was started already. */
static int build_grid(struct tc_locator *L) {
    int expected = 0;
    if (!atomic_compare_exchange_strong(&L->grid_done, &expected, 1)) return TC_OK;
    tc__locgrid *g = NULL;
    int rc = tc__locgrid_new(L->slots, L->nt, &g);
    if (g) atomic_store_explicit(&L->grid, g, memory_order_release);
    return rc;
}

int tc_locator_new(const tc_mesh *m, tc_locator **out) {
    if (!out) return TC_EINVAL;
    *out = NULL;
    if (!m || m->nt < 0 || (m->nt > 0 && (!m->xy || !m->tri || !m->orient))) return TC_EINVAL;
    if ((size_t)m->nt > SIZE_MAX / sizeof(struct slot)) return TC_ELIMIT;
    struct tc_locator *L = calloc(1, sizeof *L);
    if (!L) return TC_ENOMEM;
    if (m->nt > 0) {
        int rc = build_index(L, m);
        L->nt = m->nt;
        L->grid_after = grid_after_override >= 0 ? grid_after_override : tc__locgrid_cost(m->nt);
        if (rc == TC_OK && L->grid_after == 0) rc = build_grid(L);
        if (rc != TC_OK) {
            tc_locator_free(L);
            return rc;
        }
    }
    *out = L;
    return TC_OK;
}

void tc_locator_free(tc_locator *L) {
    if (!L) return;
    tc__free(L->nodes);
    tc__free(L->slots);
    tc__locgrid_free(atomic_load(&L->grid));
    tc__free(L);
}

/* ---- querying ---- */

/* Closed box test (a point on a face is inside); false for NaN coordinates. */
static int box_contains(const struct node *nd, double x, double y) {
    return x >= nd->lo[0] && x <= nd->hi[0] && y >= nd->lo[1] && y <= nd->hi[1];
}

enum { SLOT_OUT = TC_SLOT_OUT, SLOT_TOUCH = TC_SLOT_TOUCH, SLOT_OWN = TC_SLOT_OWN };

/* SLOT_OWN if the triangle owns P by the strict rule, SLOT_TOUCH if it only
 * contains P in the closed sense (P on an edge whose tie goes elsewhere), else
 * SLOT_OUT. An edge with the triangle on its left admits val >= 0, one with the
 * triangle on its right admits val < 0 strictly and val == 0 only closed. */
static inline __attribute__((always_inline)) int slot_test(const struct slot *s, double x, double y) {
    int touch = 0;
    for (int k = 0; k < 3; k++) {
        int j = k == 2 ? 0 : k + 1;
        if (s->left >> k & 1u) {
            if (orient_sign(s->x[k], s->y[k], s->x[j], s->y[j], x, y) < 0) return SLOT_OUT;
        } else {
            int sg = orient_sign(s->x[j], s->y[j], s->x[k], s->y[k], x, y);
            if (sg > 0) return SLOT_OUT;
            touch |= sg == 0;
        }
    }
    return touch ? SLOT_TOUCH : SLOT_OWN;
}

int tc__slot_test(const struct slot *s, double x, double y) {
    return slot_test(s, x, y);
}

/* slot_test's answer, first from the three determinants in floating point with
 * no branch per edge: an edge whose determinant clears the error bound has an
 * exact sign (the bound certifies it, as in orient_sign); one certain edge
 * with the point outside makes it OUT, three certain edges inside make it OWN
 * (certain means non-zero, so no tie is involved). Only when neither holds,
 * a point on or within rounding of an edge, is the exact test run. */
/* The filter of one edge a -> b of the slot (counter-clockwise, so its
 * inside is on the left): bit 0 when the sign of cross(b - a, P - a) is
 * certain and negative (P outside), bit 1 when it is not certain. The rule's
 * canonical frame runs a -> b for a left edge and b -> a otherwise, whose
 * determinant has the opposite exact sign; either way a certain negative sign
 * here means P is outside (left: val < 0; right: val > 0), and a certain
 * positive one means P is strictly inside that half-plane. The error bound is
 * orient_sign's, valid for this expression of any three points. */
static inline __attribute__((always_inline)) int edge_filter(double ax, double ay, double bx, double by, double x,
                                                             double y) {
    double l = (bx - ax) * (y - ay), r = (by - ay) * (x - ax), det = l - r;
    int sure = fabs(det) > ORIENT_ERRBOUND * (fabs(l) + fabs(r));
    return (sure & (det < 0)) | !sure << 1;
}

/* The three edge filters of a slot: 0 when all three are certain and inside
 * (the point is strictly inside: SLOT_OWN), bit 0 when a certain edge puts it
 * outside (SLOT_OUT), bit 1 when some edge is unsure (then only the exact
 * test can tell; bit 0 still means OUT whatever the others say). */
static inline __attribute__((always_inline)) int slot_filter(const struct slot *s, double x, double y) {
    return edge_filter(s->x[0], s->y[0], s->x[1], s->y[1], x, y) |
           edge_filter(s->x[1], s->y[1], s->x[2], s->y[2], x, y) |
           edge_filter(s->x[2], s->y[2], s->x[0], s->y[0], x, y);
}

/* Tests the leaf's triangles: returns a strict owner, or -1 after lowering
 * *closed (-1 = none yet) to the lowest index of a closed-only container. */
static int32_t leaf_test(const tc_locator *L, const struct node *leaf, double x, double y, int32_t *closed) {
    for (int32_t i = leaf->first; i < leaf->first + leaf->count; i++) {
        const struct slot *s = &L->slots[i];
        int r = slot_test(s, x, y);
        if (r == SLOT_OWN) return s->t; /* unique in a valid mesh */
        if (r == SLOT_TOUCH && (*closed < 0 || s->t < *closed)) *closed = s->t;
    }
    return -1;
}

int32_t tc__locate_tree(const tc_locator *L, double x, double y) {
    if (!L || L->nnodes == 0) return -1;
    int32_t stack[STACK_MAX];
    int sp = 0;
    int32_t n = 0, closed = -1;
    /* Depth-first: descend left, park the right child. Pending entries are one
     * per ancestor level at most, so sp <= depth < STACK_MAX. */
    for (;;) {
        const struct node *nd = &L->nodes[n];
        if (box_contains(nd, x, y)) {
            if (nd->count == 0) {
                stack[sp++] = nd->first;
                n++;
                continue;
            }
            int32_t t = leaf_test(L, nd, x, y, &closed);
            if (t >= 0) return t;
        }
        if (sp == 0) return closed;
        n = stack[--sp];
    }
}

/* The tree's answer through the grid. The tree visits leaves in slot order
 * (depth first, left first, each leaf a run of slots), and a triangle whose box
 * misses P is OUT exactly, so tc__locate_tree returns the first strict owner in
 * slot order among the triangles whose boxes hold P, else the lowest index of
 * a closed container among them, else -1 (also outside the root box, which is
 * the grid's box). P's cell lists every one of those triangles, in slot order:
 * the same scan over it gives the same answer for any mesh, valid or not. */
/* The exact scan of one block: first strict owner, else lowers *closed. */
static int32_t block_exact(const tc_locator *L, const int32_t *items, double x, double y, int32_t *closed) {
    for (int k = 0; k < TC_LOCGRID_BLOCK; k++) {
        const struct slot *s = &L->slots[items[k]];
        int r = slot_test(s, x, y);
        if (r == SLOT_OWN) return s->t;
        if (r == SLOT_TOUCH && (*closed < 0 || s->t < *closed)) *closed = s->t;
    }
    return -1;
}

/* P's cell, or SIZE_MAX outside the grid's box (NaN included): then the tree
 * would find no triangle either (the box is the root's). */
static inline __attribute__((always_inline)) size_t grid_cell(const tc__locgrid *g, double x, double y) {
    if (!(x >= g->lo[0] && x <= g->hi[0] && y >= g->lo[1] && y <= g->hi[1])) return SIZE_MAX;
    return (size_t)tc__locgrid_cell(g, 1, y) * (size_t)g->n[0] + (size_t)tc__locgrid_cell(g, 0, x);
}

/* The owner of P in cell c, whose word is w. */
static inline __attribute__((always_inline)) int32_t grid_owner(const tc_locator *L, const tc__locgrid *g, int32_t w,
                                                                double x, double y) {
    if (w < 0) return w == TC_LOCGRID_EMPTY ? -1 : -1 - w; /* none, or a cell inside one triangle */
    const int32_t *list = g->items + w + 1;
    int32_t k = list[-1], closed = -1;
    if (k > TC_LOCGRID_MAX) return tc__locate_tree(L, x, y);
    /* A block's filters run without a branch between them; only a point
     * within rounding of an edge (a filter unsure) takes the exact scan. */
    for (int32_t i = 0; i < k; i += TC_LOCGRID_BLOCK) {
        const int32_t *it = list + i;
        int f0 = slot_filter(&L->slots[it[0]], x, y), f1 = slot_filter(&L->slots[it[1]], x, y);
        if ((f0 == 2) | (f1 == 2)) { /* unsure and not OUT: the block exactly, in order */
            int32_t t = block_exact(L, it, x, y, &closed);
            if (t >= 0) return t;
            continue;
        }
        if (f0 == 0) return L->slots[it[0]].t;
        if (f1 == 0) return L->slots[it[1]].t;
    }
    return closed;
}

static inline __attribute__((always_inline)) int32_t locate_grid(const tc_locator *L, const tc__locgrid *g, double x,
                                                                 double y) {
    size_t c = grid_cell(g, x, y);
    return c == SIZE_MAX ? -1 : grid_owner(L, g, g->cell[c], x, y);
}

static const tc__locgrid *grid_of(const tc_locator *L) {
    return L ? atomic_load_explicit(&((struct tc_locator *)(uintptr_t)L)->grid, memory_order_acquire) : NULL;
}

int32_t tc_locate(const tc_locator *L, double x, double y) {
    const tc__locgrid *g = grid_of(L);
    return g ? locate_grid(L, g, x, y) : tc__locate_tree(L, x, y);
}

void tc__locator_note(const tc_locator *Lc, size_t n) {
    if (!Lc || Lc->nt == 0) return;
    /* The locator is const to its users; the grid is a cache of it, changing no
     * answer, and every locator is allocated writable (tc_locator_new). */
    struct tc_locator *L = (struct tc_locator *)(uintptr_t)Lc;
    if (atomic_load_explicit(&L->grid_done, memory_order_relaxed)) return;
    long long q = atomic_fetch_add_explicit(&L->queries, (long long)n, memory_order_relaxed) + (long long)n;
    if (q >= L->grid_after) (void)build_grid(L); /* out of memory: the tree serves */
}

void tc__locator_grid_now(const tc_locator *L) {
    if (L && L->nt > 0) (void)build_grid((struct tc_locator *)(uintptr_t)L);
}

int tc__locator_grid_cells(const tc_locator *L, int64_t *cells, int64_t *held) {
    *cells = *held = 0;
    const tc__locgrid *g = grid_of(L);
    if (!g) return 0;
    *cells = (int64_t)g->n[0] * g->n[1];
    for (int64_t c = 0; c < *cells; c++) *held += g->cell[c] < 0 && g->cell[c] != TC_LOCGRID_EMPTY;
    return 1;
}

void tc__locate_many(const tc_locator *L, size_t n, const double *xy, int32_t *tri) {
    const tc__locgrid *g = grid_of(L);
    if (!g) {
        for (size_t i = 0; i < n; i++) tri[i] = tc__locate_tree(L, xy[2 * i], xy[2 * i + 1]);
        return;
    }
    /* In groups: every cell word of a group is asked for before the first is
     * used, then every list, so the cache misses of random points overlap. */
    enum { GROUP = 16 };
    for (size_t i0 = 0; i0 < n; i0 += GROUP) {
        size_t k = n - i0 < GROUP ? n - i0 : GROUP, cell[GROUP];
        int32_t word[GROUP];
        const double *p = xy + 2 * i0;
        for (size_t j = 0; j < k; j++) {
            cell[j] = grid_cell(g, p[2 * j], p[2 * j + 1]);
            if (cell[j] != SIZE_MAX) __builtin_prefetch(&g->cell[cell[j]]);
        }
        for (size_t j = 0; j < k; j++) {
            word[j] = cell[j] == SIZE_MAX ? TC_LOCGRID_EMPTY : g->cell[cell[j]];
            if (word[j] >= 0) __builtin_prefetch(&g->items[word[j]]);
        }
        for (size_t j = 0; j < k; j++) tri[i0 + j] = grid_owner(L, g, word[j], p[2 * j], p[2 * j + 1]);
    }
}

/* Boxes meet when they overlap in both axes (closed). */
static int box_meets(const struct node *nd, const double lo[2], const double hi[2]) {
    return nd->lo[0] <= hi[0] && nd->hi[0] >= lo[0] && nd->lo[1] <= hi[1] && nd->hi[1] >= lo[1];
}

void tc__locator_query_box(const tc_locator *L, const double lo[2], const double hi[2],
                           void (*fn)(void *ctx, const struct tc__slot *s), void *ctx) {
    if (!L || L->nnodes == 0) return;
    int32_t stack[STACK_MAX];
    int sp = 0;
    int32_t n = 0;
    for (;;) { /* the same traversal as tc_locate, visiting every leaf that meets the box */
        const struct node *nd = &L->nodes[n];
        if (box_meets(nd, lo, hi)) {
            if (nd->count == 0) {
                stack[sp++] = nd->first;
                n++;
                continue;
            }
            for (int32_t i = nd->first; i < nd->first + nd->count; i++) fn(ctx, &L->slots[i]);
        }
        if (sp == 0) return;
        n = stack[--sp];
    }
}
