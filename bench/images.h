/* images.h — the side-by-side pictures (Salesin et al. Fig. 7/8): reference |
 * linear | clough-tocher-c1 | clough-tocher, and their error maps, as PNG rows. */
#ifndef BENCH_IMAGES_H
#define BENCH_IMAGES_H

#include "scenes/meshing.h"
#include "scenes/scene.h"

/* Writes <dir>/<scene>-images.png (reference, then the three reconstructions
 * on sm, each sRGB(clamp(B / scale, 0, 1))) and <dir>/<scene>-errors.png (the
 * mesh with its flags, then min(1, BENCH_ERR_GAIN |ref - rec| / scale) written
 * linearly, no transfer curve),
 * panels BENCH_FIG_PANEL wide, through tc_img_encode. 0, or -1 with a
 * message on stderr. */
int bench_images_write(const tc_scene *s, const tc_scene_mesh *sm, const char *dir);

#endif
