/* recon.c — tc_recon: one reconstruction of a mesh. Runs the build of the
 * method's row (method.c; for the methods with tangent planes pipeline.c) and
 * keeps only the coefficients and the corner planes; the rest is scratch. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/alloc.h"
#include "core/assert.h"
#include "core/mesh.h"
#include "core/option_table.h"
#include "core/parallel.h"
#include "core/range.h"
#include "core/recon.h"

void tc_recon_free(tc_recon *r) {
    if (!r) return;
    tc__free(r->coef);
    tc__free(r->planes);
    tc__free(r);
}

/* Coefficients beyond this make evaluation overflow (a few dozen of them are
 * summed with weights up to 3); refusing them keeps every output finite. */
#define TC_COEF_MAX 1e300

/* Steep tangent planes on large triangles, or values near the double range,
 * can overflow the ordinates: refuse the input, naming the triangle. */
static int bounded_from(const struct tc_recon *r, int32_t lo, int32_t hi, tc_diags *dg) {
    size_t per_tri = (size_t)r->m->nc * (size_t)r->ncoef;
    for (int32_t t = lo; t < hi; t++)
        for (size_t i = 0; i < per_tri; i++) {
            double c = r->coef[(size_t)t * per_tri + i];
            if (isfinite(c) && fabs(c) <= TC_COEF_MAX) continue;
            char path[48], size[64];
            tc__elem_path(r->m, t, path, sizeof path);
            if (isnan(c)) snprintf(size, sizeof size, "is not a number (two overflows of opposite sign met)");
            else if (isinf(c)) snprintf(size, sizeof size, "overflows the double range");
            else snprintf(size, sizeof size, "is %.3g, beyond %.0e", c, TC_COEF_MAX);
            return tc_diags_add(dg, TC_SEV_ERROR, path,
                                "the reconstruction overflows here: its ordinate %s %s; %s",
                                r->labels[i % (size_t)r->ncoef], size,
                                r->method->uses & TC__USES_PLANES
                                    ? "the tangent planes at its corners are too steep for its size, or its values "
                                      "too large"
                                    : "its values are too large");
        }
    return TC_OK;
}

/* On threads: each part finds its first unbounded triangle; the first of all
 * is reported, as the serial scan does. */
typedef struct {
    const struct tc_recon *r;
    int32_t first_bad[TC_PARALLEL_MAX];
} bounded_pass;

static void bounded_part(void *ctx, int32_t lo, int32_t hi, int part) {
    bounded_pass *bp = ctx;
    bp->first_bad[part] = INT32_MAX;
    for (int32_t t = lo; t < hi && bp->first_bad[part] == INT32_MAX; t++)
        if (bounded_from(bp->r, t, t + 1, NULL) != TC_OK) bp->first_bad[part] = t;
}

static int check_bounded(const struct tc_recon *r, tc_diags *dg) {
    bounded_pass bp;
    bp.r = r;
    int threads = r->opt.threads;
    tc__parallel_for(threads, r->m->nt, 4096, bounded_part, &bp);
    for (int p = 0; p < tc__parallel_parts(threads, r->m->nt, 4096); p++)
        if (bp.first_bad[p] != INT32_MAX) return bounded_from(r, bp.first_bad[p], r->m->nt, dg);
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
    r->coef = tc__malloc((size_t)m->nt * (size_t)m->nc, (size_t)r->ncoef * sizeof *r->coef);
    if (!r->coef) return TC_ENOMEM;
    int rc = mt->build(r, dg);
    if (rc == TC_OK && tc__recon_late(r)) rc = TC_ETIMEOUT;
    if (rc == TC_OK) rc = check_bounded(r, dg);
    if (rc == TC_OK) warn_c0_ignored(r, dg);
    return rc;
}

/* The channels whose data are all >= 0: a restricted range keeps them so. */
static void set_floors(struct tc_recon *r) {
    const struct tc_mesh *m = r->m;
    double lo[TC_MAX_CHANNELS], hi[TC_MAX_CHANNELS], big[TC_MAX_CHANNELS];
    tc__channel_range(m, m->cz, r->opt.threads, lo, hi, big);
    for (int ch = 0; ch < m->nc; ch++) r->floor0[ch] = (uint8_t)(lo[ch] >= 0);
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

int tc_recon_new(const tc_mesh *m, const tc_options *opt, tc_recon **out, tc_diags *diags) {
    TC_ASSERT(m && out);
    *out = NULL;
    struct tc_recon *r = calloc(1, sizeof *r);
    if (!r) return TC_ENOMEM;
    r->m = m;
    if (opt) r->opt = *opt;
    else tc_options_default(&r->opt);
    int from = diags ? diags->count : 0;
    int rc = build(r, diags);
    if (rc == TC_OK && r->opt.range == TC_RANGE_FREE && r->method->ordinates)
        tc__range_report_free(r, r->method->ordinates, diags);
    if (rc == TC_OK && r->opt.range != TC_RANGE_FREE && r->method->ordinates) set_floors(r);
    quad_paths(m, diags, from);
    if (rc != TC_OK) {
        tc_recon_free(r);
        return rc;
    }
    /* recon.h's invariants (check_bounded refused any coefficient beyond TC_COEF_MAX) */
    TC_ASSERT(r->method == tc__method_of(r->opt.method) && r->ncoef == r->method->ncoef);
    TC_ASSERT(r->labels == r->method->labels && r->eval == r->method->eval && r->coef);
    *out = r;
    return TC_OK;
}

const tc_mesh *tc_recon_mesh(const tc_recon *r) { return r->m; }
const tc_options *tc_recon_options(const tc_recon *r) { return &r->opt; }
int tc_recon_coef_count(const tc_recon *r) { return r->ncoef; }
const char *tc_recon_coef_label(const tc_recon *r, int i) { return i >= 0 && i < r->ncoef ? r->labels[i] : NULL; }
const double *tc_recon_coefs(const tc_recon *r) { return r->coef; }
const double *tc_recon_corner_gradients(const tc_recon *r) { return r->planes; }
