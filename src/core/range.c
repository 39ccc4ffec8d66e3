/* range.c — the projection of wedge tangent planes onto the planes whose
 * ordinates stay inside their triangles' bounds (the shared half of every range limiter). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/geom.h"
#include "core/mesh.h"
#include "core/minmax.h"
#include "core/parallel.h"
#include "core/qp.h"
#include "core/range.h"
#include "core/recon.h"

/* ---- statistics and warnings ---- */

void tc__range_stats_init(tc__range_stats *s) { memset(s, 0, sizeof *s); }

void tc__range_note(tc__range_tally *t, double size, int32_t where, int edge) {
    t->count++;
    int full = t->named == TC_RANGE_NAMED, i = full ? TC_RANGE_NAMED - 1 : t->named++;
    if (full && !(size > t->size[i])) return;
    for (; i > 0 && size > t->size[i - 1]; i--) { /* insertion, largest first */
        t->size[i] = t->size[i - 1], t->where[i] = t->where[i - 1], t->edge[i] = t->edge[i - 1];
    }
    t->size[i] = size, t->where[i] = where, t->edge[i] = edge;
}

/* x as "%.3g", or in words when it is not a finite number (data near the
 * double range: a ratio of huge values overflows); b holds 48 bytes. */
static const char *amount(double x, char *b) {
    if (isfinite(x)) snprintf(b, 48, "%.3g", x);
    else snprintf(b, 48, "more than a double holds");
    return b;
}

/* One warning per named place, each with the totals: a caller can find the
 * elements by path, a reader sees how much happened. */
void tc__range_warn(const struct tc_mesh *m, const tc__range_stats *s, tc_range mode, tc_diags *dg) {
    const char *name = mode == TC_RANGE_POSITIVE ? "positive" : "local";
    char path[48], num[48];
    for (int i = 0; i < s->planes.named; i++) {
        snprintf(path, sizeof path, "vertices[%d]", (int)s->planes.where[i]);
        tc_diags_add(dg, TC_SEV_WARNING, path,
                     "range \"%s\" limited the slope at this vertex to %s of its size to keep the reconstruction "
                     "inside its data's range (%d planes limited in all%s)", name, amount(1 - s->planes.size[i], num),
                     (int)s->planes.count, s->flattened ? ", some further so a C1 edge could stay inside" : "");
    }
    for (int i = 0; i < s->edges.named; i++) {
        tc__elem_path(m, s->edges.where[i], path, sizeof path);
        tc_diags_add(dg, TC_SEV_WARNING, path,
                     "range \"%s\": the cross-boundary derivative of edge %d here was limited, its ordinate moved by "
                     "%s of the channel's range (%d in all)", name, s->edges.edge[i], amount(s->edges.size[i], num),
                     (int)s->edges.count);
    }
    for (int i = 0; i < s->twists.named; i++) {
        snprintf(path, sizeof path, "vertices[%d]", (int)s->twists.where[i]);
        tc_diags_add(dg, TC_SEV_WARNING, path,
                     "range \"%s\": the twist (cross derivative) of the patches here was limited to %s of its "
                     "second-order part (%d in all)", name, amount(1 - s->twists.size[i], num), (int)s->twists.count);
    }
    for (int i = 0; i < s->kinks.named; i++) {
        tc__elem_path(m, s->kinks.where[i], path, sizeof path);
        tc_diags_add(dg, TC_SEV_WARNING, path,
                     "range \"%s\": edge %d here is joined C0, not C1: no C1 join stays inside the range (the two "
                     "triangles reach far along the edge's line on one side); the kink is the smallest possible, "
                     "%s of the channel's range (%d edges in all); range \"free\" keeps C1 and overshoots",
                     name, s->kinks.edge[i], amount(s->kinks.size[i], num), (int)s->kinks.count);
    }
}

/* ---- range "free": how far the reconstruction leaves its data's range ---- */

typedef struct {
    double lo, hi;   /* the channel's data range */
    double net, at;  /* the largest excursion of the net, and sampled */
    int32_t t;       /* the triangle of the largest net excursion */
    int32_t count;   /* triangles whose net leaves the range */
} excursion;

/* The largest excursion beyond [e->lo, e->hi] of triangle t's piece in
 * channel ch over a barycentric grid of step 1/6 (28 points). */
static double sampled_excursion(const struct tc_recon *r, int32_t t, int ch, const excursion *e) {
    const struct tc_mesh *m = r->m;
    const int32_t *tv = m->tri + 3 * (size_t)t;
    double worst = 0, v[TC_MAX_CHANNELS];
    for (int i = 0; i <= 6; i++)
        for (int j = 0; i + j <= 6; j++) {
            double l[3] = {i / 6.0, j / 6.0, (6 - i - j) / 6.0}, x = 0, y = 0;
            for (int k = 0; k < 3; k++) x += l[k] * tc__vxy(m, tv[k])[0], y += l[k] * tc__vxy(m, tv[k])[1];
            tc_eval_triangle(r, t, x, y, v, NULL);
            worst = tc__fmax(worst, tc__outside(v[ch], e->lo, e->hi, 0));
        }
    return worst;
}

void tc__range_report_free(const struct tc_recon *r, int nord, tc_diags *dg) {
    const struct tc_mesh *m = r->m;
    int nc = m->nc, ncoef = r->ncoef;
    for (int ch = 0; ch < nc; ch++) {
        excursion e = {INFINITY, -INFINITY, 0, 0, -1, 0};
        for (size_t c = 0; c < 3 * (size_t)m->nt; c++)
            e.lo = tc__fmin(e.lo, m->cz[c * (size_t)nc + (size_t)ch]), e.hi = tc__fmax(e.hi, m->cz[c * (size_t)nc + (size_t)ch]);
        double tol = TC_RANGE_SLACK * tc__fmax(fabs(e.lo), fabs(e.hi));
        for (int32_t t = 0; t < m->nt; t++) {
            const double *o = r->coef + tc__ix(t, nc, ch) * (size_t)ncoef;
            double out = 0;
            for (int i = 0; i < nord; i++) out = tc__fmax(out, tc__outside(o[i], e.lo, e.hi, tol));
            if (out == 0) continue;
            e.count++;
            e.at = tc__fmax(e.at, sampled_excursion(r, t, ch, &e));
            if (out > e.net) e.net = out, e.t = t;
        }
        if (!e.count) continue;
        char path[48];
        tc__elem_path(m, e.t, path, sizeof path);
        double range = e.hi > e.lo ? e.hi - e.lo : tc__fmax(fabs(e.hi), 1e-300);
        tc_diags_add(dg, TC_SEV_WARNING, path,
                     "range \"free\": channel %d leaves its data's range [%.6g, %.6g] in %d triangles: by %.3g "
                     "(%.3g of the range) or more, at most %.3g by its Bézier net, the most here; range \"local\" "
                     "keeps every triangle within its own corner values", ch, e.lo, e.hi, (int)e.count, e.at,
                     e.at / range, e.net);
    }
}

/* ---- wedge groups ---- */

/* Wedges joined through C0 sides share their slopes along those sides, so they
 * are limited together. At most GROUP_MAX wedges take part in one projection;
 * a larger group (a vertex with more C0 edges than that) is scaled instead. */
enum { GROUP_MAX = TC_QP_MAXN / 2 };

/* The group of wedge w: every wedge reachable through `across` links. */
static int group_of(const tc__wedge_set *ws, int32_t w, int32_t *g, int cap) {
    int n = 0;
    g[n++] = w;
    for (int i = 0; i < n; i++)
        for (int s = 0; s < 2; s++) {
            int32_t o = ws->w[g[i]].across[s], seen = 0;
            if (o < 0) continue;
            for (int j = 0; j < n; j++) seen |= g[j] == o;
            if (seen) continue;
            if (n == cap) return -1;
            g[n++] = o;
        }
    return n;
}

static double *plane_at(double *planes, const tc__wedge_set *ws, int nc, int32_t w, int ch) {
    return planes + tc__ix(ws->corners[ws->w[w].first], nc, ch) * 2;
}

/* Writes plane g to every corner of wedge w. */
static void set_plane(double *planes, const tc__wedge_set *ws, int nc, int32_t w, int ch, const double g[2]) {
    const tc__wedge *wd = &ws->w[w];
    for (int32_t i = 0; i < wd->count; i++) {
        double *p = planes + tc__ix(ws->corners[wd->first + i], nc, ch) * 2;
        p[0] = g[0], p[1] = g[1];
    }
}

void tc__range_scale_group(const tc__wedge_set *ws, int nc, int32_t w, int ch, double lambda, double *planes) {
    int32_t g[GROUP_MAX * 4];
    int n = group_of(ws, w, g, GROUP_MAX * 4);
    if (n < 0) n = 1; /* too large to walk here: impossible, groups live at one vertex */
    for (int i = 0; i < n; i++) {
        double *p = plane_at(planes, ws, nc, g[i], ch), s[2] = {p[0] * lambda, p[1] * lambda};
        set_plane(planes, ws, nc, g[i], ch, s);
    }
}

/* ---- the projection ---- */

/* One ordinate a wedge plane sets: lo <= g_wedge . d <= hi (relative to the corner value). */
typedef struct {
    int slot;      /* the wedge's place in the group */
    double d[2];
    double lo, hi;
} row;

typedef struct {
    const struct tc_mesh *m;
    const tc__wedge_set *ws;
    const double *cz;
    const tc__bounds *b;
    tc__plane_dirs_fn dirs;
    const void *ctx;
    int ch;
    int32_t w[GROUP_MAX];
    int k;
    row *rows;
    int nrows, cap;
    double Q[GROUP_MAX][3]; /* per slot the metric of the ordinates it moves (add_row, metrics) */
    double *C, *Aeq, *rhs; /* the QP's rows: [TC_QP_MAXM][TC_QP_MAXN], [TC_QP_MAXEQ][TC_QP_MAXN], [TC_QP_MAXM] */
} group;

/* The same direction up to rounding: one edge seen from the two faces that
 * share it, each computing it in its own frame. */
static int same_dir(const double a[2], const double b[2]) {
    return fabs(a[0] - b[0]) + fabs(a[1] - b[1]) <= 1e-12 * (fabs(a[0]) + fabs(a[1]));
}

/* Adds (or tightens, when the same direction is there already) one row, and
 * adds d d' to the slot's metric (every corner's every direction counts,
 * merged or not, so the metric does not depend on rounding). */
static int add_row(group *G, int slot, const double d[2], double lo, double hi) {
    double *q = G->Q[slot];
    q[0] += d[0] * d[0], q[1] += d[0] * d[1], q[2] += d[1] * d[1];
    for (int i = 0; i < G->nrows; i++) {
        row *r = &G->rows[i];
        if (r->slot == slot && same_dir(r->d, d)) {
            r->lo = tc__fmax(r->lo, lo), r->hi = tc__fmin(r->hi, hi);
            return 0;
        }
    }
    if (G->nrows == G->cap) return -1;
    G->rows[G->nrows++] = (row){slot, {d[0], d[1]}, lo, hi};
    return 0;
}

static int gather_rows(group *G) {
    const struct tc_mesh *m = G->m;
    int nc = m->nc;
    G->nrows = 0;
    memset(G->Q, 0, sizeof G->Q);
    for (int s = 0; s < G->k; s++) {
        const tc__wedge *wd = &G->ws->w[G->w[s]];
        for (int32_t i = 0; i < wd->count; i++) {
            int32_t c = G->ws->corners[wd->first + i];
            size_t ti = tc__ix(c / 3, nc, G->ch);
            double z = G->cz[tc__ix(c, nc, G->ch)], d[TC_PLANE_DIRS_MAX][2];
            int nd = G->dirs(G->ctx, c, d);
            for (int j = 0; j < nd; j++)
                if (add_row(G, s, d[j], G->b->lo[ti] - z, G->b->hi[ti] - z)) return -1;
        }
    }
    return 0;
}

/* How far the planes y (2 per slot) leave the rows, beyond tol. */
static double violation(const group *G, const double *y, double tol) {
    double worst = 0;
    for (int i = 0; i < G->nrows; i++) {
        const row *r = &G->rows[i];
        double v = tc__dot(r->d, y + 2 * r->slot);
        worst = tc__fmax(worst, tc__outside(v, r->lo, r->hi, tol));
    }
    return worst;
}

/* The largest lambda in [0, 1] with lambda * y inside every row it leaves by
 * more than tol (0 is inside every row). */
static double scale_inside(const group *G, const double *y, double tol) {
    double lambda = 1;
    for (int i = 0; i < G->nrows; i++) {
        const row *r = &G->rows[i];
        double v = tc__dot(r->d, y + 2 * r->slot);
        if (v > r->hi + tol) lambda = tc__fmin(lambda, r->hi / v);
        else if (v < r->lo - tol) lambda = tc__fmin(lambda, r->lo / v);
    }
    return tc__fmax(lambda, 0);
}

/* Per slot the metric of the ordinates the plane moves, Q = sum d d' over
 * its corners' directions (add_row), plus a trace-relative ridge, so a wedge
 * of needles whose directions are nearly parallel still gives a definite Q. */
static void metrics(const group *G, double Q[][3]) {
    memcpy(Q, G->Q, (size_t)G->k * sizeof *Q);
    for (int s = 0; s < G->k; s++) {
        double ridge = 1e-6 * (Q[s][0] + Q[s][2]);
        Q[s][0] += ridge, Q[s][2] += ridge;
    }
}

static double qnorm2(const double Q[][3], int k, const double *y) {
    double s = 0;
    for (int i = 0; i < k; i++) {
        const double *g = y + 2 * i;
        s += Q[i][0] * g[0] * g[0] + 2 * Q[i][1] * g[0] * g[1] + Q[i][2] * g[1] * g[1];
    }
    return s;
}

/* A C0 link inside the group: wedges s and o share side direction d. */
typedef struct {
    int s, o;
    double d[2];
} link;

/* The C0 links: for each side shared by two of the group's wedges, one. A
 * 180-degree pair shares two opposite sides along one line: one link (sides
 * this close to parallel, within the band where a straight line's kink
 * fades, count as one). Returns the count, or -1 beyond TC_QP_MAXEQ. */
static int links_of(const group *G, link *L) {
    int n = 0;
    for (int s = 0; s < G->k; s++) {
        const tc__wedge *wd = &G->ws->w[G->w[s]];
        for (int side = 0; side < 2; side++) {
            int o = -1;
            for (int j = 0; j < G->k; j++)
                if (G->w[j] == wd->across[side]) o = j;
            if (o <= s) continue; /* once per pair, from the lower slot */
            const double *d = wd->dir[side];
            int dup = 0;
            for (int e = 0; e < n; e++)
                dup |= L[e].s == s && L[e].o == o &&
                       fabs(tc__cross(d, L[e].d)) <= TC_STRAIGHT_BAND * tc__hypot(d[0], d[1]) *
                                                         tc__hypot(L[e].d[0], L[e].d[1]);
            if (dup) continue;
            if (n == TC_QP_MAXEQ) return -1;
            L[n++] = (link){s, o, {d[0], d[1]}};
        }
    }
    return n;
}

/* The QP's rows for the links: g_s . d = g_o . d (the shared slope, which
 * keeps the edge C0), and the kink across the link, n . (g_s - g_o) with n
 * normal to d, held between 0 and its value in y0: the limiter may soften a
 * kink the data has, never make or sharpen one (so where a line is bent
 * through straight and its kink fades, the limited planes fade with it). */
static int link_rows(const group *G, const double *y0, double *Aeq, double *C, double *b, int *m, int n) {
    link L[TC_QP_MAXEQ];
    int nl = links_of(G, L);
    if (nl < 0 || *m + 2 * nl > TC_QP_MAXM) return -1;
    for (int e = 0; e < nl; e++) {
        const double *d = L[e].d;
        double nrm[2] = {-d[1], d[0]}, *a = Aeq + (size_t)e * (size_t)n;
        memset(a, 0, (size_t)n * sizeof *a);
        a[2 * L[e].s] = d[0], a[2 * L[e].s + 1] = d[1], a[2 * L[e].o] = -d[0], a[2 * L[e].o + 1] = -d[1];
        double kink = tc__dot(nrm, y0 + 2 * L[e].s) - tc__dot(nrm, y0 + 2 * L[e].o);
        for (int sign = 1; sign >= -1; sign -= 2) {
            double *c = C + (size_t)*m * (size_t)n;
            memset(c, 0, (size_t)n * sizeof *c);
            c[2 * L[e].s] = sign * nrm[0], c[2 * L[e].s + 1] = sign * nrm[1];
            c[2 * L[e].o] = -sign * nrm[0], c[2 * L[e].o + 1] = -sign * nrm[1];
            b[(*m)++] = tc__fmax(0, sign * kink);
        }
    }
    return nl;
}

/* The QP keeps each link's shared slope to the rounding of its linear
 * algebra; C0 wants it to the rounding of one product: split what is left
 * between the two planes, along the side (a few sweeps settle wedges with
 * several links). */
static void exact_links(const group *G, double *y) {
    link L[TC_QP_MAXEQ];
    int nl = links_of(G, L);
    for (int sweep = 0; sweep < 4; sweep++)
        for (int e = 0; e < nl; e++) {
            const double *d = L[e].d;
            double *gs = y + 2 * L[e].s, *go = y + 2 * L[e].o;
            double r = 0.5 * (tc__dot(gs, d) - tc__dot(go, d)) / tc__dot(d, d);
            gs[0] -= r * d[0], gs[1] -= r * d[1];
            go[0] += r * d[0], go[1] += r * d[1];
        }
}

/* The planes in the admissible set nearest y0 in the metric Q, by the QP;
 * y receives them. 0 on success. */
static int project(const group *G, const double Q[][3], const double *y0, double *y) {
    int n = 2 * G->k, m = 0;
    double H[TC_QP_MAXN * TC_QP_MAXN] = {0}, f[TC_QP_MAXN];
    double *C = G->C, *Aeq = G->Aeq, *b = G->rhs;
    for (int s = 0; s < G->k; s++) {
        const double *q = Q[s], *g = y0 + 2 * s;
        H[(2 * s) * n + 2 * s] = q[0], H[(2 * s) * n + 2 * s + 1] = q[1];
        H[(2 * s + 1) * n + 2 * s] = q[1], H[(2 * s + 1) * n + 2 * s + 1] = q[2];
        f[2 * s] = -(q[0] * g[0] + q[1] * g[1]);
        f[2 * s + 1] = -(q[1] * g[0] + q[2] * g[1]);
    }
    for (int i = 0; i < G->nrows; i++) {
        const row *r = &G->rows[i];
        for (int sign = 1; sign >= -1; sign -= 2) {
            double lim = sign > 0 ? r->hi : -r->lo;
            if (isinf(lim)) continue;
            if (m == TC_QP_MAXM) return -1;
            double *c = C + (size_t)m * (size_t)n;
            memset(c, 0, (size_t)n * sizeof *c);
            c[2 * r->slot] = sign * r->d[0], c[2 * r->slot + 1] = sign * r->d[1];
            b[m++] = tc__fmax(lim, 0);
        }
    }
    int neq = link_rows(G, y0, Aeq, C, b, &m, n);
    if (neq < 0) return -1;
    if (tc__qp_solve(n, H, f, neq, Aeq, m, C, b, y) < 0) return -1;
    exact_links(G, y);
    return 0;
}

/* The largest move of an ordinate the planes set, from planes y0 to y. */
static double largest_move(const group *G, const double *y0, const double *y) {
    double worst = 0;
    for (int i = 0; i < G->nrows; i++) {
        const row *r = &G->rows[i];
        worst = tc__fmax(worst, fabs(tc__dot(r->d, y + 2 * r->slot) - tc__dot(r->d, y0 + 2 * r->slot)));
    }
    return worst;
}

/* What limiting one group did: the factor |y| / |y0| in the metric Q (1:
 * untouched) and the largest move of an ordinate. */
typedef struct {
    double factor, move;
} limited;

/* Limits one group in one channel. */
static limited limit_group(group *G, double *planes) {
    int nc = G->m->nc;
    double y0[TC_QP_MAXN], y[TC_QP_MAXN], Q[GROUP_MAX][3], tol = G->b->tol[G->ch];
    for (int s = 0; s < G->k; s++) {
        const double *p = plane_at(planes, G->ws, nc, G->w[s], G->ch);
        y0[2 * s] = p[0], y0[2 * s + 1] = p[1];
    }
    if (violation(G, y0, tol) == 0) return (limited){1, 0};
    metrics(G, Q);
    /* The projection, or the plain scaling if the QP could not be set up; then
     * whichever of the two is nearer y0 (the scaling is always admissible). */
    double lambda = scale_inside(G, y0, tol), scaled[TC_QP_MAXN];
    for (int i = 0; i < 2 * G->k; i++) scaled[i] = lambda * y0[i];
    /* Planes so steep that their ordinates leave the double range are only scaled. */
    int ok = isfinite(qnorm2(Q, G->k, y0)) && project(G, Q, y0, y) == 0;
    for (int i = 0; ok && i < 2 * G->k; i++) ok = isfinite(y[i]);
    if (ok) {
        double fix = scale_inside(G, y, tol); /* 1 but where the QP's rounding left a row */
        for (int i = 0; i < 2 * G->k; i++) y[i] *= fix;
    }
    if (!ok) memcpy(y, scaled, sizeof scaled);
    else {
        double dy = 0, ds = 0, d[TC_QP_MAXN];
        for (int i = 0; i < 2 * G->k; i++) d[i] = y[i] - y0[i];
        dy = qnorm2(Q, G->k, d);
        for (int i = 0; i < 2 * G->k; i++) d[i] = scaled[i] - y0[i];
        ds = qnorm2(Q, G->k, d);
        if (ds < dy) memcpy(y, scaled, sizeof scaled);
    }
    for (int s = 0; s < G->k; s++) set_plane(planes, G->ws, nc, G->w[s], G->ch, y + 2 * s);
    double n0 = qnorm2(Q, G->k, y0);
    return (limited){n0 > 0 ? sqrt(qnorm2(Q, G->k, y) / n0) : 1, largest_move(G, y0, y)};
}

/* A group too large for the QP (more C0 edges at a vertex than GROUP_MAX
 * wedges): every plane in it scaled by the smallest factor any needs. */
static limited shrink_group(group *G, int32_t w, double *planes) {
    const tc__wedge_set *ws = G->ws;
    int32_t w0 = w, w1 = w;
    while (w0 > 0 && ws->w[w0 - 1].v == ws->w[w].v) w0--;
    while (w1 < ws->nw && ws->w[w1].v == ws->w[w].v) w1++;
    int32_t *all = malloc((size_t)(w1 - w0) * sizeof *all);
    int n = all ? group_of(ws, w, all, w1 - w0) : -1;
    double lambda = n > 0 ? 1 : 0, move = 0;
    for (int i = 0; i < n; i++) {
        G->k = 1, G->w[0] = all[i];
        if (gather_rows(G)) lambda = 0;
        else lambda = tc__fmin(lambda, scale_inside(G, plane_at(planes, ws, G->m->nc, all[i], G->ch), G->b->tol[G->ch]));
    }
    for (int i = 0; i < n; i++) {
        double *p = plane_at(planes, ws, G->m->nc, all[i], G->ch);
        G->k = 1, G->w[0] = all[i];
        if (gather_rows(G) == 0) {
            double y0[2] = {p[0], p[1]}, y[2] = {lambda * p[0], lambda * p[1]};
            move = tc__fmax(move, largest_move(G, y0, y));
        }
    }
    tc__free(all);
    tc__range_scale_group(ws, G->m->nc, w, G->ch, lambda, planes);
    return (limited){lambda, move};
}

/* One part of the vertices (tc__parallel_for): their wedges' groups (a group
 * is at one vertex, so a part touches only its own wedges' planes), with its
 * own work space and tally. */
typedef struct {
    group inputs; /* the mesh, wedges, values, bounds and directions every part's group reads */
    double *planes;
    tc__range_tally tally[TC_PARALLEL_MAX];
    int nomem[TC_PARALLEL_MAX];
} planes_pass;

static void planes_part(void *pctx, int32_t vlo, int32_t vhi, int part) {
    planes_pass *pp = pctx;
    const struct tc_mesh *m = pp->inputs.m;
    const tc__wedge_set *ws = pp->inputs.ws;
    enum { ROWS_MAX = TC_QP_MAXM };
    tc__range_tally *tally = &pp->tally[part];
    memset(tally, 0, sizeof *tally);
    row *rows = malloc(ROWS_MAX * sizeof *rows);
    double *work = malloc((TC_QP_MAXM * TC_QP_MAXN + TC_QP_MAXEQ * TC_QP_MAXN + TC_QP_MAXM) * sizeof *work);
    pp->nomem[part] = !rows || !work;
    if (pp->nomem[part]) {
        tc__free(rows), tc__free(work);
        return;
    }
    group G = pp->inputs;
    G.rows = rows, G.cap = ROWS_MAX;
    G.C = work, G.Aeq = work + TC_QP_MAXM * TC_QP_MAXN, G.rhs = G.Aeq + TC_QP_MAXEQ * TC_QP_MAXN;
    for (int32_t w = tc__first_wedge_at(ws, vlo), end = tc__first_wedge_at(ws, vhi); w < end; w++) {
        int32_t members[GROUP_MAX];
        int k = group_of(ws, w, members, GROUP_MAX), lowest = 1;
        for (int i = 1; i < k; i++) lowest &= members[i] > w;
        if (k > 0 && !lowest) continue; /* the group's lowest wedge does it */
        for (int ch = 0; ch < m->nc; ch++) {
            G.ch = ch;
            G.k = k > 0 ? k : 1;
            memcpy(G.w, members, (size_t)G.k * sizeof *members);
            limited lim = k > 0 && gather_rows(&G) == 0 ? limit_group(&G, pp->planes) : shrink_group(&G, w, pp->planes);
            if (lim.move > TC_RANGE_MATERIAL * G.b->span[ch]) tc__range_note(tally, 1 - lim.factor, ws->w[w].v, -1);
        }
    }
    tc__free(rows);
    tc__free(work);
}

void tc__range_tally_merge(tc__range_tally *into, const tc__range_tally *part) {
    int32_t count = into->count + part->count;
    for (int i = 0; i < part->named; i++) tc__range_note(into, part->size[i], part->where[i], part->edge[i]);
    into->count = count;
}

int tc__range_planes(const struct tc_mesh *m, const tc__wedge_set *ws, const double *cz, const tc__bounds *b,
                     tc__plane_dirs_fn dirs, const void *ctx, double *planes, tc__range_stats *stats) {
    planes_pass pp = {.inputs = {.m = m, .ws = ws, .cz = cz, .b = b, .dirs = dirs, .ctx = ctx}, .planes = planes};
    tc__parallel_for(ws->threads, m->nv, 4096, planes_part, &pp);
    int rc = TC_OK;
    for (int p = 0; p < tc__parallel_parts(ws->threads, m->nv, 4096); p++) {
        if (pp.nomem[p]) rc = TC_ENOMEM;
        tc__range_tally_merge(&stats->planes, &pp.tally[p]); /* in vertex order: the serial tally */
    }
    return rc;
}
