/* surfaces.c — the realistic discontinuity-meshed surfaces: whole scenes at an angle,
 * and patches on the stiff scene's shadow sized like real renderers' output. */
#include "scenes/surfaces.h"

/* Why these. Real output (issue 12) has its worst overshoot on fan triangles
 * of aspect 470-825 with a largest angle of 116-149 degrees, whose short edge
 * crosses a thin penumbra strip. The stiff scene's strips are 3e-5 wide: on a
 * patch 0.02-0.04 across, turned 30-40 degrees, a strip is one face cut
 * obliquely by the patch's sides, and its two triangles have just that shape
 * (the tests check it). The whole scenes add hundreds of triangles, wide
 * penumbrae, C-1 contact and hard-shadow data, and the smooth case. */
static const tc_dm_surface surfaces[] = {
    {"square-light", TC_SCENE_SQUARE_LIGHT, {0, 0, 1, 1}, 30, 32},
    {"penumbra", TC_SCENE_PENUMBRA, {0, 0, 1, 1}, 30, 32},
    {"point-shadow", TC_SCENE_POINT_SHADOW, {0, 0, 1, 1}, 30, 32},
    {"box", TC_SCENE_BOX, {0, 0, 1, 1}, 30, 32},
    {"stiff", TC_SCENE_STIFF, {0, 0, 1, 1}, 30, 32},
    {"box-corner", TC_SCENE_BOX, {0.35, 0.35, 0.45, 0.45}, 25, 4},
    {"stiff-corner", TC_SCENE_STIFF, {0.305, 0.355, 0.335, 0.385}, 35, 2},
    {"stiff-far-corner", TC_SCENE_STIFF, {0.60, 0.65, 0.64, 0.69}, 40, 1},
    {"stiff-edge", TC_SCENE_STIFF, {0.31, 0.51, 0.33, 0.53}, 35, 2},
};
#define NSURFACES ((int)(sizeof surfaces / sizeof surfaces[0]))

int tc_dm_surface_count(void) { return NSURFACES; }

const tc_dm_surface *tc_dm_surface_get(int i) { return i >= 0 && i < NSURFACES ? &surfaces[i] : NULL; }

int tc_dm_surface_setup(const tc_dm_surface *f, int no_c0, tc_scene *s, tc_scene_mesh_opts *o) {
    tc_scene_mesh_opts_default(o);
    o->kind = TC_SCENE_MESH_DM;
    o->density = f->density;
    o->rotation = f->rotation;
    o->midpoints = 0;
    o->digits = 6;
    o->no_c0 = no_c0;
    return tc_scene_init_domain(s, f->scene, f->window);
}
