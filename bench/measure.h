/* measure.h — the measurement of one method on one scene mesh: build and render
 * times, errors against the exact radiosity at the pixel centres, overshoot, the scanline. */
#ifndef BENCH_MEASURE_H
#define BENCH_MEASURE_H

#include <stddef.h>
#include <stdint.h>

#include "plan.h"
#include "results.h"
#include "scenes/meshing.h"
#include "scenes/scene.h"

/* What every method of a scene is compared against, computed once per scene. */
typedef struct {
    const tc_scene *scene;
    tc_viewport vp;   /* W x W over the scene's domain */
    double *xy;       /* [W*W][2] pixel centres, tc_viewport_pixel_center */
    double *ref;      /* [W*W] exact B there */
    double *scan_xy;  /* [BENCH_SCAN_N][2] (BENCH_SCAN_X, y), y increasing */
    double *scan_ref; /* [BENCH_SCAN_N] exact B there */
    float *tile;      /* [W*W] scratch for tc_render */
    int32_t *owner;   /* [W*W] scratch for the untimed render's owners */
} bench_reference;

int bench_reference_init(bench_reference *ref, const tc_scene *s);
void bench_reference_free(bench_reference *ref);

/* One method's view of a scene mesh: its core mesh, locator and reconstruction. */
typedef struct {
    tc_mesh *mesh;
    tc_locator *loc;
    tc_recon *recon;
} bench_prepared;

/* The samples method bm takes on sm: all of sm's value samples except the
 * midpoint samples when bm does not use them. */
int64_t bench_method_samples(const tc_scene_mesh *sm, const bench_method *bm);
int64_t bench_method_gradient_samples(const tc_scene_mesh *sm, const bench_method *bm);

/* Gives bm what it uses of sm (midpoints and gradients stripped otherwise; sm
 * is the quad version of the mesh for a method that runs on quads), then
 * tc_mesh_new, tc_locator_new (their time in *mesh_ms when not NULL) and one
 * tc_recon_new. 0, or -1 with the reason in note (nothing left allocated). */
int bench_prepare(const tc_scene_mesh *sm, const bench_method *bm, bench_prepared *p, double *mesh_ms, char *note,
                  size_t notelen);
void bench_prepared_free(bench_prepared *p);

/* Measuring the methods of one mesh, with their timings interleaved so that
 * a burst of other load on the machine hits every method alike:
 *   bench_measure_begin for each method (prepare, errors, scanline, and one
 *     untimed render with owners for the overshoot and the box's corner share),
 *   bench_measure_round for round = 0 .. BENCH_ROUNDS-1, each over all methods
 *     (one tc_recon_new batch and, in the first BENCH_RENDER_REPS rounds,
 *     one tc_render),
 *   bench_measure_end for each (medians into out, frees).
 * out's scene and mesh are the caller's to set. begin returns -1 (out->ok = 0,
 * a note) for a pair that cannot run; round and end then do nothing. */
typedef struct {
    int method, active;
    bench_prepared p;
    int reps, batches;
    double build[BENCH_BUILD_BATCHES], render[BENCH_RENDER_REPS];
} bench_pending;

#define BENCH_ROUNDS (BENCH_BUILD_BATCHES > BENCH_RENDER_REPS ? BENCH_BUILD_BATCHES : BENCH_RENDER_REPS)

int bench_measure_begin(const bench_reference *ref, const tc_scene_mesh *sm, int method, bench_result *out,
                        bench_pending *pend);
void bench_measure_round(const bench_reference *ref, bench_pending *pend, int round);
void bench_measure_end(bench_pending *pend, bench_result *out);

/* The exact B's own excursion from the corner values of p's mesh (pixels
 * owned as tc_locate owns them), into *out. */
void bench_exact_overshoot(const bench_reference *ref, const bench_prepared *p, tc_overshoot_stats *out);

#endif
