/* surface_images.h — the pictures of a realistic surface: exact | the pictured methods
 * as sRGB(B / scale), and under them each one's excursion beyond its triangles' corners. */
#ifndef BENCH_SURFACE_IMAGES_H
#define BENCH_SURFACE_IMAGES_H

#include <stddef.h>

#include "surfaces.h"

/* "surface-<name>[-noc0]-<what>.png", what = "images" or "excursion". */
void bench_surface_image_name(const char *surface, int no_c0, const char *what, char *buf, size_t n);

/* Writes both rows of b into dir (panels BENCH_SURF_PANEL wide): exact, then
 * BENCH_SURF_PICTURED, each sRGB(clamp(B / scale, 0, 1)); under them the mesh
 * (dimmed) with every pixel that leaves its own triangle's corner values by
 * more than BENCH_OVER_THRESHOLD R coloured: above them red to yellow, below
 * blue to cyan, from BENCH_OVER_THRESHOLD R to 1 R and more (log scale).
 * 0, or -1 with a message on stderr. */
int bench_surface_images_write(const bench_surface *b, const char *dir);

#endif
