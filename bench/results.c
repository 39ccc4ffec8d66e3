/* results.c — one measured (scene, mesh, method) triple, the growing list of
 * them, look-ups by key, results.csv and the per-scene scanline CSV. */
#include "results.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/strbuf.h"
#include "util.h"

bench_result *bench_results_add(bench_results *rs) {
    if (rs->n == rs->cap) {
        int cap = rs->cap ? 2 * rs->cap : 256;
        bench_result *nr = realloc(rs->r, (size_t)cap * sizeof *nr);
        if (!nr) return NULL;
        rs->r = nr, rs->cap = cap;
    }
    bench_result *r = &rs->r[rs->n++];
    memset(r, 0, sizeof *r);
    return r;
}

const bench_result *bench_results_find(const bench_results *rs, int scene, int mesh, int method, int ok_only) {
    for (int i = 0; i < rs->n; i++) {
        const bench_result *r = &rs->r[i];
        if (r->scene == scene && r->mesh == mesh && r->method == method) return !ok_only || r->ok ? r : NULL;
    }
    return NULL;
}

void bench_results_free(bench_results *rs) {
    for (int i = 0; i < rs->n; i++) free(rs->r[i].scan);
    free(rs->r);
    memset(rs, 0, sizeof *rs);
}

double bench_result_run_ms(const bench_result *r) { return r->build_ms + r->render_ms; }

int bench_results_write_csv(const bench_results *rs, const char *path) {
    tc_strbuf b;
    tc_strbuf_init(&b);
    tc_strbuf_puts(&b, "scene,mesh,density,threshold,max_depth,method,base_method,cross_boundary,wedges,tangents,"
                       "range,status,vertices,triangles,flagged_c0,flagged_cm1,worst_aspect,samples,gradient_samples,"
                       "mesh_ms,build_ms,build_reps,render_ms,run_ms,max_abs,rms,mean_rel,scale,pixels,outside,"
                       "over_negative,over_beyond,over_worst,exact_over_beyond,exact_over_worst,tangent_impact,tangent_err,tangent_err_rms,tangent_x,tangent_y,tangent_scene,tangent_used,"
                       "corner_share,sq_err,sq_err_by_flat,note\n");
    for (int i = 0; i < rs->n; i++) {
        const bench_result *r = &rs->r[i];
        const bench_mesh_spec *m = &bench_meshes[r->mesh];
        const bench_method *bm = &bench_methods[r->method];
        int adaptive = m->kind == TC_SCENE_MESH_ADAPTIVE;
        tc_strbuf_printf(&b, "%s,%s,%d,", tc_scene_name((tc_scene_id)r->scene), tc_scene_mesh_kind_name(m->kind),
                         m->density);
        if (adaptive) tc_strbuf_printf(&b, "%g,%d,", m->threshold, m->max_depth);
        else tc_strbuf_puts(&b, ",,");
        tc_strbuf_printf(&b, "%s,%s,%s,%s,%s,%s,%s,", bm->name, tc_method_name(bm->opt.method),
                         tc_cross_name(bm->opt.cross_boundary), tc_wedges_name(bm->opt.wedges),
                         tc_tangents_name(bm->opt.tangents), tc_range_name(bm->opt.range), r->ok ? "ok" : "skipped");
        tc_strbuf_printf(&b, "%d,%d,%d,%d,%.4g,%lld,%lld,", (int)r->nverts, (int)r->ntris, (int)r->flagged_c0,
                         (int)r->flagged_cm1, r->worst_aspect, (long long)r->samples, (long long)r->gradient_samples);
        if (r->ok)
            tc_strbuf_printf(&b, "%.4f,%.6f,%d,%.4f,%.4f,%.9g,%.9g,%.9g,%.9g,%lld,%lld,%lld,%.6g,%.6g,%.6g,%.6g,",
                             r->mesh_ms, r->build_ms, r->build_reps, r->render_ms, bench_result_run_ms(r),
                             r->err.max_abs, r->err.rms, r->err.mean_rel, r->err.scale, (long long)r->err.n,
                             (long long)r->err.outside, (long long)r->over.negative, r->over.beyond_fraction,
                             r->over.worst, r->exact_over.beyond_fraction, r->exact_over.worst);
        else
            tc_strbuf_puts(&b, ",,,,,,,,,,,,,,,,");
        if (r->ok && r->has_tangents)
            tc_strbuf_printf(&b, "%.6g,%.6g,%.6g,%.9g,%.9g,%.6g,%.6g,", r->tan_impact, r->tan_max, r->tan_rms,
                             r->tan_at[0], r->tan_at[1], r->tan_scene, r->tan_used);
        else
            tc_strbuf_puts(&b, ",,,,,,,");
        if (r->ok && r->corner_share == r->corner_share) tc_strbuf_printf(&b, "%.4f,", r->corner_share);
        else tc_strbuf_puts(&b, ",");
        if (r->ok) tc_strbuf_printf(&b, "%.9g,%.9g,", r->sq_err, r->sq_err_by_flat);
        else tc_strbuf_puts(&b, ",,");
        bench_csv_text(&b, r->note);
        tc_strbuf_putc(&b, '\n');
    }
    int st = b.oom ? -1 : bench_write_file(path, b.buf, b.len);
    tc_strbuf_free(&b);
    return st;
}

/* The scanline columns: every method on the representative disc mesh, then
 * linear on the uniform meshes (the profile's comparison picks among them). */
static int scan_column(const bench_result *r) {
    const bench_mesh_spec *m = &bench_meshes[r->mesh];
    if (!r->ok || !r->scan) return 0;
    if (m->kind == TC_SCENE_MESH_DISC) return m->density == BENCH_REP_DENSITY;
    return m->kind == TC_SCENE_MESH_UNIFORM && strcmp(bench_methods[r->method].name, M_LINEAR) == 0;
}

int bench_scanlines_write_csv(const bench_results *rs, int scene, const double *scan_xy, const double *scan_ref,
                              const char *path) {
    tc_strbuf b;
    tc_strbuf_init(&b);
    tc_strbuf_puts(&b, "x,y,reference");
    for (int i = 0; i < rs->n; i++) {
        if (rs->r[i].scene != scene || !scan_column(&rs->r[i])) continue;
        char label[64];
        bench_mesh_label(&bench_meshes[rs->r[i].mesh], label, sizeof label);
        tc_strbuf_printf(&b, ",%s@%s", bench_methods[rs->r[i].method].name, label);
    }
    tc_strbuf_putc(&b, '\n');
    for (int j = 0; j < BENCH_SCAN_N; j++) {
        tc_strbuf_printf(&b, "%.9g,%.9g,%.9g", scan_xy[2 * j], scan_xy[2 * j + 1], scan_ref[j]);
        for (int i = 0; i < rs->n; i++)
            if (rs->r[i].scene == scene && scan_column(&rs->r[i])) tc_strbuf_printf(&b, ",%.6g", rs->r[i].scan[j]);
        tc_strbuf_putc(&b, '\n');
    }
    int st = b.oom ? -1 : bench_write_file(path, b.buf, b.len);
    tc_strbuf_free(&b);
    return st;
}
