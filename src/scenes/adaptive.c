/* adaptive.c — the a posteriori mesher: a quadtree over an N x N start grid,
 * split on the spread of B at cell corners, 2:1 balanced, fan-triangulated. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scenes/build.h"

/* Positions are integers in "half units": a level-D cell (the finest) is 2 half
 * units wide, so cell corners are even and cell centres of the finest level
 * odd. A node at level L is S = 2^(D-L) finest units = 2S half units wide. */
typedef struct {
    int32_t x, y;  /* lower-left corner, finest units */
    int32_t child; /* first of 4 children (ll, lr, ul, ur), -1 for a leaf */
    int8_t level;
} node;

/* Values and vertex ids by position: open addressing, linear probing, at most
 * half full. key = hx * (2R + 1) + hy, -1 empty. */
typedef struct {
    int64_t *key;
    double *val;
    int32_t *vid;
    size_t cap, count;
} vmap;

typedef struct {
    const tc_scene *s;
    int N, D;
    int64_t R; /* finest units per axis */
    node *nodes;
    int32_t n, cap;
    vmap map;
    int64_t evals;
    double limit; /* split while the corner spread exceeds this */
    int status;   /* first error (TC_ENOMEM, TC_ELIMIT), sticky */
} qtree;

static int32_t size_of(const qtree *q, int level) { return (int32_t)1 << (q->D - level); }

/* ---- the value map ---------------------------------------------------------------- */

static size_t slot_of(const vmap *m, int64_t key) {
    uint64_t h = (uint64_t)key * 0x9E3779B97F4A7C15ull;
    size_t i = (size_t)(h >> 17) & (m->cap - 1);
    while (m->key[i] != -1 && m->key[i] != key) i = (i + 1) & (m->cap - 1);
    return i;
}

static int vmap_grow(vmap *m) {
    vmap g = {0};
    g.cap = m->cap ? 2 * m->cap : 1024;
    g.key = malloc(g.cap * sizeof *g.key);
    g.val = malloc(g.cap * sizeof *g.val);
    g.vid = malloc(g.cap * sizeof *g.vid);
    if (!g.key || !g.val || !g.vid) {
        free(g.key), free(g.val), free(g.vid);
        return -1;
    }
    memset(g.key, 0xff, g.cap * sizeof *g.key); /* all -1 */
    for (size_t i = 0; i < m->cap; i++) {
        if (m->key[i] == -1) continue;
        size_t j = slot_of(&g, m->key[i]);
        g.key[j] = m->key[i], g.val[j] = m->val[i], g.vid[j] = m->vid[i];
    }
    g.count = m->count;
    free(m->key), free(m->val), free(m->vid);
    *m = g;
    return 0;
}

static void world(const qtree *q, int64_t hx, int64_t hy, double *x, double *y) {
    const double *d = q->s->domain;
    double span = (double)(2 * q->R);
    *x = d[0] + (d[2] - d[0]) * ((double)hx / span);
    *y = d[1] + (d[3] - d[1]) * ((double)hy / span);
}

/* The map slot of position (hx, hy), evaluating B there on first use; SIZE_MAX on error. */
static size_t entry(qtree *q, int64_t hx, int64_t hy) {
    vmap *m = &q->map;
    if (2 * (m->count + 1) > m->cap && vmap_grow(m)) {
        q->status = TC_ENOMEM;
        return (size_t)-1;
    }
    int64_t key = hx * (2 * q->R + 1) + hy;
    size_t i = slot_of(m, key);
    if (m->key[i] == -1) {
        double x, y;
        world(q, hx, hy, &x, &y);
        m->key[i] = key, m->val[i] = tc_scene_value(q->s, x, y), m->vid[i] = -1;
        m->count++, q->evals++;
    }
    return i;
}

/* ---- the tree ------------------------------------------------------------------------ */

static int32_t add_node(qtree *q, int32_t x, int32_t y, int level) {
    if (q->n == q->cap) {
        int32_t cap = q->cap ? 2 * q->cap : 256;
        node *p = cap > 0 ? realloc(q->nodes, (size_t)cap * sizeof *p) : NULL;
        if (!p) {
            q->status = TC_ENOMEM;
            return -1;
        }
        q->nodes = p, q->cap = cap;
    }
    q->nodes[q->n] = (node){x, y, -1, (int8_t)level};
    return q->n++;
}

/* Splits leaf i into four. Leaves stay within budget: each becomes <= 8 triangles. */
static void split(qtree *q, int32_t i) {
    if (q->n + 4 > TC__SCENE_MAX_TRIS / 8) {
        q->status = TC_ELIMIT;
        return;
    }
    node c = q->nodes[i];
    int32_t h = size_of(q, c.level) / 2, first = q->n;
    for (int k = 0; k < 4 && q->status == TC_OK; k++) add_node(q, c.x + (k & 1) * h, c.y + (k >> 1) * h, c.level + 1);
    if (q->status == TC_OK) q->nodes[i].child = first;
}

/* The leaf containing half-unit position (hx, hy) (odd in at least the coordinate
 * across a side, so never on that side), or -1 outside the domain. */
static int32_t locate(const qtree *q, int64_t hx, int64_t hy) {
    int64_t root = 2 * (int64_t)size_of(q, 0);
    if (hx < 0 || hy < 0 || hx >= 2 * q->R || hy >= 2 * q->R) return -1;
    int32_t i = (int32_t)((hy / root) * q->N + hx / root);
    while (q->nodes[i].child >= 0) {
        const node *c = &q->nodes[i];
        int64_t s = size_of(q, c->level); /* half the node's width in half units */
        i = c->child + (hx >= 2 * (int64_t)c->x + s) + 2 * (hy >= 2 * (int64_t)c->y + s);
    }
    return i;
}

/* The half-unit point just outside side k (0 bottom, 1 right, 2 top, 3 left) of
 * node c at offset t (half units) along the side, counter-clockwise. */
static void outside(const qtree *q, const node *c, int k, int64_t t, int64_t *hx, int64_t *hy) {
    int64_t x0 = 2 * (int64_t)c->x, y0 = 2 * (int64_t)c->y, w = 2 * (int64_t)size_of(q, c->level);
    switch (k) {
    case 0: *hx = x0 + t, *hy = y0 - 1; break;
    case 1: *hx = x0 + w + 1, *hy = y0 + t; break;
    case 2: *hx = x0 + w - t, *hy = y0 + w + 1; break;
    default: *hx = x0 - 1, *hy = y0 + w - t; break;
    }
}

static int level_at(const qtree *q, int64_t hx, int64_t hy) {
    int32_t i = locate(q, hx, hy);
    return i < 0 ? -1 : q->nodes[i].level;
}

/* A leaf is unbalanced when a leaf two or more levels deeper touches it: such
 * a leaf fills or lies inside one of the four quarter-cells along a side, so
 * probing the quarter midpoints finds it. */
static int unbalanced(const qtree *q, int32_t i) {
    const node *c = &q->nodes[i];
    int64_t s = size_of(q, c->level);
    if (s < 4) return 0;
    for (int k = 0; k < 4; k++)
        for (int j = 0; j < 4; j++) {
            int64_t hx, hy;
            outside(q, c, k, (2 * j + 1) * s / 4, &hx, &hy);
            if (level_at(q, hx, hy) > c->level + 1) return 1;
        }
    return 0;
}

static double spread(qtree *q, const node *c) {
    int64_t x = 2 * (int64_t)c->x, y = 2 * (int64_t)c->y, w = 2 * (int64_t)size_of(q, c->level);
    double lo = INFINITY, hi = -INFINITY;
    for (int k = 0; k < 4 && q->status == TC_OK; k++) {
        size_t e = entry(q, x + (k & 1) * w, y + (k >> 1) * w);
        if (e == (size_t)-1) break;
        lo = fmin(lo, q->map.val[e]), hi = fmax(hi, q->map.val[e]);
    }
    return hi - lo;
}

/* Splits cells breadth-first while their corner spread is too large, then
 * splits leaves until the tree is 2:1 balanced across edges. */
static void refine(qtree *q) {
    for (int32_t j = 0; j < q->N && q->status == TC_OK; j++)
        for (int32_t i = 0; i < q->N && q->status == TC_OK; i++) add_node(q, i * size_of(q, 0), j * size_of(q, 0), 0);
    for (int32_t i = 0; i < q->n && q->status == TC_OK; i++)
        if (q->nodes[i].level < q->D && spread(q, &q->nodes[i]) > q->limit) split(q, i);
    for (int changed = 1; changed && q->status == TC_OK;) {
        changed = 0;
        for (int32_t i = 0; i < q->n && q->status == TC_OK; i++)
            if (q->nodes[i].child < 0 && unbalanced(q, i)) split(q, i), changed = 1;
    }
}

/* ---- output ------------------------------------------------------------------------ */

static int32_t vertex(qtree *q, tc__mbuild *b, int64_t hx, int64_t hy) {
    size_t e = entry(q, hx, hy);
    if (e == (size_t)-1) return -1;
    if (q->map.vid[e] < 0) {
        double x, y;
        world(q, hx, hy, &x, &y);
        q->map.vid[e] = tc__mb_vertex(b, x, y);
    }
    return q->map.vid[e];
}

/* A leaf as a fan from its centre over its corners and the midpoints of the
 * sides a finer neighbour splits (at most one per side when balanced). */
static void emit_leaf(qtree *q, tc__mbuild *b, const node *c) {
    int64_t s = size_of(q, c->level), x0 = 2 * (int64_t)c->x, y0 = 2 * (int64_t)c->y, w = 2 * s;
    const int64_t corner[4][2] = {{x0, y0}, {x0 + w, y0}, {x0 + w, y0 + w}, {x0, y0 + w}};
    int32_t ring[8], n = 0;
    for (int k = 0; k < 4; k++) {
        ring[n++] = vertex(q, b, corner[k][0], corner[k][1]);
        int64_t hx, hy;
        outside(q, c, k, s / 2, &hx, &hy);
        if (s >= 2 && level_at(q, hx, hy) > c->level) {
            int64_t mx = (corner[k][0] + corner[(k + 1) % 4][0]) / 2, my = (corner[k][1] + corner[(k + 1) % 4][1]) / 2;
            ring[n++] = vertex(q, b, mx, my);
        }
    }
    int32_t centre = vertex(q, b, x0 + s, y0 + s);
    for (int k = 0; k < n; k++) tc__mb_triangle(b, centre, ring[k], ring[(k + 1) % n]);
}

static void emit(qtree *q, tc__mbuild *b) {
    for (int32_t i = 0; i < q->n && q->status == TC_OK && !b->oom; i++)
        if (q->nodes[i].child < 0) emit_leaf(q, b, &q->nodes[i]);
    if (q->status != TC_OK || b->oom) return;
    b->values = malloc((size_t)(b->nv ? b->nv : 1) * sizeof *b->values);
    if (!b->values) {
        q->status = TC_ENOMEM;
        return;
    }
    for (size_t i = 0; i < q->map.cap; i++)
        if (q->map.key[i] != -1 && q->map.vid[i] >= 0) b->values[q->map.vid[i]] = q->map.val[i];
    b->value_evals = q->evals;
}

int tc__scene_adaptive(const tc_scene *s, const tc_scene_mesh_opts *o, tc__mbuild *b) {
    qtree q = {0};
    q.s = s, q.N = o->density, q.D = o->max_depth;
    q.R = (int64_t)o->density << o->max_depth;
    q.limit = o->threshold * s->scale;
    q.status = TC_OK;
    if ((int64_t)q.N * q.N * 8 > TC__SCENE_MAX_TRIS) q.status = TC_ELIMIT;
    if (q.status == TC_OK) refine(&q);
    if (q.status == TC_OK) emit(&q, b);
    int rc = q.status != TC_OK ? q.status : b->oom ? TC_ENOMEM : TC_OK;
    free(q.nodes), free(q.map.key), free(q.map.val), free(q.map.vid);
    return rc;
}
