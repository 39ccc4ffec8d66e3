/* analysis.c — numbers derived from the measurements for the figures and the
 * prose: which meshes to show, sample-count matches, convergence slopes. */
#include "analysis.h"

#include <math.h>

int bench_mesh_find(tc_scene_mesh_kind kind, int density) {
    for (int i = 0; i < bench_nmeshes; i++)
        if (bench_meshes[i].kind == kind && kind != TC_SCENE_MESH_ADAPTIVE && bench_meshes[i].density == density)
            return i;
    return -1;
}

int bench_mesh_find_adaptive(double threshold) {
    for (int i = 0; i < bench_nmeshes; i++)
        if (bench_meshes[i].kind == TC_SCENE_MESH_ADAPTIVE && bench_meshes[i].threshold == threshold) return i;
    return -1;
}

void bench_match_uniform(const bench_results *rs, int scene, int method, double target, bench_match *out) {
    *out = (bench_match){0, NAN, NAN, NAN, -1, -1, -1, INFINITY, 0};
    int prev = -1; /* the last uniform mesh (in density order) still above target */
    for (int i = 0; i < bench_nmeshes; i++) {
        if (bench_meshes[i].kind != TC_SCENE_MESH_UNIFORM) continue;
        const bench_result *r = bench_results_find(rs, scene, i, method, 1);
        if (!r) continue;
        if (r->err.mean_rel < out->best_mrel)
            out->best_mrel = r->err.mean_rel, out->best_mesh = i, out->best_samples = r->samples;
        if (out->found) continue;
        if (r->err.mean_rel > target) {
            prev = i;
            continue;
        }
        out->found = 1, out->hi_mesh = i, out->lo_mesh = prev;
        if (prev < 0) {
            out->samples = (double)r->samples, out->N = bench_meshes[i].density;
            out->run_ms = bench_result_run_ms(r);
            continue;
        }
        const bench_result *p = bench_results_find(rs, scene, prev, method, 1);
        double t = (log(target) - log(p->err.mean_rel)) / (log(r->err.mean_rel) - log(p->err.mean_rel));
        out->samples = exp(log((double)p->samples) + t * (log((double)r->samples) - log((double)p->samples)));
        out->N = exp(log(bench_meshes[prev].density) + t * (log(bench_meshes[i].density) - log(bench_meshes[prev].density)));
        double ra = bench_result_run_ms(p), rb = bench_result_run_ms(r);
        out->run_ms = exp(log(ra) + t * (log(rb) - log(ra)));
    }
}

double bench_slope(const bench_results *rs, int scene, tc_scene_mesh_kind kind, int method, int min_density,
                   int *npoints) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int n = 0;
    for (int i = 0; i < bench_nmeshes; i++) {
        if (bench_meshes[i].kind != kind || bench_meshes[i].density < min_density) continue;
        const bench_result *r = bench_results_find(rs, scene, i, method, 1);
        if (!r || !(r->err.mean_rel > 0)) continue;
        double x = log((double)r->samples), y = log(r->err.mean_rel);
        sx += x, sy += y, sxx += x * x, sxy += x * y, n++;
    }
    if (npoints) *npoints = n;
    double den = n * sxx - sx * sx;
    return n >= 2 && den > 0 ? (n * sxy - sx * sy) / den : NAN;
}

int bench_scan_uniform_mesh(const bench_results *rs, int scene, int disc_mesh) {
    const bench_result *ct = bench_results_find(rs, scene, disc_mesh, bench_method_find(M_CT), 1);
    int lin = bench_method_find(M_LINEAR), best = -1;
    if (!ct) return -1;
    double want = log(BENCH_SCAN_UNIFORM_FACTOR * (double)ct->samples), dbest = INFINITY;
    for (int i = 0; i < bench_nmeshes; i++) {
        if (bench_meshes[i].kind != TC_SCENE_MESH_UNIFORM) continue;
        const bench_result *r = bench_results_find(rs, scene, i, lin, 1);
        if (!r) continue;
        double d = fabs(log((double)r->samples) - want);
        if (d < dbest) dbest = d, best = i;
    }
    return best;
}
