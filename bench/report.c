/* report.c — `build/report`: measures every method on every mesh of every
 * reference scene and writes docs/report.md, docs/report/ (CSV, SVG, PNG). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "images.h"
#include "markdown.h"
#include "measure.h"
#include "plots.h"
#include "plan.h"
#include "results.h"
#include "util.h"

static const char usage[] =
    "usage: build/report [--out DIR] [--template FILE] [--scenes a,b,...] [--max-density N]\n"
    "  Writes DIR/report.md (default DIR = docs) and DIR/report/: results.csv, per scene\n"
    "  SVG plots, the scanline CSV and PNG image rows. --scenes and --max-density cut the\n"
    "  run down for quick looks (uniform and disc meshes denser than N are left out).\n";

typedef struct {
    const char *out, *tmpl;
    int scene_on[TC_SCENE_COUNT];
    int max_density;
} args;

static int parse_args(int argc, char **argv, args *a) {
    a->out = "docs", a->tmpl = "bench/report.md.in", a->max_density = 1 << 20;
    for (int s = 0; s < TC_SCENE_COUNT; s++) a->scene_on[s] = 1;
    for (int i = 1; i < argc; i++) {
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(argv[i], "--out") && v) a->out = v, i++;
        else if (!strcmp(argv[i], "--template") && v) a->tmpl = v, i++;
        else if (!strcmp(argv[i], "--max-density") && v) a->max_density = atoi(v), i++;
        else if (!strcmp(argv[i], "--scenes") && v) {
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
            i++;
        } else {
            fputs(usage, stderr);
            return -1;
        }
    }
    return 0;
}

static void machine_info(bench_run_info *info) {
    snprintf(info->machine, sizeof info->machine, "unknown CPU");
    FILE *f = fopen("/proc/cpuinfo", "r");
    char line[512];
    while (f && fgets(line, sizeof line, f)) {
        if (strncmp(line, "model name", 10) != 0) continue;
        char *p = strchr(line, ':');
        if (!p) continue;
        for (p++; *p == ' ' || *p == '\t'; p++) {}
        p[strcspn(p, "\r\n")] = '\0';
        snprintf(info->machine, sizeof info->machine, "%s", p);
        break;
    }
    if (f) fclose(f);
    char n[32];
    bench_command_line("nproc 2>/dev/null", n, sizeof n, "0");
    info->nproc = atoi(n);
    /* "-dirty" only for changed sources: the report's own earlier outputs under docs/ do not count. */
    bench_command_line("c=$(git rev-parse --short HEAD 2>/dev/null) && { git diff --quiet HEAD -- . ':(exclude)docs'"
                       " 2>/dev/null || c=\"$c-dirty\"; echo \"$c\"; }",
                       info->commit, sizeof info->commit, "unknown");
}

static int mesh_wanted(const args *a, const bench_mesh_spec *m) {
    return m->kind == TC_SCENE_MESH_ADAPTIVE || m->density <= a->max_density;
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

int main(int argc, char **argv) {
    args a;
    if (parse_args(argc, argv, &a) != 0) return 2;
    if (bench_nmethods > BENCH_MAX_METHODS) {
        fprintf(stderr, "report: %d methods in bench/plan.c; at most %d\n", bench_nmethods, BENCH_MAX_METHODS);
        return 1;
    }
    bench_log_start();
    char figdir[1024], path[1100];
    snprintf(figdir, sizeof figdir, "%s/report", a.out);
    if (bench_mkdirs(figdir) != 0) {
        fprintf(stderr, "report: cannot create %s\n", figdir);
        return 1;
    }
    bench_run_info info = {0};
    machine_info(&info);
    info.fig_rel = "report";
    info.images_ok = 1;
    bench_log("report: %d scenes x %d meshes x %d methods, W = %d, on %s (%d cores)", TC_SCENE_COUNT, bench_nmeshes,
              bench_nmethods, BENCH_W, info.machine, info.nproc);
    bench_results rs = {0};
    int fail = 0;
    for (int sid = 0; sid < TC_SCENE_COUNT && !fail; sid++) {
        if (!a.scene_on[sid]) continue;
        tc_scene s;
        tc_scene_init(&s, (tc_scene_id)sid);
        bench_reference ref;
        if (bench_reference_init(&ref, &s) != TC_OK) {
            fail = 1;
            break;
        }
        for (int i = 0; i < bench_nmeshes && !fail; i++)
            if (mesh_wanted(&a, &bench_meshes[i])) fail = measure_mesh(&rs, &ref, i, figdir, &info.images_ok) != 0;
        if (!fail && bench_plots_write(&rs, &ref, figdir) != 0) fail = 1;
        bench_reference_free(&ref);
    }
    if (fail) {
        fprintf(stderr, "report: failed (out of memory or a file could not be written)\n");
        bench_results_free(&rs);
        return 1;
    }
    snprintf(path, sizeof path, "%s/results.csv", figdir);
    int st = bench_results_write_csv(&rs, path);
    info.total_s = bench_elapsed_s();
    snprintf(path, sizeof path, "%s/report.md", a.out);
    int md = bench_markdown_write(&rs, &info, a.tmpl, path);
    if (md < 0) st = -1;
    int skipped = 0;
    for (int i = 0; i < rs.n; i++) skipped += !rs.r[i].ok;
    bench_log("wrote %s and %s/ (%d rows, %d skipped)%s", path, figdir, rs.n, skipped,
              md > 0 ? "; the template has unknown keys (marked {{?key}})" : "");
    fprintf(stderr, "report: total run time %.1f s\n", bench_elapsed_s());
    bench_results_free(&rs);
    return st ? 1 : 0;
}
