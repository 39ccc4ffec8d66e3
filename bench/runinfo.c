/* runinfo.c — run.json: what the presentation script (bench/report.py) needs beyond
 * the CSVs: the machine and tree, the run's constants, the methods, scenes and surfaces. */
#include "runinfo.h"

#include <cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "plan.h"
#include "scenes/surfaces.h"
#include "surface_images.h"
#include "util.h"

void bench_run_info_init(bench_run_info *info) {
    memset(info, 0, sizeof *info);
    info->images_ok = 1;
    snprintf(info->machine, sizeof info->machine, "unknown CPU");
    FILE *f = fopen("/proc/cpuinfo", "r");
    char line[512];
    while (f && fgets(line, sizeof line, f)) {
        char *p = strchr(line, ':');
        if (strncmp(line, "model name", 10) != 0 || !p) continue;
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

/* The plan's constants, under the names the script uses. */
static cJSON *constants(void) {
    cJSON *c = cJSON_CreateObject();
    const struct { const char *k; double v; } kv[] = {
        {"W", BENCH_W}, {"render_reps", BENCH_RENDER_REPS}, {"build_batches", BENCH_BUILD_BATCHES},
        {"build_batch_ms", BENCH_BUILD_BATCH_MS}, {"build_big_ms", BENCH_BUILD_BIG_MS}, {"scan_x", BENCH_SCAN_X},
        {"scan_n", BENCH_SCAN_N}, {"rep_N", BENCH_REP_DENSITY}, {"fig_N", BENCH_FIG_DENSITY},
        {"fig_panel", BENCH_FIG_PANEL}, {"err_gain", BENCH_ERR_GAIN}, {"corner_radius", BENCH_CORNER_RADIUS},
        {"over_threshold", BENCH_OVER_THRESHOLD}, {"surf_W", BENCH_SURF_W}, {"surf_panel", BENCH_SURF_PANEL},
    };
    for (size_t i = 0; i < sizeof kv / sizeof kv[0]; i++) cJSON_AddNumberToObject(c, kv[i].k, kv[i].v);
    return c;
}

/* An option's name, or null when the method does not read it. */
static void add_option(cJSON *o, const char *key, unsigned reads, unsigned bit, const char *name) {
    if (reads & bit) cJSON_AddStringToObject(o, key, name);
    else cJSON_AddNullToObject(o, key);
}

static cJSON *options(const tc_options *opt) {
    cJSON *o = cJSON_CreateObject();
    unsigned r = tc_method_reads(opt->method);
    cJSON_AddStringToObject(o, "method", tc_method_name(opt->method));
    add_option(o, "cross_boundary", r, TC_READS_CROSS_BOUNDARY, tc_cross_name(opt->cross_boundary));
    add_option(o, "wedges", r, TC_READS_WEDGES, tc_wedges_name(opt->wedges));
    add_option(o, "tangents", r, TC_READS_TANGENTS, tc_tangents_name(opt->tangents));
    add_option(o, "twist", r, TC_READS_TWIST, tc_twist_name(opt->twist));
    add_option(o, "average", r, TC_READS_AVERAGE, tc_average_name(opt->average));
    add_option(o, "range", r, TC_READS_RANGE, tc_range_name(opt->range));
    return o;
}

static cJSON *methods(void) {
    cJSON *a = cJSON_CreateArray();
    for (int m = 0; m < bench_nmethods; m++) {
        const bench_method *bm = &bench_methods[m];
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "name", bm->name);
        cJSON_AddItemToObject(o, "options", options(&bm->opt));
        cJSON_AddBoolToObject(o, "midpoints", bm->midpoints);
        cJSON_AddBoolToObject(o, "gradients", bm->gradients);
        cJSON_AddBoolToObject(o, "quads", bm->quads);
        cJSON_AddStringToObject(o, "what", bm->what);
        cJSON_AddItemToArray(a, o);
    }
    return a;
}

static cJSON *meshes(void) {
    cJSON *a = cJSON_CreateArray();
    for (int i = 0; i < bench_nmeshes; i++) {
        const bench_mesh_spec *m = &bench_meshes[i];
        cJSON *o = cJSON_CreateObject();
        char label[64];
        bench_mesh_label(m, label, sizeof label);
        cJSON_AddStringToObject(o, "label", label);
        cJSON_AddStringToObject(o, "kind", tc_scene_mesh_kind_name(m->kind));
        cJSON_AddNumberToObject(o, "density", m->density);
        cJSON_AddNumberToObject(o, "threshold", m->threshold);
        cJSON_AddNumberToObject(o, "max_depth", m->max_depth);
        cJSON_AddItemToArray(a, o);
    }
    return a;
}

static cJSON *numbers(const double *v, int n) {
    cJSON *a = cJSON_CreateArray();
    for (int i = 0; i < n; i++) cJSON_AddItemToArray(a, cJSON_CreateNumber(v[i]));
    return a;
}

static cJSON *scene(const tc_scene *s) {
    cJSON *o = cJSON_CreateObject(), *ev = cJSON_CreateArray();
    cJSON_AddStringToObject(o, "name", tc_scene_name(s->id));
    cJSON_AddStringToObject(o, "summary", tc_scene_summary(s->id));
    cJSON_AddNumberToObject(o, "scale", s->scale);
    cJSON_AddItemToObject(o, "domain", numbers(s->domain, 4));
    for (int i = 0; i < s->nevents; i++) {
        const tc_scene_event *e = &s->events[i];
        cJSON *x = cJSON_CreateObject();
        cJSON_AddStringToObject(x, "kind", e->kind == TC_CM1 ? "C-1" : "C0");
        cJSON_AddNumberToObject(x, "axis", e->axis);
        cJSON_AddNumberToObject(x, "at", e->at);
        cJSON_AddNumberToObject(x, "lo", e->lo);
        cJSON_AddNumberToObject(x, "hi", e->hi);
        cJSON_AddItemToArray(ev, x);
    }
    cJSON_AddItemToObject(o, "events", ev);
    return o;
}

static cJSON *scenes(const int *scene_on) {
    cJSON *a = cJSON_CreateArray();
    for (int id = 0; id < TC_SCENE_COUNT; id++) {
        tc_scene s;
        if (scene_on[id] && tc_scene_init(&s, (tc_scene_id)id) == TC_OK) cJSON_AddItemToArray(a, scene(&s));
    }
    return a;
}

static cJSON *surfaces(void) {
    cJSON *a = cJSON_CreateArray();
    for (int i = 0; i < tc_dm_surface_count(); i++) {
        const tc_dm_surface *f = tc_dm_surface_get(i);
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "name", f->name);
        cJSON_AddStringToObject(o, "scene", tc_scene_name(f->scene));
        cJSON_AddItemToObject(o, "window", numbers(f->window, 4));
        cJSON_AddNumberToObject(o, "rotation", f->rotation);
        cJSON_AddNumberToObject(o, "density", f->density);
        cJSON_AddItemToArray(a, o);
    }
    return a;
}

static cJSON *surface_methods(void) {
    cJSON *a = cJSON_CreateArray();
    for (int k = 0; k < bench_nsurface_methods; k++) {
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "name", bench_surface_methods[k].name);
        cJSON_AddItemToObject(o, "options", options(&bench_surface_methods[k].opt));
        cJSON_AddStringToObject(o, "what", bench_surface_methods[k].what);
        cJSON_AddItemToArray(a, o);
    }
    return a;
}

/* The pictured surfaces, their files and the panels from left to right. */
static cJSON *pictures(void) {
    cJSON *o = cJSON_CreateObject(), *a = cJSON_CreateArray(), *panels = cJSON_CreateArray();
    const char *pictured[BENCH_SURF_NPICTURED] = BENCH_SURF_PICTURED;
    cJSON_AddItemToArray(panels, cJSON_CreateString("exact"));
    for (int k = 0; k < BENCH_SURF_NPICTURED; k++) cJSON_AddItemToArray(panels, cJSON_CreateString(pictured[k]));
    for (int i = 0; i < bench_nsurface_pictures; i++) {
        const bench_surface_picture *p = &bench_surface_pictures[i];
        cJSON *x = cJSON_CreateObject();
        char name[256];
        cJSON_AddStringToObject(x, "surface", p->surface);
        cJSON_AddBoolToObject(x, "c0_flags", !p->no_c0);
        bench_surface_image_name(p->surface, p->no_c0, "images", name, sizeof name);
        cJSON_AddStringToObject(x, "images", name);
        bench_surface_image_name(p->surface, p->no_c0, "excursion", name, sizeof name);
        cJSON_AddStringToObject(x, "excursion", name);
        cJSON_AddItemToArray(a, x);
    }
    cJSON_AddItemToObject(o, "panels", panels);
    cJSON_AddItemToObject(o, "surfaces", a);
    return o;
}

int bench_run_info_write(const bench_run_info *info, const int *scene_on, const char *path) {
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "machine", info->machine);
    cJSON_AddNumberToObject(o, "nproc", info->nproc);
    cJSON_AddStringToObject(o, "commit", info->commit);
    cJSON_AddNumberToObject(o, "total_s", info->total_s);
    cJSON_AddBoolToObject(o, "images_ok", info->images_ok);
    cJSON_AddItemToObject(o, "constants", constants());
    cJSON_AddItemToObject(o, "methods", methods());
    cJSON_AddItemToObject(o, "meshes", meshes());
    cJSON_AddItemToObject(o, "scenes", scenes(scene_on));
    cJSON_AddItemToObject(o, "surfaces", surfaces());
    cJSON_AddItemToObject(o, "surface_methods", surface_methods());
    cJSON_AddItemToObject(o, "surface_pictures", pictures());
    char *text = cJSON_Print(o);
    int st = text ? bench_write_file(path, text, strlen(text)) : -1;
    cJSON_free(text);
    cJSON_Delete(o);
    return st;
}
