/* results.h — one measured (scene, mesh, method) triple, the growing list of
 * them, look-ups by key, results.csv and the per-scene scanline CSV. */
#ifndef BENCH_RESULTS_H
#define BENCH_RESULTS_H

#include <stdint.h>

#include "plan.h"
#include "tocher.h"

typedef struct {
    int scene, mesh, method;   /* tc_scene_id, index in bench_meshes, in bench_methods */
    int ok;                    /* 0: the pair could not run; note says why */
    char note[320];
    int32_t nverts, ntris, flagged_c0, flagged_cm1;
    double worst_aspect;
    int64_t samples;           /* scene evaluations behind the values the method used */
    int64_t gradient_samples;  /* scene evaluations behind the gradients it used */
    double mesh_ms;            /* tc_mesh_new + tc_locator_new, one call each */
    double build_ms;           /* tc_recon_new, median per call */
    int build_reps;            /* calls per timed batch */
    double render_ms;          /* tc_render of the W x W tile, 1 thread, median */
    tc_error_stats err;        /* against B at the W x W pixel centres */
    tc_overshoot_stats over;   /* the W x W tile against its own triangles' corner
                                * values (threshold BENCH_OVER_THRESHOLD) */
    tc_overshoot_stats exact_over; /* the exact B's own, on the same mesh (the same
                                    * for every method of the mesh) */
    double *scan;              /* [BENCH_SCAN_N] |ref - rec| / scale along x = BENCH_SCAN_X */
    /* The tangent planes the method used at the triangle corners against the
     * scene's corner gradients (one-sided differences): has_tangents = 0 for
     * methods without tangent planes. The corner reported has the largest
     * tan_impact = the error its plane puts into a Bezier ordinate next to it,
     * |(g_used - g_scene) . (v - u)| / 3 over its two edges (B units);
     * there tan_max = |g_used - g_scene|, tan_scene = |g_scene|, tan_used =
     * |g_used| (B per unit length), at the point tan_at. tan_rms: of
     * |g_used - g_scene| over all corners. */
    int has_tangents;
    double tan_impact, tan_max, tan_rms, tan_at[2], tan_scene, tan_used;
    /* Scenes with a box: the share of the summed |ref - rec| over the pixels
     * that lies within BENCH_CORNER_RADIUS of the footprint's corners (from the
     * untimed render); NAN for other scenes. */
    double corner_share;
    /* The untimed render's summed squared error (ref - tile)^2, and the part of
     * it in pixels whose triangle shares a vertex with a flat one (all its
     * corner values equal): where a range-limited cubic must keep its planes
     * flat, so an unflagged step next to flat data cannot be followed steeply. */
    double sq_err, sq_err_by_flat;
} bench_result;

typedef struct {
    bench_result *r;
    int n, cap;
} bench_results;

/* A zeroed new entry (NULL when out of memory). */
bench_result *bench_results_add(bench_results *rs);
/* The entry for the triple, or NULL. ok_only: NULL also for skipped pairs. */
const bench_result *bench_results_find(const bench_results *rs, int scene, int mesh, int method, int ok_only);
void bench_results_free(bench_results *rs);
/* Build + render: the run time the plots use. */
double bench_result_run_ms(const bench_result *r);

/* results.csv: a header line, then one line per entry in the order measured. */
int bench_results_write_csv(const bench_results *rs, const char *path);

/* <scene>-scanline.csv: x, y, the exact B, then |ref - rec| / scale of every
 * method on the disc mesh N = BENCH_REP_DENSITY and of linear on every uniform
 * mesh, one column each, named "method@mesh label". */
int bench_scanlines_write_csv(const bench_results *rs, int scene, const double *scan_xy, const double *scan_ref,
                              const char *path);

#endif
