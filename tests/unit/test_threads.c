/* test_threads.c — the validation (tc_mesh_desc.threads) and the build (tc_options.threads)
 * on several threads give the serial mesh, ordinates, planes and findings bit for bit,
 * errors included: the error reported is the one the serial check reports. */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "core/mesh.h"
#include "core/parallel.h"
#include "core/wedge.h"
#include "meshgen.h"
#include "props.h"
#include "quadgen.h"

/* Everything a validation and build produce that a caller can see. */
typedef struct {
    int mesh_rc, recon_rc;
    tc_diags dg;
    size_t ncoef, nplanes;
    double *coef, *planes;
    int32_t nt;
    int32_t *nbr; /* [3nt] neighbour across each edge, and its flag in the high bits */
} outcome;

static void run(const tc_mesh_desc *d0, const tc_options *o0, int threads, outcome *out) {
    tc_mesh_desc d = *d0;
    tc_options o = *o0;
    d.threads = threads, o.threads = threads;
    memset(out, 0, sizeof *out);
    tc_diags_init(&out->dg);
    tc_mesh *m = NULL;
    tc_recon *r = NULL;
    out->mesh_rc = tc_mesh_new(&d, &m, &out->dg);
    if (out->mesh_rc != TC_OK) return;
    out->nt = tc_mesh_triangle_count(m);
    out->nbr = malloc(3 * (size_t)out->nt * sizeof *out->nbr);
    for (int32_t t = 0; t < out->nt; t++)
        for (int k = 0; k < 3; k++)
            out->nbr[3 * t + k] = tc_mesh_neighbor(m, t, k, NULL) * 4 + (int32_t)tc_mesh_edge_flag(m, t, k) + 1;
    out->recon_rc = tc_recon_new(m, &o, &r, &out->dg);
    if (out->recon_rc == TC_OK) {
        out->ncoef = (size_t)out->nt * (size_t)tc_mesh_channel_count(m) * (size_t)tc_recon_coef_count(r);
        out->coef = malloc(out->ncoef * sizeof *out->coef);
        memcpy(out->coef, tc_recon_coefs(r), out->ncoef * sizeof *out->coef);
        const double *pl = tc_recon_corner_gradients(r);
        out->nplanes = pl ? (size_t)out->nt * 3 * (size_t)tc_mesh_channel_count(m) * 2 : 0;
        out->planes = malloc((out->nplanes ? out->nplanes : 1) * sizeof *out->planes);
        if (pl) memcpy(out->planes, pl, out->nplanes * sizeof *out->planes);
    }
    tc_recon_free(r);
    tc_mesh_free(m);
}

static void outcome_free(outcome *o) {
    tc_diags_free(&o->dg);
    free(o->coef), free(o->planes), free(o->nbr);
}

/* The build on 2, 3 and 8 threads equals the serial one bit for bit; returns the
 * serial mesh status (the caller checks it is what the case means). */
static int same_on_threads(const char *what, const tc_mesh_desc *d, const tc_options *o) {
    static const int threads[] = {2, 3, 8};
    outcome s;
    run(d, o, 1, &s);
    for (size_t i = 0; i < sizeof threads / sizeof threads[0]; i++) {
        outcome p;
        run(d, o, threads[i], &p);
        const char *w = what;
        int n = threads[i];
        CHECK_MSG(p.mesh_rc == s.mesh_rc && p.recon_rc == s.recon_rc, "%s, %d threads: status %d/%d, serial %d/%d", w,
                  n, p.mesh_rc, p.recon_rc, s.mesh_rc, s.recon_rc);
        CHECK_MSG(p.dg.count == s.dg.count && p.dg.errors == s.dg.errors && p.dg.warnings == s.dg.warnings,
                  "%s, %d threads: %d findings (%d errors), serial %d (%d)", w, n, p.dg.count, p.dg.errors,
                  s.dg.count, s.dg.errors);
        for (int j = 0; j < p.dg.count && j < s.dg.count; j++)
            CHECK_MSG(p.dg.items[j].severity == s.dg.items[j].severity &&
                          !strcmp(p.dg.items[j].path, s.dg.items[j].path) &&
                          !strcmp(p.dg.items[j].message, s.dg.items[j].message),
                      "%s, %d threads: finding %d is %s: %s; serial %s: %s", w, n, j, p.dg.items[j].path,
                      p.dg.items[j].message, s.dg.items[j].path, s.dg.items[j].message);
        CHECK_MSG(p.nt == s.nt && (!s.nbr || !memcmp(p.nbr, s.nbr, 3 * (size_t)s.nt * sizeof *s.nbr)),
                  "%s, %d threads: the topology differs", w, n);
        CHECK_MSG(p.ncoef == s.ncoef && (!s.coef || !memcmp(p.coef, s.coef, s.ncoef * sizeof *s.coef)),
                  "%s, %d threads: the ordinates differ", w, n);
        CHECK_MSG(p.nplanes == s.nplanes && (!s.nplanes || !memcmp(p.planes, s.planes, s.nplanes * sizeof *s.planes)),
                  "%s, %d threads: the corner planes differ", w, n);
        outcome_free(&p);
    }
    int rc = s.mesh_rc;
    if (getenv("TC_TEST_SHOW"))
        for (int j = 0; j < s.dg.count; j++) fprintf(stderr, "    %s: %s: %s\n", what, s.dg.items[j].path, s.dg.items[j].message);
    outcome_free(&s);
    return rc;
}

/* A 130 x 130 jittered grid (33 800 triangles, 17 161 vertices: every loop is split in
 * several parts on 8 threads) with random C0 and C-1 polylines, 2 channels, gradients
 * given at some vertices. */
static void big_mesh(tmesh *g, trng *r) {
    tmesh_grid(g, 130, 130, 0.3, -1, r);
    for (int i = 0; i < 12; i++) tmesh_random_line(g, i % 2 ? TC_CM1 : TC_C0, 60, r);
    tmesh_sample(g, 2, smooth_f, NULL, 1, 0, 0.3);
}

TEST(threads_build_bit_identical) {
    trng r;
    trng_seed(&r, tc_test_seed() + 17);
    tmesh g;
    big_mesh(&g, &r);
    tc_mesh_desc d;
    tmesh_desc(&g, &d);
    tc_options o;
    tc_options_default(&o);
    CHECK(same_on_threads("clough-tocher", &d, &o) == TC_OK);
    o.range = TC_RANGE_FREE;
    CHECK(same_on_threads("clough-tocher, range free", &d, &o) == TC_OK);
    o.cross_boundary = TC_CROSS_SALESIN, o.wedges = TC_WEDGES_LITERAL, o.average = TC_AVERAGE_NORMALS;
    CHECK(same_on_threads("salesin literal", &d, &o) == TC_OK);
    tc_options_default(&o);
    o.wedges = TC_WEDGES_LITERAL; /* the C0 wedges' planes by Figure 6's Project, in parts */
    CHECK(same_on_threads("wedges literal", &d, &o) == TC_OK);
    for (int mt = 0; mt < tc_method_count(); mt++) {
        if (tc_method_quads_only((tc_method)mt)) continue;
        tc_options_default(&o);
        o.method = (tc_method)mt;
        CHECK(same_on_threads(tc_method_name((tc_method)mt), &d, &o) == TC_OK);
    }
    tmesh_free(&g);
}

/* Planes from midpoint samples and estimated ones (the clamp reports merged across
 * parts), and tangents "given" without gradients (an error per corner). */
TEST(threads_build_samples_bit_identical) {
    trng r;
    trng_seed(&r, tc_test_seed() + 19);
    tmesh g;
    tmesh_grid(&g, 130, 130, 0.15, -1, &r);
    for (int i = 0; i < 12; i++) tmesh_random_line(&g, i % 2 ? TC_CM1 : TC_C0, 60, &r);
    tmesh_sample(&g, 1, wave_f, NULL, 0, 1, 0.3);
    tc_mesh_desc d;
    tmesh_desc(&g, &d);
    tc_options o;
    tc_options_default(&o);
    CHECK(same_on_threads("midpoints", &d, &o) == TC_OK);
    o.tangents = TC_TANGENTS_ESTIMATE;
    CHECK(same_on_threads("estimate", &d, &o) == TC_OK);
    o.range = TC_RANGE_POSITIVE;
    CHECK(same_on_threads("estimate, positive", &d, &o) == TC_OK);
    o.tangents = TC_TANGENTS_GIVEN;
    CHECK(same_on_threads("given, none given", &d, &o) == TC_OK); /* the mesh is fine: the build fails */
    tmesh_free(&g);
}

/* Long obtuse triangles (the grid stretched 200 x and sheared) with random values
 * and steep random gradients: range "local" limits planes, scales them at darts
 * (the ordered pass after the threaded one) and clamps cross-boundary ordinates. */
TEST(threads_range_limiter_bit_identical) {
    trng r;
    trng_seed(&r, tc_test_seed() + 21);
    tmesh g;
    big_mesh(&g, &r);
    for (int32_t i = 0; i < g.nv; i++) {
        double *p = g.xy + 2 * i;
        p[0] = 200 * p[0] + 150 * p[1];
    }
    for (int32_t i = 0; i < g.nv * g.nc; i++) {
        g.values[i] = trng_uniform(&r);
        g.grads[2 * i] = 3 * (trng_uniform(&r) - 0.5), g.grads[2 * i + 1] = 600 * (trng_uniform(&r) - 0.5);
    }
    tc_mesh_desc d;
    tmesh_desc(&g, &d);
    d.ncorner_values = 0; /* the random values replace the generator's jumps */
    tc_options o;
    tc_options_default(&o);
    for (int c = 0; c < 3; c++) {
        o.cross_boundary = (tc_cross)c;
        CHECK(same_on_threads(tc_cross_name((tc_cross)c), &d, &o) == TC_OK);
    }
    o.method = TC_METHOD_CLOUGH_TOCHER_C1;
    CHECK(same_on_threads("c1", &d, &o) == TC_OK);
    tmesh_free(&g);
}

static void wavy_q(const void *ctx, double x, double y, int ch, double *v, double g[2], double h[3]) {
    (void)ctx;
    double s = sin(3 * x + ch), c = cos(2 * y);
    *v = s * c;
    g[0] = 3 * cos(3 * x + ch) * c, g[1] = -2 * s * sin(2 * y);
    h[0] = -9 * s * c, h[1] = -6 * cos(3 * x + ch) * sin(2 * y), h[2] = -4 * s * c;
}

/* A quad mesh (hermite, and the triangle methods on its split): 2 x 100 x 100 triangles. */
TEST(threads_quads_bit_identical) {
    trng r;
    trng_seed(&r, tc_test_seed() + 22);
    qmesh q;
    qgrid_opts go = {0.1, 0, {0, 0, 0, 0}, {0, 0}};
    qmesh_grid(&q, 100, 100, &go, &r);
    qmesh_sample(&q, 2, wavy_q, NULL);
    tc_mesh_desc d;
    qmesh_desc(&q, 0, 0, &d);
    tc_options o;
    tc_options_default(&o);
    o.method = TC_METHOD_HERMITE;
    CHECK(same_on_threads("hermite, estimated", &d, &o) == TC_OK);
    qmesh_desc(&q, 1, 0, &d);
    CHECK(same_on_threads("hermite, gradients", &d, &o) == TC_OK);
    o.method = TC_METHOD_CLOUGH_TOCHER;
    CHECK(same_on_threads("clough-tocher on quads", &d, &o) == TC_OK);
    qmesh_free(&q);
}

/* Data errors: gradients that are no numbers (validation), and so steep that the
 * ordinates overflow (the build), each at an early and a late vertex. */
TEST(threads_data_errors_as_serial) {
    trng r;
    trng_seed(&r, tc_test_seed() + 20);
    tmesh g;
    big_mesh(&g, &r);
    tc_mesh_desc d;
    tmesh_desc(&g, &d);
    tc_options o;
    tc_options_default(&o);
    size_t nsz = (size_t)g.nv * (size_t)g.nc * 2;
    double *grads = malloc(nsz * sizeof *grads);
    memcpy(grads, g.grads, nsz * sizeof *grads);
    int32_t late = g.nv - 200, early = 300;
    grads[(size_t)late * 4 + 1] = NAN, grads[(size_t)early * 4 + 2] = INFINITY;
    d.gradients = grads;
    CHECK(same_on_threads("gradients not finite", &d, &o) == TC_EINVAL);
    memcpy(grads, g.grads, nsz * sizeof *grads);
    grads[(size_t)late * 4] = 1e306, grads[(size_t)early * 4 + 3] = -1e306;
    o.range = TC_RANGE_FREE;
    CHECK(same_on_threads("overflow", &d, &o) == TC_OK); /* the mesh is fine: the build fails */
    free(grads);
    size_t vsz = (size_t)g.nv * (size_t)g.nc, xsz = (size_t)g.nv * 2; /* values and vertices that are no numbers */
    double *vals = malloc(vsz * sizeof *vals), *xy = malloc(xsz * sizeof *xy);
    memcpy(vals, g.values, vsz * sizeof *vals);
    vals[(size_t)late * 2 + 1] = NAN, vals[(size_t)early * 2] = -INFINITY;
    tmesh_desc(&g, &d);
    d.values = vals;
    CHECK(same_on_threads("values not finite", &d, &o) == TC_EINVAL);
    memcpy(xy, g.xy, xsz * sizeof *xy);
    xy[(size_t)late * 2] = INFINITY, xy[(size_t)early * 2 + 1] = NAN;
    tmesh_desc(&g, &d);
    d.xy = xy;
    CHECK(same_on_threads("vertices not finite", &d, &o) == TC_EINVAL);
    free(vals), free(xy);
    tmesh_free(&g);
}

/* The big mesh with triangles appended (after the last part's start on any thread
 * count) and the vertices they need; the caller's arrays are freed by the caller. */
typedef struct {
    double *xy, *val;
    int32_t *tri;
} grown;

static void grow(const tmesh *g, tc_mesh_desc *d, const int32_t *tris, int ntris, const double *xy, int nxy, grown *gr) {
    gr->xy = malloc(((size_t)g->nv + (size_t)nxy) * 2 * sizeof *gr->xy);
    gr->val = malloc(((size_t)g->nv + (size_t)nxy) * (size_t)g->nc * sizeof *gr->val);
    gr->tri = malloc(((size_t)g->nt + (size_t)ntris) * 3 * sizeof *gr->tri);
    memcpy(gr->xy, g->xy, (size_t)g->nv * 2 * sizeof *gr->xy);
    if (nxy) memcpy(gr->xy + 2 * g->nv, xy, (size_t)nxy * 2 * sizeof *gr->xy); /* xy may be NULL */
    memcpy(gr->val, g->values, (size_t)g->nv * (size_t)g->nc * sizeof *gr->val);
    for (size_t i = (size_t)g->nv * (size_t)g->nc; i < ((size_t)g->nv + (size_t)nxy) * (size_t)g->nc; i++)
        gr->val[i] = 0.5;
    memcpy(gr->tri, g->tri, (size_t)g->nt * 3 * sizeof *gr->tri);
    if (ntris) memcpy(gr->tri + 3 * g->nt, tris, (size_t)ntris * 3 * sizeof *gr->tri);
    tmesh_desc(g, d);
    d->nverts = g->nv + nxy, d->xy = gr->xy, d->values = gr->val;
    d->ntris = g->nt + ntris, d->tris = gr->tri;
    d->gradients = NULL, d->gradients_mask = NULL;
    d->ncorner_values = 0, d->ncorner_gradients = 0, d->nmidpoints = 0;
}

static void grown_free(grown *gr) { free(gr->xy), free(gr->val), free(gr->tri); }

TEST(threads_errors_as_serial) {
    trng r;
    trng_seed(&r, tc_test_seed() + 18);
    tmesh g;
    tmesh_grid(&g, 130, 130, 0.2, 0, &r);
    tmesh_sample(&g, 1, smooth_f, NULL, 0, 0, 0);
    tc_options o;
    tc_options_default(&o);
    int32_t last = g.nt - 1, early = 5, inner = g.nt - 3 * 2 * 130 + 2 * 50; /* a cell of row 127 */
    const int32_t *tl = g.tri + 3 * last, *te = g.tri + 3 * early, *ti = g.tri + 3 * inner;
    int32_t v_in = tmesh_gv(130, 65, 65), nv = g.nv;
    const double *p = g.xy + 2 * v_in;
    double far_xy[4] = {p[0] + 1e-3, p[1] + 1e-4, p[0] + 1e-3, p[1] - 1e-4};
    struct {
        const char *what;
        int32_t tris[9];
        int ntris;
        const double *xy;
        int nxy;
    } cases[] = {
        /* the last triangle and an early one repeated: both reported, in order */
        {"repeats", {tl[0], tl[1], tl[2], te[2], te[1], te[0]}, 2, NULL, 0},
        /* an interior edge shared by a third triangle */
        {"non-manifold", {ti[0], ti[1], nv}, 1, far_xy, 1},
        /* a thin triangle at an interior vertex only: it overlaps its closed fan */
        {"fan overlap", {v_in, nv, nv + 1}, 1, far_xy, 2},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        tc_mesh_desc d;
        grown gr;
        grow(&g, &d, cases[c].tris, cases[c].ntris, cases[c].xy, cases[c].nxy, &gr);
        CHECK_MSG(same_on_threads(cases[c].what, &d, &o) == TC_EINVAL, "%s: not refused", cases[c].what);
        grown_free(&gr);
    }
    /* polylines whose segments are no edges, late and early */
    tc_mesh_desc d;
    tmesh_desc(&g, &d);
    int32_t verts[] = {tmesh_gv(130, 1, 1), tmesh_gv(130, 2, 1), tmesh_gv(130, 9, 9), tmesh_gv(130, 9, 10),
                       tmesh_gv(130, 120, 100), tmesh_gv(130, 3, 3)};
    int32_t start[] = {0, 6};
    d.c0 = (tc_polylines){1, start, verts};
    CHECK(same_on_threads("polyline", &d, &o) == TC_EINVAL);
    tmesh_free(&g);
}

/* The wedges of one set equal another's, field by field (not memcmp: padding). */
static int same_wedges(const tc__wedge_set *a, const tc__wedge_set *b, int32_t ncorner, int32_t nv) {
    if (a->nw != b->nw || a->ncoupled != b->ncoupled) return 0;
    for (int32_t i = 0; i < a->nw; i++) {
        const tc__wedge *x = &a->w[i], *y = &b->w[i];
        if (x->v != y->v || x->first != y->first || x->count != y->count || x->collinear != y->collinear) return 0;
        for (int s = 0; s < 2; s++)
            if (x->side_edge[s] != y->side_edge[s] || x->side_kind[s] != y->side_kind[s] ||
                x->across[s] != y->across[s] || memcmp(x->dir[s], y->dir[s], sizeof x->dir[s]))
                return 0;
    }
    return !memcmp(a->corners, b->corners, (size_t)ncorner * sizeof *a->corners) &&
           !memcmp(a->of_corner, b->of_corner, (size_t)ncorner * sizeof *a->of_corner) &&
           !memcmp(a->vclass, b->vclass, (size_t)nv * sizeof *a->vclass);
}

/* What the threads build inside: the vertex -> corner lists (corners sent to buckets
 * by vertex range, each range sorted on its own thread) and their longest, the adjacency, the
 * corner values, and the wedge sets (each part's wedges copied into one array), on
 * a mesh where every one of those loops is split in parts. */
TEST(threads_mesh_internals_bit_identical) {
    trng r;
    trng_seed(&r, tc_test_seed() + 23);
    tmesh g;
    big_mesh(&g, &r);
    tc_mesh_desc d;
    tmesh_desc(&g, &d);
    d.threads = 1;
    tc_mesh *s = NULL;
    CHECK(tc_mesh_new(&d, &s, NULL) == TC_OK);
    int32_t nc = 3 * s->nt;
    static const int threads[] = {2, 3, 8};
    static const int honor[] = {TC_HONOR_NONE, TC_HONOR_ALL, TC_HONOR_CM1};
    for (size_t i = 0; s && i < sizeof threads / sizeof threads[0]; i++) {
        tc_mesh *m = NULL;
        d.threads = threads[i];
        CHECK(tc_mesh_new(&d, &m, NULL) == TC_OK);
        if (!m) continue;
        CHECK_MSG(!memcmp(m->vstart, s->vstart, ((size_t)s->nv + 1) * sizeof *s->vstart) &&
                      !memcmp(m->vcorner, s->vcorner, (size_t)nc * sizeof *s->vcorner),
                  "%d threads: the vertex corner lists differ", threads[i]);
        CHECK_MSG(m->max_valence == s->max_valence, "%d threads: max_valence %d, not %d", threads[i],
                  (int)m->max_valence, (int)s->max_valence);
        CHECK_MSG(!memcmp(m->nbr, s->nbr, (size_t)nc * sizeof *s->nbr) &&
                      !memcmp(m->nbr_k, s->nbr_k, (size_t)nc * sizeof *s->nbr_k) &&
                      !memcmp(m->flag, s->flag, (size_t)nc * sizeof *s->flag),
                  "%d threads: the adjacency differs", threads[i]);
        CHECK_MSG(!memcmp(m->cz, s->cz, (size_t)nc * (size_t)s->nc * sizeof *s->cz),
                  "%d threads: the corner values differ", threads[i]);
        for (size_t h = 0; h < sizeof honor / sizeof honor[0]; h++) {
            tc__wedge_set ws1, wsn;
            CHECK(tc__wedges_build_on(s, honor[h], 1, &ws1) == TC_OK);
            CHECK(tc__wedges_build_on(m, honor[h], threads[i], &wsn) == TC_OK);
            CHECK_MSG(same_wedges(&ws1, &wsn, nc, s->nv), "%d threads, honour %d: the wedges differ", threads[i],
                      honor[h]);
            tc__wedges_free(&ws1), tc__wedges_free(&wsn);
        }
        tc_mesh_free(m);
    }
    tc_mesh_free(s);
    tmesh_free(&g);
}

/* Every edge flagged C0: each corner is a wedge of its own (3nt of them, six per interior
 * vertex), so each part's wedge array, first sized for about one per vertex, grows many
 * times; the set is the serial one on any number of threads. */
TEST(threads_wedges_every_edge_flagged) {
    trng r;
    trng_seed(&r, tc_test_seed() + 29);
    tmesh g;
    tmesh_grid(&g, 130, 130, 0.3, -1, &r);
    tmesh_sample(&g, 1, smooth_f, NULL, 1, 0, 0.3);
    int32_t *start = malloc((3 * (size_t)g.nt + 1) * sizeof *start), *verts = malloc(6 * (size_t)g.nt * sizeof *verts);
    int32_t nl = 0;
    start[0] = 0;
    for (int32_t c = 0; c < 3 * g.nt; c++) /* each interior edge once, a C0 polyline of its own */
        if (g.enbr[c] > c / 3) {
            verts[2 * nl] = g.tri[c], verts[2 * nl + 1] = g.tri[c / 3 * 3 + (c % 3 + 1) % 3];
            nl++, start[nl] = 2 * nl;
        }
    tc_mesh_desc d;
    tmesh_desc(&g, &d);
    d.c0 = (tc_polylines){nl, start, verts};
    tc_mesh *m = NULL;
    CHECK(tc_mesh_new(&d, &m, NULL) == TC_OK);
    static const int threads[] = {1, 3, 8};
    tc__wedge_set ws1 = {0};
    for (size_t i = 0; m && i < sizeof threads / sizeof threads[0]; i++) {
        tc__wedge_set ws;
        CHECK(tc__wedges_build_on(m, TC_HONOR_ALL, threads[i], &ws) == TC_OK);
        CHECK_MSG(ws.nw == 3 * m->nt, "%d threads: %d wedges, not one per corner (%d)", threads[i], (int)ws.nw,
                  (int)(3 * m->nt));
        if (i == 0) ws1 = ws;
        else {
            CHECK_MSG(same_wedges(&ws1, &ws, 3 * m->nt, m->nv), "%d threads: the wedges differ", threads[i]);
            tc__wedges_free(&ws);
        }
    }
    tc__wedges_free(&ws1);
    tc_mesh_free(m);
    tmesh_free(&g);
    free(start), free(verts);
}

/* Figure 6's literal Project amplifying the gradient (test_wedges.c's star: C0 on one
 * side of its vertex, C-1 on the other, steep given planes) at 3000 disjoint copies of
 * the star, each with its planes scaled differently (by lo .. hi): the
 * amplification warning (count, first vertices, worst) merged from the parts of the C0
 * wedges' planes is the serial one; with a wider range some star is singular, and the
 * error is the serial one (the first such vertex). Returns the finding it checked. */
static int literal_stars(double lo, double hi, const char *want) {
    static const double xy[10] = {0, 0, 1, 0, -1, 0, 0, 1, 0, -1};
    static const double cg[24] = {10.920623257253608, -15.971620080979365, 3.1670205030436716, -1.5876232001872848,
                                  -8.5570255613685688, -14.675991979742417, 14.554001090374777, -4.0375080816622404,
                                  1.3454544271088453,  3.9829071909109626,  -1.0125139639771152, 12.748638052841947,
                                  -14.818304513962151, 5.8202596874070611,  16.759694869052474, 1.8499370021046779,
                                  2.0653158901563451,  10.486855930875457,  7.6292296813937055, -12.452525772365055,
                                  -9.6824571255978462, -2.0391880637217263, 12.636214454023268, 2.0197554780262328};
    static const int32_t tri[12] = {0, 1, 3, 0, 3, 2, 0, 2, 4, 0, 4, 1};
    enum { N = 3000 };
    double *pxy = malloc(N * 10 * sizeof *pxy), *z = malloc(N * 5 * sizeof *z), *pcg = malloc(N * 24 * sizeof *pcg);
    int32_t *ptri = malloc(N * 12 * sizeof *ptri), *cgt = malloc(N * 4 * sizeof *cgt);
    int32_t *c0s = malloc((N + 1) * sizeof *c0s), *c0v = malloc(N * 2 * sizeof *c0v);
    int32_t *cms = malloc((N + 1) * sizeof *cms), *cmv = malloc(N * 2 * sizeof *cmv);
    for (int i = 0; i < N; i++) {
        for (int j = 0; j < 5; j++) {
            pxy[10 * i + 2 * j] = xy[2 * j] + 3.0 * (i % 60), pxy[10 * i + 2 * j + 1] = xy[2 * j + 1] + 3.0 * (i / 60);
            z[5 * i + j] = 0.1 * j + 0.01 * (i % 13);
        }
        for (int j = 0; j < 12; j++) ptri[12 * i + j] = 5 * i + tri[j];
        for (int j = 0; j < 24; j++) pcg[24 * i + j] = cg[j] * (lo + (hi - lo) * ((i * 37) % 101) / 100.0);
        for (int j = 0; j < 4; j++) cgt[4 * i + j] = 4 * i + j;
        c0s[i] = cms[i] = 2 * i;
        c0v[2 * i] = 5 * i, c0v[2 * i + 1] = 5 * i + 1, cmv[2 * i] = 5 * i + 2, cmv[2 * i + 1] = 5 * i;
    }
    c0s[N] = cms[N] = 2 * N;
    tc_mesh_desc d;
    tc_mesh_desc_init(&d);
    d.nverts = 5 * N, d.xy = pxy, d.ntris = 4 * N, d.tris = ptri, d.nchan = 1, d.values = z;
    d.ncorner_gradients = 4 * N, d.corner_gradients_tri = cgt, d.corner_gradients = pcg;
    d.c0 = (tc_polylines){N, c0s, c0v}, d.cm1 = (tc_polylines){N, cms, cmv};
    tc_options o;
    tc_options_default(&o);
    o.tangents = TC_TANGENTS_GIVEN, o.wedges = TC_WEDGES_LITERAL, o.range = TC_RANGE_FREE;
    CHECK(same_on_threads(want, &d, &o) == TC_OK);
    outcome s; /* the case is what it means */
    run(&d, &o, 1, &s);
    int found = 0;
    for (int j = 0; j < s.dg.count; j++) found |= strstr(s.dg.items[j].message, want) != NULL;
    outcome_free(&s);
    free(pxy), free(z), free(pcg), free(ptri), free(cgt), free(c0s), free(c0v), free(cms), free(cmv);
    return found;
}

TEST(threads_literal_project_as_serial) {
    CHECK_MSG(literal_stars(0.98, 1.02, "wedge planes (literal Project) amplify"), "no amplification warning");
    CHECK_MSG(literal_stars(0.2, 1.1, "Project is singular at vertex"), "no singular Project");
}

/* Snakes over the grid's rows (C0 over rows 0..63, C-1 over rows 66..130, 8000 and more
 * segments each): their edge look-ups run in parts; the flags, and the errors of
 * segments that are no edges or repeat a vertex, early and late, as serially. */
static int32_t snake(int32_t *v, int row0, int row1) {
    int32_t n = 0;
    for (int row = row0; row <= row1; row++)
        for (int k = 0; k <= 130; k++) v[n++] = tmesh_gv(130, (row - row0) % 2 ? 130 - k : k, row);
    return n;
}

TEST(threads_long_polylines_as_serial) {
    trng r;
    trng_seed(&r, tc_test_seed() + 24);
    tmesh g;
    tmesh_grid(&g, 130, 130, 0.2, -1, &r);
    tmesh_sample(&g, 1, smooth_f, NULL, 1, 0, 0);
    tc_mesh_desc d;
    tmesh_desc(&g, &d);
    tc_options o;
    tc_options_default(&o);
    int32_t *c0v = malloc(131 * 131 * sizeof *c0v), *cmv = malloc(131 * 131 * sizeof *cmv), c0s[2], cms[2];
    c0s[0] = cms[0] = 0, c0s[1] = snake(c0v, 0, 63), cms[1] = snake(cmv, 66, 130);
    d.c0 = (tc_polylines){1, c0s, c0v}, d.cm1 = (tc_polylines){1, cms, cmv};
    CHECK(same_on_threads("long polylines", &d, &o) == TC_OK);
    c0v[c0s[1] - 3] = tmesh_gv(130, 65, 100), c0v[5] = c0v[4];
    CHECK(same_on_threads("long polylines, bad segments", &d, &o) == TC_EINVAL);
    free(c0v), free(cmv);
    tmesh_free(&g);
}

/* tc__parallel_trace (bench/perf/phases.c): each loop recorded while on, in call order, with
 * its part function, size, parts and clocks; nothing once off; the count says how many. */
static void fill_part(void *ctx, int32_t lo, int32_t hi, int part) {
    int32_t *x = ctx;
    (void)part;
    for (int32_t i = lo; i < hi; i++) x[i] = i;
}

static void count_part(void *ctx, int32_t lo, int32_t hi, int part) {
    int32_t *x = ctx;
    (void)part;
    for (int32_t i = lo; i < hi; i++) x[i]++;
}

static void noop_part(void *ctx, int32_t lo, int32_t hi, int part) {
    (void)ctx, (void)lo, (void)hi, (void)part;
}

TEST(threads_trace_records_loops) {
    enum { N = 1 << 16 };
    int32_t *x = calloc(N, sizeof *x);
    tc__loop_record rec[2];
    CHECK(x != NULL);
    if (!x) return;
    tc__parallel_trace(rec, 2);
    tc__parallel_for(4, N, 1024, fill_part, x);
    tc__parallel_for(1, 10, 1, noop_part, NULL);
    tc__parallel_for(2, 10, 1, noop_part, NULL); /* beyond the 2 kept: counted only */
    CHECK(tc__parallel_trace(NULL, 0) == 3);
    tc__parallel_for(4, N, 1024, noop_part, NULL); /* off: not recorded, not counted */
    CHECK(tc__parallel_trace(NULL, 0) == 0);
    CHECK(rec[0].fn == (const void *)fill_part && rec[0].n == N && rec[0].parts == tc__parallel_parts(4, N, 1024));
    CHECK(rec[1].fn == (const void *)noop_part && rec[1].n == 10 && rec[1].parts == 1);
    CHECK(rec[0].end_s >= rec[0].start_s && rec[1].start_s >= rec[0].end_s);
    CHECK(rec[0].cpu_s >= 0 && rec[0].slowest_s >= 0 && rec[0].slowest_s <= rec[0].end_s - rec[0].start_s);
    int all = 1;
    for (int32_t i = 0; i < N; i++) all &= x[i] == i; /* the loop itself ran, traced */
    CHECK(all);
    free(x);
}

/* A few parts per thread (a slow thread then delays one small part, not the loop by
 * its whole share), at most TC_PARALLEL_MAX, none under min_part items; and every
 * index in exactly one part, whichever thread takes it. */
TEST(threads_parts_several_per_thread) {
    CHECK(tc__parallel_parts(1, 1 << 20, 1) == 1);
    CHECK(tc__parallel_parts(2, 1 << 20, 1) == 8);
    CHECK(tc__parallel_parts(16, 1 << 20, 1) == TC_PARALLEL_MAX);
    CHECK(tc__parallel_parts(200, 1 << 20, 1) == TC_PARALLEL_MAX);
    CHECK(tc__parallel_parts(4, 5000, 1000) == 5);
    CHECK(tc__parallel_parts(4, 500, 1000) == 1);
    enum { N = 100003 };
    int32_t *x = calloc(N, sizeof *x);
    CHECK(x != NULL);
    if (!x) return;
    for (int threads = 2; threads <= 9; threads++) {
        memset(x, 0, N * sizeof *x);
        tc__parallel_for(threads, N, 100, count_part, x);
        int once = 1;
        for (int32_t i = 0; i < N; i++) once &= x[i] == 1;
        CHECK_MSG(once, "%d threads: an index not run exactly once", threads);
        memset(x, 0, N * sizeof *x);
        tc__parallel_for_threads(threads, N, 100, count_part, x);
        once = 1;
        for (int32_t i = 0; i < N; i++) once &= x[i] == 1;
        CHECK_MSG(once, "%d threads, one part each: an index not run exactly once", threads);
    }
    free(x);
}

/* One part per thread (textpar's answer buffers, the render's workers): no more parts
 * than threads, as many as the items allow. */
TEST(threads_one_part_per_thread) {
    CHECK(tc__parallel_thread_parts(1, 1 << 20, 1) == 1);
    CHECK(tc__parallel_thread_parts(2, 1 << 20, 2048) == 2);
    CHECK(tc__parallel_thread_parts(16, 16, 1) == 16);
    CHECK(tc__parallel_thread_parts(16, 20, 1) == 16);
    CHECK(tc__parallel_thread_parts(200, 1 << 20, 1) == TC_PARALLEL_MAX);
    CHECK(tc__parallel_thread_parts(4, 5000, 2000) == 2);
    CHECK(tc__parallel_thread_parts(4, 500, 1000) == 1);
}

/* The live threads of this process (/proc/self/status), or -1. */
static int live_threads(void) {
    FILE *f = fopen("/proc/self/status", "r");
    char line[256];
    int n = -1;
    while (f && fgets(line, sizeof line, f))
        if (sscanf(line, "Threads: %d", &n) == 1) break;
    if (f) fclose(f);
    return n;
}

/* tc__parallel_stop ends the pool's workers (the tests call it before they exit, so
 * that LeakSanitizer's exit scan has fewer threads to stop); a later loop starts as
 * many as it needs again and runs whole; a second stop, or one with no pool, does
 * nothing. (Other threads of this process, the image libraries' own pools, are
 * counted in `base` and left alone.) */
TEST(threads_pool_stops_and_starts_again) {
    enum { N = 50021 };
    int32_t *x = calloc(N, sizeof *x);
    CHECK(x != NULL);
    if (!x) return;
    tc__parallel_stop();
    int base = live_threads();
    CHECK(base >= 1);
    tc__parallel_for(8, N, 100, count_part, x); /* 7 workers and this thread */
    CHECK_MSG(live_threads() == base + 7, "%d threads with the pool, %d without", live_threads(), base);
    tc__parallel_stop();
    CHECK_MSG(live_threads() == base, "%d threads after the stop, %d before the pool", live_threads(), base);
    tc__parallel_stop();
    CHECK(live_threads() == base);
    tc__parallel_for(5, N, 100, count_part, x);
    CHECK(live_threads() == base + 4);
    tc__parallel_for(3, N, 100, count_part, x); /* the pool keeps its 4 */
    CHECK(live_threads() == base + 4);
    int thrice = 1;
    for (int32_t i = 0; i < N; i++) thrice &= x[i] == 3;
    CHECK(thrice);
    tc__parallel_stop();
    CHECK(live_threads() == base);
    free(x);
}
