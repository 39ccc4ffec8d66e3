/* stab.c — the stability suite's shared machinery: method variants, owned mesh
 * descriptions and their transforms, running a variant, and reporting figures. */
#include "stab.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"

const stab_variant stab_var[STAB_NVAR] = {
    {"constant", "constant", TC_METHOD_CONSTANT, TC_CROSS_NORMAL, TC_WEDGES_CORRECTED},
    {"linear", "linear", TC_METHOD_LINEAR, TC_CROSS_NORMAL, TC_WEDGES_CORRECTED},
    {"linear4", "linear4", TC_METHOD_LINEAR4, TC_CROSS_NORMAL, TC_WEDGES_CORRECTED},
    {"clough-tocher/normal/corrected", "ct-normal", TC_METHOD_CLOUGH_TOCHER, TC_CROSS_NORMAL, TC_WEDGES_CORRECTED},
    {"clough-tocher/salesin/corrected", "ct-salesin", TC_METHOD_CLOUGH_TOCHER, TC_CROSS_SALESIN,
     TC_WEDGES_CORRECTED},
    {"clough-tocher/affine/corrected", "ct-affine", TC_METHOD_CLOUGH_TOCHER, TC_CROSS_AFFINE, TC_WEDGES_CORRECTED},
    {"clough-tocher/normal/literal", "ct-normal-lit", TC_METHOD_CLOUGH_TOCHER, TC_CROSS_NORMAL, TC_WEDGES_LITERAL},
    {"clough-tocher/salesin/literal", "ct-salesin-lit", TC_METHOD_CLOUGH_TOCHER, TC_CROSS_SALESIN,
     TC_WEDGES_LITERAL},
    {"clough-tocher-c1/normal", "ct-c1", TC_METHOD_CLOUGH_TOCHER_C1, TC_CROSS_NORMAL, TC_WEDGES_CORRECTED},
    {"powell-sabin", "powell-sabin", TC_METHOD_POWELL_SABIN, TC_CROSS_NORMAL, TC_WEDGES_CORRECTED},
    {"hermite", "hermite", TC_METHOD_HERMITE, TC_CROSS_NORMAL, TC_WEDGES_CORRECTED},
};

void stab_options(int v, tc_tangents tangents, tc_options *o) {
    tc_options_default(o);
    o->method = stab_var[v].method;
    o->cross_boundary = stab_var[v].cross;
    o->wedges = stab_var[v].wedges;
    o->tangents = tangents;
}

int stab_literal(int v) { return stab_var[v].wedges == TC_WEDGES_LITERAL; }

/* From the method table: the methods that read `tangents` run the tangent-plane pipeline. */
int stab_has_planes(int v) { return (tc_method_reads(stab_var[v].method) & TC_READS_TANGENTS) != 0; }

/* A method added to the table without a variant here would go untested by the
 * whole suite: refuse that. */
TEST(stab_variants_cover_every_method) {
    for (int m = 0; m < tc_method_count(); m++) {
        int found = 0;
        for (int v = 0; v < STAB_NVAR; v++) found |= stab_var[v].method == (tc_method)m;
        CHECK_MSG(found, "method %s has no variant in stab_var (tests/stability/stab.c)", tc_method_name((tc_method)m));
    }
    CHECK(stab_var[STAB_HERMITE].method == TC_METHOD_HERMITE);
}

/* ---- owned descriptions ---- */

static void *xmalloc(size_t n) {
    void *p = malloc(n ? n : 1);
    if (!p) abort();
    return p;
}

static void *keep(sdesc *s, void *p) {
    if (s->nown == (int)(sizeof s->own / sizeof s->own[0])) abort();
    s->own[s->nown++] = p;
    return p;
}

static void *dup(sdesc *s, const void *p, size_t bytes) {
    if (!p) return NULL;
    void *q = keep(s, xmalloc(bytes));
    memcpy(q, p, bytes);
    return q;
}

static void dup_lines(sdesc *s, tc_polylines *pl) {
    if (pl->count == 0 || !pl->start) return;
    const int32_t *start = pl->start;
    pl->start = dup(s, start, ((size_t)pl->count + 1) * sizeof *start);
    pl->verts = dup(s, pl->verts, (size_t)start[pl->count] * sizeof *pl->verts);
}

void sdesc_copy(sdesc *s, const tc_mesh_desc *d) {
    memset(s, 0, sizeof *s);
    s->d = *d;
    tc_mesh_desc *o = &s->d;
    size_t nv = (size_t)d->nverts, nc = (size_t)d->nchan, nk = d->nquads > 0 ? 4 : 3;
    size_t ncv = (size_t)d->ncorner_values, ncg = (size_t)d->ncorner_gradients, nm = (size_t)d->nmidpoints;
    o->xy = dup(s, d->xy, 2 * nv * sizeof(double));
    o->tris = dup(s, d->tris, 3 * (size_t)d->ntris * sizeof(int32_t));
    o->quads = dup(s, d->quads, 4 * (size_t)d->nquads * sizeof(int32_t));
    o->values = dup(s, d->values, nv * nc * sizeof(double));
    o->corner_values_tri = dup(s, d->corner_values_tri, ncv * sizeof(int32_t));
    o->corner_values = dup(s, d->corner_values, ncv * nk * nc * sizeof(double));
    o->gradients = dup(s, d->gradients, nv * nc * 2 * sizeof(double));
    o->gradients_mask = dup(s, d->gradients_mask, nv);
    o->normals = dup(s, d->normals, nv * nc * 3 * sizeof(double));
    o->normals_mask = dup(s, d->normals_mask, nv);
    o->hessians = dup(s, d->hessians, nv * nc * 3 * sizeof(double));
    o->hessians_mask = dup(s, d->hessians_mask, nv);
    o->corner_gradients_tri = dup(s, d->corner_gradients_tri, ncg * sizeof(int32_t));
    o->corner_gradients = dup(s, d->corner_gradients, ncg * nk * nc * 2 * sizeof(double));
    o->corner_gradients_mask = dup(s, d->corner_gradients_mask, ncg * nk);
    o->midpoint_edge = dup(s, d->midpoint_edge, 2 * nm * sizeof(int32_t));
    o->midpoint_tri = dup(s, d->midpoint_tri, nm * sizeof(int32_t));
    o->midpoint_values = dup(s, d->midpoint_values, nm * nc * sizeof(double));
    dup_lines(s, &o->c0);
    dup_lines(s, &o->cm1);
}

void sdesc_free(sdesc *s) {
    for (int i = 0; i < s->nown; i++) free(s->own[i]);
    memset(s, 0, sizeof *s);
}

static void scale_array(const double *p, size_t n, double k) {
    double *q = (double *)p; /* owned: copied by sdesc_copy */
    for (size_t i = 0; q && i < n; i++) q[i] *= k;
}

/* Normals (n_x, n_y, n_z) -> (a n_x, a n_y, b n_z), renormalized: slopes times a / b. */
static void scale_normals(sdesc *s, double a, double b) {
    double *n = (double *)s->d.normals;
    for (size_t i = 0; n && i < (size_t)s->d.nverts * (size_t)s->d.nchan; i++) {
        double x = a * n[3 * i], y = a * n[3 * i + 1], z = b * n[3 * i + 2], len = hypot(hypot(x, y), z);
        if (!(len > 0) || !isfinite(len)) continue;
        n[3 * i] = x / len, n[3 * i + 1] = y / len, n[3 * i + 2] = z / len;
    }
}

static size_t corners_per_elem(const tc_mesh_desc *d) { return d->nquads > 0 ? 4 : 3; }

void sdesc_move(sdesc *s, double scale, double dx, double dy) {
    tc_mesh_desc *d = &s->d;
    double *xy = (double *)d->xy;
    size_t nv = (size_t)d->nverts, nc = (size_t)d->nchan;
    for (size_t i = 0; i < nv; i++) xy[2 * i] = scale * xy[2 * i] + dx, xy[2 * i + 1] = scale * xy[2 * i + 1] + dy;
    if (scale == 1) return;
    scale_array(d->gradients, nv * nc * 2, 1 / scale);
    scale_array(d->corner_gradients, (size_t)d->ncorner_gradients * corners_per_elem(d) * nc * 2, 1 / scale);
    scale_array(d->hessians, nv * nc * 3, 1 / (scale * scale));
    scale_normals(s, 1, scale);
}

void sdesc_scale_values(sdesc *s, double k) {
    tc_mesh_desc *d = &s->d;
    size_t nv = (size_t)d->nverts, nc = (size_t)d->nchan, nk = corners_per_elem(d);
    scale_array(d->values, nv * nc, k);
    scale_array(d->corner_values, (size_t)d->ncorner_values * nk * nc, k);
    scale_array(d->midpoint_values, (size_t)d->nmidpoints * nc, k);
    scale_array(d->gradients, nv * nc * 2, k);
    scale_array(d->corner_gradients, (size_t)d->ncorner_gradients * nk * nc * 2, k);
    scale_array(d->hessians, nv * nc * 3, k);
    scale_normals(s, k, 1);
}

static int pair_cmp(const void *a, const void *b) {
    const int32_t *p = a, *q = b;
    return p[0] != q[0] ? (p[0] < q[0] ? -1 : 1) : (p[1] > q[1]) - (p[1] < q[1]);
}

/* Every edge of the mesh's triangles (a quad split along a-c) as sorted pairs, unique. */
static int32_t all_edges(const tc_mesh_desc *d, int32_t **out) {
    int32_t nt = d->nquads > 0 ? 2 * d->nquads : d->ntris, *e = xmalloc(6 * (size_t)nt * sizeof *e), n = 0;
    for (int32_t t = 0; t < nt; t++) {
        int32_t v[3];
        if (d->nquads > 0) {
            const int32_t *q = d->quads + 4 * (size_t)(t / 2);
            v[0] = q[0], v[1] = q[t % 2 ? 2 : 1], v[2] = q[t % 2 ? 3 : 2];
        } else {
            memcpy(v, d->tris + 3 * (size_t)t, sizeof v);
        }
        for (int k = 0; k < 3; k++, n++) {
            int32_t a = v[k], b = v[(k + 1) % 3];
            e[2 * n] = a < b ? a : b, e[2 * n + 1] = a < b ? b : a;
        }
    }
    qsort(e, (size_t)n, 2 * sizeof *e, pair_cmp);
    int32_t u = 0;
    for (int32_t i = 0; i < n; i++)
        if (!u || pair_cmp(e + 2 * i, e + 2 * (u - 1))) e[2 * u] = e[2 * i], e[2 * u + 1] = e[2 * i + 1], u++;
    *out = e;
    return u;
}

void sdesc_add_midpoints(sdesc *s, tfunc f, const void *ctx) {
    tc_mesh_desc *d = &s->d;
    int32_t *e, n = all_edges(d, &e), nc = d->nchan;
    double *val = keep(s, xmalloc((size_t)n * (size_t)nc * sizeof *val));
    for (int32_t i = 0; i < n; i++) {
        const double *a = d->xy + 2 * (size_t)e[2 * i], *b = d->xy + 2 * (size_t)e[2 * i + 1];
        for (int ch = 0; ch < nc; ch++) {
            double g[2];
            f(ctx, 0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), ch, &val[(size_t)i * (size_t)nc + (size_t)ch], g);
        }
    }
    d->nmidpoints = n, d->midpoint_edge = keep(s, e), d->midpoint_tri = NULL, d->midpoint_values = val;
}

static void set_segments(sdesc *s, tc_polylines *pl, const int32_t *seg) {
    int32_t n = 0;
    while (seg && seg[2 * n] >= 0) n++;
    int32_t *start = keep(s, xmalloc(((size_t)n + 1) * sizeof *start));
    int32_t *verts = keep(s, xmalloc((2 * (size_t)n + 1) * sizeof *verts));
    for (int32_t i = 0; i <= n; i++) start[i] = 2 * i;
    if (n) memcpy(verts, seg, 2 * (size_t)n * sizeof *verts);
    *pl = (tc_polylines){n, start, verts};
}

void sdesc_set_lines(sdesc *s, const int32_t *c0, const int32_t *cm1) {
    set_segments(s, &s->d.c0, c0);
    set_segments(s, &s->d.cm1, cm1);
}

/* ---- hand-built meshes ---- */

typedef struct { int32_t a, b, t, k; } erec;

static int erec_cmp(const void *x, const void *y) {
    const erec *p = x, *q = y;
    if (p->a != q->a) return p->a < q->a ? -1 : 1;
    if (p->b != q->b) return p->b < q->b ? -1 : 1;
    return (p->t > q->t) - (p->t < q->t);
}

static void adjacency(tmesh *g) {
    size_t n = 3 * (size_t)g->nt;
    erec *e = xmalloc(n * sizeof *e);
    for (int32_t t = 0; t < g->nt; t++)
        for (int k = 0; k < 3; k++) {
            int32_t a = g->tri[3 * t + k], b = g->tri[3 * t + (k + 1) % 3];
            e[3 * t + k] = (erec){a < b ? a : b, a < b ? b : a, t, k};
            g->enbr[3 * t + k] = -1;
            g->eflag[3 * t + k] = -1;
        }
    qsort(e, n, sizeof *e, erec_cmp);
    for (size_t i = 0; i + 1 < n; i++)
        if (e[i].a == e[i + 1].a && e[i].b == e[i + 1].b) {
            g->enbr[3 * e[i].t + e[i].k] = e[i + 1].t, g->enbr[3 * e[i + 1].t + e[i + 1].k] = e[i].t;
            g->eflag[3 * e[i].t + e[i].k] = g->eflag[3 * e[i + 1].t + e[i + 1].k] = 1;
        }
    free(e);
}

void stab_tmesh(tmesh *g, int32_t nv, const double *xy, int32_t nt, const int32_t *tri) {
    memset(g, 0, sizeof *g);
    g->nv = nv, g->nt = nt;
    g->xy = xmalloc(2 * (size_t)nv * sizeof *g->xy);
    g->tri = xmalloc(3 * (size_t)nt * sizeof *g->tri);
    g->eflag = xmalloc(3 * (size_t)nt * sizeof *g->eflag);
    g->enbr = xmalloc(3 * (size_t)nt * sizeof *g->enbr);
    memcpy(g->xy, xy, 2 * (size_t)nv * sizeof *xy);
    memcpy(g->tri, tri, 3 * (size_t)nt * sizeof *tri);
    adjacency(g);
}

void stab_dyadic(tmesh *g, int bits) {
    double q = ldexp(1.0, bits);
    for (size_t i = 0; i < 2 * (size_t)g->nv; i++) g->xy[i] = nearbyint(g->xy[i] * q) / q;
}

/* ---- running ---- */

int srun_start(srun *x, const tc_mesh_desc *d, const tc_options *o) {
    memset(x, 0, sizeof *x);
    tc_diags_init(&x->dg);
    if (tc_mesh_new(d, &x->m, &x->dg) != TC_OK) return x->stage = 1;
    if (tc_recon_new(x->m, o, &x->r, &x->dg) != TC_OK) return x->stage = 2;
    if (tc_locator_new(x->m, &x->L) != TC_OK) return x->stage = 3;
    return 0;
}

void srun_end(srun *x) {
    tc_locator_free(x->L);
    tc_recon_free(x->r);
    tc_mesh_free(x->m);
    tc_diags_free(&x->dg);
    memset(x, 0, sizeof *x);
}

const tc_diag *srun_error(const srun *x) {
    for (int i = 0; i < x->dg.count; i++)
        if (x->dg.items[i].severity == TC_SEV_ERROR) return &x->dg.items[i];
    return NULL;
}

static int has_index(const char *s) {
    for (const char *p = strchr(s, '['); p; p = strchr(p + 1, '['))
        if (isdigit((unsigned char)p[1])) return 1;
    return 0;
}

int stab_names_element(const tc_diag *d) {
    return d && d->path[0] && (has_index(d->path) || has_index(d->message));
}

static int lower_contains(const char *hay, const char *word) {
    size_t n = strlen(word);
    for (; *hay; hay++) {
        size_t i = 0;
        while (i < n && hay[i] && tolower((unsigned char)hay[i]) == tolower((unsigned char)word[i])) i++;
        if (i == n) return 1;
    }
    return 0;
}

static int mentions_figure(const char *msg, double figure) {
    if (figure <= 0) return 1;
    for (const char *p = msg; *p; p++) {
        if (!isdigit((unsigned char)*p) || (p > msg && (isdigit((unsigned char)p[-1]) || p[-1] == '.'))) continue;
        char *end;
        double x = strtod(p, &end);
        if (x >= 0.5 * figure && x <= 2 * figure) return 1;
        p = end - 1;
    }
    return 0;
}

int stab_has_warning(const tc_diags *dg, const char *path, const char *word, double figure) {
    size_t n = strlen(path);
    for (int i = 0; i < dg->count; i++) {
        const tc_diag *d = &dg->items[i];
        if (d->severity != TC_SEV_WARNING || strncmp(d->path, path, n) || isdigit((unsigned char)d->path[n]))
            continue;
        if (lower_contains(d->message, word) && mentions_figure(d->message, figure)) return 1;
    }
    return 0;
}

int stab_recon_finite(const tc_recon *r) {
    const tc_mesh *m = tc_recon_mesh(r);
    size_t nt = (size_t)tc_mesh_triangle_count(m), nc = (size_t)tc_mesh_channel_count(m);
    const double *c = tc_recon_coefs(r), *g = tc_recon_corner_gradients(r);
    for (size_t i = 0; i < nt * nc * (size_t)tc_recon_coef_count(r); i++)
        if (!isfinite(c[i])) return 0;
    for (size_t i = 0; g && i < 6 * nt * nc; i++)
        if (!isfinite(g[i])) return 0;
    return 1;
}

/* ---- figures ---- */

void stab_acc_init(stab_acc *a, int n) {
    memset(a, 0, (size_t)n * sizeof *a);
    for (int i = 0; i < n; i++) a[i].worst = -1;
}

void stab_acc_fig(stab_acc *a, double fig, const char *where) {
    a->runs++;
    if (!isfinite(fig)) {
        if (!a->nonfinite++) snprintf(a->where, sizeof a->where, "%s", where ? where : "");
        return;
    }
    if (fig > a->worst) {
        a->worst = fig;
        snprintf(a->where, sizeof a->where, "%s", where ? where : "");
    }
}

void stab_acc_refusal(stab_acc *a, const srun *x) {
    const tc_diag *e = srun_error(x);
    a->runs++, a->refused++;
    if (!stab_names_element(e)) a->unnamed++;
    if (!a->refusal[0])
        if (snprintf(a->refusal, sizeof a->refusal, "%s: %s", e ? e->path : "(no error)", e ? e->message : "") < 0)
            a->refusal[0] = 0; /* (truncation is fine: the start names the element) */
}

static FILE *table_file(void) {
    static FILE *f;
    static int tried;
    if (tried) return f;
    tried = 1;
    const char *path = getenv("TC_STABILITY_TABLE");
    if (!path || !*path) return NULL;
    f = fopen(path, "w");
    if (f) fprintf(f, "case\tmethod\tmeasure\tworst\tbound\tverdict\tdetail\n");
    return f;
}

void stab_table(const char *case_name, const char *method, const char *measure, double worst, double bound,
                const char *verdict, const char *detail) {
    FILE *f = table_file();
    if (!f) return;
    char w[32] = "-", b[32] = "-";
    if (worst >= 0) snprintf(w, sizeof w, "%.3g", worst);
    if (bound >= 0) snprintf(b, sizeof b, "%.3g", bound);
    fprintf(f, "%s\t%s\t%s\t%s\t%s\t%s\t%s\n", case_name, method, measure, w, b, verdict, detail ? detail : "");
    fflush(f);
}

static const char *verdict_of(const stab_acc *a, int v, double bound, int flags) {
    if (a->runs == 0) return "n/a";
    if (a->nonfinite) return "FAIL-nonfinite";
    if (a->unnamed) return "FAIL-unnamed-refusal";
    if (a->refused && (flags & STAB_NO_REFUSAL)) return "FAIL-refused";
    int bounded = !(flags & STAB_INFO) && !((flags & STAB_EXEMPT_LITERAL) && stab_literal(v));
    if (a->worst > bound && bounded) return "FAIL";
    if (a->refused == a->runs) return "refused";
    if (!bounded) return flags & STAB_INFO ? "info" : "exempt";
    return a->refused ? "pass+refused" : "pass";
}

static void detail_of(const stab_acc *a, char *buf, size_t n) {
    if (snprintf(buf, n, "runs %d, refused %d%s%s%s%s", a->runs, a->refused, a->where[0] ? ", worst at " : "", a->where,
                 a->refusal[0] ? "; first refusal " : "", a->refusal) < 0)
        buf[0] = 0;
}

/* Appends " brief figure (verdict)," for one variant to the stderr line. */
static int append_entry(char *buf, int n, int cap, int v, const stab_acc *a, const char *verdict) {
    if (n > cap - 80) return n;
    if (a->worst >= 0) n += snprintf(buf + n, (size_t)(cap - n), " %s %.2g", stab_var[v].brief, a->worst);
    else n += snprintf(buf + n, (size_t)(cap - n), " %s -", stab_var[v].brief);
    if (strcmp(verdict, "pass") && strcmp(verdict, "info")) n += snprintf(buf + n, (size_t)(cap - n), " (%s)", verdict);
    return n + snprintf(buf + n, (size_t)(cap - n), ",");
}

void stab_report_lit(const char *file, int line, const char *case_name, const char *measure, const stab_acc *acc,
                     double bound, double lit_bound, int flags) {
    char buf[1600], detail[400];
    int any = 0, n;
    for (int v = 0; v < STAB_NVAR; v++) any |= acc[v].runs > 0;
    if (!any) return;
    n = snprintf(buf, sizeof buf, "  [%s] %s", case_name, measure);
    if (!(flags & STAB_INFO)) n += snprintf(buf + n, sizeof buf - (size_t)n, " (bound %.3g)", bound);
    if (!(flags & STAB_INFO) && lit_bound != bound)
        n += snprintf(buf + n, sizeof buf - (size_t)n, " (literal %.3g)", lit_bound);
    n += snprintf(buf + n, sizeof buf - (size_t)n, ":");
    for (int v = 0; v < STAB_NVAR; v++) {
        const stab_acc *a = &acc[v];
        if (a->runs == 0) continue; /* n/a: no line */
        double b = stab_literal(v) ? lit_bound : bound;
        const char *verdict = verdict_of(a, v, b, flags);
        detail_of(a, detail, sizeof detail);
        stab_table(case_name, stab_var[v].name, measure, a->worst, flags & STAB_INFO ? -1 : b, verdict, detail);
        n = append_entry(buf, n, (int)sizeof buf, v, a, verdict);
        if (!strncmp(verdict, "FAIL", 4))
            tc_test_fail(file, line, "%s, %s, %s: %s %.3g (bound %.3g) %s", case_name, stab_var[v].name, measure,
                         verdict, a->worst, b, detail);
    }
    if (buf[n - 1] == ',') buf[n - 1] = 0;
    fprintf(stderr, "%s\n", buf);
}

void stab_report(const char *file, int line, const char *case_name, const char *measure, const stab_acc *acc,
                 double bound, int flags) {
    stab_report_lit(file, line, case_name, measure, acc, bound, bound, flags);
}
