/* scene.h — analytic reference scenes: a planar receiver lit by one light, with
 * exact radiosity everywhere and the discontinuity events a front-end would mesh. */
#ifndef TC_SCENES_SCENE_H
#define TC_SCENES_SCENE_H

#include "tocher.h"

/* Every scene shares one receiver: the plane z = 0 (normal +z) over the domain
 * [0,1]^2, reflectance rho = 0.8, one channel. Lights and occluders are parallel
 * to it and axis-aligned (the box's sides are vertical):
 *
 *   square-light  light [0.25,0.75]^2 at z = 0.4, nothing in the way (Salesin Fig. 7)
 *   penumbra      light [0.35,0.65]^2 at H = 1; square occluder [0.32,0.62]x[0.37,0.67]
 *                 at h = 0.5: umbra, penumbrae, C0 shadow edges (Fig. 8)
 *   point-shadow  point light at (0.5,0.5,1), intensity 1; occluder [0.35,0.65]^2 at
 *                 h = 0.5: a hard shadow [0.2,0.8]^2 with C-1 edges
 *   box           light [0.35,0.65]^2 at H = 1 over a box [0.4,0.6]^2 x [0,0.15]
 *                 standing on the receiver: C-1 contact line, its shadow around it
 *   stiff         as penumbra with the occluder at h = 1e-4: penumbrae ~3e-5 wide
 *
 * Area lights have radiance Le = 1 and B = rho Le F, F the form factor of the
 * light's visible part. The point light is isotropic with intensity I:
 * B = rho I cos(theta) / (pi r^2) — the small-area-light limit of rho Le F with
 * Le A cos(theta_light) replaced by the constant I. */
typedef enum {
    TC_SCENE_SQUARE_LIGHT = 0,
    TC_SCENE_PENUMBRA,
    TC_SCENE_POINT_SHADOW,
    TC_SCENE_BOX,
    TC_SCENE_STIFF,
    TC_SCENE_COUNT
} tc_scene_id;

/* "square-light", "penumbra", "point-shadow", "box", "stiff"; NULL if out of range. */
const char *tc_scene_name(tc_scene_id id);
/* A one-line description (for `tocher scene --list`); NULL if out of range. */
const char *tc_scene_summary(tc_scene_id id);
/* 0 and *out set, or -1 if the name is unknown. */
int tc_scene_parse(const char *name, tc_scene_id *out);

typedef enum { TC_OCCLUDER_NONE = 0, TC_OCCLUDER_SQUARE, TC_OCCLUDER_BOX } tc_occluder_kind;

/* A discontinuity of B on the receiver: the segment of the line x = at (axis 0)
 * or y = at (axis 1) whose other coordinate runs over [lo, hi]. kind TC_C0 is a
 * D1 event (a kink), TC_CM1 a D0 event (a jump). D2 events (C1 with a jump in
 * the second derivative) are not listed: a front-end leaves them C1. */
typedef struct {
    tc_continuity kind;
    int axis;
    double at, lo, hi;
} tc_scene_event;

#define TC_SCENE_MAX_EVENTS 32

/* A scene is plain data, filled by tc_scene_init and never changed after. */
typedef struct {
    tc_scene_id id;
    double domain[4];     /* x0 y0 x1 y1 of the receiver that is meshed */
    double rho;           /* receiver reflectance */
    int point_light;      /* 1: a point light at (light[0], light[1], light_z) */
    double light[4];      /* area light: the rectangle x0 y0 x1 y1, facing down */
    double light_z;       /* the light's height */
    double emit;          /* area light: radiance Le; point light: intensity I */
    tc_occluder_kind occluder;
    double occ[4];        /* occluder's rectangle (box: its footprint) x0 y0 x1 y1 */
    double occ_z0, occ_z1;/* square: both its height; box: 0 and its top */
    double box_clip;      /* box: occlusion uses box ∩ {z >= box_clip}, see scene.c */
    double scale;         /* value scale: the maximum of B without the occluder */
    int nevents;
    tc_scene_event events[TC_SCENE_MAX_EVENTS]; /* derived from the geometry */
} tc_scene;

/* Fills s for scene id; TC_OK, or TC_EINVAL for an unknown id. */
int tc_scene_init(tc_scene *s, tc_scene_id id);
/* The same scene over another receiver rectangle x0 y0 x1 y1 (x0 < x1, y0 < y1):
 * only the events change (clipped to it). The discontinuity mesher uses it to
 * get the events of a rotated receiver's bounding box. */
int tc_scene_init_domain(tc_scene *s, tc_scene_id id, const double domain[4]);

/* B at the receiver point (x, y) — any point of the plane, not only the domain.
 * On a C-1 line the dark side's value is returned (occluder and box are closed
 * sets), up to rounding of where exactly the line is. */
double tc_scene_value(const tc_scene *s, double x, double y);

/* The limit of B at (x, y) approached from direction (dx, dy) (not both 0; then
 * it is tc_scene_value). The side is decided at (x, y) + 1e-9 max(1, |x|, |y|)
 * (dx, dy)/|(dx, dy)|, but the smooth part is evaluated at (x, y) itself, so the
 * result is the exact one-sided limit — no nudge error — wherever no other
 * C-1 line passes within that distance. The one exception is a corner of the
 * box's footprint, where the limit from outside depends on the direction (it
 * varies continuously over the two quadrants next to the box); there the value
 * seen from the corner itself is returned for every outside direction, which is
 * the limit along the outward diagonal. */
double tc_scene_value_from(const tc_scene *s, double x, double y, double dx, double dy);

/* Area lights: the form factor F of the light's part visible from (x, y) (0 on
 * the box's closed footprint). Point light: 1 if the light is visible, else 0. */
double tc_scene_visibility(const tc_scene *s, double x, double y);

#endif
