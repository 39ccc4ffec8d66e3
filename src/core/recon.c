/* recon.c — tc_recon: one reconstruction of a mesh. Runs the build of the
 * method's row (method.c) — for the cubics wedges -> tangent planes -> ordinates —
 * and keeps only the coefficients and the corner planes; the rest is scratch. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/ct.h"
#include "core/internal.h"
#include "core/range.h"
#include "core/recon.h"
#include "core/tangent.h"

void tc_recon_free(tc_recon *r) {
    if (!r) return;
    free(r->coef);
    free(r->cgrad);
    free(r);
}

/* Without flags every wedge is bounded by the mesh boundary only; corner
 * values that differ inside one wedge (C-1 data) are replaced by their mean,
 * so the C1 baseline really is continuous there. NULL: use the mesh's values
 * (also whenever C-1 edges delimit wedges: values agree inside each wedge). */
static double *merged_values(const struct tc_mesh *m, const tc_wedge_set *ws, int *st) {
    *st = TC_OK;
    if (ws->honor_flags != TC_HONOR_NONE || m->ncorner_overrides == 0) return NULL;
    int nc = m->nc;
    double *cz = tc__malloc(3 * (size_t)m->nt * nc, sizeof *cz);
    if (!cz) {
        *st = TC_ENOMEM;
        return NULL;
    }
    for (int32_t w = 0; w < ws->nw; w++) {
        const tc_wedge *wd = &ws->w[w];
        for (int ch = 0; ch < nc; ch++) {
            double s = 0;
            for (int32_t i = 0; i < wd->count; i++) s += m->cz[(size_t)ws->corners[wd->first + i] * nc + ch];
            for (int32_t i = 0; i < wd->count; i++) cz[(size_t)ws->corners[wd->first + i] * nc + ch] = s / wd->count;
        }
    }
    return cz;
}

typedef struct {
    tc_wedge_set ws;
    double *cz_own; /* merged values, or NULL */
    double *in;     /* [3nt][nc][2] corner input planes */
    double *wp;     /* [nw][nc][2] wedge planes */
} ct_scratch;

static void ct_scratch_free(ct_scratch *s) {
    tc__wedges_free(&s->ws);
    free(s->cz_own);
    free(s->in);
    free(s->wp);
}

/* Wedges delimited per the method's honour (TC_HONOR_*) -> corner inputs ->
 * wedge planes; fills r->cgrad and leaves the intermediate steps in s. */
static int ct_planes(struct tc_recon *r, ct_scratch *s, tc_diags *dg) {
    const struct tc_mesh *m = r->m;
    size_t stride = 2 * (size_t)m->nc;
    int st = tc__wedges_build(m, r->method->honour, &s->ws);
    if (st != TC_OK) return st;
    s->cz_own = merged_values(m, &s->ws, &st);
    if (st != TC_OK) return st;
    s->in = tc__malloc(3 * (size_t)m->nt, stride * sizeof *s->in);
    s->wp = tc__malloc((size_t)s->ws.nw, stride * sizeof *s->wp);
    r->cgrad = tc__malloc(3 * (size_t)m->nt, stride * sizeof *r->cgrad);
    if (!s->in || !s->wp || !r->cgrad) return TC_ENOMEM;
    const double *cz = s->cz_own ? s->cz_own : m->cz;
    if ((st = tc__corner_inputs(m, &s->ws, cz, r->opt.tangents, s->in, dg)) != TC_OK) return st;
    if ((st = tc__wedge_planes(m, &s->ws, s->in, r->opt.wedges, r->opt.average, s->wp, dg)) != TC_OK) return st;
    for (size_t c = 0; c < 3 * (size_t)m->nt; c++)
        memcpy(r->cgrad + c * stride, s->wp + (size_t)s->ws.of_corner[c] * stride, stride * sizeof *r->cgrad);
    return TC_OK;
}

/* Limits the planes r->cgrad (range.h) for a method that uses them as `use` says. */
static int limit_planes(struct tc_recon *r, const ct_scratch *s, const tc_plane_use *use, tc_diags *dg) {
    const double *cz = s->cz_own ? s->cz_own : r->m->cz;
    tc_bounds b;
    tc_range_stats st;
    tc__range_stats_init(&st);
    int rc = tc__bounds_build(r->m, &s->ws, cz, r->cgrad, r->opt.tangents, r->opt.range, use->per_quad, &b);
    if (rc == TC_OK) rc = tc__range_planes(r->m, &s->ws, cz, &b, use->dirs, use->ctx, r->cgrad, &st);
    if (rc == TC_OK) tc__range_warn(r->m, &st, r->opt.range, dg);
    tc__bounds_free(&b);
    return rc;
}

int tc__recon_planes(struct tc_recon *r, const tc_plane_use *use, tc_diags *dg) {
    ct_scratch s;
    memset(&s, 0, sizeof s);
    int st = ct_planes(r, &s, dg);
    if (st == TC_OK && use && use->dirs && r->opt.range != TC_RANGE_FREE) st = limit_planes(r, &s, use, dg);
    ct_scratch_free(&s);
    return st;
}

int tc__ct_build(struct tc_recon *r, tc_diags *dg) {
    ct_scratch s;
    memset(&s, 0, sizeof s);
    int st = ct_planes(r, &s, dg);
    if (st == TC_OK) {
        tc_ct_input x = {r->m, &s.ws, s.cz_own ? s.cz_own : r->m->cz, r->cgrad, s.in,
                         r->opt.cross_boundary, r->opt.tangents, r->opt.wedges,
                         r->opt.wedges == TC_WEDGES_CORRECTED && r->opt.average == TC_AVERAGE_AREA};
        st = r->opt.range == TC_RANGE_FREE ? tc__ct_ordinates(&x, r->coef, dg)
                                           : tc__ct_ordinates_ranged(&x, r->opt.range, r->cgrad, r->coef, dg);
    }
    ct_scratch_free(&s);
    return st;
}

/* Coefficients beyond this make evaluation overflow (a few dozen of them are
 * summed with weights up to 3); refusing them keeps every output finite. */
#define TC_COEF_MAX 1e300

/* Steep tangent planes on large triangles, or values near the double range,
 * can overflow the ordinates: refuse the input, naming the triangle. */
static int check_bounded(const struct tc_recon *r, tc_diags *dg) {
    size_t per_tri = (size_t)r->m->nc * r->ncoef;
    for (int32_t t = 0; t < r->m->nt; t++)
        for (size_t i = 0; i < per_tri; i++) {
            double c = r->coef[(size_t)t * per_tri + i];
            if (isfinite(c) && fabs(c) <= TC_COEF_MAX) continue;
            char path[48];
            tc__elem_path(r->m, t, path, sizeof path);
            return tc_diags_add(dg, TC_SEV_ERROR, path,
                                "the reconstruction overflows here (ordinate %s = %g): the tangent planes at its corners "
                                "are too steep for its size, or its values too large",
                                r->labels[i % r->ncoef], c);
        }
    return TC_OK;
}

/* A method that keeps C-1 but not C0 flags reads them as C1: say so once,
 * counting the edges, after the build (so an error stays the first finding). */
static void warn_c0_ignored(const struct tc_recon *r, tc_diags *dg) {
    const struct tc_mesh *m = r->m;
    int32_t n = 0;
    if (r->method->honour != TC_HONOR_CM1) return;
    for (int32_t e = 0; e < 3 * m->nt; e++) n += m->flag[e] == TC_C0 && m->nbr[e] > e / 3;
    if (n)
        tc_diags_add(dg, TC_SEV_WARNING, "discontinuities.c0", "%s cannot honour C0 flags; they are treated as C1 (%d edges): the kinks are "
                     "smoothed, use clough-tocher to keep them",
                     r->method->name, (int)n);
}

static int build(struct tc_recon *r, tc_diags *dg) {
    const struct tc_mesh *m = r->m;
    const tc__method *mt = tc__method_of(r->opt.method);
    if (!mt) return tc_diags_add(dg, TC_SEV_ERROR, "method", "unknown method %d", (int)r->opt.method);
    if (mt->quads_only && m->nq == 0)
        return tc_diags_add(dg, TC_SEV_ERROR, "triangles", "%s needs quads: give the mesh as \"quads\": [[a, b, c, d], ...]",
                            mt->name);
    r->method = mt, r->ncoef = mt->ncoef, r->labels = mt->labels, r->eval = mt->eval;
    r->coef = tc__malloc((size_t)m->nt * m->nc, (size_t)r->ncoef * sizeof *r->coef);
    if (!r->coef) return TC_ENOMEM;
    int st = mt->build(r, dg);
    if (st == TC_OK) st = check_bounded(r, dg);
    if (st == TC_OK) warn_c0_ignored(r, dg);
    return st;
}

/* The channels whose data are all >= 0: a restricted range keeps them so. */
static void set_floors(struct tc_recon *r) {
    const struct tc_mesh *m = r->m;
    for (int ch = 0; ch < m->nc; ch++) {
        int nonneg = 1;
        for (size_t c = 0; c < 3 * (size_t)m->nt && nonneg; c++) nonneg = m->cz[c * m->nc + ch] >= 0;
        r->floor0[ch] = (uint8_t)nonneg;
    }
}

/* A method that formats "triangles[t]" itself on a quad mesh would name an
 * element the caller never sent: the findings this build added are renamed to
 * "quads[t/2]" (the rest of the path kept), so every path is the request's. */
static void quad_paths(const struct tc_mesh *m, tc_diags *dg, int from) {
    for (int i = from; m->nq && dg && i < dg->count; i++) {
        char *p = dg->items[i].path, renamed[2 * sizeof dg->items[i].path];
        int t, n = 0;
        if (sscanf(p, "triangles[%d]%n", &t, &n) != 1 || n == 0 || t < 0) continue;
        int len = snprintf(renamed, sizeof renamed, "quads[%d]%s", t / 2, p + n);
        if (len > 0 && (size_t)len < sizeof dg->items[i].path) memcpy(p, renamed, (size_t)len + 1); /* shorter */
    }
}

int tc_recon_new(const tc_mesh *m, const tc_options *o, tc_recon **out, tc_diags *diags) {
    *out = NULL;
    struct tc_recon *r = calloc(1, sizeof *r);
    if (!r) return TC_ENOMEM;
    r->m = m;
    if (o) r->opt = *o;
    else tc_options_default(&r->opt);
    int from = diags ? diags->count : 0;
    int st = build(r, diags);
    if (st == TC_OK && r->opt.range == TC_RANGE_FREE && r->method->ordinates)
        tc__range_report_free(r, r->method->ordinates, diags);
    if (st == TC_OK && r->opt.range != TC_RANGE_FREE && r->method->ordinates) set_floors(r);
    quad_paths(m, diags, from);
    if (st != TC_OK) {
        tc_recon_free(r);
        return st;
    }
    *out = r;
    return TC_OK;
}

const tc_mesh *tc_recon_mesh(const tc_recon *r) { return r->m; }
const tc_options *tc_recon_options(const tc_recon *r) { return &r->opt; }
int tc_recon_coef_count(const tc_recon *r) { return r->ncoef; }
const char *tc_recon_coef_label(const tc_recon *r, int i) { return i >= 0 && i < r->ncoef ? r->labels[i] : NULL; }
const double *tc_recon_coefs(const tc_recon *r) { return r->coef; }
const double *tc_recon_corner_gradients(const tc_recon *r) { return r->cgrad; }
