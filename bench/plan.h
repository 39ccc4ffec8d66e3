/* plan.h — what the report measures: the one table of reconstruction methods,
 * the meshes of every scene, the realistic surfaces, and which of them are pictured. */
#ifndef BENCH_PLAN_H
#define BENCH_PLAN_H

#include "scenes/meshing.h"
#include "tocher.h"

/* One reconstruction the report compares. A new method is one more line of
 * bench_methods[] in plan.c (its plot colour and marker, if not the default
 * cycle's, in bench/present/style.py). */
typedef struct {
    const char *name;     /* label in tables, plots and results.csv */
    tc_options opt;       /* what tc_recon_new is asked for */
    int midpoints;        /* uses the edge-midpoint samples (counted in its samples) */
    int gradients;        /* uses the corner gradients (counted as gradient samples) */
    int quads;            /* runs on the quad version of the mesh (the same cells, one
                           * quad each; disc and uniform meshes only) */
    const char *what;     /* one line for the report's method table */
} bench_method;

extern const bench_method bench_methods[];
extern const int bench_nmethods;
#define BENCH_MAX_METHODS 64 /* bench_nmethods may not exceed this */
/* Index of the method called name, or -1. */
int bench_method_find(const char *name);

/* The methods the figures and the prose single out (names from the table). */
#define M_LINEAR "linear"
#define M_CT "clough-tocher"
#define M_CT_C1 "clough-tocher-c1"

/* One mesh of a scene. */
typedef struct {
    tc_scene_mesh_kind kind;
    int density;      /* disc, uniform: N; adaptive: the start grid */
    double threshold; /* adaptive only */
    int max_depth;    /* adaptive only */
} bench_mesh_spec;

extern const bench_mesh_spec bench_meshes[];
extern const int bench_nmeshes;
/* "disc N=8", "uniform N=64", "adaptive t=0.05" */
void bench_mesh_label(const bench_mesh_spec *m, char *buf, unsigned n);

/* The render tile (W x W pixels over [0,1]^2), repetitions and the scanline. */
#define BENCH_W 512
#define BENCH_RENDER_REPS 3   /* tc_render timed this many times, median */
#define BENCH_BUILD_BATCHES 5 /* tc_recon_new: median of this many batches ... */
#define BENCH_BUILD_BATCH_MS 2.0 /* ... each repeating the call for at least this long */
#define BENCH_BUILD_BIG_MS 50.0  /* a single call longer than this: 3 batches of 1 */
#define BENCH_SCAN_X 0.5         /* the vertical scanline of the profiles */
#define BENCH_SCAN_N BENCH_W     /* points along it, at the pixel rows' y */

/* The disc density of the per-scene tables, the scanline profile and the prose
 * (every method's scanline on it is written), and the one of the side-by-side images. */
#define BENCH_REP_DENSITY 8
#define BENCH_FIG_DENSITY 2
#define BENCH_FIG_PANEL 384    /* pixels per side of each image panel */
#define BENCH_ERR_GAIN 10.0    /* error maps show gain * |ref - rec| / scale */

/* The box scene: how near a footprint corner a pixel must be to count as "at
 * the corners" (results.h, corner_share). */
#define BENCH_CORNER_RADIUS 0.05

/* Overshoot (tc_overshoot): a pixel is "beyond" when it leaves its own
 * triangle's corner values by more than this fraction of the data range R
 * (issue 12's measure). */
#define BENCH_OVER_THRESHOLD 0.05

/* The realistic discontinuity-meshed surfaces (src/scenes/surfaces.h), each
 * measured with and without C0 flags, as front-ends send them (estimated
 * tangents, 6 digits): these methods, plus the exact function's own excursion. */
typedef struct {
    const char *name; /* label in surfaces.csv and the report */
    tc_options opt;
    const char *what;
} bench_surface_method;

extern const bench_surface_method bench_surface_methods[];
extern const int bench_nsurface_methods;
/* Index of the surface method called name, or -1. */
int bench_surface_method_find(const char *name);

/* The surfaces pictured: exact | the methods of BENCH_SURF_PICTURED, and
 * their excursion maps. */
typedef struct {
    const char *surface; /* a tc_dm_surface name */
    int no_c0;
} bench_surface_picture;

extern const bench_surface_picture bench_surface_pictures[];
extern const int bench_nsurface_pictures;
#define BENCH_SURF_PICTURED {"ct-free", "clough-tocher", "linear"}
#define BENCH_SURF_NPICTURED 3
#define BENCH_SURF_W 512     /* the measured tile of a surface's window */
#define BENCH_SURF_PANEL 320 /* pixels per side of each pictured panel */

#endif
