/* surfaces.h — the realistic discontinuity-meshed surfaces (src/scenes/surfaces.h):
 * the overshoot and error of each surface method and of the exact function itself. */
#ifndef BENCH_SURFACES_H
#define BENCH_SURFACES_H

#include "scenes/meshing.h"
#include "scenes/surfaces.h"

/* One surface, one flag variant, meshed as a front-end sends it. */
typedef struct {
    const tc_dm_surface *f;
    int no_c0;
    tc_scene s;
    tc_scene_mesh *sm;
    tc_mesh *m;
    tc_locator *L;
} bench_surface;

/* Sets up and meshes surface f; 0, or -1 with the reason in note (nothing left allocated). */
int bench_surface_open(bench_surface *b, const tc_dm_surface *f, int no_c0, char *note, size_t notelen);
void bench_surface_close(bench_surface *b);

/* B at mesh point (x, y) of b: the mesh is the scene turned by f->rotation
 * about the window's centre, so the point is turned back by it. */
double bench_surface_exact(const bench_surface *b, double x, double y);

/* Measures every surface whose name is in the comma list only (all when only
 * is NULL) with and without C0 flags, writes <dir>/surfaces.csv and the
 * pictures of bench_surface_pictures among them. 0, or -1 (out of memory or
 * a file not written); *images_ok = 0 when a picture was not written. */
int bench_surfaces_run(const char *only, const char *dir, int *images_ok);

#endif
