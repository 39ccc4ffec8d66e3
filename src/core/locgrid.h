/* locgrid.h — a uniform grid of cells over a mesh's box, each cell listing the locator
 * slots whose boxes meet it: the O(1) first step of tc_locate (locate.c queries it). */
#ifndef TC_CORE_LOCGRID_H
#define TC_CORE_LOCGRID_H

#include <stdint.h>

#include "core/locate.h"

/* Invariants: lo/hi is the closed union of every slot's box; a slot whose box
 * [bx0, bx1] x [by0, by1] is listed in every cell (cx, cy) with
 * cell(0, bx0) <= cx <= cell(0, bx1), likewise in y, where its triangle may
 * meet the cell (a slot is left out only where its exact test says SLOT_OUT at
 * every point of the cell; locgrid.c). The cell map is monotone, so a point in
 * a slot's box always finds it in its cell, unless the slot is OUT there.
 * Cell c's word cell[c] is
 *  - TC_LOCGRID_EMPTY: no triangle meets the cell;
 *  - w < 0 otherwise: the cell lies strictly inside triangle -1 - w, which is
 *    the only one meeting it, so that triangle owns every point of the cell
 *    (one load answers most points of a small mesh);
 *  - w >= 0: items[w] = k, then k slot indices in increasing slot order (what
 *    the tree's rule "first strict owner in slot order" needs), k a multiple
 *    of TC_LOCGRID_BLOCK, the last real one repeated to fill the block.
 * A list longer than TC_LOCGRID_MAX makes the query walk the tree instead
 * (fans, long slivers), so no point costs O(T). */
typedef struct tc__locgrid {
    double lo[2], hi[2];
    double org[2];   /* where cell 0 begins (a fraction of a cell before lo) */
    double scale[2]; /* cells per unit, >= 0 and finite */
    int32_t n[2];    /* cells per axis, >= 1 */
    int32_t *cell;   /* [n0 * n1] */
    int32_t *items;
} tc__locgrid;

#define TC_LOCGRID_EMPTY INT32_MIN
#define TC_LOCGRID_MAX 48
#define TC_LOCGRID_BLOCK 2

/* The cell column of x (row: axis 1). Monotone non-decreasing in x, whatever
 * the rounding: a difference, a product by a constant >= 0, a truncation and a
 * clamp; NaN maps to cell 0. */
static inline int32_t tc__locgrid_cell(const tc__locgrid *g, int axis, double x) {
    double u = (x - g->org[axis]) * g->scale[axis];
    if (!(u >= 0)) return 0;
    return u < (double)g->n[axis] ? (int32_t)u : g->n[axis] - 1;
}

/* Builds the grid over slots[nt] (nt >= 1). TC_OK with *out NULL when no grid
 * is made: a non-finite coordinate (the tree's handling of those is kept), or
 * boxes so long that every resolution tried lists too many. TC_ENOMEM. */
int tc__locgrid_new(const struct tc__slot *slots, int32_t nt, tc__locgrid **out);
void tc__locgrid_free(tc__locgrid *g);

/* About what building the grid over nt triangles costs, in points located
 * (a point saves ~50-100 ns against the tree; a cell costs ~100 ns to build). */
long long tc__locgrid_cost(int32_t nt);

#endif
