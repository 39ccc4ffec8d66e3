/* meshing.h — the meshes a radiosity front-end would send tocher for a scene:
 * discontinuity-meshed, uniform or adaptive, with the samples each would take. */
#ifndef TC_SCENES_MESHING_H
#define TC_SCENES_MESHING_H

#include <stdint.h>

#include "scenes/scene.h"
#include "tocher.h"

typedef enum {
    TC_SCENE_MESH_DISC = 0, /* a priori: the scene's events as flagged grid lines */
    TC_SCENE_MESH_UNIFORM,  /* N x N squares, two triangles each, no flags */
    TC_SCENE_MESH_ADAPTIVE, /* a posteriori: balanced quadtree split on value spread, no flags */
    TC_SCENE_MESH_DM        /* as real discontinuity meshers: faces of the event segments,
                             * each fanned from one vertex (dm.c) */
} tc_scene_mesh_kind;

/* "disc", "uniform", "adaptive", "dm"; NULL if out of range. */
const char *tc_scene_mesh_kind_name(tc_scene_mesh_kind k);
/* 0 and *out set, or -1 if the name is unknown. */
int tc_scene_mesh_kind_parse(const char *s, tc_scene_mesh_kind *out);

typedef struct {
    tc_scene_mesh_kind kind;
    int density;      /* N: disc — no cell side longer than 1/N of the domain;
                       * uniform — N x N cells; adaptive — the N x N start grid;
                       * dm — no face side piece longer than 1/N of the domain. 1..1024 */
    int midpoints;    /* sample every edge midpoint (per side on C-1 edges) */
    int gradients;    /* per-corner gradients by one-sided differences */
    double threshold; /* adaptive: split while (max - min) of B at a cell's corners
                       * exceeds threshold * the scene's scale */
    int max_depth;    /* adaptive: at most this many splits below the start grid, 0..12 */
    int quads;        /* disc, uniform: each cell one quad instead of two triangles
                       * (adaptive meshes have hanging vertices: refused) */
    int no_c0;        /* leave the C0 events unflagged (C1), as formats without C0 flags
                       * do; they are still mesh lines, and C-1 stays flagged */
    int digits;       /* 1..17: every value (vertex, corner, midpoint) rounded to this many
                       * significant digits, as a front-end prints them; 0 = exact */
    double rotation;  /* dm only: the scene's geometry turned by this many degrees about
                       * the receiver's centre, so events meet its sides at an angle */
} tc_scene_mesh_opts;

/* disc, N = 8, midpoints on, gradients off, threshold 0.1, depth 4, triangles,
 * C0 flagged, exact values, no rotation. */
void tc_scene_mesh_opts_default(tc_scene_mesh_opts *o);
/* NULL if the options are valid, else what is wrong with them (one sentence). */
const char *tc_scene_mesh_opts_check(const tc_scene_mesh_opts *o);

/* A mesh with its samples. desc is ready for tc_mesh_new and tc_json_request
 * and points into arrays this object owns. Triangles are counter-clockwise.
 * Vertex values are B (rounded to opts.digits when asked; on a turned dm mesh,
 * B of the scene turned by opts.rotation); where a vertex lies on a C-1 line,
 * the triangles on each side get that side's limit as corner values (only triangles whose corner
 * differs from the vertex value are listed). Midpoint samples on C-1 edges are
 * per side ("triangle" set), elsewhere shared. Flagged edges are given as
 * polylines along each flagged line.
 * With opts.quads the cells are given as quads (desc.nquads, desc.quads;
 * desc.tris NULL): quad q is the cell whose two triangles would have been 2q
 * and 2q+1, listed (v00, v10, v11, v01) so that its split is exactly those two
 * triangles; corner values, corner gradients (along the quad's own edges) and
 * midpoint sides then name quads, and every diagonal keeps its midpoint sample. */
typedef struct {
    tc_mesh_desc desc;
    int64_t samples;          /* scene evaluations for vertex, corner and midpoint values */
    int64_t gradient_samples; /* scene evaluations for the corner gradients */
    int32_t flagged_c0;       /* mesh edges flagged C0 */
    int32_t flagged_cm1;      /* mesh edges flagged C-1 */
    double worst_aspect;      /* max over triangles of longest edge / shortest altitude */
    double largest_angle;     /* max over triangles of the largest angle, degrees */
    double worst_aspect_angle;/* the largest angle of the worst-aspect triangle, degrees */

    /* storage behind desc (owned) */
    double *xy_, *values_, *corner_values_, *corner_gradients_, *midpoint_values_;
    int32_t *tris_, *quads_, *corner_values_tri_, *corner_gradients_tri_, *midpoint_edge_, *midpoint_tri_;
    int32_t *line_start_[2], *line_verts_[2]; /* [0] c0, [1] c-1 */
} tc_scene_mesh;

/* Meshes and samples scene s. Returns TC_OK (*out set), TC_EINVAL for bad
 * options (tc_scene_mesh_opts_check says which), TC_ELIMIT when the mesh would exceed 2^24 triangles, TC_ENOMEM. */
int tc_scene_mesh_new(const tc_scene *s, const tc_scene_mesh_opts *o, tc_scene_mesh **out);
void tc_scene_mesh_free(tc_scene_mesh *m);

/* Longest edge over shortest altitude (= longest^2 / (2 area)); 2/sqrt(3) for
 * an equilateral triangle. */
double tc_scene_triangle_aspect(const double a[2], const double b[2], const double c[2]);
/* The largest interior angle in degrees (60 for an equilateral triangle, 180 when degenerate). */
double tc_scene_triangle_largest_angle(const double a[2], const double b[2], const double c[2]);

#endif
