/* report.c — `build/report`: measures every method on every mesh of every reference
 * scene, and the realistic surfaces, into CSV, PNG and run.json (bench/report.py presents them). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "images.h"
#include "measure.h"
#include "plan.h"
#include "results.h"
#include "runinfo.h"
#include "surfaces.h"
#include "util.h"

static const char usage[] =
    "usage: build/report [--out DIR] [--scenes a,b,...] [--max-density N] [--min-threshold T]\n"
    "                    [--surfaces a,b,...|none]\n"
    "  Writes into DIR (default docs/report): results.csv, surfaces.csv, run.json, per scene\n"
    "  the scanline CSV and PNG image rows, per pictured surface its PNG rows.\n"
    "  --scenes, --max-density (disc and uniform meshes denser than N are left out),\n"
    "  --min-threshold (adaptive meshes finer than T are left out) and --surfaces cut the\n"
    "  run down for quick looks. bench/report.py then writes the report from DIR.\n";

typedef struct {
    const char *out, *surfaces; /* surfaces: a comma list, NULL = all, "none" */
    int scene_on[TC_SCENE_COUNT];
    int max_density;
    double min_threshold;
} args;

static int parse_scenes(const char *v, args *a) {
    for (int s = 0; s < TC_SCENE_COUNT; s++) a->scene_on[s] = 0;
    char buf[256];
    snprintf(buf, sizeof buf, "%s", v);
    for (char *tok = strtok(buf, ","); tok; tok = strtok(NULL, ",")) {
        tc_scene_id id;
        if (tc_scene_parse(tok, &id) != 0) {
            fprintf(stderr, "report: unknown scene '%s'\n", tok);
            return -1;
        }
        a->scene_on[id] = 1;
    }
    return 0;
}

static int parse_args(int argc, char **argv, args *a) {
    a->out = "docs/report", a->surfaces = NULL, a->max_density = 1 << 20, a->min_threshold = 0;
    for (int s = 0; s < TC_SCENE_COUNT; s++) a->scene_on[s] = 1;
    for (int i = 1; i < argc; i++) {
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        int st = 0;
        if (!v) st = -1;
        else if (!strcmp(argv[i], "--out")) a->out = v;
        else if (!strcmp(argv[i], "--max-density")) a->max_density = atoi(v);
        else if (!strcmp(argv[i], "--min-threshold")) a->min_threshold = atof(v);
        else if (!strcmp(argv[i], "--surfaces")) a->surfaces = v;
        else if (!strcmp(argv[i], "--scenes")) st = parse_scenes(v, a);
        else st = -1;
        if (st != 0) {
            fputs(usage, stderr);
            return -1;
        }
        i++;
    }
    return 0;
}

static int mesh_wanted(const args *a, const bench_mesh_spec *m) {
    return m->kind == TC_SCENE_MESH_ADAPTIVE ? m->threshold >= a->min_threshold : m->density <= a->max_density;
}

/* The quad version of a disc or uniform mesh (same cells, one quad each) for
 * the methods that run on quads; NULL with the reason in note otherwise. */
static tc_scene_mesh *quad_version(const tc_scene *s, tc_scene_mesh_opts o, char *note, size_t n) {
    tc_scene_mesh *q = NULL;
    int need = 0;
    for (int m = 0; m < bench_nmethods; m++) need |= bench_methods[m].quads;
    o.quads = 1;
    const char *why = tc_scene_mesh_opts_check(&o);
    int st = !need || why ? TC_EINVAL : tc_scene_mesh_new(s, &o, &q);
    if (st != TC_OK) snprintf(note, n, "needs a quad mesh: %s", why ? why : "tc_scene_mesh_new failed");
    return q;
}

/* The exact B's own overshoot on the mesh, into every row of it (from the
 * first method that runs on triangles: a quad version is the same cells). */
static void exact_overshoot(bench_results *rs, int first, const bench_reference *ref, const bench_pending *pend) {
    tc_overshoot_stats o;
    int m = 0;
    while (m < bench_nmethods && (!pend[m].active || bench_methods[m].quads)) m++;
    if (m == bench_nmethods) return;
    bench_exact_overshoot(ref, &pend[m].p, &o);
    for (int k = 0; k < bench_nmethods; k++) rs->r[first + k].exact_over = o;
}

/* Every method on one mesh of one scene. Returns -1 only when out of memory. */
static int measure_mesh(bench_results *rs, const bench_reference *ref, int mesh, const char *figdir, int *images_ok) {
    const tc_scene *s = ref->scene;
    const bench_mesh_spec *spec = &bench_meshes[mesh];
    char label[64];
    bench_mesh_label(spec, label, sizeof label);
    tc_scene_mesh_opts o;
    tc_scene_mesh_opts_default(&o);
    o.kind = spec->kind, o.density = spec->density, o.midpoints = 1, o.gradients = 0;
    if (spec->kind == TC_SCENE_MESH_ADAPTIVE) o.threshold = spec->threshold, o.max_depth = spec->max_depth;
    for (int m = 0; m < bench_nmethods; m++) o.gradients |= bench_methods[m].gradients;
    double t0 = bench_now_ms();
    tc_scene_mesh *sm = NULL, *sq = NULL;
    char qnote[200] = "";
    int st = tc_scene_mesh_new(s, &o, &sm);
    if (st == TC_OK) sq = quad_version(s, o, qnote, sizeof qnote);
    double gen_ms = bench_now_ms() - t0;
    int first = rs->n;
    for (int m = 0; m < bench_nmethods; m++) {
        bench_result *r = bench_results_add(rs);
        if (!r) {
            tc_scene_mesh_free(sm), tc_scene_mesh_free(sq);
            return -1;
        }
        r->scene = (int)s->id, r->mesh = mesh, r->method = m;
        if (st != TC_OK) snprintf(r->note, sizeof r->note, "tc_scene_mesh_new failed with status %d", st);
    }
    bench_pending pend[BENCH_MAX_METHODS];
    for (int m = 0; st == TC_OK && m < bench_nmethods; m++) {
        const tc_scene_mesh *use = bench_methods[m].quads ? sq : sm;
        int ok = use != NULL;
        if (!ok) { /* a pair that cannot run: skipped with the reason, like a refusal */
            memset(&pend[m], 0, sizeof pend[m]);
            snprintf(rs->r[first + m].note, sizeof rs->r[first + m].note, "%s", qnote);
        } else {
            ok = bench_measure_begin(ref, use, m, &rs->r[first + m], &pend[m]) == 0;
        }
        if (!ok)
            fprintf(stderr, "          %s %s %s: skipped: %s\n", tc_scene_name(s->id), label, bench_methods[m].name,
                    rs->r[first + m].note);
    }
    if (st == TC_OK) exact_overshoot(rs, first, ref, pend);
    for (int round = 0; st == TC_OK && round < BENCH_ROUNDS; round++)
        for (int m = 0; m < bench_nmethods; m++) bench_measure_round(ref, &pend[m], round);
    for (int m = 0; st == TC_OK && m < bench_nmethods; m++) bench_measure_end(&pend[m], &rs->r[first + m]);
    if (st != TC_OK) {
        bench_log("%s %s: tc_scene_mesh_new failed with status %d; all methods skipped", tc_scene_name(s->id), label,
                  st);
        return 0;
    }
    const bench_result *lin = bench_results_find(rs, (int)s->id, mesh, bench_method_find(M_LINEAR), 1);
    const bench_result *ct = bench_results_find(rs, (int)s->id, mesh, bench_method_find(M_CT), 1);
    bench_log("%-12s %-16s %6d verts %7d tris  mesh %6.0f ms  mean rel: linear %.3g, clough-tocher %.3g  (%.1f s)",
              tc_scene_name(s->id), label, (int)sm->desc.nverts, (int)sm->desc.ntris, gen_ms,
              lin ? lin->err.mean_rel : -1, ct ? ct->err.mean_rel : -1, (bench_now_ms() - t0) / 1e3);
    if (spec->kind == TC_SCENE_MESH_DISC && spec->density == BENCH_FIG_DENSITY)
        if (bench_images_write(s, sm, figdir) != 0) *images_ok = 0;
    tc_scene_mesh_free(sm);
    tc_scene_mesh_free(sq);
    return 0;
}

/* Every wanted mesh of scene sid, then its scanline CSV. 0, or -1. */
static int measure_scene(bench_results *rs, const args *a, int sid, bench_run_info *info) {
    tc_scene s;
    tc_scene_init(&s, (tc_scene_id)sid);
    bench_reference ref;
    if (bench_reference_init(&ref, &s) != TC_OK) return -1;
    int fail = 0;
    for (int i = 0; i < bench_nmeshes && !fail; i++)
        if (mesh_wanted(a, &bench_meshes[i])) fail = measure_mesh(rs, &ref, i, a->out, &info->images_ok) != 0;
    char path[1100];
    snprintf(path, sizeof path, "%s/%s-scanline.csv", a->out, tc_scene_name(s.id));
    if (!fail) fail = bench_scanlines_write_csv(rs, sid, ref.scan_xy, ref.scan_ref, path) != 0;
    bench_reference_free(&ref);
    return fail ? -1 : 0;
}

int main(int argc, char **argv) {
    args a;
    if (parse_args(argc, argv, &a) != 0) return 2;
    if (bench_nmethods > BENCH_MAX_METHODS) {
        fprintf(stderr, "report: %d methods in bench/plan.c; at most %d\n", bench_nmethods, BENCH_MAX_METHODS);
        return 1;
    }
    bench_log_start();
    if (bench_mkdirs(a.out) != 0) {
        fprintf(stderr, "report: cannot create %s\n", a.out);
        return 1;
    }
    bench_run_info info;
    bench_run_info_init(&info);
    bench_log("report: %d scenes x %d meshes x %d methods, W = %d, on %s (%d cores)", TC_SCENE_COUNT, bench_nmeshes,
              bench_nmethods, BENCH_W, info.machine, info.nproc);
    bench_results rs = {0};
    int fail = 0;
    for (int sid = 0; sid < TC_SCENE_COUNT && !fail; sid++)
        if (a.scene_on[sid]) fail = measure_scene(&rs, &a, sid, &info) != 0;
    char path[1100];
    snprintf(path, sizeof path, "%s/results.csv", a.out);
    if (!fail) fail = bench_results_write_csv(&rs, path) != 0;
    int no_surfaces = a.surfaces && !strcmp(a.surfaces, "none");
    if (!fail && !no_surfaces) fail = bench_surfaces_run(a.surfaces, a.out, &info.images_ok) != 0;
    snprintf(path, sizeof path, "%s/surfaces.csv", a.out);
    if (no_surfaces) remove(path); /* an earlier run's would be read as this one's */
    info.total_s = bench_elapsed_s();
    snprintf(path, sizeof path, "%s/run.json", a.out);
    if (!fail) fail = bench_run_info_write(&info, a.scene_on, path) != 0;
    int skipped = 0;
    for (int i = 0; i < rs.n; i++) skipped += !rs.r[i].ok;
    if (fail) fprintf(stderr, "report: failed (out of memory or a file could not be written)\n");
    else bench_log("wrote %s/ (%d rows, %d skipped)", a.out, rs.n, skipped);
    bench_results_free(&rs);
    return fail ? 1 : 0;
}
