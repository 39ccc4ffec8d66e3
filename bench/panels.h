/* panels.h — a row of square picture panels with white gaps between them, written
 * as one PNG through tc_img_encode: grey or coloured pixels, a mesh's edges on top. */
#ifndef BENCH_PANELS_H
#define BENCH_PANELS_H

#include "tocher.h"

typedef struct {
    int panel, npanel, width; /* panel side, panels, row width in pixels */
    float *px;                /* [panel][width][3] */
} bench_row;

/* A white row of npanel panels of panel x panel pixels; 0, or -1 out of memory. */
int bench_row_init(bench_row *r, int panel, int npanel);
void bench_row_free(bench_row *r);
/* Pixel (i, j) of panel k (j = 0 the top row); outside the panel: nothing. */
void bench_row_put(bench_row *r, int k, int i, int j, const float rgb[3]);
/* Panel k grey, from v[panel * panel] (row-major, top row first). */
void bench_row_grey(bench_row *r, int k, const float *v);
/* m's edges over panel k (vp: the panel's viewport): C1 grey, C0 yellow, C-1
 * red, boundary white, each colour times gain. */
void bench_row_mesh(bench_row *r, int k, const tc_mesh *m, const tc_viewport *vp, float gain);
/* linear: 1 = the values as they are, 0 = through the sRGB transfer. 0, or -1
 * with a message on stderr. */
int bench_row_write_png(const bench_row *r, int linear, const char *path);

#endif
