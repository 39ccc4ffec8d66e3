/* pipeline.c — the tangent-plane pipeline the methods with tangent planes share:
 * wedges -> corner input planes -> wedge planes -> (range-limited) corner planes, and
 * the cubics' build on top of it (the ordinates, ct.c / ct_range.c). */
#include <string.h>

#include "core/alloc.h"
#include "core/ct.h"
#include "core/parallel.h"
#include "core/pipeline.h"
#include "core/recon.h"
#include "core/tangent.h"

/* Without flags every wedge is bounded by the mesh boundary only; corner
 * values that differ inside one wedge (C-1 data) are replaced by their mean,
 * so the C1 baseline really is continuous there. NULL: use the mesh's values
 * (also whenever C-1 edges delimit wedges: values agree inside each wedge). */
static double *merged_values(const struct tc_mesh *m, const tc__wedge_set *ws, int *rc) {
    *rc = TC_OK;
    if (ws->honor_flags != TC_HONOR_NONE || m->ncorner_overrides == 0) return NULL;
    int nc = m->nc;
    double *cz = tc__malloc(3 * (size_t)m->nt * (size_t)nc, sizeof *cz);
    if (!cz) {
        *rc = TC_ENOMEM;
        return NULL;
    }
    for (int32_t w = 0; w < ws->nw; w++) {
        const tc__wedge *wd = &ws->w[w];
        for (int ch = 0; ch < nc; ch++) {
            double s = 0;
            for (int32_t i = 0; i < wd->count; i++) s += m->cz[tc__ix(ws->corners[wd->first + i], nc, ch)];
            for (int32_t i = 0; i < wd->count; i++) cz[tc__ix(ws->corners[wd->first + i], nc, ch)] = s / wd->count;
        }
    }
    return cz;
}

typedef struct {
    tc__wedge_set ws;
    double *cz_own; /* merged values, or NULL */
    double *inputs;       /* [3nt][nc][2] corner input planes */
    double *wedge_planes; /* [nw][nc][2] */
} ct_scratch;

static void ct_scratch_free(ct_scratch *s) {
    tc__wedges_free(&s->ws);
    tc__free(s->cz_own);
    tc__free(s->inputs);
    tc__free(s->wedge_planes);
}

/* Each corner's plane is its wedge's: planes[c] = wedge_planes[of_corner[c]]. */
typedef struct {
    double *planes;
    const double *wedge_planes;
    const int32_t *of_corner;
    size_t stride;
} corner_copy;

static void copy_planes(void *ctx, int32_t lo, int32_t hi, int part) {
    const corner_copy *cc = ctx;
    (void)part;
    for (int32_t c = lo; c < hi; c++) {
        const double *src = cc->wedge_planes + (size_t)cc->of_corner[c] * cc->stride;
        double *dst = cc->planes + (size_t)c * cc->stride;
        for (size_t i = 0; i < cc->stride; i++) dst[i] = src[i];
    }
}

/* Wedges delimited per the method's honour (TC_HONOR_*) -> corner inputs ->
 * wedge planes; fills r->planes and leaves the intermediate steps in s. */
static int ct_planes(struct tc_recon *r, ct_scratch *s, tc_diags *dg) {
    const struct tc_mesh *m = r->m;
    size_t stride = 2 * (size_t)m->nc;
    int rc = tc__wedges_build_on(m, r->method->honour, r->opt.threads, &s->ws);
    if (rc != TC_OK) return rc;
    if (tc__recon_late(r)) return TC_ETIMEOUT;
    s->ws.deadline_ms = r->opt.deadline_ms; /* the corner inputs' fits: the build's longest loop */
    s->cz_own = merged_values(m, &s->ws, &rc);
    if (rc != TC_OK) return rc;
    s->inputs = tc__malloc(3 * (size_t)m->nt, stride * sizeof *s->inputs);
    s->wedge_planes = tc__malloc((size_t)s->ws.nw, stride * sizeof *s->wedge_planes);
    r->planes = tc__malloc(3 * (size_t)m->nt, stride * sizeof *r->planes);
    if (!s->inputs || !s->wedge_planes || !r->planes) return TC_ENOMEM;
    const double *cz = s->cz_own ? s->cz_own : m->cz;
    rc = tc__corner_inputs(m, &s->ws, cz, r->opt.tangents, s->inputs, dg);
    if (rc != TC_OK) return rc;
    if (tc__recon_late(r)) return TC_ETIMEOUT;
    rc = tc__wedge_planes(m, &s->ws, s->inputs, r->opt.wedges, r->opt.average, s->wedge_planes, dg);
    if (rc != TC_OK) return rc;
    corner_copy cc = {r->planes, s->wedge_planes, s->ws.of_corner, stride};
    tc__parallel_for(r->opt.threads, 3 * m->nt, 4096, copy_planes, &cc);
    return tc__recon_late(r) ? TC_ETIMEOUT : TC_OK; /* before the callers' next stage */
}

/* Limits the planes r->planes (range.h) for a method that uses them as `use` says. */
static int limit_planes(struct tc_recon *r, const ct_scratch *s, const tc__plane_use *use, tc_diags *dg) {
    const double *cz = s->cz_own ? s->cz_own : r->m->cz;
    tc__bounds b;
    tc__range_stats stats;
    tc__range_stats_init(&stats);
    int rc = tc__bounds_build(r->m, &s->ws, cz, r->planes, r->opt.tangents, r->opt.range, use->per_quad, &b);
    if (rc == TC_OK) rc = tc__range_planes(r->m, &s->ws, cz, &b, use->dirs, use->ctx, r->planes, &stats);
    if (rc == TC_OK) tc__range_warn(r->m, &stats, r->opt.range, dg);
    tc__bounds_free(&b);
    return rc;
}

int tc__planes_build(struct tc_recon *r, const tc__plane_use *use, tc_diags *dg) {
    ct_scratch s;
    memset(&s, 0, sizeof s);
    int rc = ct_planes(r, &s, dg);
    if (rc == TC_OK && use && use->dirs && r->opt.range != TC_RANGE_FREE) rc = limit_planes(r, &s, use, dg);
    ct_scratch_free(&s);
    return rc;
}

int tc__ct_build(struct tc_recon *r, tc_diags *dg) {
    ct_scratch s;
    memset(&s, 0, sizeof s);
    int rc = ct_planes(r, &s, dg);
    if (rc == TC_OK) {
        tc__ct_input ci = {r->m, &s.ws, s.cz_own ? s.cz_own : r->m->cz, r->planes, s.inputs,
                         r->opt.cross_boundary, r->opt.tangents, r->opt.wedges,
                         r->opt.wedges == TC_WEDGES_CORRECTED && r->opt.average == TC_AVERAGE_AREA,
                         r->opt.threads};
        rc = r->opt.range == TC_RANGE_FREE ? tc__ct_ordinates(&ci, r->coef, dg)
                                           : tc__ct_ordinates_ranged(&ci, r->opt.range, r->planes, r->coef, dg);
    }
    ct_scratch_free(&s);
    return rc;
}
