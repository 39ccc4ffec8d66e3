/* dm_graph.h — the planar straight-line graph behind the discontinuity mesher:
 * segments split at every crossing and touch, reflex corners removed, edges subdivided. */
#ifndef TC_SCENES_DM_GRAPH_H
#define TC_SCENES_DM_GRAPH_H

#include <stdint.h>

/* Points closer than this are one vertex (the receiver is about 1 wide; the
 * stiff scene's narrowest strips are 3e-5). */
#define TC__DM_TOL 1e-12

/* An input segment: a side of the receiver, or an event (a discontinuity). */
typedef struct {
    double a[2], b[2];
    int8_t flag;  /* TC_C1 for sides, the event's kind (TC_C0, TC_CM1) otherwise */
    int8_t side;  /* 1: a side of the receiver */
} tc__dm_seg;

/* An edge of the graph. Invariants: a != b; no two edges join the same two
 * vertices; an edge lies on segment seg (-1: a ray added by tc__dm_unreflex). */
typedef struct {
    int32_t a, b;
    int32_t seg;
    int8_t flag;  /* TC_C1, TC_C0 or TC_CM1 (a jump outranks a kink where segments overlap) */
    int8_t side;  /* on the receiver's boundary */
} tc__dm_edge;

typedef struct {
    double *xy; /* [nv][2] */
    int32_t nv, cap_v;
    tc__dm_edge *e;
    int32_t ne, cap_e;
    int oom; /* sticky: every later append is a no-op */
} tc__dm_graph;

/* The arrangement of n segments: every end, crossing and touch (T-junction) a
 * vertex, every segment split into edges between consecutive vertices on it.
 * Where collinear segments overlap, the shared edges take the strongest flag
 * (a jump outranks a kink). TC_OK or TC_ENOMEM. */
int tc__dm_arrange(tc__dm_graph *g, const tc__dm_seg *segs, int n);

/* Removes every reflex corner (a gap wider than 180 degrees between two
 * consecutive edges at a vertex off the receiver's boundary: a segment's free
 * end, a hole's corner) by prolonging one of its edges to the first edge it
 * meets — locally, as a BSP-based mesher does, never across the receiver. The
 * faces are then convex and simply connected. TC_OK or TC_ENOMEM. */
int tc__dm_unreflex(tc__dm_graph *g);

/* Splits every receiver side and prolongation longer than max_len into equal
 * pieces (both faces of an edge get the same new vertices, so the mesh stays
 * conforming). Event edges stay whole, as a discontinuity mesher leaves them:
 * a thin penumbra strip remains one face between its two lines, fanned into
 * long triangles, not a stack of small cells. */
int tc__dm_subdivide(tc__dm_graph *g, double max_len);

void tc__dm_graph_free(tc__dm_graph *g);

#endif
