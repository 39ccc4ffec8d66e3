/* plots.c — the per-scene figures built from the results: mean relative error
 * against run time and against samples, and the scanline error profile. */
#include "plots.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "analysis.h"
#include "io/strbuf.h"
#include "svg.h"
#include "util.h"

#define DASHED "7,4"
#define DOTTED "2,3"

/* One curve: method over the meshes of kind, in plan order; x = run time
 * (by_time) or samples, y = mean relative error. */
static void add_curve(svg_plot *p, const bench_results *rs, int scene, int method, tc_scene_mesh_kind kind,
                      int by_time, const char *label, const char *dash) {
    double x[64], y[64];
    int n = 0;
    for (int i = 0; i < bench_nmeshes && n < 64; i++) {
        if (bench_meshes[i].kind != kind) continue;
        const bench_result *r = bench_results_find(rs, scene, i, method, 1);
        if (!r) continue;
        x[n] = by_time ? bench_result_run_ms(r) : (double)r->samples;
        y[n++] = r->err.mean_rel;
    }
    const bench_method *bm = &bench_methods[method];
    if (n) svg_plot_series(p, label, bm->color, dash, bm->marker, dash ? 1.3 : 1.8, n, x, y);
}

static int error_plot(const bench_results *rs, int scene, int by_time, const char *path) {
    const char *name = tc_scene_name((tc_scene_id)scene);
    char title[160];
    snprintf(title, sizeof title, "%s: mean relative error against %s", name, by_time ? "run time" : "samples");
    svg_plot *p = svg_plot_new(title, by_time ? "run time: tc_recon_new + tc_render 512x512, 1 thread (ms)"
                                              : "samples taken (scene evaluations; gradients not counted)",
                               "mean relative error |ref - rec| / scale", 1, 1);
    if (!p) return -1;
    for (int m = 0; m < bench_nmethods; m++)
        add_curve(p, rs, scene, m, TC_SCENE_MESH_DISC, by_time, bench_methods[m].name, NULL);
    const char *extra[] = {M_LINEAR, M_CT};
    for (int k = 0; k < 2; k++) {
        int m = bench_method_find(extra[k]);
        char label[96];
        snprintf(label, sizeof label, "%s, uniform", extra[k]);
        add_curve(p, rs, scene, m, TC_SCENE_MESH_UNIFORM, by_time, label, DASHED);
        snprintf(label, sizeof label, "%s, adaptive", extra[k]);
        add_curve(p, rs, scene, m, TC_SCENE_MESH_ADAPTIVE, by_time, label, DOTTED);
    }
    svg_plot_note(p, "Solid: discontinuity meshes N = 1..32. Dashed: uniform N = 4..256. Dotted: adaptive, "
                     "threshold 0.4..0.025. One run; times are medians.");
    int st = svg_plot_write(p, path);
    svg_plot_free(p);
    return st;
}

/* The profile's curves: linear, clough-tocher-c1, clough-tocher on the disc
 * mesh, linear on the uniform mesh bench_scan_uniform_mesh picks. */
typedef struct {
    const bench_result *r;
    char label[96];
    const char *dash;
} curve;

static int profile_curves(const bench_results *rs, int scene, curve c[4]) {
    int disc = bench_mesh_find(TC_SCENE_MESH_DISC, BENCH_REP_DENSITY);
    const char *names[3] = {M_LINEAR, M_CT_C1, M_CT};
    int n = 0;
    for (int k = 0; k < 3; k++) {
        const bench_result *r = bench_results_find(rs, scene, disc, bench_method_find(names[k]), 1);
        if (!r) continue;
        c[n].r = r, c[n].dash = NULL;
        snprintf(c[n++].label, sizeof c[0].label, "%s, disc N=%d (%lld)", names[k], BENCH_REP_DENSITY,
                 (long long)r->samples);
    }
    int u = bench_scan_uniform_mesh(rs, scene, disc);
    const bench_result *r = u >= 0 ? bench_results_find(rs, scene, u, bench_method_find(M_LINEAR), 1) : NULL;
    if (r) {
        c[n].r = r, c[n].dash = DASHED;
        snprintf(c[n++].label, sizeof c[0].label, "linear, uniform N=%d (%lld)", bench_meshes[u].density,
                 (long long)r->samples);
    }
    return n;
}

static int profile_plot(const bench_reference *ref, const curve *c, int n, int scene, int ylog, const char *path) {
    char title[160];
    snprintf(title, sizeof title, "%s: relative error along x = %g%s", tc_scene_name((tc_scene_id)scene), BENCH_SCAN_X,
             ylog ? " (log scale)" : "");
    svg_plot *p = svg_plot_new(title, "y", "|ref - rec| / scale", 0, ylog);
    if (!p) return -1;
    double y[BENCH_SCAN_N], hi = 0;
    for (int j = 0; j < BENCH_SCAN_N; j++) y[j] = ref->scan_xy[2 * j + 1];
    for (int k = 0; k < n; k++) {
        const bench_method *bm = &bench_methods[c[k].r->method];
        svg_plot_series(p, c[k].label, bm->color, c[k].dash, MK_NONE, 1.3, BENCH_SCAN_N, y, c[k].r->scan);
        for (int j = 0; j < BENCH_SCAN_N; j++) hi = fmax(hi, c[k].r->scan[j]);
    }
    const tc_scene *s = ref->scene;
    svg_plot_xrange(p, s->domain[1], s->domain[3]);
    if (ylog && hi > 0) {
        double top = pow(10, ceil(log10(hi) - 1e-9));
        svg_plot_yrange(p, top * 1e-6, top);
    }
    /* The discontinuities the scanline crosses. */
    for (int i = 0; i < s->nevents; i++) {
        const tc_scene_event *e = &s->events[i];
        if (e->axis == 1 && e->lo <= BENCH_SCAN_X && BENCH_SCAN_X <= e->hi)
            svg_plot_vline(p, e->at, e->kind == TC_CM1 ? "C-1" : "C0");
    }
    svg_plot_note(p, "Dotted verticals: discontinuities crossed (C0 kink, C-1 jump). Legend: method, mesh (samples).");
    int st = svg_plot_write(p, path);
    svg_plot_free(p);
    return st;
}

static int profile_csv(const bench_reference *ref, const curve *c, int n, const char *path) {
    tc_strbuf b;
    tc_strbuf_init(&b);
    tc_strbuf_printf(&b, "x,y,reference");
    for (int k = 0; k < n; k++) tc_strbuf_printf(&b, ",\"%s\"", c[k].label);
    tc_strbuf_putc(&b, '\n');
    for (int j = 0; j < BENCH_SCAN_N; j++) {
        tc_strbuf_printf(&b, "%.9g,%.9g,%.9g", ref->scan_xy[2 * j], ref->scan_xy[2 * j + 1], ref->scan_ref[j]);
        for (int k = 0; k < n; k++) tc_strbuf_printf(&b, ",%.6g", c[k].r->scan[j]);
        tc_strbuf_putc(&b, '\n');
    }
    int st = b.oom ? -1 : bench_write_file(path, b.buf, b.len);
    tc_strbuf_free(&b);
    return st;
}

int bench_plots_write(const bench_results *rs, const bench_reference *ref, const char *dir) {
    int scene = (int)ref->scene->id, st = 0;
    const char *name = tc_scene_name(ref->scene->id);
    char path[1024];
    snprintf(path, sizeof path, "%s/%s-time.svg", dir, name);
    st |= error_plot(rs, scene, 1, path);
    snprintf(path, sizeof path, "%s/%s-samples.svg", dir, name);
    st |= error_plot(rs, scene, 0, path);
    curve c[4];
    int n = profile_curves(rs, scene, c);
    snprintf(path, sizeof path, "%s/%s-scanline.svg", dir, name);
    st |= profile_plot(ref, c, n, scene, 0, path);
    snprintf(path, sizeof path, "%s/%s-scanline-log.svg", dir, name);
    st |= profile_plot(ref, c, n, scene, 1, path);
    snprintf(path, sizeof path, "%s/%s-scanline.csv", dir, name);
    st |= profile_csv(ref, c, n, path);
    return st ? -1 : 0;
}
