/* mesh.h — the core's internal view of a validated mesh (struct tc_mesh).
 * Shared by the core modules; not part of the public API. */
#ifndef TC_CORE_MESH_H
#define TC_CORE_MESH_H

#include "core/assert.h"
#include "tocher.h"

/* Corner (t, k) has id 3t+k. Edge k of triangle t joins corners k and (k+1)%3.
 * A quad mesh (nq > 0) is held as its split triangles: quad q = (a, b, c, d)
 * is triangle 2q = (a, b, c) and 2q+1 = (a, c, d), so its diagonal a-c is edge 2
 * of 2q and edge 0 of 2q+1, and both triangles start at a.
 * Triangles dropped as degenerate are not in tri[]: the others keep their
 * order, and given[]/kept[] map their indices to the request's and back.
 * Invariants once tc_mesh_new returns TC_OK:
 *  - nt >= 1; ngiven >= nt, and given == kept == NULL when ngiven == nt;
 *  - nq > 0: nt == 2 nq, ngiven == nt, every quad strictly convex with distinct corners, and
 *    no quad repeated; the diagonals are interior C1 edges, never flagged;
 *  - every triangle has non-zero area (relative to its edge lengths), distinct
 *    vertices, and appears once;
 *  - every edge has at most two triangles; nbr/nbr_k are mutual
 *    (nbr[nbr[3t+k]*3 + nbr_k[3t+k]] == t);
 *  - flag[] is TC_CM1 on boundary edges and equal on both sides of an edge;
 *  - across a TC_C0 / TC_C1 edge the corner values at both ends agree;
 *  - all numbers are finite.
 * tc__mesh_check (invariants.c) checks these; tc_mesh_new asserts it (TC_DEBUG). */
struct tc_mesh {
    int32_t nv, nt;
    int nc;
    double *xy;         /* [nv][2] */
    int32_t *tri;       /* [nt][3] as given */
    int8_t *orient;     /* [nt] +1 counter-clockwise, -1 clockwise */
    double *cz;         /* [nt][3][nc] corner values */
    double cz_lo[TC_MAX_CHANNELS], cz_hi[TC_MAX_CHANNELS], cz_big[TC_MAX_CHANNELS]; /* per channel the
                         * smallest, largest and largest |.| of cz: tc__channel_range's, kept once */
    int cz_range_kept;  /* 1 once those are set (tc_mesh_new, after the samples) */
    int32_t ngiven;     /* triangles as given: nt plus those dropped as degenerate */
    int32_t *given;     /* [nt] the given index of each triangle, or NULL (none dropped) */
    int32_t *kept;      /* [ngiven] the triangle of each given index or -1, or NULL */
    int32_t nq;         /* quads as given, or 0 for a mesh given as triangles */
    int32_t *quad;      /* [nq][4] as given, or NULL */

    double *given_grad; /* [nt][3][nc][2] tangent gradients the request gave, or NULL */
    uint8_t *given_grad_has; /* [3nt] 1 where given_grad holds one, or NULL */
    double *mid;        /* [nt][3][nc] midpoint sample of edge k, or NULL */
    uint8_t *mid_has;   /* [3nt] 1 where mid holds a sample, or NULL */
    double *hess;       /* [nv][nc][3] given second derivatives (fxx, fxy, fyy), or NULL */
    uint8_t *hess_has;  /* [nv] 1 where hess holds one, or NULL */

    int32_t *nbr;       /* [3nt] triangle across edge k, -1 on the boundary */
    int8_t *nbr_k;      /* [3nt] that triangle's index of the same edge */
    int8_t *flag;       /* [3nt] tc_continuity of edge k */
    int32_t *vstart;    /* [nv+1] CSR: corners of vertex v are */
    int32_t *vcorner;   /*   vcorner[vstart[v] .. vstart[v+1]) */
    int32_t max_valence; /* the most corners any vertex has (topology.c) */
    int32_t nflagged;   /* interior edges flagged C0 or C-1 */
    int32_t ncorner_overrides; /* corners whose value differs from the vertex value */
    int threads;        /* threads the build's steps may use (tc_mesh_desc); no effect on any result */
    int32_t *dstart;    /* while tc_mesh_new runs, if triangles were dropped: CSR [nv+1] of */
    int32_t *dtri;      /*   the dropped triangles (given index, increasing) at each vertex; else NULL */
};

/* Quad corner k (0..3) lands on corner (k == 3 ? 2 : k) of triangle 2q, and
 * corners 0 and 2 also on corners 0 and 1 of triangle 2q+1. Returns how many
 * corner ids went to out (1 or 2). */
static inline int tc__quad_corners(int32_t q, int k, int32_t out[2]) {
    TC_ASSERT(q >= 0 && k >= 0 && k < 4 && out);
    int32_t t0 = 3 * (2 * q), t1 = 3 * (2 * q + 1);
    static const int8_t first[4] = {0, 1, 2, -1}, second[4] = {0, -1, 1, 2};
    int n = 0;
    if (first[k] >= 0) out[n++] = t0 + first[k];
    if (second[k] >= 0) out[n++] = t1 + second[k];
    return n;
}

/* The inverse: the quad corner (0..3) that corner k of split triangle t is. */
static inline int tc__quad_corner_of(int32_t t, int k) {
    TC_ASSERT(t >= 0 && k >= 0 && k < 3);
    static const int8_t of_second[3] = {0, 2, 3};
    return t % 2 == 0 ? k : of_second[k];
}

/* The request's index of triangle t, and the triangle of given index i (-1: dropped). */
static inline int32_t tc__given(const struct tc_mesh *m, int32_t t) {
    TC_ASSERT(t >= 0 && t < m->nt);
    return m->given ? m->given[t] : t;
}
static inline int32_t tc__kept(const struct tc_mesh *m, int32_t i) {
    TC_ASSERT(i >= 0 && i < m->ngiven);
    return m->kept ? m->kept[i] : i;
}

static inline const double *tc__vxy(const struct tc_mesh *m, int32_t v) {
    TC_ASSERT(v >= 0 && v < m->nv);
    return m->xy + 2 * (size_t)v;
}
static inline int32_t tc__cv(const struct tc_mesh *m, int32_t corner) {
    TC_ASSERT(corner >= 0 && corner < 3 * m->nt);
    return m->tri[corner];
}

/* ---- queries on the mesh (topology.c, quads.c) ---- */

/* The corner of triangle t at vertex v, or -1. */
static inline int tc__corner_of(const struct tc_mesh *m, int32_t t, int32_t v) {
    TC_ASSERT(t >= 0 && t < m->nt);
    const int32_t *tv = m->tri + 3 * (size_t)t;
    return tv[0] == v ? 0 : tv[1] == v ? 1 : tv[2] == v ? 2 : -1;
}
/* The corner id 3t+k whose edge k joins vertices a and b (either direction),
 * or -1 if (a, b) is not a mesh edge. Prefers the lowest triangle index. */
int32_t tc__find_edge(const struct tc_mesh *m, int32_t a, int32_t b);

/* The request element a triangle came from, for messages: its JSON path
 * ("triangles[i]" with i its given index, or "quads[q]" for a split triangle
 * of quad q), its word ("triangle", "quad") and index (i, or q). Every error
 * about a triangle names it through these, so the errors name what the caller
 * sent, whatever was split or dropped. */
void tc__elem_path(const struct tc_mesh *m, int32_t t, char *buf, size_t n);
const char *tc__elem_word(const struct tc_mesh *m);
static inline int32_t tc__elem_index(const struct tc_mesh *m, int32_t t) {
    TC_ASSERT(t >= 0 && t < m->nt);
    return m->nq ? t / 2 : tc__given(m, t);
}
/* Corner k of triangle t as a corner of its element (k, or the quad corner). */
static inline int tc__elem_corner(const struct tc_mesh *m, int32_t t, int k) {
    return m->nq ? tc__quad_corner_of(t, k) : k;
}
/* Edge id e (3t+k) is the diagonal a-c of a split quad. */
static inline int tc__is_diagonal(const struct tc_mesh *m, int32_t e) {
    TC_ASSERT(e >= 0 && e < 3 * m->nt);
    int32_t t = e / 3, k = e % 3;
    return m->nq > 0 && k == (t % 2 == 0 ? 2 : 0);
}

/* invariants.c: 0 when the invariants above hold for m, else nonzero with the
 * first one found broken written to why[n] (why may be NULL). O(nt + nv). */
int tc__mesh_check(const struct tc_mesh *m, char *why, size_t n);

#endif
