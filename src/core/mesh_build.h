/* mesh_build.h — the steps of tc_mesh_new (mesh.c) in their own modules: quads split,
 * topology and flags, samples, agreement of values. Only mesh.c and the steps use it. */
#ifndef TC_CORE_MESH_BUILD_H
#define TC_CORE_MESH_BUILD_H

#include "core/mesh.h"

/* quads.c: checks the description's quads (indices, distinct corners, strict
 * convexity, repeats; errors at "quads[q]") and splits them into m->tri. */
int tc__quads_split(struct tc_mesh *m, const tc_mesh_desc *desc, tc_diags *d);

/* topology.c: vertex -> corner lists, edge adjacency, non-manifold / repeat /
 * fold checks; then the edges of the c0 and c-1 polylines of the description flagged. */
int tc__topology_build(struct tc_mesh *m, tc_diags *d);
int tc__flags_apply(struct tc_mesh *m, const tc_mesh_desc *desc, tc_diags *d);

/* mesh.c: a triangle dropped as degenerate that has the edge [a, b] (its given
 * index), or -1: what is said about such an edge is ignored with a warning. */
int32_t tc__dropped_with_edge(const struct tc_mesh *m, const tc_mesh_desc *d, int32_t a, int32_t b);

/* samples.c: corner values, given tangent planes and midpoint samples. */
/* 1 if x[0 .. n) are all finite, checked in parts on `threads` threads (the
 * findings, if not, are made by the caller's serial loop, in order). */
int tc__all_finite_on(int threads, const double *x, size_t n);

int tc__samples_build(struct tc_mesh *m, const tc_mesh_desc *desc, tc_diags *d);

/* agree.c: corner values joined across C0/C1 edges at a vertex must agree within
 * `tolerance` (value_tolerance, at least 1e-12) of their channel's scale;
 * within it they are replaced by their mean (a warning counts them), beyond
 * it the error names the edge and the entry (cv_src[3nt]: corner_values entry
 * per corner, -1 where none, or NULL). Midpoint samples of both sides of a
 * C0/C1 edge within the tolerance are averaged too (mid_src[3nt]: midpoints
 * entry per edge side, for the warning's path); larger differences stay. */
int tc__values_agree(struct tc_mesh *m, double tolerance, const int32_t *cv_src, const int32_t *mid_src,
                     tc_diags *dg);

#endif
