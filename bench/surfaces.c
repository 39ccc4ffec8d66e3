/* surfaces.c — the realistic discontinuity-meshed surfaces (src/scenes/surfaces.h):
 * the overshoot and error of each surface method and of the exact function itself. */
#include "surfaces.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/strbuf.h"
#include "plan.h"
#include "surface_images.h"
#include "util.h"

#define PI 3.14159265358979323846
#define W BENCH_SURF_W

int bench_surface_open(bench_surface *b, const tc_dm_surface *f, int no_c0, char *note, size_t notelen) {
    memset(b, 0, sizeof *b);
    b->f = f, b->no_c0 = no_c0;
    tc_scene_mesh_opts o;
    int st = tc_dm_surface_setup(f, no_c0, &b->s, &o);
    if (st == TC_OK) st = tc_scene_mesh_new(&b->s, &o, &b->sm);
    tc_diags dg;
    tc_diags_init(&dg);
    if (st == TC_OK) st = tc_mesh_new(&b->sm->desc, &b->m, &dg);
    if (st == TC_OK) st = tc_locator_new(b->m, &b->L);
    if (st != TC_OK)
        snprintf(note, notelen, "meshing failed with status %d%s%s", st, dg.count ? ": " : "",
                 dg.count ? dg.items[0].message : "");
    tc_diags_free(&dg);
    if (st != TC_OK) bench_surface_close(b);
    return st == TC_OK ? 0 : -1;
}

void bench_surface_close(bench_surface *b) {
    tc_locator_free(b->L);
    tc_mesh_free(b->m);
    tc_scene_mesh_free(b->sm);
    b->L = NULL, b->m = NULL, b->sm = NULL;
}

/* The inverse of src/scenes/dm.c's turn: its sampling frame maps mesh point p
 * to o + R(-rotation) (p - o), o the window's centre. */
double bench_surface_exact(const bench_surface *b, double x, double y) {
    const double *w = b->f->window;
    double o[2] = {0.5 * (w[0] + w[2]), 0.5 * (w[1] + w[3])};
    double c = cos(b->f->rotation * PI / 180), s = sin(b->f->rotation * PI / 180);
    double dx = x - o[0], dy = y - o[1];
    return tc_scene_value(&b->s, o[0] + c * dx + s * dy, o[1] - s * dx + c * dy);
}

/* The measured tile over the surface's window: pixel centres, the exact B
 * there (double, and as the float a pixel holds), owners, a render scratch. */
typedef struct {
    tc_viewport vp;
    double *xy, *exact;
    float *exact_px, *tile;
    int32_t *owner;
} surf_tile;

static void tile_free(surf_tile *t) {
    free(t->xy), free(t->exact), free(t->exact_px), free(t->tile), free(t->owner);
    memset(t, 0, sizeof *t);
}

static int tile_init(surf_tile *t, const bench_surface *b) {
    const double *w = b->f->window;
    size_t np = (size_t)W * W;
    t->vp = (tc_viewport){w[0], w[1], w[2], w[3], W, W};
    t->xy = malloc(2 * np * sizeof *t->xy), t->exact = malloc(np * sizeof *t->exact);
    t->exact_px = malloc(np * sizeof *t->exact_px), t->tile = malloc(np * sizeof *t->tile);
    t->owner = malloc(np * sizeof *t->owner);
    if (!t->xy || !t->exact || !t->exact_px || !t->tile || !t->owner) {
        tile_free(t);
        return -1;
    }
    for (int32_t j = 0; j < W; j++)
        for (int32_t i = 0; i < W; i++) {
            size_t k = (size_t)j * W + (size_t)i;
            tc_viewport_pixel_center(&t->vp, i, j, &t->xy[2 * k], &t->xy[2 * k + 1]);
            t->exact[k] = bench_surface_exact(b, t->xy[2 * k], t->xy[2 * k + 1]);
            t->exact_px[k] = (float)t->exact[k];
            t->owner[k] = tc_locate(b->L, t->xy[2 * k], t->xy[2 * k + 1]);
        }
    return 0;
}

/* The columns every row of a surface variant starts with. */
static void row_head(tc_strbuf *out, const bench_surface *b) {
    const tc_dm_surface *f = b->f;
    const tc_scene_mesh *sm = b->sm;
    tc_strbuf_printf(out, "%s,%s,%g,%g,%g,%g,%g,%d,%d,", f->name, tc_scene_name(f->scene), f->window[0],
                     f->window[1], f->window[2], f->window[3], f->rotation, f->density, !b->no_c0);
    tc_strbuf_printf(out, "%d,%d,%d,%d,%.4g,%.4g,", (int)sm->desc.nverts, (int)sm->desc.ntris, (int)sm->flagged_c0,
                     (int)sm->flagged_cm1, sm->worst_aspect, sm->largest_angle);
}

/* The overshoot columns, with the shape of the worst pixel's triangle. */
static void row_over(tc_strbuf *out, const bench_surface *b, const tc_overshoot_stats *o) {
    double aspect = 0, angle = 0;
    if (o->worst_tri >= 0) {
        const int32_t *t = tc_mesh_triangles(b->m) + 3 * (size_t)o->worst_tri;
        const double *xy = tc_mesh_xy(b->m);
        const double *p = xy + 2 * (size_t)t[0], *q = xy + 2 * (size_t)t[1], *r = xy + 2 * (size_t)t[2];
        aspect = tc_scene_triangle_aspect(p, q, r), angle = tc_scene_triangle_largest_angle(p, q, r);
    }
    tc_strbuf_printf(out, "%lld,%.9g,%.9g,%.9g,%lld,%lld,%.6g,%.6g,%.9g,%.9g,%.9g,%d,%.4g,%.4g,", (long long)o->pixels,
                     o->lo, o->hi, o->unit, (long long)o->negative, (long long)o->beyond, o->beyond_fraction, o->worst,
                     (double)o->worst_value, o->min_value, o->max_value, (int)o->worst_tri, aspect, angle);
}

#define HEADER                                                                                                        \
    "surface,scene,window_x0,window_y0,window_x1,window_y1,rotation,density,c0_flags,vertices,triangles,flagged_c0,"   \
    "flagged_cm1,worst_aspect,largest_angle,method,range,cross_boundary,status,pixels,lo,hi,unit,negative,beyond,"     \
    "beyond_fraction,worst,worst_value,min_value,max_value,worst_tri,worst_tri_aspect,worst_tri_angle,max_abs,rms,"    \
    "mean_rel,scale,note\n"
#define EMPTY_OVER ",,,,,,,,,,,,,,"

/* The exact function's own excursion from the mesh's corner values. */
static void row_exact(tc_strbuf *out, const bench_surface *b, const surf_tile *t) {
    tc_overshoot_stats o;
    row_head(out, b);
    tc_strbuf_puts(out, "exact,,,");
    if (tc_overshoot(b->m, t->exact_px, t->owner, W, W, BENCH_OVER_THRESHOLD, &o) != TC_OK) {
        tc_strbuf_puts(out, "skipped," EMPTY_OVER ",,,,tc_overshoot failed\n");
        return;
    }
    tc_strbuf_puts(out, "ok,");
    row_over(out, b, &o);
    tc_strbuf_printf(out, "0,0,0,%.9g,\n", b->s.scale);
}

/* Surface method k: its render's overshoot and its error against the exact B. */
static void row_method(tc_strbuf *out, const bench_surface *b, surf_tile *t, int k) {
    const bench_surface_method *sm = &bench_surface_methods[k];
    row_head(out, b);
    tc_strbuf_printf(out, "%s,%s,%s,", sm->name, tc_range_name(sm->opt.range), tc_cross_name(sm->opt.cross_boundary));
    tc_recon *r = NULL;
    tc_diags dg;
    tc_diags_init(&dg);
    int st = tc_recon_new(b->m, &sm->opt, &r, &dg);
    tc_overshoot_stats o;
    tc_error_stats e;
    tc_render_options ro = {.threads = 2};
    if (st == TC_OK) st = tc_render(r, b->L, &t->vp, &ro, t->tile, t->owner);
    if (st == TC_OK) st = tc_overshoot(b->m, t->tile, t->owner, W, W, BENCH_OVER_THRESHOLD, &o);
    if (st == TC_OK) st = tc_compare(r, b->L, (size_t)W * W, t->xy, t->exact, b->s.scale, &e);
    if (st != TC_OK) {
        char note[320];
        snprintf(note, sizeof note, "status %d: %s", st, dg.count ? dg.items[0].message : "failed");
        tc_strbuf_puts(out, "skipped," EMPTY_OVER ",,,,");
        bench_csv_text(out, note);
        tc_strbuf_putc(out, '\n');
    } else {
        tc_strbuf_puts(out, "ok,");
        row_over(out, b, &o);
        tc_strbuf_printf(out, "%.9g,%.9g,%.9g,%.9g,\n", e.max_abs, e.rms, e.mean_rel, e.scale);
    }
    tc_diags_free(&dg);
    tc_recon_free(r);
}

static int pictured(const bench_surface *b) {
    for (int i = 0; i < bench_nsurface_pictures; i++)
        if (!strcmp(bench_surface_pictures[i].surface, b->f->name) && bench_surface_pictures[i].no_c0 == b->no_c0)
            return 1;
    return 0;
}

/* One surface variant: its rows, and its pictures when pictured. */
static int measure_variant(tc_strbuf *out, const tc_dm_surface *f, int no_c0, const char *dir, int *images_ok) {
    bench_surface b;
    surf_tile t;
    char note[320];
    double t0 = bench_now_ms();
    if (bench_surface_open(&b, f, no_c0, note, sizeof note) != 0) {
        bench_log("surface %s%s: %s", f->name, no_c0 ? " (no C0)" : "", note);
        return 0;
    }
    if (tile_init(&t, &b) != 0) {
        bench_surface_close(&b);
        return -1;
    }
    row_exact(out, &b, &t);
    for (int k = 0; k < bench_nsurface_methods; k++) row_method(out, &b, &t, k);
    if (pictured(&b) && bench_surface_images_write(&b, dir) != 0) *images_ok = 0;
    bench_log("surface %-16s %-6s %5d tris, worst aspect %6.0f  (%.1f s)", f->name, no_c0 ? "no C0" : "C0",
              (int)b.sm->desc.ntris, b.sm->worst_aspect, (bench_now_ms() - t0) / 1e3);
    tile_free(&t);
    bench_surface_close(&b);
    return 0;
}

/* name is in the comma list only (or only is NULL). */
static int wanted(const char *only, const char *name) {
    if (!only) return 1;
    size_t n = strlen(name);
    for (const char *p = only; *p;) {
        size_t k = strcspn(p, ",");
        if (k == n && !strncmp(p, name, n)) return 1;
        p += k + (p[k] == ',');
    }
    return 0;
}

int bench_surfaces_run(const char *only, const char *dir, int *images_ok) {
    tc_strbuf out;
    tc_strbuf_init(&out);
    tc_strbuf_puts(&out, HEADER);
    int st = 0;
    for (int i = 0; st == 0 && i < tc_dm_surface_count(); i++)
        for (int no_c0 = 0; st == 0 && no_c0 < 2; no_c0++)
            if (wanted(only, tc_dm_surface_get(i)->name))
                st = measure_variant(&out, tc_dm_surface_get(i), no_c0, dir, images_ok);
    char path[1024];
    snprintf(path, sizeof path, "%s/surfaces.csv", dir);
    if (st == 0) st = out.oom ? -1 : bench_write_file(path, out.buf, out.len);
    tc_strbuf_free(&out);
    return st;
}
