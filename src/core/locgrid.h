/* locgrid.h — a uniform grid of cells over a mesh's box, each cell listing the locator
 * slots whose boxes meet it: the O(1) first step of tc_locate (locate.c queries it). */
#ifndef TC_CORE_LOCGRID_H
#define TC_CORE_LOCGRID_H

#include <stdint.h>

#include "core/locate.h"

/* Invariants: lo/hi is the closed union of every slot's box; a slot whose box
 * [bx0, bx1] x [by0, by1] is listed in every cell (cx, cy) with
 * cell_x(bx0) <= cx <= cell_x(bx1) and likewise in y, where cell_x is the
 * monotone map below. So a point in a slot's box always finds the slot in its
 * cell. Each cell's list is in increasing slot order (what the tree's rule
 * "first strict owner in slot order" needs), padded to a multiple of
 * TC_LOCGRID_BLOCK entries by repeating its last slot (empty lists stay empty). A cell listing more than
 * TC_LOCGRID_MAX slots has start[c + 1] - start[c] > TC_LOCGRID_MAX: the query
 * then walks the tree instead (fans, long slivers), so no point costs O(T). */
typedef struct tc__locgrid {
    double lo[2], hi[2];
    double scale[2]; /* cells per unit, >= 0 and finite */
    int32_t n[2];    /* cells per axis, >= 1 */
    int32_t *start;  /* [n0 * n1 + 1] offsets into items */
    int32_t *items;  /* slot indices */
} tc__locgrid;

#define TC_LOCGRID_MAX 48
#define TC_LOCGRID_BLOCK 4

/* The cell column of x (row: axis 1). Monotone non-decreasing in x, whatever
 * the rounding: a difference, a product by a constant >= 0, a truncation and a
 * clamp; NaN maps to cell 0. */
static inline int32_t tc__locgrid_cell(const tc__locgrid *g, int axis, double x) {
    double u = (x - g->lo[axis]) * g->scale[axis];
    if (!(u >= 0)) return 0;
    return u < (double)g->n[axis] ? (int32_t)u : g->n[axis] - 1;
}

/* Builds the grid over slots[nt] (nt >= 1). TC_OK with *out NULL when no grid
 * is made: a non-finite coordinate (the tree's handling of those is kept), or
 * boxes so long that every resolution tried lists too many. TC_ENOMEM. */
int tc__locgrid_new(const struct tc__slot *slots, int32_t nt, tc__locgrid **out);
void tc__locgrid_free(tc__locgrid *g);

#endif
