/* surfaces.h — receiver patches meshed the way discontinuity-meshing renderers output
 * them: the test material for overshoot (issue 12), shared by the tests and the report. */
#ifndef TC_SCENES_SURFACES_H
#define TC_SCENES_SURFACES_H

#include "scenes/meshing.h"
#include "scenes/scene.h"

/* A surface: a rectangle of one scene's receiver plane (the whole domain, or
 * a small patch on a shadow's corner or edge) with the scene turned against
 * it, so that events meet its sides and each other's faces at angles. */
typedef struct {
    const char *name;
    tc_scene_id scene;
    double window[4]; /* x0 y0 x1 y1 of the patch */
    double rotation;  /* degrees the scene is turned about the patch's centre */
    int density;      /* dm: receiver sides cut into pieces of at most 1/N of the patch */
} tc_dm_surface;

int tc_dm_surface_count(void);
/* Surface i (0 .. count-1), or NULL. */
const tc_dm_surface *tc_dm_surface_get(int i);

/* The scene and the mesh options of surface f as a real front-end sends it:
 * a dm mesh, values printed to 6 significant digits, no midpoint samples and no
 * gradients (the tangent planes are estimated), C0 events flagged unless no_c0
 * (the real format has no C0 flags). TC_OK, or TC_EINVAL for a bad surface. */
int tc_dm_surface_setup(const tc_dm_surface *f, int no_c0, tc_scene *s, tc_scene_mesh_opts *o);

#endif
