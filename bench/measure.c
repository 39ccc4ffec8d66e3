/* measure.c — the measurement of one method on one scene mesh: build and render
 * times, errors against the exact radiosity at the pixel centres, overshoot, the scanline. */
#include "measure.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "util.h"

int bench_reference_init(bench_reference *ref, const tc_scene *s) {
    memset(ref, 0, sizeof *ref);
    ref->scene = s;
    ref->vp = (tc_viewport){s->domain[0], s->domain[1], s->domain[2], s->domain[3], BENCH_W, BENCH_W};
    size_t np = (size_t)BENCH_W * BENCH_W;
    ref->xy = malloc(2 * np * sizeof *ref->xy);
    ref->ref = malloc(np * sizeof *ref->ref);
    ref->tile = malloc(np * sizeof *ref->tile);
    ref->owner = malloc(np * sizeof *ref->owner);
    ref->scan_xy = malloc(2 * (size_t)BENCH_SCAN_N * sizeof *ref->scan_xy);
    ref->scan_ref = malloc((size_t)BENCH_SCAN_N * sizeof *ref->scan_ref);
    if (!ref->xy || !ref->ref || !ref->tile || !ref->owner || !ref->scan_xy || !ref->scan_ref) {
        bench_reference_free(ref);
        return TC_ENOMEM;
    }
    for (int32_t j = 0; j < BENCH_W; j++)
        for (int32_t i = 0; i < BENCH_W; i++) {
            size_t k = (size_t)j * BENCH_W + (size_t)i;
            tc_viewport_pixel_center(&ref->vp, i, j, &ref->xy[2 * k], &ref->xy[2 * k + 1]);
            ref->ref[k] = tc_scene_value(s, ref->xy[2 * k], ref->xy[2 * k + 1]);
        }
    /* The scanline at the pixel rows' y, bottom to top. */
    for (int j = 0; j < BENCH_SCAN_N; j++) {
        double y = s->domain[1] + (s->domain[3] - s->domain[1]) * ((j + 0.5) / BENCH_SCAN_N);
        ref->scan_xy[2 * j] = BENCH_SCAN_X, ref->scan_xy[2 * j + 1] = y;
        ref->scan_ref[j] = tc_scene_value(s, BENCH_SCAN_X, y);
    }
    return TC_OK;
}

void bench_reference_free(bench_reference *ref) {
    free(ref->xy), free(ref->ref), free(ref->tile), free(ref->owner), free(ref->scan_xy), free(ref->scan_ref);
    memset(ref, 0, sizeof *ref);
}

int64_t bench_method_samples(const tc_scene_mesh *sm, const bench_method *bm) {
    return sm->samples - (bm->midpoints ? 0 : sm->desc.nmidpoints);
}

int64_t bench_method_gradient_samples(const tc_scene_mesh *sm, const bench_method *bm) {
    return bm->gradients ? sm->gradient_samples : 0;
}

static void diag_note(const tc_diags *dg, const char *what, int st, char *note, size_t n) {
    if (dg->count > 0)
        snprintf(note, n, "%s refused it: %s%s%s", what, dg->items[0].path, dg->items[0].path[0] ? ": " : "",
                 dg->items[0].message);
    else
        snprintf(note, n, "%s failed with status %d", what, st);
}

int bench_prepare(const tc_scene_mesh *sm, const bench_method *bm, bench_prepared *p, double *mesh_ms, char *note,
                  size_t notelen) {
    memset(p, 0, sizeof *p);
    if (bm->midpoints && sm->desc.nmidpoints == 0) {
        snprintf(note, notelen, "needs edge-midpoint samples; the mesh has none");
        return -1;
    }
    if (bm->gradients && sm->desc.ncorner_gradients == 0 && !sm->desc.gradients) {
        snprintf(note, notelen, "needs corner gradients; the mesh has none");
        return -1;
    }
    tc_mesh_desc d = sm->desc;
    if (!bm->midpoints) {
        d.nmidpoints = 0;
        d.midpoint_edge = NULL, d.midpoint_tri = NULL, d.midpoint_values = NULL;
    }
    if (!bm->gradients) {
        d.ncorner_gradients = 0;
        d.corner_gradients_tri = NULL, d.corner_gradients = NULL, d.corner_gradients_mask = NULL;
        d.gradients = NULL, d.gradients_mask = NULL, d.normals = NULL, d.normals_mask = NULL;
    }
    tc_diags dg;
    tc_diags_init(&dg);
    double t0 = bench_now_ms();
    int st = tc_mesh_new(&d, &p->mesh, &dg);
    if (st != TC_OK) {
        diag_note(&dg, "tc_mesh_new", st, note, notelen);
        tc_diags_free(&dg);
        return -1;
    }
    st = tc_locator_new(p->mesh, &p->loc);
    if (mesh_ms) *mesh_ms = bench_now_ms() - t0;
    if (st != TC_OK) {
        snprintf(note, notelen, "tc_locator_new failed with status %d", st);
        tc_diags_free(&dg);
        bench_prepared_free(p);
        return -1;
    }
    tc_diags_clear(&dg);
    st = tc_recon_new(p->mesh, &bm->opt, &p->recon, &dg);
    if (st != TC_OK) {
        diag_note(&dg, "tc_recon_new", st, note, notelen);
        tc_diags_free(&dg);
        bench_prepared_free(p);
        return -1;
    }
    tc_diags_free(&dg);
    return 0;
}

void bench_prepared_free(bench_prepared *p) {
    tc_recon_free(p->recon);
    tc_locator_free(p->loc);
    tc_mesh_free(p->mesh);
    memset(p, 0, sizeof *p);
}

/* One timed batch of tc_recon_new (+ tc_recon_free, which is small) calls: ms per call. */
static double build_batch(const tc_mesh *m, const tc_options *o, int reps) {
    tc_recon *r = NULL;
    double t0 = bench_now_ms();
    for (int k = 0; k < reps; k++) {
        tc_recon_new(m, o, &r, NULL);
        tc_recon_free(r);
    }
    return (bench_now_ms() - t0) / reps;
}

/* Corner j of entry k of the scene's corner gradients: the corner id (3t + c)
 * of the core's triangles that holds its plane (a quad mesh is held as its
 * split, quad q = triangles 2q = (a, b, c) and 2q+1 = (a, c, d)), its vertex
 * and the two vertices along its element's own edges. Returns the corners per entry. */
static int entry_corner(const tc_mesh_desc *d, int32_t k, int j, int32_t *cid, int32_t v[3]) {
    int32_t e = d->corner_gradients_tri[k];
    if (d->ntris > 0) {
        const int32_t *tv = d->tris + 3 * (size_t)e;
        *cid = 3 * e + j, v[0] = tv[j], v[1] = tv[(j + 1) % 3], v[2] = tv[(j + 2) % 3];
        return 3;
    }
    static const int split[4] = {0, 1, 2, 5};
    const int32_t *qv = d->quads + 4 * (size_t)e;
    *cid = 6 * e + split[j], v[0] = qv[j], v[1] = qv[(j + 1) % 4], v[2] = qv[(j + 3) % 4];
    return 4;
}

/* The corner tangent planes r used against the scene mesh's corner gradients.
 * The corner reported is the one whose plane error moves a Bezier ordinate the
 * most: uuv = z_u + g_u . (v - u) / 3, so the ordinate error is
 * |(g_used - g_scene) . (v - u)| / 3 over the corner's two edges. (The raw slope
 * error peaks inside slivers, across which it hardly moves anything.) */
static void tangent_error(const tc_recon *r, const tc_scene_mesh *sm, bench_result *out) {
    const double *used = tc_recon_corner_gradients(r);
    const tc_mesh_desc *d = &sm->desc;
    if (!used || !d->corner_gradients || d->nchan != 1) return;
    double sum2 = 0;
    int64_t n = 0;
    for (int32_t k = 0; k < d->ncorner_gradients; k++) {
        int32_t cid, v[3];
        for (int c = 0, nk = entry_corner(d, k, 0, &cid, v); c < nk; c++) {
            entry_corner(d, k, c, &cid, v);
            const double *gs = d->corner_gradients + 2 * ((size_t)nk * (size_t)k + (size_t)c), *gu = used + 2 * (size_t)cid;
            const double *p = d->xy + 2 * (size_t)v[0];
            double dg[2] = {gu[0] - gs[0], gu[1] - gs[1]}, e = hypot(dg[0], dg[1]), moved = 0;
            for (int j = 1; j <= 2; j++) {
                const double *q = d->xy + 2 * (size_t)v[j];
                moved = fmax(moved, fabs(dg[0] * (q[0] - p[0]) + dg[1] * (q[1] - p[1])) / 3);
            }
            sum2 += e * e, n++;
            if (moved <= out->tan_impact) continue;
            out->tan_impact = moved, out->tan_max = e, out->tan_at[0] = p[0], out->tan_at[1] = p[1];
            out->tan_scene = hypot(gs[0], gs[1]), out->tan_used = hypot(gu[0], gu[1]);
        }
    }
    out->has_tangents = n > 0;
    out->tan_rms = n ? sqrt(sum2 / (double)n) : 0;
}

/* The box: the share of the image's summed error near the footprint corners,
 * from the tile in ref->tile. */
static double corner_share(const bench_reference *ref) {
    const tc_scene *s = ref->scene;
    if (s->occluder != TC_OCCLUDER_BOX) return NAN;
    double near = 0, all = 0, r2 = BENCH_CORNER_RADIUS * BENCH_CORNER_RADIUS;
    for (size_t k = 0; k < (size_t)BENCH_W * BENCH_W; k++) {
        double e = fabs(ref->ref[k] - ref->tile[k]), x = ref->xy[2 * k], y = ref->xy[2 * k + 1], d2 = INFINITY;
        for (int c = 0; c < 4; c++) {
            double dx = x - s->occ[c & 1 ? 2 : 0], dy = y - s->occ[c & 2 ? 3 : 1];
            d2 = fmin(d2, dx * dx + dy * dy);
        }
        all += e;
        if (d2 <= r2) near += e;
    }
    return all > 0 ? near / all : NAN;
}

/* The squared error of the tile in ref->tile, all of it and the part in pixels
 * whose triangle touches a flat one (results.h, sq_err_by_flat). */
static void flat_error(const bench_reference *ref, const tc_mesh *m, bench_result *out) {
    int32_t nv = tc_mesh_vertex_count(m), nt = tc_mesh_triangle_count(m);
    const int32_t *tri = tc_mesh_triangles(m);
    unsigned char *flat_vertex = calloc((size_t)nv, 1);
    out->sq_err = out->sq_err_by_flat = NAN;
    if (!flat_vertex) return;
    for (int32_t t = 0; t < nt; t++) {
        double a = tc_mesh_corner_value(m, t, 0)[0];
        if (a == tc_mesh_corner_value(m, t, 1)[0] && a == tc_mesh_corner_value(m, t, 2)[0])
            for (int k = 0; k < 3; k++) flat_vertex[tri[3 * t + k]] = 1;
    }
    double all = 0, by_flat = 0;
    for (size_t k = 0; k < (size_t)BENCH_W * BENCH_W; k++) {
        double e = ref->ref[k] - ref->tile[k];
        int32_t t = ref->owner[k];
        all += e * e;
        if (t >= 0 && (flat_vertex[tri[3 * t]] || flat_vertex[tri[3 * t + 1]] || flat_vertex[tri[3 * t + 2]]))
            by_flat += e * e;
    }
    free(flat_vertex);
    out->sq_err = all, out->sq_err_by_flat = by_flat;
}

/* One render with owners, outside the timed ones (which write no owners, as
 * a caller that only wants the picture would): the overshoot against each
 * pixel's own triangle, and the box's corner share. */
static void untimed_render(const bench_reference *ref, const bench_prepared *p, bench_result *out) {
    tc_render_options ro = {.threads = 2}; /* the same bytes on any thread count */
    tc_render(p->recon, p->loc, &ref->vp, &ro, ref->tile, ref->owner);
    tc_overshoot(p->mesh, ref->tile, ref->owner, BENCH_W, BENCH_W, BENCH_OVER_THRESHOLD, &out->over);
    out->corner_share = corner_share(ref);
    flat_error(ref, p->mesh, out);
}

int bench_measure_begin(const bench_reference *ref, const tc_scene_mesh *sm, int method, bench_result *out,
                        bench_pending *pend) {
    const bench_method *bm = &bench_methods[method];
    const tc_scene *s = ref->scene;
    memset(pend, 0, sizeof *pend);
    pend->method = method;
    out->method = method;
    out->nverts = sm->desc.nverts; /* a quad version: its split triangles, the same cells */
    out->ntris = sm->desc.ntris > 0 ? sm->desc.ntris : 2 * sm->desc.nquads;
    out->flagged_c0 = sm->flagged_c0, out->flagged_cm1 = sm->flagged_cm1;
    out->worst_aspect = sm->worst_aspect;
    out->samples = bench_method_samples(sm, bm);
    out->corner_share = NAN;
    out->gradient_samples = bench_method_gradient_samples(sm, bm);
    if (bench_prepare(sm, bm, &pend->p, &out->mesh_ms, out->note, sizeof out->note) != 0) return -1;
    tc_compare(pend->p.recon, pend->p.loc, (size_t)BENCH_W * BENCH_W, ref->xy, ref->ref, s->scale, &out->err);
    tangent_error(pend->p.recon, sm, out);
    untimed_render(ref, &pend->p, out);
    out->scan = malloc((size_t)BENCH_SCAN_N * sizeof *out->scan);
    double *v = malloc((size_t)BENCH_SCAN_N * sizeof *v);
    if (!out->scan || !v) {
        free(v);
        snprintf(out->note, sizeof out->note, "out of memory");
        bench_prepared_free(&pend->p);
        return -1;
    }
    tc_eval_points(pend->p.recon, pend->p.loc, BENCH_SCAN_N, ref->scan_xy, v, NULL, NULL);
    for (int j = 0; j < BENCH_SCAN_N; j++) out->scan[j] = fabs(ref->scan_ref[j] - v[j]) / s->scale;
    free(v);
    /* One untimed call sets the batch size: a batch lasts BENCH_BUILD_BATCH_MS;
     * a call longer than BENCH_BUILD_BIG_MS is timed alone, 3 times. */
    double t0 = bench_now_ms();
    tc_recon *r = NULL;
    tc_recon_new(pend->p.mesh, &bm->opt, &r, NULL);
    double first = bench_now_ms() - t0;
    tc_recon_free(r);
    pend->batches = BENCH_BUILD_BATCHES, pend->reps = 1;
    if (first > BENCH_BUILD_BIG_MS) pend->batches = 3;
    else pend->reps = (int)fmin(100000, fmax(1, ceil(BENCH_BUILD_BATCH_MS / fmax(first, 1e-6))));
    pend->active = 1;
    return 0;
}

void bench_measure_round(const bench_reference *ref, bench_pending *pend, int round) {
    if (!pend->active) return;
    if (round < pend->batches)
        pend->build[round] = build_batch(pend->p.mesh, &bench_methods[pend->method].opt, pend->reps);
    if (round < BENCH_RENDER_REPS) {
        tc_render_options ro = {.threads = 1};
        double t0 = bench_now_ms();
        tc_render(pend->p.recon, pend->p.loc, &ref->vp, &ro, ref->tile, NULL);
        pend->render[round] = bench_now_ms() - t0;
    }
}

void bench_measure_end(bench_pending *pend, bench_result *out) {
    if (!pend->active) return;
    out->build_ms = bench_median(pend->build, pend->batches);
    out->build_reps = pend->reps;
    out->render_ms = bench_median(pend->render, BENCH_RENDER_REPS);
    out->ok = 1;
    bench_prepared_free(&pend->p);
    pend->active = 0;
}

void bench_exact_overshoot(const bench_reference *ref, const bench_prepared *p, tc_overshoot_stats *out) {
    for (size_t k = 0; k < (size_t)BENCH_W * BENCH_W; k++) {
        ref->tile[k] = (float)ref->ref[k];
        ref->owner[k] = tc_locate(p->loc, ref->xy[2 * k], ref->xy[2 * k + 1]);
    }
    tc_overshoot(p->mesh, ref->tile, ref->owner, BENCH_W, BENCH_W, BENCH_OVER_THRESHOLD, out);
}
