/* wedge.h — vertex classes and the wedges around each vertex (paper §2, Fig. 4).
 * A wedge (tc__wedge) is a maximal fan of faces at a vertex not separated by a
 * delimiter; the public tc_wedges is the option choosing the rule for its plane. */
#ifndef TC_CORE_WEDGE_H
#define TC_CORE_WEDGE_H

#include "core/mesh.h"

enum { TC_SIDE_A = 0, TC_SIDE_B = 1 };

/* Invariants: the corners of a wedge are contiguous in tc__wedge_set.corners and
 * ordered counter-clockwise from side A to side B; a wedge at a C1 vertex is a
 * full turn with no sides (side_edge = -1); a side of kind TC_C0 always has a
 * different wedge `across` it, whose side across it is across to this one;
 * of_corner[c] is the wedge whose corners hold c, and every corner is in one
 * wedge, of its own vertex. tc__wedges_check (invariants.c) checks these;
 * tc__wedges_build asserts it (TC_DEBUG). */
typedef struct {
    int32_t v;            /* the vertex */
    int32_t first, count; /* corners[first .. first + count) */
    int32_t side_edge[2]; /* bounding edge as an edge id 3t+k (t inside the wedge), or -1 */
    int8_t side_kind[2];  /* TC_C0, or TC_CM1 for C-1 and boundary edges */
    int32_t across[2];    /* the wedge across a TC_C0 side, else -1 */
    double dir[2][2];     /* from v along each bounding edge to its other end */
    uint8_t collinear;    /* two distinct sides at 180 degrees (paper's Collinear(W)) */
} tc__wedge;

typedef struct {
    int32_t nw;
    tc__wedge *w;
    int32_t *corners;    /* [3nt] corner ids grouped by wedge */
    int32_t *of_corner;  /* [3nt] wedge of each corner */
    int8_t *vclass;      /* [nv] TC_C1, TC_C0 or TC_CM1 */
    int honor_flags;     /* TC_HONOR_*: which interior flags delimit wedges */
    int32_t ncoupled;    /* wedges with a C0 side: work for WedgeNormal steps 3-4 */
    int threads;         /* threads of the steps that read this set (tc_options.threads); no
                          * effect on any result */
    double deadline_ms;  /* tc_options.deadline_ms, for the long loops of those steps (0: none;
                          * set by the build after tc__wedges_build_on, which leaves it 0) */
} tc__wedge_set;

/* Which interior flags a reconstruction honours (tc__wedges_build's
 * honor_flags; 0 and 1 are also plain booleans). The boundary always delimits. */
enum {
    TC_HONOR_NONE = 0, /* every interior edge is C1 (clough-tocher-c1) */
    TC_HONOR_ALL = 1,  /* C0 and C-1 as flagged (clough-tocher) */
    TC_HONOR_CM1 = 2   /* C-1 only, C0 read as C1: for a scheme that cannot keep a kink (powell-sabin) */
};

/* The continuity of edge id e as the reconstruction sees it. */
static inline int tc__eff_flag(const struct tc_mesh *m, int honor_flags, int32_t e) {
    TC_ASSERT(e >= 0 && e < 3 * m->nt);
    TC_ASSERT(honor_flags == TC_HONOR_NONE || honor_flags == TC_HONOR_ALL || honor_flags == TC_HONOR_CM1);
    int f = m->flag[e];
    if (honor_flags == TC_HONOR_ALL || m->nbr[e] < 0) return f;
    return honor_flags == TC_HONOR_CM1 && f == TC_CM1 ? TC_CM1 : TC_C1;
}

int tc__wedges_build(const struct tc_mesh *m, int honor_flags, tc__wedge_set *ws);
/* The same on up to `threads` threads (kept in ws->threads for the steps after);
 * the set is the serial one. */
int tc__wedges_build_on(const struct tc_mesh *m, int honor_flags, int threads, tc__wedge_set *ws);
/* The first wedge at a vertex >= v (the wedges are in vertex order; nw if none):
 * the wedges of vertices [a, b) are [tc__first_wedge_at(a), tc__first_wedge_at(b)). */
int32_t tc__first_wedge_at(const tc__wedge_set *ws, int32_t v);
void tc__wedges_free(tc__wedge_set *ws);

/* invariants.c: 0 when ws, built on m, keeps the invariants above (and the
 * corners of a wedge are the faces of one fan, consecutive ones across an edge
 * that does not delimit it), else nonzero with the first one found broken
 * written to why[n] (why may be NULL). O(nt + nv). */
int tc__wedges_check(const struct tc_mesh *m, const tc__wedge_set *ws, char *why, size_t n);

#endif
