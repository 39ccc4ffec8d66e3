/* markdown.c — docs/report.md: the numbers, tables and figure links of one run
 * filled into the prose template bench/report.md.in. */
#include "markdown.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "analysis.h"
#include "io/strbuf.h"
#include "plan.h"
#include "template.h"
#include "util.h"

/* The keys this file sets are listed in bench/report.md.in's header comment. */

typedef struct {
    tmpl_dict *d;
    const bench_results *rs;
    const bench_run_info *info;
    int scene;
    const char *sn; /* scene name: the key prefix */
    double scale;   /* the scene's full scale */
} sctx;

/* ---- formatting into keys -------------------------------------------------------- */

static void set_g3(sctx *c, const char *key, double v) {
    char b[32];
    bench_fmt_g3(b, sizeof b, v);
    tmpl_setp(c->d, c->sn, key, "%s", b);
}

static void set_ms(sctx *c, const char *key, double v) {
    char b[32];
    bench_fmt_ms(b, sizeof b, v);
    tmpl_setp(c->d, c->sn, key, "%s", b);
}

static void set_ratio(sctx *c, const char *key, double v) {
    char b[32];
    bench_fmt_ratio(b, sizeof b, v);
    tmpl_setp(c->d, c->sn, key, "%s", b);
}

static void set_int(sctx *c, const char *key, long long v) { tmpl_setp(c->d, c->sn, key, "%lld", v); }
static void set_str(sctx *c, const char *key, const char *v) { tmpl_setp(c->d, c->sn, key, "%s", v); }
static void set_bool(sctx *c, const char *key, int v) { tmpl_setp(c->d, c->sn, key, "%s", v ? "1" : ""); }

static void cell_g3(tc_strbuf *b, double v) {
    char s[32];
    bench_fmt_g3(s, sizeof s, v);
    tc_strbuf_printf(b, " %s |", s);
}

static void cell_ms(tc_strbuf *b, double v) {
    char s[32];
    bench_fmt_ms(s, sizeof s, v);
    tc_strbuf_printf(b, " %s |", s);
}

static void set_buf(sctx *c, const char *key, tc_strbuf *b) {
    set_str(c, key, b->buf ? b->buf : "");
    tc_strbuf_free(b);
}

static const bench_result *get(const sctx *c, int mesh, const char *method) {
    int m = bench_method_find(method);
    return mesh >= 0 && m >= 0 ? bench_results_find(c->rs, c->scene, mesh, m, 1) : NULL;
}

/* Any entry for the mesh, skipped or not: for its vertex and triangle counts. */
static const bench_result *any_on(const sctx *c, int mesh) {
    for (int m = 0; m < bench_nmethods; m++) {
        const bench_result *r = bench_results_find(c->rs, c->scene, mesh, m, 0);
        if (r) return r;
    }
    return NULL;
}

/* ---- tables ---------------------------------------------------------------------- */

/* Every method on one mesh. */
static void table_mesh(sctx *c, int mesh, const char *key) {
    tc_strbuf b;
    tc_strbuf_init(&b);
    tc_strbuf_puts(&b, "| method | samples | gradient samples | build ms | render ms | max abs | RMS | mean relative |\n"
                       "|---|--:|--:|--:|--:|--:|--:|--:|\n");
    for (int m = 0; m < bench_nmethods; m++) {
        const bench_result *r = bench_results_find(c->rs, c->scene, mesh, m, 0);
        if (!r) continue;
        tc_strbuf_printf(&b, "| %s | %lld | %lld |", bench_methods[m].name, (long long)r->samples,
                         (long long)r->gradient_samples);
        if (!r->ok) {
            tc_strbuf_printf(&b, " skipped: %s | | | | | |\n", r->note);
            continue;
        }
        cell_ms(&b, r->build_ms), cell_ms(&b, r->render_ms);
        cell_g3(&b, r->err.max_abs), cell_g3(&b, r->err.rms), cell_g3(&b, r->err.mean_rel);
        tc_strbuf_putc(&b, '\n');
    }
    set_buf(c, key, &b);
}

/* Mean relative error of every method on every disc mesh. */
static void table_disc_all(sctx *c) {
    tc_strbuf b;
    tc_strbuf_init(&b);
    tc_strbuf_puts(&b, "| disc N | vertices |");
    for (int m = 0; m < bench_nmethods; m++) tc_strbuf_printf(&b, " %s |", bench_methods[m].name);
    tc_strbuf_puts(&b, "\n|--:|--:|");
    for (int m = 0; m < bench_nmethods; m++) tc_strbuf_puts(&b, "--:|");
    tc_strbuf_putc(&b, '\n');
    for (int i = 0; i < bench_nmeshes; i++) {
        if (bench_meshes[i].kind != TC_SCENE_MESH_DISC) continue;
        const bench_result *a = any_on(c, i);
        if (!a) continue;
        tc_strbuf_printf(&b, "| %d | %d |", bench_meshes[i].density, (int)a->nverts);
        for (int m = 0; m < bench_nmethods; m++) {
            const bench_result *r = bench_results_find(c->rs, c->scene, i, m, 1);
            if (r) cell_g3(&b, r->err.mean_rel);
            else tc_strbuf_puts(&b, " skipped |");
        }
        tc_strbuf_putc(&b, '\n');
    }
    set_buf(c, "table_disc_all", &b);
}

/* linear and clough-tocher on every mesh. */
static void table_kinds(sctx *c) {
    tc_strbuf b;
    tc_strbuf_init(&b);
    tc_strbuf_puts(&b, "| mesh | vertices | triangles | linear samples | linear mean rel. | linear run ms "
                       "| clough-tocher samples | clough-tocher mean rel. | clough-tocher run ms | linear / clough-tocher error |\n"
                       "|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n");
    for (int i = 0; i < bench_nmeshes; i++) {
        const bench_result *a = any_on(c, i);
        if (!a) continue;
        char label[64];
        bench_mesh_label(&bench_meshes[i], label, sizeof label);
        tc_strbuf_printf(&b, "| %s | %d | %d |", label, (int)a->nverts, (int)a->ntris);
        const bench_result *r[2] = {get(c, i, M_LINEAR), get(c, i, M_CT)};
        for (int k = 0; k < 2; k++) {
            if (!r[k]) {
                tc_strbuf_puts(&b, " | skipped | |");
                continue;
            }
            tc_strbuf_printf(&b, " %lld |", (long long)r[k]->samples);
            cell_g3(&b, r[k]->err.mean_rel);
            cell_ms(&b, bench_result_run_ms(r[k]));
        }
        char x[32] = "";
        if (r[0] && r[1]) bench_fmt_ratio(x, sizeof x, r[0]->err.mean_rel / r[1]->err.mean_rel);
        tc_strbuf_printf(&b, " %s |\n", x);
    }
    set_buf(c, "table_kinds", &b);
}

/* ---- numbers for the prose --------------------------------------------------------- */

/* <prefix>_samples, _rms, _mrel, _max, _build_ms, _render_ms, _run_ms of a result. */
static void result_keys(sctx *c, const char *prefix, const bench_result *r) {
    char k[64];
    snprintf(k, sizeof k, "%s_ok", prefix), set_bool(c, k, r != NULL);
    if (!r) return;
    snprintf(k, sizeof k, "%s_samples", prefix), set_int(c, k, r->samples);
    snprintf(k, sizeof k, "%s_gsamples", prefix), set_int(c, k, r->gradient_samples);
    snprintf(k, sizeof k, "%s_rms", prefix), set_g3(c, k, r->err.rms);
    snprintf(k, sizeof k, "%s_mrel", prefix), set_g3(c, k, r->err.mean_rel);
    snprintf(k, sizeof k, "%s_max", prefix), set_g3(c, k, r->err.max_abs);
    snprintf(k, sizeof k, "%s_build_ms", prefix), set_ms(c, k, r->build_ms);
    snprintf(k, sizeof k, "%s_render_ms", prefix), set_ms(c, k, r->render_ms);
    snprintf(k, sizeof k, "%s_run_ms", prefix), set_ms(c, k, bench_result_run_ms(r));
    snprintf(k, sizeof k, "%s_max_pct", prefix), set_g3(c, k, 100 * r->err.max_abs / c->scale);
    snprintf(k, sizeof k, "%s_mrel_pct", prefix), set_g3(c, k, 100 * r->err.mean_rel);
    snprintf(k, sizeof k, "%s_has_tan", prefix), set_bool(c, k, r->has_tangents);
    snprintf(k, sizeof k, "%s_has_corner", prefix), set_bool(c, k, isfinite(r->corner_share));
    if (isfinite(r->corner_share))
        snprintf(k, sizeof k, "%s_corner_pct", prefix), tmpl_setp(c->d, c->sn, k, "%.0f", 100 * r->corner_share);
    if (!r->has_tangents) return;
    snprintf(k, sizeof k, "%s_tan_impact_pct", prefix), set_g3(c, k, 100 * r->tan_impact / c->scale);
    snprintf(k, sizeof k, "%s_tan_max", prefix), set_g3(c, k, r->tan_max);
    snprintf(k, sizeof k, "%s_tan_rms", prefix), set_g3(c, k, r->tan_rms);
    snprintf(k, sizeof k, "%s_tan_x", prefix), tmpl_setp(c->d, c->sn, k, "%.6f", r->tan_at[0]);
    snprintf(k, sizeof k, "%s_tan_y", prefix), tmpl_setp(c->d, c->sn, k, "%.6f", r->tan_at[1]);
    snprintf(k, sizeof k, "%s_tan_scene", prefix), set_g3(c, k, r->tan_scene);
    snprintf(k, sizeof k, "%s_tan_used", prefix), set_g3(c, k, r->tan_used);
}

/* <prefix>_rms etc.: a's error over b's; _inv: b's over a's; _gt: a's is the larger. */
static void ratio_keys(sctx *c, const char *prefix, const bench_result *a, const bench_result *b) {
    char k[64];
    snprintf(k, sizeof k, "%s_ok", prefix), set_bool(c, k, a && b);
    if (!a || !b) return;
    const char *what[4] = {"rms", "mrel", "max", "run"};
    double va[4] = {a->err.rms, a->err.mean_rel, a->err.max_abs, bench_result_run_ms(a)};
    double vb[4] = {b->err.rms, b->err.mean_rel, b->err.max_abs, bench_result_run_ms(b)};
    for (int i = 0; i < 4; i++) {
        snprintf(k, sizeof k, "%s_%s", prefix, what[i]), set_ratio(c, k, va[i] / vb[i]);
        snprintf(k, sizeof k, "%s_%s_inv", prefix, what[i]), set_ratio(c, k, vb[i] / va[i]);
        snprintf(k, sizeof k, "%s_%s_gt", prefix, what[i]), set_bool(c, k, va[i] > vb[i]);
    }
}

/* Where clough-tocher's mean relative error is above linear's (a list of mesh labels). */
static void loses_keys(sctx *c) {
    tc_strbuf b;
    tc_strbuf_init(&b);
    int n = 0;
    for (int i = 0; i < bench_nmeshes; i++) {
        const bench_result *lin = get(c, i, M_LINEAR), *ct = get(c, i, M_CT);
        if (!lin || !ct || ct->err.mean_rel <= lin->err.mean_rel) continue;
        char label[64];
        bench_mesh_label(&bench_meshes[i], label, sizeof label);
        tc_strbuf_printf(&b, "%s%s", n++ ? ", " : "", label);
    }
    set_bool(c, "ct_loses", n > 0);
    set_int(c, "ct_loses_n", n);
    set_buf(c, "ct_loses_list", &b);
    /* and where its max abs error is above linear's, on the disc meshes */
    tc_strbuf_init(&b);
    n = 0;
    for (int i = 0; i < bench_nmeshes; i++) {
        if (bench_meshes[i].kind != TC_SCENE_MESH_DISC) continue;
        const bench_result *lin = get(c, i, M_LINEAR), *ct = get(c, i, M_CT);
        if (!lin || !ct || ct->err.max_abs <= lin->err.max_abs) continue;
        tc_strbuf_printf(&b, "%sN=%d", n++ ? ", " : "", bench_meshes[i].density);
    }
    set_bool(c, "ct_loses_max", n > 0);
    set_buf(c, "ct_loses_max_list", &b);
}

/* How many samples linear needs on the uniform (and adaptive) meshes to match
 * clough-tocher's mean relative error on the representative disc mesh. */
static void match_keys(sctx *c, const char *prefix, const bench_result *target, int method) {
    char k[64];
    bench_match mt;
    if (!target) return;
    bench_match_uniform(c->rs, c->scene, method, target->err.mean_rel, &mt);
    snprintf(k, sizeof k, "%s_found", prefix), set_bool(c, k, mt.found);
    snprintf(k, sizeof k, "%s_interp", prefix), set_bool(c, k, mt.found && mt.lo_mesh >= 0);
    snprintf(k, sizeof k, "%s_coarsest", prefix), set_bool(c, k, mt.found && mt.lo_mesh < 0);
    if (mt.found) {
        snprintf(k, sizeof k, "%s_samples", prefix), set_int(c, k, llround(mt.samples));
        snprintf(k, sizeof k, "%s_N", prefix), set_ratio(c, k, mt.N);
        snprintf(k, sizeof k, "%s_x", prefix), set_ratio(c, k, mt.samples / (double)target->samples);
        snprintf(k, sizeof k, "%s_x_verts", prefix), set_ratio(c, k, mt.samples / (double)target->nverts);
        snprintf(k, sizeof k, "%s_run_ms", prefix), set_ms(c, k, mt.run_ms);
        snprintf(k, sizeof k, "%s_run_x", prefix), set_ratio(c, k, mt.run_ms / bench_result_run_ms(target));
        const bench_result *hi = bench_results_find(c->rs, c->scene, mt.hi_mesh, method, 1);
        snprintf(k, sizeof k, "%s_hi_N", prefix), set_int(c, k, bench_meshes[mt.hi_mesh].density);
        snprintf(k, sizeof k, "%s_hi_samples", prefix), set_int(c, k, hi->samples);
        snprintf(k, sizeof k, "%s_hi_mrel", prefix), set_g3(c, k, hi->err.mean_rel);
        if (mt.lo_mesh >= 0) {
            const bench_result *lo = bench_results_find(c->rs, c->scene, mt.lo_mesh, method, 1);
            snprintf(k, sizeof k, "%s_lo_N", prefix), set_int(c, k, bench_meshes[mt.lo_mesh].density);
            snprintf(k, sizeof k, "%s_lo_samples", prefix), set_int(c, k, lo->samples);
            snprintf(k, sizeof k, "%s_lo_mrel", prefix), set_g3(c, k, lo->err.mean_rel);
        }
    }
    if (mt.best_mesh >= 0) {
        snprintf(k, sizeof k, "%s_best_N", prefix), set_int(c, k, bench_meshes[mt.best_mesh].density);
        snprintf(k, sizeof k, "%s_best_samples", prefix), set_int(c, k, mt.best_samples);
        snprintf(k, sizeof k, "%s_best_mrel", prefix), set_g3(c, k, mt.best_mrel);
        snprintf(k, sizeof k, "%s_best_x", prefix), set_ratio(c, k, mt.best_mrel / target->err.mean_rel);
        snprintf(k, sizeof k, "%s_best_sx", prefix), set_ratio(c, k, (double)mt.best_samples / (double)target->samples);
    }
}

static void slope_keys(sctx *c, const char *key, tc_scene_mesh_kind kind, const char *method, int min_density) {
    int n;
    double s = bench_slope(c->rs, c->scene, kind, bench_method_find(method), min_density, &n);
    char k[64], b[32];
    snprintf(b, sizeof b, "%.2f", s);
    snprintf(k, sizeof k, "%s", key), set_str(c, k, isfinite(s) ? b : "n/a");
    snprintf(b, sizeof b, "%.2f", -2 * s);
    snprintf(k, sizeof k, "%s_order", key), set_str(c, k, isfinite(s) ? b : "n/a");
    snprintf(k, sizeof k, "%s_n", key), set_int(c, k, n);
}

/* "0.0035 (N=1), ..." : method's largest error on each disc mesh. */
static void max_list_key(sctx *c, const char *key, const char *method) {
    tc_strbuf b;
    tc_strbuf_init(&b);
    for (int i = 0; i < bench_nmeshes; i++) {
        const bench_result *r = bench_meshes[i].kind == TC_SCENE_MESH_DISC ? get(c, i, method) : NULL;
        if (!r) continue;
        char v[32];
        bench_fmt_g3(v, sizeof v, r->err.max_abs);
        tc_strbuf_printf(&b, "%s%s (N=%d)", b.len ? ", " : "", v, bench_meshes[i].density);
    }
    set_buf(c, key, &b);
}

static void scene_keys(sctx *c) {
    tc_scene s;
    tc_scene_init(&s, (tc_scene_id)c->scene);
    c->scale = s.scale;
    set_str(c, "name", c->sn);
    set_str(c, "summary", tc_scene_summary((tc_scene_id)c->scene));
    set_g3(c, "scale", s.scale);
    int nc0 = 0, ncm1 = 0;
    for (int i = 0; i < s.nevents; i++) nc0 += s.events[i].kind == TC_C0, ncm1 += s.events[i].kind == TC_CM1;
    set_int(c, "events_c0", nc0), set_int(c, "events_cm1", ncm1);
    set_bool(c, "smooth", s.nevents == 0);

    int rep = bench_mesh_find(TC_SCENE_MESH_DISC, BENCH_REP_DENSITY);
    const bench_result *a = any_on(c, rep);
    set_int(c, "rep_N", BENCH_REP_DENSITY);
    if (a) {
        set_int(c, "rep_verts", a->nverts), set_int(c, "rep_tris", a->ntris);
        set_int(c, "rep_c0", a->flagged_c0), set_int(c, "rep_cm1", a->flagged_cm1);
        set_g3(c, "rep_aspect", a->worst_aspect);
    }
    table_mesh(c, rep, "table_rep");
    table_disc_all(c);
    table_kinds(c);

    const char *rel = c->info->fig_rel;
    const char *figs[][2] = {{"fig_time", "time.svg"},         {"fig_samples", "samples.svg"},
                             {"fig_scan", "scanline.svg"},     {"fig_scan_log", "scanline-log.svg"},
                             {"scan_csv", "scanline.csv"},     {"fig_images", "images.png"},
                             {"fig_errors", "errors.png"}};
    for (size_t i = 0; i < sizeof figs / sizeof figs[0]; i++)
        tmpl_setp(c->d, c->sn, figs[i][0], "%s/%s-%s", rel, c->sn, figs[i][1]);
    int fig = bench_mesh_find(TC_SCENE_MESH_DISC, BENCH_FIG_DENSITY);
    const bench_result *f = any_on(c, fig);
    set_int(c, "fig_N", BENCH_FIG_DENSITY);
    if (f) set_int(c, "fig_tris", f->ntris);
    if (fig >= 0) table_mesh(c, fig, "table_fig");
    result_keys(c, "fig_ct", get(c, fig, M_CT));
    result_keys(c, "fig_lin", get(c, fig, M_LINEAR));
    result_keys(c, "fig_c1", get(c, fig, M_CT_C1));
    result_keys(c, "fig_given", get(c, fig, "ct-given"));
    result_keys(c, "fig_est", get(c, fig, "ct-estimate"));
    result_keys(c, "d32_ct", get(c, bench_mesh_find(TC_SCENE_MESH_DISC, 32), M_CT));
    result_keys(c, "d32_lin", get(c, bench_mesh_find(TC_SCENE_MESH_DISC, 32), M_LINEAR));
    ratio_keys(c, "fig_x_lin", get(c, fig, M_LINEAR), get(c, fig, M_CT));

    /* The representative disc mesh: clough-tocher against the others. */
    const bench_result *ct = get(c, rep, M_CT), *lin = get(c, rep, M_LINEAR), *c1 = get(c, rep, M_CT_C1);
    result_keys(c, "ct", ct);
    result_keys(c, "lin", lin);
    result_keys(c, "c1", c1);
    result_keys(c, "lin4", get(c, rep, "linear4"));
    result_keys(c, "given", get(c, rep, "ct-given"));
    result_keys(c, "lit", get(c, rep, "ct-literal"));
    result_keys(c, "sal", get(c, rep, "ct-salesin"));
    result_keys(c, "aff", get(c, rep, "ct-affine"));
    result_keys(c, "est", get(c, rep, "ct-estimate"));
    result_keys(c, "const", get(c, rep, "constant"));
    if (ct) set_int(c, "ct_verts", ct->nverts);
    ratio_keys(c, "x_lin", lin, ct);  /* linear's error / clough-tocher's */
    ratio_keys(c, "x_c1", c1, ct);
    ratio_keys(c, "x_c1lin", c1, lin);
    ratio_keys(c, "x_lit", get(c, rep, "ct-literal"), ct);
    ratio_keys(c, "x_given", ct, get(c, rep, "ct-given"));
    ratio_keys(c, "x_est", get(c, rep, "ct-estimate"), ct);
    ratio_keys(c, "x_lin4", get(c, rep, "linear4"), ct);
    /* The other smooth schemes (issue 5): Powell-Sabin on the triangles, Hermite on the quads. */
    result_keys(c, "ps", get(c, rep, "powell-sabin"));
    result_keys(c, "herm", get(c, rep, "hermite"));
    result_keys(c, "hermz", get(c, rep, "hermite-zero-twist"));
    ratio_keys(c, "x_ps", get(c, rep, "powell-sabin"), ct);
    ratio_keys(c, "x_herm", get(c, rep, "hermite"), ct);
    ratio_keys(c, "x_pslin", get(c, rep, "powell-sabin"), lin);
    ratio_keys(c, "x_hermlin", get(c, rep, "hermite"), lin);
    ratio_keys(c, "x_hermz", get(c, rep, "hermite-zero-twist"), get(c, rep, "hermite"));
    const bench_result *lit_any = bench_results_find(c->rs, c->scene, rep, bench_method_find("ct-literal"), 0);
    if (lit_any && !lit_any->ok) set_str(c, "lit_note", lit_any->note);

    /* The best method on the representative mesh by mean relative error. */
    const bench_result *best = NULL;
    for (int m = 0; m < bench_nmethods; m++) {
        const bench_result *r = bench_results_find(c->rs, c->scene, rep, m, 1);
        if (r && (!best || r->err.mean_rel < best->err.mean_rel)) best = r;
    }
    if (best) set_str(c, "best_name", bench_methods[best->method].name), set_g3(c, "best_mrel", best->err.mean_rel);

    /* Linear on uniform meshes against clough-tocher on the disc mesh, and
     * against the vertex-only clough-tocher (ct-estimate). */
    match_keys(c, "match", ct, bench_method_find(M_LINEAR));
    match_keys(c, "match_est", get(c, rep, "ct-estimate"), bench_method_find(M_LINEAR));
    match_keys(c, "match_ctu", ct, bench_method_find(M_CT));

    /* The profile's uniform mesh, Bastos & Oliveira's comparison. */
    int u = bench_scan_uniform_mesh(c->rs, c->scene, rep);
    const bench_result *lu = u >= 0 ? get(c, u, M_LINEAR) : NULL;
    set_bool(c, "scanu_ok", lu && ct);
    if (lu && ct) {
        set_int(c, "scanu_N", bench_meshes[u].density);
        set_int(c, "scanu_samples", lu->samples);
        set_g3(c, "scanu_mrel", lu->err.mean_rel);
        set_ratio(c, "scanu_sx", (double)lu->samples / (double)ct->samples);
        double pct = 100 * (1 - ct->err.mean_rel / lu->err.mean_rel);
        char b[32];
        snprintf(b, sizeof b, "%.1f", fabs(pct));
        set_str(c, "scanu_pct", b);
        set_bool(c, "scanu_ct_better", pct > 0);
    }

    /* Convergence: slopes of log(mean rel) against log(samples). */
    slope_keys(c, "slope_lin_u", TC_SCENE_MESH_UNIFORM, M_LINEAR, 16);
    slope_keys(c, "slope_ct_u", TC_SCENE_MESH_UNIFORM, M_CT, 16);
    slope_keys(c, "slope_lin_d", TC_SCENE_MESH_DISC, M_LINEAR, 4);
    slope_keys(c, "slope_ct_d", TC_SCENE_MESH_DISC, M_CT, 4);
    slope_keys(c, "slope_c1_d", TC_SCENE_MESH_DISC, M_CT_C1, 4);
    slope_keys(c, "slope_given_u", TC_SCENE_MESH_UNIFORM, "ct-given", 16);
    loses_keys(c);
    max_list_key(c, "ct_max_list", M_CT);
    max_list_key(c, "lin_max_list", M_LINEAR);

    /* The finest uniform mesh: what the build costs per triangle. */
    int fine = bench_mesh_find(TC_SCENE_MESH_UNIFORM, 256);
    const bench_result *fct = get(c, fine, M_CT), *flin = get(c, fine, M_LINEAR);
    set_bool(c, "fine_ok", fct && flin);
    if (fct && flin) {
        set_int(c, "fine_tris", fct->ntris);
        set_ms(c, "fine_ct_build", fct->build_ms), set_ms(c, "fine_ct_render", fct->render_ms);
        set_ms(c, "fine_lin_build", flin->build_ms), set_ms(c, "fine_lin_render", flin->render_ms);
        set_g3(c, "fine_ct_us_per_tri", 1e3 * fct->build_ms / fct->ntris);
    }
}

/* ---- the run ------------------------------------------------------------------------ */

static void methods_table(tmpl_dict *d) {
    tc_strbuf b;
    tc_strbuf_init(&b);
    tc_strbuf_puts(&b, "| name | method | cross_boundary | wedges | tangents | samples used | what |\n"
                       "|---|---|---|---|---|---|---|\n");
    for (int m = 0; m < bench_nmethods; m++) {
        const bench_method *bm = &bench_methods[m];
        unsigned reads = tc_method_reads(bm->opt.method); /* blank: the option does not apply */
        tc_strbuf_printf(&b, "| %s | %s | %s | %s | %s | vertices%s%s | %s |\n", bm->name,
                         tc_method_name(bm->opt.method),
                         reads & TC_READS_CROSS_BOUNDARY ? tc_cross_name(bm->opt.cross_boundary) : "",
                         reads & TC_READS_WEDGES ? tc_wedges_name(bm->opt.wedges) : "",
                         reads & TC_READS_TANGENTS ? tc_tangents_name(bm->opt.tangents) : "",
                         bm->midpoints ? " + midpoints" : "", bm->gradients ? " + gradients" : "", bm->what);
    }
    tmpl_set(d, "methods_table", "%s", b.buf ? b.buf : "");
    tc_strbuf_free(&b);
}

static void skipped_table(tmpl_dict *d, const bench_results *rs) {
    tc_strbuf b;
    tc_strbuf_init(&b);
    int n = 0;
    for (int i = 0; i < rs->n; i++) {
        const bench_result *r = &rs->r[i];
        if (r->ok) continue;
        if (!n) tc_strbuf_puts(&b, "| scene | mesh | method | why |\n|---|---|---|---|\n");
        char label[64];
        bench_mesh_label(&bench_meshes[r->mesh], label, sizeof label);
        tc_strbuf_printf(&b, "| %s | %s | %s | %s |\n", tc_scene_name((tc_scene_id)r->scene), label,
                         bench_methods[r->method].name, r->note);
        n++;
    }
    tmpl_set(d, "skipped_n", "%d", n);
    tmpl_set(d, "skipped", "%s", n ? "1" : "");
    tmpl_set(d, "skipped_table", "%s", b.buf ? b.buf : "");
    tc_strbuf_free(&b);
}

static void list_keys(tmpl_dict *d) {
    tc_strbuf b[3];
    for (int k = 0; k < 3; k++) tc_strbuf_init(&b[k]);
    int depth = 0, start = 0;
    for (int i = 0; i < bench_nmeshes; i++) {
        const bench_mesh_spec *m = &bench_meshes[i];
        int k = (int)m->kind;
        if (m->kind == TC_SCENE_MESH_ADAPTIVE) {
            tc_strbuf_printf(&b[k], "%s%g", b[k].len ? ", " : "", m->threshold);
            depth = m->max_depth, start = m->density;
        } else {
            tc_strbuf_printf(&b[k], "%s%d", b[k].len ? ", " : "", m->density);
        }
    }
    tmpl_set(d, "disc_Ns", "%s", b[0].buf ? b[0].buf : "");
    tmpl_set(d, "uniform_Ns", "%s", b[1].buf ? b[1].buf : "");
    tmpl_set(d, "thresholds", "%s", b[2].buf ? b[2].buf : "");
    tmpl_set(d, "adaptive_start", "%d", start);
    tmpl_set(d, "adaptive_depth", "%d", depth);
    tmpl_set(d, "adaptive_finest", "%d", start << depth);
    for (int k = 0; k < 3; k++) tc_strbuf_free(&b[k]);
}

int bench_markdown_write(const bench_results *rs, const bench_run_info *info, const char *template_path,
                         const char *out_path) {
    char *tmpl = bench_read_file(template_path);
    if (!tmpl) return -1;
    tmpl_dict d;
    tmpl_init(&d);
    tmpl_set(&d, "machine", "%s", info->machine);
    tmpl_set(&d, "nproc", "%d", info->nproc);
    tmpl_set(&d, "commit", "%s", info->commit);
    tmpl_set(&d, "total_s", "%.0f", info->total_s);
    tmpl_set(&d, "fig_dir", "%s", info->fig_rel);
    tmpl_set(&d, "images_ok", "%s", info->images_ok ? "1" : "");
    tmpl_set(&d, "W", "%d", BENCH_W);
    tmpl_set(&d, "render_reps", "%d", BENCH_RENDER_REPS);
    tmpl_set(&d, "build_batches", "%d", BENCH_BUILD_BATCHES);
    tmpl_set(&d, "build_batch_ms", "%g", BENCH_BUILD_BATCH_MS);
    tmpl_set(&d, "build_big_ms", "%g", BENCH_BUILD_BIG_MS);
    tmpl_set(&d, "scan_x", "%g", BENCH_SCAN_X);
    tmpl_set(&d, "scan_n", "%d", BENCH_SCAN_N);
    tmpl_set(&d, "scan_factor", "%g", BENCH_SCAN_UNIFORM_FACTOR);
    tmpl_set(&d, "rep_N", "%d", BENCH_REP_DENSITY);
    tmpl_set(&d, "fig_N", "%d", BENCH_FIG_DENSITY);
    tmpl_set(&d, "panel", "%d", BENCH_FIG_PANEL);
    tmpl_set(&d, "gain", "%g", BENCH_ERR_GAIN);
    tmpl_set(&d, "corner_radius", "%g", BENCH_CORNER_RADIUS);
    tmpl_set(&d, "rows", "%d", rs->n);
    tmpl_set(&d, "nmethods", "%d", bench_nmethods);
    tmpl_set(&d, "nmeshes", "%d", bench_nmeshes);
    list_keys(&d);
    methods_table(&d);
    skipped_table(&d, rs);

    char scenes[256] = "";
    for (int s = 0; s < TC_SCENE_COUNT; s++) {
        int any = 0;
        for (int i = 0; i < rs->n && !any; i++) any = rs->r[i].scene == s;
        if (!any) continue;
        sctx c = {&d, rs, info, s, tc_scene_name((tc_scene_id)s), 1};
        scene_keys(&c);
        snprintf(scenes + strlen(scenes), sizeof scenes - strlen(scenes), "%s%s", scenes[0] ? " " : "", c.sn);
    }
    tmpl_set_list(&d, "scenes", scenes);

    tc_strbuf out;
    tc_strbuf_init(&out);
    int problems = tmpl_render(tmpl, &d, &out);
    int st = d.oom || out.oom ? -1 : bench_write_file(out_path, out.buf, out.len);
    tc_strbuf_free(&out);
    tmpl_free(&d);
    free(tmpl);
    return st ? -1 : problems ? 1 : 0;
}
