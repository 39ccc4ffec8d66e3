/* locate.h — the locator's internals the rasterizer shares, so a pixel centre
 * is owned by exactly the triangle tc_locate would return for that point. */
#ifndef TC_CORE_LOCATE_H
#define TC_CORE_LOCATE_H

#include "tocher.h"

/* A triangle as the locator stores it: corners counter-clockwise, and per edge
 * whether the triangle lies left of the edge's canonical (coordinate-sorted) direction. */
struct tc__slot {
    double x[3], y[3];
    int32_t t;     /* the triangle's index in the mesh */
    uint32_t left; /* bit k: corner k < corner k+1, the triangle is left of edge k's frame */
};

enum { TC_SLOT_OUT = 0, TC_SLOT_TOUCH = 1, TC_SLOT_OWN = 2 };

/* TC_SLOT_OWN if the triangle owns (x, y) by the strict rule, TC_SLOT_TOUCH if it
 * only contains it in the closed sense, else TC_SLOT_OUT. Exact. */
int tc__slot_test(const struct tc__slot *s, double x, double y);

/* Calls fn for every triangle whose box meets the closed box [lo, hi]. */
void tc__locator_query_box(const tc_locator *L, const double lo[2], const double hi[2],
                           void (*fn)(void *ctx, const struct tc__slot *s), void *ctx);

#endif
