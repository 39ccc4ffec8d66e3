/* stab_props.c — what every method promises, measured on any mesh (interpolation, C0, C1 on local
 * scales), and dense sampling for the reconstruction's range, overshoot and largest gradient. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/ct.h"
#include "core/geom.h"
#include "core/mesh.h"
#include "core/recon.h"
#include "stab.h"

/* What a method promises, and which interior flags it honours (1 all, 0 none, 2 C-1 only). */
typedef struct {
    int interp, c0, c1, vertex, internal, honor;
} promise;

static promise promises_of(const tc_options *o) {
    switch (o->method) {
    case TC_METHOD_CONSTANT: return (promise){0, 0, 0, 0, 0, 1};
    case TC_METHOD_LINEAR:
    case TC_METHOD_LINEAR4:
    case TC_METHOD_HERMITE: return (promise){1, 1, 0, 0, 0, 1};
    case TC_METHOD_CLOUGH_TOCHER: return (promise){1, 1, 1, 1, 1, 1};
    case TC_METHOD_CLOUGH_TOCHER_C1: return (promise){1, 1, 1, 1, 1, 0};
    case TC_METHOD_POWELL_SABIN: return (promise){1, 1, 1, 0, 0, 2};
    case TC_METHOD_COUNT: break; /* not a method */
    }
    return (promise){0, 0, 0, 0, 0, 1};
}

static int eff_flag(const tc_mesh *m, int32_t e, int honor) {
    if (m->nbr[e] < 0) return TC_CM1;
    int f = m->flag[e];
    if (honor == 1) return f;
    return honor == 2 && f == TC_CM1 ? TC_CM1 : TC_C1;
}

/* Floors of the local scales: DBL_EPSILON times the mesh's largest, so a region where
 * the data and its slopes are 0 is measured against the rounding of the whole mesh. */
static double vfloor = DBL_TRUE_MIN, gfloor = DBL_TRUE_MIN;

/* Local scales of triangle t: gs the largest corner plane or edge slope; vs the
 * largest |corner value| plus gs times the longest edge (what the piece can reach). */
static void tri_scales(const tc_recon *r, int32_t t, double *vs, double *gs) {
    const tc_mesh *m = tc_recon_mesh(r);
    const double *cg = tc_recon_corner_gradients(r);
    int nc = m->nc;
    double zmax = 0, lmax = 0;
    *gs = gfloor;
    for (int k = 0; k < 3; k++) {
        const double *a = tc__vxy(m, m->tri[3 * t + k]), *b = tc__vxy(m, m->tri[3 * t + (k + 1) % 3]);
        double len = hypot(b[0] - a[0], b[1] - a[1]);
        lmax = fmax(lmax, len);
        for (int ch = 0; ch < nc; ch++) {
            size_t c = 3 * (size_t)t + (size_t)k, c2 = 3 * (size_t)t + (size_t)(k + 1) % 3;
            zmax = fmax(zmax, fabs(m->cz[c * (size_t)nc + (size_t)ch]));
            *gs = fmax(*gs, fabs(m->cz[c2 * (size_t)nc + (size_t)ch] - m->cz[c * (size_t)nc + (size_t)ch]) / len);
            if (cg) *gs = fmax(*gs, hypot(cg[(c * (size_t)nc + (size_t)ch) * 2], cg[(c * (size_t)nc + (size_t)ch) * 2 + 1]));
        }
    }
    *vs = fmax(vfloor, zmax + *gs * lmax);
}

static const double S[] = {0.0, 0.137, 0.5, 0.771, 1.0};
#define NS (sizeof S / sizeof S[0])

/* Value and gradient of t's piece at s of the way from vertex a to vertex b, with
 * barycentrics exactly on the edge (the point itself is off it by rounding). */
static void on_edge(const tc_recon *r, int32_t t, int32_t a, int32_t b, double s, double *v, double *g) {
    const tc_mesh *m = tc_recon_mesh(r);
    const double *pa = tc__vxy(m, a), *pb = tc__vxy(m, b);
    tc__eval_point at;
    tc__at(m, t, pa[0] + s * (pb[0] - pa[0]), pa[1] + s * (pb[1] - pa[1]), &at);
    int ka = tc__corner_of(m, t, a), kb = tc__corner_of(m, t, b);
    at.lam[ka] = 1 - s, at.lam[kb] = s, at.lam[3 - ka - kb] = 0;
    const double *coef = r->coef + (size_t)t * (size_t)m->nc * (size_t)r->ncoef;
    for (int ch = 0; ch < m->nc; ch++) r->eval(coef + (size_t)ch * (size_t)r->ncoef, &at, v + ch, g + 2 * ch);
}

/* Mismatch of the pieces of t and its neighbour along their edge k, values and
 * gradients from barycentrics exactly on the edge. A point computed on an edge is
 * off it by up to half an ulp, and across a sliver the two pieces' derivatives
 * (free to differ: a kink across a C0 edge, the second derivatives across a C1
 * one) turn that offset into a difference of (derivative jump) * ulp / width:
 * an artifact of the measuring point, not of the reconstruction. The points as
 * callers compute them are still evaluated (tc_eval_triangle) for finiteness. */
static void edge_residual(const tc_recon *r, int32_t t, int k, double *rv, double *rg) {
    const tc_mesh *m = tc_recon_mesh(r);
    int nc = m->nc;
    int32_t t2 = m->nbr[3 * t + k], ia = m->tri[3 * t + k], ib = m->tri[3 * t + (k + 1) % 3];
    const double *a = tc__vxy(m, ia), *b = tc__vxy(m, ib);
    double vs1, gs1, vs2, gs2;
    tri_scales(r, t, &vs1, &gs1);
    tri_scales(r, t2, &vs2, &gs2);
    double vs = fmax(vs1, vs2), gs = fmax(gs1, gs2);
    *rv = *rg = 0;
    for (size_t i = 0; i < NS; i++) {
        double x = a[0] + S[i] * (b[0] - a[0]), y = a[1] + S[i] * (b[1] - a[1]);
        double v1[TC_MAX_CHANNELS], v2[TC_MAX_CHANNELS], g1[2 * TC_MAX_CHANNELS], g2[2 * TC_MAX_CHANNELS];
        tc_eval_triangle(r, t, x, y, v1, NULL);
        tc_eval_triangle(r, t2, x, y, v2, NULL);
        for (int ch = 0; ch < nc; ch++)
            if (!isfinite(v1[ch]) || !isfinite(v2[ch])) *rv = INFINITY;
        on_edge(r, t, ia, ib, S[i], v1, g1);
        on_edge(r, t2, ia, ib, S[i], v2, g2);
        for (int ch = 0; ch < nc; ch++) *rv = fmax(*rv, fabs(v1[ch] - v2[ch]) / vs);
        for (int ch = 0; ch < nc; ch++) {
            *rg = fmax(*rg, hypot(g1[2 * ch] - g2[2 * ch], g1[2 * ch + 1] - g2[2 * ch + 1]) / gs);
            if (!isfinite(v1[ch] - v2[ch]) || !isfinite(g1[2 * ch] - g2[2 * ch] + g1[2 * ch + 1] - g2[2 * ch + 1]))
                *rv = *rg = INFINITY;
        }
    }
}

/* All corners of vertex v carry the same values. */
static int single_valued(const tc_mesh *m, int32_t v) {
    for (int32_t i = m->vstart[v] + 1; i < m->vstart[v + 1]; i++)
        if (memcmp(m->cz + (size_t)m->vcorner[i] * (size_t)m->nc, m->cz + (size_t)m->vcorner[m->vstart[v]] * (size_t)m->nc,
                   (size_t)m->nc * sizeof *m->cz))
            return 0;
    return 1;
}

static double corner_residual(const tc_recon *r, int skip_multi) {
    const tc_mesh *m = tc_recon_mesh(r);
    double worst = 0, val[TC_MAX_CHANNELS], vs, gs;
    for (int32_t t = 0; t < m->nt; t++) {
        tri_scales(r, t, &vs, &gs);
        for (int k = 0; k < 3; k++) {
            int32_t v = m->tri[3 * t + k];
            if (skip_multi && !single_valued(m, v)) continue;
            tc_eval_triangle(r, t, tc__vxy(m, v)[0], tc__vxy(m, v)[1], val, NULL);
            for (int ch = 0; ch < m->nc; ch++) {
                double d = fabs(val[ch] - m->cz[(3 * (size_t)t + (size_t)k) * (size_t)m->nc + (size_t)ch]) / vs;
                worst = isfinite(d) ? fmax(worst, d) : INFINITY;
            }
        }
    }
    return worst;
}

/* Vertex class as the paper defines it, from the flags the method honours. */
static int c1_vertex(const tc_mesh *m, int32_t v, int honor) {
    int ncm1 = 0, nc0 = 0;
    double d[2][2] = {{0, 0}, {0, 0}};
    for (int32_t i = m->vstart[v]; i < m->vstart[v + 1]; i++) {
        int32_t c = m->vcorner[i], t = c / 3, k = c % 3, es[2] = {c, 3 * t + (k + 2) % 3};
        for (int j = 0; j < 2; j++) {
            int32_t e = es[j], a = m->tri[e], b = m->tri[3 * (e / 3) + (e % 3 + 1) % 3], o = a == v ? b : a;
            if (m->nbr[e] >= 0 && m->nbr[e] < t) continue;
            int f = eff_flag(m, e, honor);
            ncm1 += f == TC_CM1;
            if (f == TC_C0 && nc0 < 2) tc__sub(d[nc0], tc__vxy(m, o), tc__vxy(m, v));
            nc0 += f == TC_C0;
        }
    }
    return !ncm1 && (nc0 <= 1 || (nc0 == 2 && !tc__antiparallel(d[0], d[1])));
}

static double vertex_residual(const tc_recon *r, int honor) {
    const tc_mesh *m = tc_recon_mesh(r);
    double worst = 0;
    for (int32_t v = 0; v < m->nv; v++) {
        if (m->vstart[v] == m->vstart[v + 1] || !c1_vertex(m, v, honor)) continue;
        double g0[2 * TC_MAX_CHANNELS], gi[2 * TC_MAX_CHANNELS], val[TC_MAX_CHANNELS], gs = 1e-300, vs;
        for (int32_t i = m->vstart[v]; i < m->vstart[v + 1]; i++) {
            double s;
            tri_scales(r, m->vcorner[i] / 3, &vs, &s);
            gs = fmax(gs, s);
        }
        const double *p = tc__vxy(m, v);
        tc_eval_triangle(r, m->vcorner[m->vstart[v]] / 3, p[0], p[1], val, g0);
        for (int32_t i = m->vstart[v] + 1; i < m->vstart[v + 1]; i++) {
            tc_eval_triangle(r, m->vcorner[i] / 3, p[0], p[1], val, gi);
            for (int ch = 0; ch < m->nc; ch++) {
                double d = hypot(gi[2 * ch] - g0[2 * ch], gi[2 * ch + 1] - g0[2 * ch + 1]) / gs;
                worst = isfinite(d) ? fmax(worst, d) : INFINITY;
            }
        }
    }
    return worst;
}

/* The three internal edges (corner -> centroid) of the cubic split. */
static double internal_tri(const tc_recon *r, int32_t t) {
    const tc_mesh *m = tc_recon_mesh(r);
    int nc = m->nc;
    double lam[3], dl1[2], dl2[2], vs, gs, worst = 0;
    const double *p = tc__vxy(m, m->tri[3 * t]);
    tri_scales(r, t, &vs, &gs);
    tc__bary(m, t, p[0], p[1], lam, dl1, dl2);
    for (int i = 0; i < 3; i++)
        for (size_t j = 0; j < NS; j++) {
            double L[3];
            for (int q = 0; q < 3; q++) L[q] = (1 - S[j]) * (q == i) + S[j] / 3;
            for (int ch = 0; ch < nc; ch++) {
                const double *o = tc_recon_coefs(r) + ((size_t)t * (size_t)nc + (size_t)ch) * TC_CT_ORDINATES;
                double va, vb, ga[2], gb[2];
                tc__ct_eval_sub(o, (i + 1) % 3, L, dl1, dl2, &va, ga);
                tc__ct_eval_sub(o, (i + 2) % 3, L, dl1, dl2, &vb, gb);
                double d = fmax(fabs(va - vb) / vs, hypot(ga[0] - gb[0], ga[1] - gb[1]) / gs);
                worst = isfinite(d) ? fmax(worst, d) : INFINITY;
            }
        }
    return worst;
}

static void set_floors(const tc_recon *r) {
    double vmax = 0, gmax = 0, vs, gs;
    vfloor = gfloor = DBL_TRUE_MIN;
    for (int32_t t = 0; t < tc_recon_mesh(r)->nt; t++) {
        tri_scales(r, t, &vs, &gs);
        vmax = fmax(vmax, vs), gmax = fmax(gmax, gs);
    }
    vfloor = fmax(DBL_TRUE_MIN, DBL_EPSILON * vmax), gfloor = fmax(DBL_TRUE_MIN, DBL_EPSILON * gmax);
}

static double worst_aspect(const tc_mesh *m) {
    double worst = 1;
    for (int32_t t = 0; t < m->nt; t++) {
        const double *p = tc__vxy(m, m->tri[3 * t]), *q = tc__vxy(m, m->tri[3 * t + 1]), *s = tc__vxy(m, m->tri[3 * t + 2]);
        double e[3][2] = {{q[0] - p[0], q[1] - p[1]}, {s[0] - q[0], s[1] - q[1]}, {p[0] - s[0], p[1] - s[1]}}, l = 0;
        for (int k = 0; k < 3; k++) l = fmax(l, hypot(e[k][0], e[k][1]));
        double a = l * l / fabs(e[0][0] * e[2][1] - e[0][1] * e[2][0]);
        if (a > worst) worst = a;
    }
    return worst;
}

double stab_c1_over_bound(const stab_cont *c) {
    double r = fmax(c->c1, fmax(c->vertex, c->internal));
    return isfinite(r) ? r / fmax(1e-9, STAB_C1_ULPS * DBL_EPSILON * c->aspect) : INFINITY;
}

void stab_continuity(const tc_recon *r, stab_cont *c) {
    const tc_mesh *m = tc_recon_mesh(r);
    const tc_options *o = tc_recon_options(r);
    promise p = promises_of(o);
    memset(c, 0, sizeof *c);
    c->aspect = worst_aspect(m);
    set_floors(r);
    if (p.interp) c->corner = corner_residual(r, o->method == TC_METHOD_CLOUGH_TOCHER_C1);
    for (int32_t t = 0; t < m->nt; t++)
        for (int k = 0; k < 3 && p.c0; k++) {
            int32_t e = 3 * t + k, t2 = m->nbr[e];
            int f = eff_flag(m, e, p.honor);
            if (t2 < t || f == TC_CM1) continue;
            double rv, rg;
            edge_residual(r, t, k, &rv, &rg);
            c->c0 = fmax(c->c0, rv);
            if (p.c1 && f == TC_C1) c->c1 = fmax(c->c1, rg);
        }
    if (p.vertex) c->vertex = vertex_residual(r, p.honor);
    for (int32_t t = 0; t < m->nt && p.internal; t++) c->internal = fmax(c->internal, internal_tri(r, t));
}

const char *stab_cont_which(const stab_cont *c) {
    double w = stab_cont_worst(c);
    return w == c->corner ? "corner" : w == c->c0 ? "C0" : w == c->c1 ? "C1 edge" : w == c->vertex ? "C1 vertex"
                                                                                            : "internal";
}

double stab_cont_worst(const stab_cont *c) {
    double w = fmax(fmax(c->corner, c->c0), fmax(fmax(c->c1, c->vertex), c->internal));
    return isfinite(c->corner + c->c0 + c->c1 + c->vertex + c->internal) ? w : INFINITY;
}

/* ---- dense sampling ---- */

static void sample_at(const tc_recon *r, int32_t t, double x, double y, stab_range *s) {
    int nc = tc_recon_mesh(r)->nc;
    double v[TC_MAX_CHANNELS], g[2 * TC_MAX_CHANNELS];
    tc_eval_triangle(r, t, x, y, v, g);
    for (int ch = 0; ch < nc; ch++) {
        double gn = hypot(g[2 * ch], g[2 * ch + 1]);
        if (!isfinite(v[ch]) || !isfinite(gn)) {
            s->nonfinite++;
            continue;
        }
        s->vmin = fmin(s->vmin, v[ch]), s->vmax = fmax(s->vmax, v[ch]), s->gmax = fmax(s->gmax, gn);
    }
}

static void data_range(const tc_mesh *m, stab_range *s) {
    s->zmin = INFINITY, s->zmax = -INFINITY;
    for (size_t i = 0; i < 3 * (size_t)m->nt * (size_t)m->nc; i++)
        s->zmin = fmin(s->zmin, m->cz[i]), s->zmax = fmax(s->zmax, m->cz[i]);
    for (size_t c = 0; m->mid && c < 3 * (size_t)m->nt; c++)
        for (int ch = 0; m->mid_has[c] && ch < m->nc; ch++)
            s->zmin = fmin(s->zmin, m->mid[c * (size_t)m->nc + (size_t)ch]),
            s->zmax = fmax(s->zmax, m->mid[c * (size_t)m->nc + (size_t)ch]);
}

void stab_sample(const tc_recon *r, int per_tri, uint64_t seed, stab_range *s) {
    const tc_mesh *m = tc_recon_mesh(r);
    trng g;
    trng_seed(&g, seed);
    memset(s, 0, sizeof *s);
    s->vmin = INFINITY, s->vmax = -INFINITY;
    data_range(m, s);
    for (int32_t t = 0; t < m->nt; t++) {
        const double *p[3] = {tc__vxy(m, m->tri[3 * t]), tc__vxy(m, m->tri[3 * t + 1]), tc__vxy(m, m->tri[3 * t + 2])};
        for (int i = 0; i < per_tri + 3 * (int)NS; i++) {
            double l[3];
            if (i < per_tri) {
                double a = trng_uniform(&g), b = trng_uniform(&g);
                if (a + b > 1) a = 1 - a, b = 1 - b;
                l[0] = 1 - a - b, l[1] = a, l[2] = b;
            } else { /* along edge k at S[j] */
                int k = (i - per_tri) / (int)NS, j = (i - per_tri) % (int)NS;
                l[k] = 1 - S[j], l[(k + 1) % 3] = S[j], l[(k + 2) % 3] = 0;
            }
            /* Relative to the first corner, as the core does. */
            double x = p[0][0] + (l[1] * (p[1][0] - p[0][0]) + l[2] * (p[2][0] - p[0][0]));
            double y = p[0][1] + (l[1] * (p[1][1] - p[0][1]) + l[2] * (p[2][1] - p[0][1]));
            sample_at(r, t, x, y, s);
        }
    }
}

double stab_overshoot(const stab_range *s) {
    double range = s->zmax - s->zmin;
    if (!(range > 0)) range = fmax(fabs(s->zmax), DBL_TRUE_MIN);
    double o = fmax(0, fmax(s->vmax - s->zmax, s->zmin - s->vmin));
    return s->nonfinite ? INFINITY : o / range;
}

static double max_norm2(const double *g, size_t n, const uint8_t *mask, size_t per) {
    double w = 0;
    for (size_t i = 0; g && i < n; i++)
        if (!mask || mask[i / per]) w = fmax(w, hypot(g[2 * i], g[2 * i + 1]));
    return w;
}

double stab_given_gradient(const tc_mesh_desc *d) {
    size_t nv = (size_t)d->nverts, nc = (size_t)d->nchan, nk = d->nquads > 0 ? 4 : 3;
    double w = max_norm2(d->gradients, nv * nc, d->gradients_mask, nc);
    w = fmax(w, max_norm2(d->corner_gradients, (size_t)d->ncorner_gradients * nk * nc, d->corner_gradients_mask, nc));
    for (size_t i = 0; d->normals && i < nv * nc; i++) {
        const double *n = d->normals + 3 * i;
        if ((!d->normals_mask || d->normals_mask[i / nc]) && n[2] > 0) w = fmax(w, hypot(n[0], n[1]) / n[2]);
    }
    return w;
}

int stab_measure(const tc_recon *r, int per_tri, uint64_t seed, stab_cont *c, stab_range *s) {
    stab_continuity(r, c);
    stab_sample(r, per_tri, seed, s);
    return stab_recon_finite(r) && !s->nonfinite;
}
