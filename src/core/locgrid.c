/* locgrid.c — builds the locator's grid of cells (locgrid.h): each cell lists the slots
 * whose boxes meet it, so a point's candidates are one cell's short list. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/locgrid.h"
#include "core/minmax.h"
#include "tocher.h"

/* Cells per triangle tried first, then a quarter as many while the lists grow
 * too long in all (long boxes cover many cells). Small meshes get many cells,
 * so that most cells lie inside one triangle and need no test at all (on a
 * 512-triangle grid: 18% of the cells at 8 per triangle, 51% at 32, 73% at
 * 128; a random point's location plus evaluation took 56, 47, 38 ns, and 32
 * against 27 ns from 128 to 256 per triangle), up to CELL_BUDGET cells in all
 * (1 MiB of cell words, plus the lists); large meshes ~2 per triangle (lists
 * of ~4 slots, ~40 bytes per triangle). The grid is built only once enough
 * points were asked for to pay for it (tc__locgrid_cost, locate.c). */
#define CELLS_SMALL 256.0
#define CELL_BUDGET 262144.0
#define CELLS_LARGE 2.0
#define TRIES 4
/* Items allowed per triangle (plus 4 per cell) before a coarser grid is tried. */
#define ITEMS_PER_TRIANGLE 32
/* The grid's origin sits this fraction of a cell before the box, so that the
 * lines of a regular mesh (multiples of a spacing from the box's corner) fall
 * inside cells, not on their borders, where they would touch both cells. */
#define ORIGIN_SHIFT 0.3819660112501051

static void slot_box(const struct tc__slot *s, double b[4]) {
    b[0] = tc__fmin(tc__fmin(s->x[0], s->x[1]), s->x[2]);
    b[1] = tc__fmin(tc__fmin(s->y[0], s->y[1]), s->y[2]);
    b[2] = tc__fmax(tc__fmax(s->x[0], s->x[1]), s->x[2]);
    b[3] = tc__fmax(tc__fmax(s->y[0], s->y[1]), s->y[2]);
}

/* `want` cells across the box along one axis, one more for the shifted origin;
 * one cell (scale 0, every point in it) when the extent is 0 or the scale
 * would not be finite. */
static void axis_cells(tc__locgrid *g, int axis, double want) {
    double lo = g->lo[axis], w = g->hi[axis] - lo;
    double n = floor(want + 0.5);
    if (!(n >= 1)) n = 1;
    if (n > 32767) n = 32767;
    double s = n / w, org = lo - ORIGIN_SHIFT * (w / n);
    if (!(w > 0) || !isfinite(w) || !isfinite(s) || !isfinite(org)) {
        g->n[axis] = 1, g->scale[axis] = 0, g->org[axis] = lo;
        return;
    }
    g->n[axis] = (int32_t)n + 1;
    g->scale[axis] = s;
    g->org[axis] = org;
}

/* Sizes the grid for `cells` cells in all, shaped like the box. */
static void size_grid(tc__locgrid *g, double cells) {
    double w = g->hi[0] - g->lo[0], h = g->hi[1] - g->lo[1];
    double nx = w > 0 && h > 0 ? sqrt(cells * w / h) : w > 0 ? cells : 1;
    axis_cells(g, 0, nx);
    axis_cells(g, 1, cells / tc__fmax(1, floor(nx + 0.5)));
}

/* Number of (slot, cell) pairs, or -1 past `limit`. */
static int64_t count_items(const tc__locgrid *g, const double *box, int32_t nt, int64_t limit) {
    int64_t total = 0;
    for (int32_t i = 0; i < nt; i++) {
        const double *b = box + 4 * (size_t)i;
        int64_t cx = tc__locgrid_cell(g, 0, b[2]) - tc__locgrid_cell(g, 0, b[0]) + 1;
        int64_t cy = tc__locgrid_cell(g, 1, b[3]) - tc__locgrid_cell(g, 1, b[1]) + 1;
        total += cx * cy;
        if (total > limit) return -1;
    }
    return total;
}

/* The closed x (axis 0) or y range that holds every point of the box that
 * tc__locgrid_cell puts in cell c, widened by a margin far above the rounding
 * of the cell map (relative 1e-15 of a cell, or of the coordinates' size). */
static void cell_range(const tc__locgrid *g, int axis, int32_t c, double *a, double *b) {
    double lo = g->lo[axis], hi = g->hi[axis];
    if (g->n[axis] == 1) {
        *a = lo, *b = hi;
    } else {
        double cw = 1 / g->scale[axis];
        *a = c == 0 ? tc__fmin(lo, g->org[axis]) : g->org[axis] + c * cw;
        *b = c == g->n[axis] - 1 ? tc__fmax(hi, g->org[axis] + (c + 1) * cw) : g->org[axis] + (c + 1) * cw;
    }
    double m = 1e-3 * (*b - *a) + 1e-12 * tc__fmax(fabs(lo), fabs(hi));
    *a -= m, *b += m;
}

/* True only if no point of the rectangle lies in the slot's closed triangle:
 * the rectangle is outside one edge's half-plane by more than any rounding of
 * the edge function (relative 1e-9 of its terms; tiny scales are never
 * culled). Then tc__slot_test, exact, says SLOT_OUT at every point there, so
 * leaving the slot out of the cell changes no answer. The slot's corners are
 * in the order its tests use (counter-clockwise: inside is left of k -> k+1). */
static int misses(const struct tc__slot *s, double x0, double x1, double y0, double y1) {
    for (int k = 0; k < 3; k++) {
        int j = k == 2 ? 0 : k + 1;
        double ex = s->x[j] - s->x[k], ey = s->y[j] - s->y[k];
        double qx = ey < 0 ? x1 : x0, qy = ex > 0 ? y1 : y0; /* the corner most inside */
        double dx = qx - s->x[k], dy = qy - s->y[k];
        double f = ex * dy - ey * dx, tol = 1e-9 * (fabs(ex) + fabs(ey)) * (fabs(dx) + fabs(dy));
        if (tol > 1e-250 && f < -tol) return 1;
    }
    return 0;
}

/* True only if every point of the rectangle is strictly inside the slot's
 * triangle: inside each edge's half-plane by more than any rounding. Then the
 * exact tc__slot_test says SLOT_OWN at every point there. */
static int holds(const struct tc__slot *s, double x0, double x1, double y0, double y1) {
    for (int k = 0; k < 3; k++) {
        int j = k == 2 ? 0 : k + 1;
        double ex = s->x[j] - s->x[k], ey = s->y[j] - s->y[k];
        double qx = ey > 0 ? x1 : x0, qy = ex > 0 ? y0 : y1; /* the corner least inside */
        double dx = qx - s->x[k], dy = qy - s->y[k];
        double f = ex * dy - ey * dx, tol = 1e-9 * (fabs(ex) + fabs(ey)) * (fabs(dx) + fabs(dy));
        if (!(tol > 1e-250 && f > tol)) return 0;
    }
    return 1;
}

/* cell_range of every column and row, computed once: [2c] and [2c + 1]. */
typedef struct {
    double *r[2];
} ranges;

static int ranges_new(const tc__locgrid *g, ranges *R) {
    for (int a = 0; a < 2; a++) {
        R->r[a] = tc__malloc((size_t)g->n[a], 2 * sizeof *R->r[a]);
        if (!R->r[a]) return TC_ENOMEM;
        for (int32_t c = 0; c < g->n[a]; c++) cell_range(g, a, c, &R->r[a][2 * c], &R->r[a][2 * c + 1]);
    }
    return TC_OK;
}

/* Runs BODY (with c the cell's index) for every cell c the slot's box covers
 * and its triangle may meet (a box within one cell: that cell, no test). */
#define FOR_CELLS(g, R, s, b, BODY)                                                                       \
    do {                                                                                                 \
        int32_t x0_ = tc__locgrid_cell(g, 0, (b)[0]), x1_ = tc__locgrid_cell(g, 0, (b)[2]);               \
        int32_t y0_ = tc__locgrid_cell(g, 1, (b)[1]), y1_ = tc__locgrid_cell(g, 1, (b)[3]);               \
        for (int32_t cy_ = y0_; cy_ <= y1_; cy_++) {                                                     \
            const double *ry_ = (R)->r[1] + 2 * cy_;                                                     \
            for (int32_t cx_ = x0_; cx_ <= x1_; cx_++) {                                                 \
                const double *rx_ = (R)->r[0] + 2 * cx_;                                                 \
                if ((x0_ < x1_ || y0_ < y1_) && misses(s, rx_[0], rx_[1], ry_[0], ry_[1])) continue;    \
                size_t c = (size_t)cy_ * (size_t)(g)->n[0] + (size_t)cx_;                                \
                BODY;                                                                                    \
            }                                                                                            \
        }                                                                                                \
    } while (0)

/* Cell c with the single candidate `slot`: does the slot hold the whole cell? */
static int cell_held(const tc__locgrid *g, const ranges *R, const struct tc__slot *s, size_t c) {
    const double *rx = R->r[0] + 2 * (c % (size_t)g->n[0]), *ry = R->r[1] + 2 * (c / (size_t)g->n[0]);
    return holds(s, rx[0], rx[1], ry[0], ry[1]);
}

/* Writes the final layout (locgrid.h) from the lists items[start[c] ..
 * next[c]) of each cell: a held cell's word is -1 - its triangle, an empty
 * one's TC_LOCGRID_EMPTY, the others' their list's offset in g->items. */
static int compact(tc__locgrid *g, const ranges *R, const struct tc__slot *slots, const int32_t *start,
                   const int32_t *next, const int32_t *items) {
    size_t ncell = (size_t)g->n[0] * (size_t)g->n[1];
    int64_t total = 0;
    for (size_t c = 0; c < ncell; c++) { /* the words of empty and held cells; the others' sizes */
        int32_t k = next[c] - start[c];
        g->cell[c] = 0;
        if (k == 0) g->cell[c] = TC_LOCGRID_EMPTY;
        else if (k == 1 && cell_held(g, R, &slots[items[start[c]]], c)) g->cell[c] = -1 - slots[items[start[c]]].t;
        else total += 1 + (k + TC_LOCGRID_BLOCK - 1) / TC_LOCGRID_BLOCK * TC_LOCGRID_BLOCK;
    }
    if (total > INT32_MAX) return TC_ELIMIT;
    g->items = tc__malloc((size_t)total, sizeof *g->items);
    if (!g->items) return TC_ENOMEM;
    int32_t at = 0;
    for (size_t c = 0; c < ncell; c++) {
        if (g->cell[c] < 0) continue;
        int32_t k = next[c] - start[c]; /* count, the slots, the last one repeated up to a whole block */
        const int32_t *list = items + start[c];
        int32_t padded = (k + TC_LOCGRID_BLOCK - 1) / TC_LOCGRID_BLOCK * TC_LOCGRID_BLOCK;
        g->cell[c] = at;
        g->items[at] = padded;
        for (int32_t i = 0; i < padded; i++) g->items[at + 1 + i] = list[i < k ? i : k - 1];
        at += 1 + padded;
    }
    return TC_OK;
}

/* Lists, for every cell, the slots whose triangles may meet it, in increasing
 * slot order, then lays them out (compact). */
static int fill(tc__locgrid *g, const struct tc__slot *slots, const double *box, int32_t nt) {
    size_t ncell = (size_t)g->n[0] * (size_t)g->n[1];
    int32_t *start = tc__calloc(ncell + 1, sizeof *start), *next = tc__malloc(ncell, sizeof *next), *items = NULL;
    ranges R = {{NULL, NULL}};
    g->cell = tc__malloc(ncell, sizeof *g->cell);
    int rc = start && next && g->cell ? ranges_new(g, &R) : TC_ENOMEM;
    if (rc == TC_OK) {
        for (int32_t i = 0; i < nt; i++) FOR_CELLS(g, &R, &slots[i], box + 4 * (size_t)i, start[c + 1]++);
        for (size_t c = 0; c < ncell && rc == TC_OK; c++) {
            if ((int64_t)start[c + 1] + start[c] > INT32_MAX) rc = TC_ELIMIT;
            else start[c + 1] += start[c];
        }
    }
    if (rc == TC_OK) {
        items = tc__malloc((size_t)start[ncell], sizeof *items);
        if (!items) rc = TC_ENOMEM;
    }
    if (rc == TC_OK) {
        memcpy(next, start, ncell * sizeof *next);
        for (int32_t i = 0; i < nt; i++) FOR_CELLS(g, &R, &slots[i], box + 4 * (size_t)i, items[next[c]++] = i);
        rc = compact(g, &R, slots, start, next, items);
    }
    tc__free(start), tc__free(next), tc__free(items), tc__free(R.r[0]), tc__free(R.r[1]);
    return rc;
}

/* Cells per triangle of the first grid tried. */
static double cells_per_triangle(int32_t nt) {
    return tc__fmax(CELLS_LARGE, tc__fmin(CELLS_SMALL, CELL_BUDGET / nt));
}

long long tc__locgrid_cost(int32_t nt) {
    return (long long)(cells_per_triangle(nt) * nt) + 8 * (long long)nt;
}

int tc__locgrid_new(const struct tc__slot *slots, int32_t nt, tc__locgrid **out) {
    *out = NULL;
    double *box = tc__malloc((size_t)nt, 4 * sizeof *box);
    tc__locgrid *g = calloc(1, sizeof *g);
    int rc = box && g ? TC_OK : TC_ENOMEM;
    if (rc == TC_OK) {
        g->lo[0] = g->lo[1] = INFINITY;
        g->hi[0] = g->hi[1] = -INFINITY;
    }
    for (int32_t i = 0; rc == TC_OK && i < nt; i++) {
        double *b = box + 4 * (size_t)i;
        const struct tc__slot *sl = &slots[i];
        int finite = 1;
        for (int k = 0; k < 3; k++) finite &= isfinite(sl->x[k]) && isfinite(sl->y[k]);
        if (!finite) { /* fmin/fmax would skip a NaN: the tree keeps its own rule for such meshes */
            tc__free(box), tc__locgrid_free(g);
            return TC_OK;
        }
        slot_box(sl, b);
        g->lo[0] = tc__fmin(g->lo[0], b[0]), g->lo[1] = tc__fmin(g->lo[1], b[1]);
        g->hi[0] = tc__fmax(g->hi[0], b[2]), g->hi[1] = tc__fmax(g->hi[1], b[3]);
    }
    int64_t total = -1, limit = (int64_t)ITEMS_PER_TRIANGLE * nt;
    double per = cells_per_triangle(nt);
    double cells = per * nt;
    for (int k = 0; rc == TC_OK && k < TRIES && total < 0; k++, cells /= 4) {
        size_grid(g, cells);
        int64_t lim = limit + 4 * (int64_t)g->n[0] * g->n[1];
        total = count_items(g, box, nt, lim < INT32_MAX ? lim : INT32_MAX);
    }
    if (rc == TC_OK && total >= 0) rc = fill(g, slots, box, nt);
    tc__free(box);
    if (rc != TC_OK || total < 0) {
        tc__locgrid_free(g);
        return rc;
    }
    *out = g;
    return TC_OK;
}

void tc__locgrid_free(tc__locgrid *g) {
    if (!g) return;
    tc__free(g->cell);
    tc__free(g->items);
    tc__free(g);
}
