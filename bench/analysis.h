/* analysis.h — numbers derived from the measurements for the figures and the
 * prose: which meshes to show, sample-count matches, convergence slopes. */
#ifndef BENCH_ANALYSIS_H
#define BENCH_ANALYSIS_H

#include <stdint.h>

#include "plan.h"
#include "results.h"

/* Index in bench_meshes of (kind, density) (adaptive: threshold), or -1. */
int bench_mesh_find(tc_scene_mesh_kind kind, int density);
int bench_mesh_find_adaptive(double threshold);

/* How many samples method needs on the uniform meshes of scene to reach a mean
 * relative error of target. found: 1 if some uniform density reaches it; then
 * samples/N are interpolated log-log between the last density above the target
 * (lo_mesh) and the first at or below it (hi_mesh), or are hi_mesh's own when
 * the coarsest already reaches it (lo_mesh = -1, so the figure is an upper
 * bound). best_*: the uniform mesh with the lowest error. */
typedef struct {
    int found;
    double samples, N, run_ms; /* run_ms interpolated like samples */
    int lo_mesh, hi_mesh;
    int best_mesh;
    double best_mrel;
    int64_t best_samples;
} bench_match;

void bench_match_uniform(const bench_results *rs, int scene, int method, double target, bench_match *out);

/* Least-squares slope of log(mean_rel) against log(samples) over the meshes of
 * kind with density >= min_density (disc/uniform) where method ran; NAN with
 * fewer than 2 points. *npoints receives the count used. */
double bench_slope(const bench_results *rs, int scene, tc_scene_mesh_kind kind, int method, int min_density,
                   int *npoints);

/* The uniform mesh whose linear sample count is nearest in log to
 * BENCH_SCAN_UNIFORM_FACTOR times clough-tocher's on the disc mesh disc_mesh;
 * -1 if neither ran. */
int bench_scan_uniform_mesh(const bench_results *rs, int scene, int disc_mesh);

#endif
