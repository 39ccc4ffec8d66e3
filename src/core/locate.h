/* locate.h — the locator's internals the rasterizer shares, so a pixel centre
 * is owned by exactly the triangle tc_locate would return for that point. */
#ifndef TC_CORE_LOCATE_H
#define TC_CORE_LOCATE_H

#include <stddef.h>

#include "tocher.h"

/* A triangle as the locator stores it: corners counter-clockwise, and per edge
 * whether the triangle lies left of the edge's canonical (coordinate-sorted) direction. */
struct tc__slot {
    double x[3], y[3];
    int32_t t;       /* the triangle's index in the mesh */
    uint32_t left;   /* bit k: corner k < corner k+1, the triangle is left of edge k's frame */
    uint32_t across; /* bit k: edge k is not left, and the mesh's triangle across it owns every point
                      * strictly between its corners (locate.c's fill_across), so that the
                      * rasterizer need not claim them as closed-only candidates */
};

enum { TC_SLOT_OUT = 0, TC_SLOT_TOUCH = 1, TC_SLOT_OWN = 2 };

/* The mesh corner a slot's corner k holds (and the slot corner holding mesh corner k: the
 * map is its own inverse): a slot keeps the corners counter-clockwise, the mesh's order with
 * corners 1 and 2 swapped where the triangle is clockwise (orient < 0). */
static inline int tc__slot_corner(int clockwise, int k) {
    return clockwise && k ? 3 - k : k;
}

/* TC_SLOT_OWN if the triangle owns (x, y) by the strict rule, TC_SLOT_TOUCH if it
 * only contains it in the closed sense, else TC_SLOT_OUT. Exact. */
int tc__slot_test(const struct tc__slot *s, double x, double y);

/* The owner by a walk down the bounding-volume tree alone: the first strict
 * owner in slot order, else the lowest-index closed container, else -1. The
 * reference tc_locate's faster paths must agree with, point for point. */
int32_t tc__locate_tree(const tc_locator *L, double x, double y);

/* tri[i] = tc_locate(L, xy[2i], xy[2i + 1]) for i < n, without a call per point. */
void tc__locate_many(const tc_locator *L, size_t n, const double *xy, int32_t *tri);

/* Counts n more points asked of L in a batch; once they pay for it (about
 * the grid's build cost in points, tc__locgrid_cost), builds L's grid of
 * cells (locgrid.h), which answers later queries faster and identically.
 * Thread-safe: the first caller past the mark builds, others carry on. */
void tc__locator_note(const tc_locator *L, size_t n);
/* Tests: builds L's grid now (if it has none yet). */
void tc__locator_grid_now(const tc_locator *L);
/* Tests: the grid is built after this many noted points (0: by tc_locator_new);
 * -1 restores the cost estimate. Locators made afterwards follow it. */
void tc__locator_grid_after(long long queries);

/* Tests: 1 if L has a grid of cells (locgrid.h), with *cells cells of which
 * *held lie inside one triangle; 0 (and zeros) if its queries walk the tree. */
int tc__locator_grid_cells(const tc_locator *L, int64_t *cells, int64_t *held);

/* Calls fn for every triangle whose box meets the closed box [lo, hi]. */
void tc__locator_query_box(const tc_locator *L, const double lo[2], const double hi[2],
                           void (*fn)(void *ctx, const struct tc__slot *s), void *ctx);

#endif
