/* mesh.h — the core's internal view of a validated mesh (struct tc_mesh).
 * Shared by the core modules; not part of the public API. */
#ifndef TC_CORE_MESH_H
#define TC_CORE_MESH_H

#include "tocher.h"

/* Corner (t, k) has id 3t+k. Edge k of triangle t joins corners k and (k+1)%3.
 * Invariants once tc_mesh_new returns TC_OK:
 *  - every triangle has non-zero area (relative to its edge lengths), distinct
 *    vertices, and appears once;
 *  - every edge has at most two triangles; nbr/nbr_k are mutual
 *    (nbr[nbr[3t+k]*3 + nbr_k[3t+k]] == t);
 *  - flag[] is TC_CM1 on boundary edges and equal on both sides of an edge;
 *  - across a TC_C0 / TC_C1 edge the corner values at both ends agree;
 *  - all numbers are finite. */
struct tc_mesh {
    int32_t nv, nt;
    int nc;
    double *xy;         /* [nv][2] */
    int32_t *tri;       /* [nt][3] as given */
    int8_t *orient;     /* [nt] +1 counter-clockwise, -1 clockwise */
    double *cz;         /* [nt][3][nc] corner values */

    double *cg;         /* [nt][3][nc][2] given tangent gradients, or NULL */
    uint8_t *cg_has;    /* [3nt] 1 where cg holds a given gradient, or NULL */
    double *mid;        /* [nt][3][nc] midpoint sample of edge k, or NULL */
    uint8_t *mid_has;   /* [3nt] 1 where mid holds a sample, or NULL */

    int32_t *nbr;       /* [3nt] triangle across edge k, -1 on the boundary */
    int8_t *nbr_k;      /* [3nt] that triangle's index of the same edge */
    int8_t *flag;       /* [3nt] tc_continuity of edge k */
    int32_t *vstart;    /* [nv+1] CSR: corners of vertex v are */
    int32_t *vcorner;   /*   vcorner[vstart[v] .. vstart[v+1]) */
    int32_t nflagged;   /* interior edges flagged C0 or C-1 */
    int32_t ncorner_overrides; /* corners whose value differs from the vertex value */
};

static inline const double *tc__vxy(const struct tc_mesh *m, int32_t v) { return m->xy + 2 * (size_t)v; }
static inline int32_t tc__cv(const struct tc_mesh *m, int32_t corner) { return m->tri[corner]; }

#endif
