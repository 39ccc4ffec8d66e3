/* internal.h — functions the core modules share but the public API hides.
 * Names carry the tc__ prefix; none of this is stable outside src/core. */
#ifndef TC_CORE_INTERNAL_H
#define TC_CORE_INTERNAL_H

#include <stdlib.h>

#include "core/mesh.h"

/* Overflow-checked allocation of n elements of size sz (NULL on overflow). */
static inline void *tc__calloc(size_t n, size_t sz) {
    return n ? calloc(n, sz) : calloc(1, 1);
}
static inline void *tc__malloc(size_t n, size_t sz) {
    if (sz && n > (size_t)-1 / sz) return NULL;
    size_t bytes = n * sz;
    return malloc(bytes ? bytes : 1);
}

/* ---- topology.c ---- */
/* Vertex -> corner lists, edge adjacency, non-manifold / repeat / fold checks. */
int tc__topology_build(struct tc_mesh *m, tc_diags *d);
/* The corner id 3t+k whose edge k joins vertices a and b (either direction),
 * or -1 if (a, b) is not a mesh edge. Prefers the lowest triangle index. */
int32_t tc__find_edge(const struct tc_mesh *m, int32_t a, int32_t b);
/* Flags the edges of the c0 and c-1 polylines of the description. */
int tc__flags_apply(struct tc_mesh *m, const tc_mesh_desc *desc, tc_diags *d);
/* The corner of triangle t at vertex v, or -1. */
static inline int tc__corner_of(const struct tc_mesh *m, int32_t t, int32_t v) {
    const int32_t *tv = m->tri + 3 * (size_t)t;
    return tv[0] == v ? 0 : tv[1] == v ? 1 : tv[2] == v ? 2 : -1;
}

/* ---- quads.c ---- */
/* Checks the description's quads (indices, distinct corners, strict
 * convexity, repeats; errors at "quads[q]") and splits them into m->tri. */
int tc__quads_split(struct tc_mesh *m, const tc_mesh_desc *desc, tc_diags *d);
/* The request element a triangle came from, for messages: its JSON path
 * ("triangles[i]" with i its given index, or "quads[q]" for a split triangle
 * of quad q), its word ("triangle", "quad") and index (i, or q). Every error
 * about a triangle names it through these, so the errors name what the caller
 * sent, whatever was split or dropped. */
void tc__elem_path(const struct tc_mesh *m, int32_t t, char *buf, size_t n);
const char *tc__elem_word(const struct tc_mesh *m);
static inline int32_t tc__elem_index(const struct tc_mesh *m, int32_t t) { return m->nq ? t / 2 : tc__given(m, t); }
/* Corner k of triangle t as a corner of its element (k, or the quad corner). */
static inline int tc__elem_corner(const struct tc_mesh *m, int32_t t, int k) {
    return m->nq ? tc__quad_corner_of(t, k) : k;
}
/* Edge id e (3t+k) is the diagonal a-c of a split quad. */
static inline int tc__is_diagonal(const struct tc_mesh *m, int32_t e) {
    int32_t t = e / 3, k = e % 3;
    return m->nq > 0 && k == (t % 2 == 0 ? 2 : 0);
}

/* ---- mesh.c ---- */
/* A triangle dropped as degenerate that has the edge [a, b] (its given
 * index), or -1: what is said about such an edge is ignored with a warning. */
int32_t tc__dropped_with_edge(const struct tc_mesh *m, const tc_mesh_desc *d, int32_t a, int32_t b);

/* ---- samples.c ---- */
/* Corner values, given tangent planes and midpoint samples. */
int tc__samples_build(struct tc_mesh *m, const tc_mesh_desc *desc, tc_diags *d);

/* ---- agree.c ---- */
/* Corner values joined across C0/C1 edges at a vertex must agree within
 * `tolerance` (value_tolerance, at least 1e-12) of their channel's scale;
 * within it they are replaced by their mean (a warning counts them), beyond
 * it the error names the edge and the entry (cv_src[3nt]: corner_values entry
 * per corner, -1 where none, or NULL). Midpoint samples of both sides of a
 * C0/C1 edge within the tolerance are averaged too (mid_src[3nt]: midpoints
 * entry per edge side, for the warning's path); larger differences stay. */
int tc__values_agree(struct tc_mesh *m, double tolerance, const int32_t *cv_src, const int32_t *mid_src,
                     tc_diags *dg);

#endif
