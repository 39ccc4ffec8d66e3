/* pipeline.h — the tangent-plane pipeline every method with tangent planes runs
 * (pipeline.c): wedges delimited per the method's honour -> each corner's input
 * plane per the `tangents` option -> one plane per wedge (Figure 6) -> unless
 * range is free, the planes limited so the method's ordinates stay in range. */
#ifndef TC_CORE_PIPELINE_H
#define TC_CORE_PIPELINE_H

#include "core/range.h"

struct tc_recon;

/* How a method's ordinates depend on its corner planes, for the range
 * limiter (range.h): the directions per corner, and whether a piece spans a
 * quad (its bound is the quad's). NULL dirs: the planes are not limited. */
typedef struct {
    tc__plane_dirs_fn dirs;
    const void *ctx;
    int per_quad;
} tc__plane_use;

/* Fills r->planes (allocating it) with each corner's wedge plane, limited for
 * `use` unless r->opt.range is free. Corner values are the mesh's, so the
 * method must not have honour TC_HONOR_NONE on C-1 data (the cubic's own build
 * merges them). */
int tc__planes_build(struct tc_recon *r, const tc__plane_use *use, tc_diags *dg);

#endif
