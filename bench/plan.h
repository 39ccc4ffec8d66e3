/* plan.h — what the report measures: the one table of reconstruction methods,
 * the meshes of every scene, and which of them the tables and figures show. */
#ifndef BENCH_PLAN_H
#define BENCH_PLAN_H

#include "scenes/meshing.h"
#include "tocher.h"

/* Plot markers (svg.h draws them). */
typedef enum { MK_NONE = 0, MK_CIRCLE, MK_SQUARE, MK_TRIANGLE, MK_DIAMOND, MK_DOWN, MK_PLUS, MK_CROSS, MK_STAR } bench_marker;

/* One reconstruction the report compares. A new method is one more line of
 * bench_methods[] in plan.c. */
typedef struct {
    const char *name;     /* label in tables, plots and results.csv */
    tc_options opt;       /* what tc_recon_new is asked for */
    int midpoints;        /* uses the edge-midpoint samples (counted in its samples) */
    int gradients;        /* uses the corner gradients (counted as gradient samples) */
    int quads;            /* runs on the quad version of the mesh (the same cells, one
                           * quad each; disc and uniform meshes only) */
    const char *color;    /* plot colour */
    bench_marker marker;  /* plot marker */
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

/* The disc density of the per-scene tables, the scanline profile and the prose,
 * and the one of the side-by-side images. */
#define BENCH_REP_DENSITY 8
#define BENCH_FIG_DENSITY 2
#define BENCH_FIG_PANEL 384    /* pixels per side of each image panel */
#define BENCH_ERR_GAIN 10.0    /* error maps show gain * |ref - rec| / scale */

/* The scanline profile also shows linear on the uniform mesh whose sample count
 * is nearest (in log) to this many times clough-tocher's on the disc mesh. */
#define BENCH_SCAN_UNIFORM_FACTOR 15.0

/* The box scene: how near a footprint corner a pixel must be to count as "at
 * the corners" (results.h, corner_share). */
#define BENCH_CORNER_RADIUS 0.05

#endif
