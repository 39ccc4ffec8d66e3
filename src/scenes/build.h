/* build.h — internals shared by the scene meshers: growable mesh storage, the
 * adaptive quadtree, and the sampling stage that turns a mesh into samples. */
#ifndef TC_SCENES_BUILD_H
#define TC_SCENES_BUILD_H

#include <stdint.h>

#include "scenes/meshing.h"

/* Most triangles a scene mesh may have (TC_ELIMIT beyond). */
#define TC__SCENE_MAX_TRIS (1 << 24)

/* A mesh under construction. Invariants: triangles are counter-clockwise;
 * every polyline has >= 2 vertices and each consecutive pair is a mesh edge;
 * values is NULL unless the mesher already sampled every vertex (then
 * value_evals counts the evaluations behind them). Once oom is set every
 * append is a no-op. */
typedef struct {
    int32_t nv, nt, cap_v, cap_t;
    double *xy;   /* [nv][2] */
    int32_t *tri; /* [nt][3] */
    double *values;
    int64_t value_evals;
    int32_t nline[2], cap_line[2], nlv[2], cap_lv[2]; /* [0] c0, [1] c-1 */
    int32_t *line_start[2], *line_verts[2];            /* start has nline + 1 entries */
    /* Where the scene is evaluated: mesh point p is scene point
     * frame[0..1] + [frame[2] frame[3]; frame[4] frame[5]] (p - frame[0..1]);
     * identity unless framed (the rotated dm meshes). */
    int framed;
    double frame[6];
    int oom;
} tc__mbuild;

void tc__mb_init(tc__mbuild *b);
void tc__mb_free(tc__mbuild *b);
/* Appends a vertex and returns its index (-1 once oom). */
int32_t tc__mb_vertex(tc__mbuild *b, double x, double y);
void tc__mb_triangle(tc__mbuild *b, int32_t p, int32_t q, int32_t r);
/* Appends a polyline of kind 0 (c0) or 1 (c-1) over n >= 2 vertices. */
void tc__mb_line(tc__mbuild *b, int kind, const int32_t *verts, int32_t n);

/* The discontinuity mesher (dm.c). */
int tc__scene_dm(const tc_scene *s, const tc_scene_mesh_opts *o, tc__mbuild *b);

/* The a posteriori mesher (adaptive.c). */
int tc__scene_adaptive(const tc_scene *s, const tc_scene_mesh_opts *o, tc__mbuild *b);

/* Samples s on the mesh in b and moves b's arrays into m (sampling.c); b is
 * left empty. m must be zeroed. */
int tc__scene_sample(const tc_scene *s, const tc_scene_mesh_opts *o, tc__mbuild *b, tc_scene_mesh *m);

#endif
