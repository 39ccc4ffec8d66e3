/* plan.c — what the report measures: the one table of reconstruction methods,
 * the meshes of every scene, the realistic surfaces, and which of them are pictured. */
#include "plan.h"

#include <stdio.h>
#include <string.h>

/* Options not named keep their default (every default is 0, tocher.h). */
#define OPT(m, c, w, t) {.method = TC_METHOD_##m, .cross_boundary = TC_CROSS_##c, .wedges = TC_WEDGES_##w, .tangents = TC_TANGENTS_##t}
#define OPT_TWIST(m, t, tw) {.method = TC_METHOD_##m, .tangents = TC_TANGENTS_##t, .twist = TC_TWIST_##tw}
#define OPT_RANGE(m, t, r) {.method = TC_METHOD_##m, .tangents = TC_TANGENTS_##t, .range = TC_RANGE_##r}

/* name, options (method, cross_boundary, wedges, tangents[, twist]), uses
 * midpoints, uses gradients, runs on quads, description. */
const bench_method bench_methods[] = {
    {"constant", OPT(CONSTANT, NORMAL, CORRECTED, AUTO), 0, 0, 0, "one value per triangle (corner mean)"},
    {"linear", OPT(LINEAR, NORMAL, CORRECTED, AUTO), 0, 0, 0, "piecewise linear on the mesh (Gouraud)"},
    {"linear4", OPT(LINEAR4, NORMAL, CORRECTED, AUTO), 1, 0, 0,
     "linear on the 4-split through the midpoint samples (Salesin's baseline)"},
    {"clough-tocher", OPT(CLOUGH_TOCHER, NORMAL, CORRECTED, MIDPOINTS), 1, 0, 0,
     "cubic, flags kept; cross_boundary normal, wedges corrected, tangents from midpoints, range local"},
    {"ct-free", OPT_RANGE(CLOUGH_TOCHER, MIDPOINTS, FREE), 1, 0, 0,
     "as clough-tocher with range free: the unlimited cubic (the paper's; matplotlib's)"},
    {"ct-salesin", OPT(CLOUGH_TOCHER, SALESIN, CORRECTED, MIDPOINTS), 1, 0, 0,
     "as clough-tocher with cross_boundary salesin"},
    {"ct-affine", OPT(CLOUGH_TOCHER, AFFINE, CORRECTED, MIDPOINTS), 1, 0, 0,
     "as clough-tocher with cross_boundary affine"},
    {"ct-literal", OPT(CLOUGH_TOCHER, NORMAL, LITERAL, MIDPOINTS), 1, 0, 0,
     "as clough-tocher with wedges literal (Figure 6 as printed)"},
    {"clough-tocher-c1", OPT(CLOUGH_TOCHER_C1, NORMAL, CORRECTED, MIDPOINTS), 1, 0, 0,
     "cubic, C1 everywhere: flags ignored; tangents from midpoints"},
    {"ct-given", OPT(CLOUGH_TOCHER, NORMAL, CORRECTED, GIVEN), 0, 1, 0,
     "as clough-tocher with tangents given: the scene's corner gradients"},
    {"ct-estimate", OPT(CLOUGH_TOCHER, NORMAL, CORRECTED, ESTIMATE), 0, 0, 0,
     "as clough-tocher with tangents estimated per wedge: vertex samples only"},
    {"ct-estimate-free", OPT_RANGE(CLOUGH_TOCHER, ESTIMATE, FREE), 0, 0, 0, "as ct-estimate with range free"},
    {"powell-sabin", OPT(POWELL_SABIN, NORMAL, CORRECTED, MIDPOINTS), 1, 0, 0,
     "C1 quadratic on the 6-split (incenter); C-1 cuts, C0 read as C1; tangents from midpoints"},
    {"hermite", OPT_TWIST(HERMITE, MIDPOINTS, ESTIMATE), 1, 0, 1,
     "bicubic Hermite patches on the quad version of the mesh (one quad per cell); flags kept, "
     "tangents from midpoints (diagonals included), twist estimated from the neighbouring planes"},
    {"hermite-zero-twist", OPT_TWIST(HERMITE, MIDPOINTS, ZERO), 1, 0, 1,
     "as hermite with twist zero (only the bilinear map's own g . x_st)"},
};
const int bench_nmethods = (int)(sizeof bench_methods / sizeof bench_methods[0]);

int bench_method_find(const char *name) {
    for (int i = 0; i < bench_nmethods; i++)
        if (strcmp(bench_methods[i].name, name) == 0) return i;
    return -1;
}

#define DISC(n) {TC_SCENE_MESH_DISC, n, 0, 0}
#define UNIFORM(n) {TC_SCENE_MESH_UNIFORM, n, 0, 0}
/* Adaptive: a 4 x 4 start grid split at most 6 times (finest cells 1/256). */
#define ADAPTIVE(t) {TC_SCENE_MESH_ADAPTIVE, 4, t, 6}

const bench_mesh_spec bench_meshes[] = {
    DISC(1),     DISC(2),      DISC(4),      DISC(8),        DISC(16),      DISC(32),
    UNIFORM(4),  UNIFORM(8),   UNIFORM(16),  UNIFORM(32),    UNIFORM(64),   UNIFORM(128), UNIFORM(256),
    ADAPTIVE(0.4), ADAPTIVE(0.2), ADAPTIVE(0.1), ADAPTIVE(0.05), ADAPTIVE(0.025),
};
const int bench_nmeshes = (int)(sizeof bench_meshes / sizeof bench_meshes[0]);

void bench_mesh_label(const bench_mesh_spec *m, char *buf, unsigned n) {
    if (m->kind == TC_SCENE_MESH_ADAPTIVE) snprintf(buf, n, "adaptive t=%g", m->threshold);
    else snprintf(buf, n, "%s N=%d", tc_scene_mesh_kind_name(m->kind), m->density);
}

/* On the surfaces tangents are "auto": no midpoint samples and no gradients are
 * sent, so every cubic estimates its tangent planes, as with real front-ends. */
const bench_surface_method bench_surface_methods[] = {
    {"clough-tocher", {.method = TC_METHOD_CLOUGH_TOCHER}, "the default: range local, cross_boundary normal"},
    {"ct-free", {.method = TC_METHOD_CLOUGH_TOCHER, .range = TC_RANGE_FREE}, "range free: the unlimited cubic"},
    {"ct-affine", {.method = TC_METHOD_CLOUGH_TOCHER, .cross_boundary = TC_CROSS_AFFINE},
     "range local, cross_boundary affine"},
    {"linear", {.method = TC_METHOD_LINEAR}, "piecewise linear (Gouraud)"},
};
const int bench_nsurface_methods = (int)(sizeof bench_surface_methods / sizeof bench_surface_methods[0]);

int bench_surface_method_find(const char *name) {
    for (int i = 0; i < bench_nsurface_methods; i++)
        if (strcmp(bench_surface_methods[i].name, name) == 0) return i;
    return -1;
}

/* Without C0 flags, as the real format sends them: where the free cubic fails. */
const bench_surface_picture bench_surface_pictures[] = {
    {"square-light", 1}, {"penumbra", 1}, {"box", 1}, {"stiff-corner", 1},
};
const int bench_nsurface_pictures = (int)(sizeof bench_surface_pictures / sizeof bench_surface_pictures[0]);
