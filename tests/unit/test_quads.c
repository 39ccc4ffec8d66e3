/* test_quads.c — quad meshes: validation with the quads' paths, per-quad corner entries, the split,
 * every triangle method bit for bit equal on quads and their split, request reader/writer, scenes. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "io/api.h"
#include "io/request.h"
#include "io/request_write.h"
#include "quadgen.h"
#include "scenes/meshing.h"

/* ---- a base input: two unit squares side by side --------------------------------- *
 *   3 --- 4 --- 5
 *   |  0  |  1  |      quads [0, 1, 4, 3] and [1, 2, 5, 4]
 *   0 --- 1 --- 2                                                                    */

static const double Q_XY[] = {0, 0, 1, 0, 2, 0, 0, 1, 1, 1, 2, 1};
static const int32_t Q_QUADS[] = {0, 1, 4, 3, 1, 2, 5, 4};
static const double Q_VAL[] = {1, 2, 3, 4, 5, 6};

static tc_mesh_desc two_quads(void) {
    tc_mesh_desc d;
    memset(&d, 0, sizeof d);
    d.nverts = 6, d.xy = Q_XY;
    d.nquads = 2, d.quads = Q_QUADS;
    d.nchan = 1, d.values = Q_VAL;
    return d;
}

/* The first finding is an error at `path` whose message contains `needle`. */
static void check_first(const char *file, int line, const tc_diags *dg, const char *path, const char *needle) {
    if (dg->count < 1 || dg->errors < 1) {
        tc_test_fail(file, line, "no error reported");
        return;
    }
    const tc_diag *e = &dg->items[0];
    if (e->severity != TC_SEV_ERROR || strcmp(e->path, path) != 0 || !strstr(e->message, needle))
        tc_test_fail(file, line, "first finding '%s: %s', expected an error at '%s' containing '%s'", e->path,
                     e->message, path, needle);
}

static void mesh_fails(const char *file, int line, const tc_mesh_desc *d, const char *path, const char *needle) {
    tc_mesh *m = (tc_mesh *)&m;
    tc_diags dg;
    tc_diags_init(&dg);
    int st = tc_mesh_new(d, &m, &dg);
    if (st != TC_EINVAL || m != NULL) tc_test_fail(file, line, "status %d, expected TC_EINVAL and no mesh", st);
    check_first(file, line, &dg, path, needle);
    if (st == TC_OK) tc_mesh_free(m);
    tc_diags_free(&dg);
}
#define FAILS(d, path, needle) mesh_fails(__FILE__, __LINE__, d, path, needle)

static tc_mesh *mesh_ok(const tc_mesh_desc *d) {
    tc_mesh *m = NULL;
    tc_diags dg;
    tc_diags_init(&dg);
    int st = tc_mesh_new(d, &m, &dg);
    CHECK_MSG(st == TC_OK, "status %d (%s: %s)", st, dg.count ? dg.items[0].path : "",
              dg.count ? dg.items[0].message : "");
    tc_diags_free(&dg);
    return m;
}

/* ---- validation ------------------------------------------------------------------- */

TEST(quads_validation_shapes) {
    tc_mesh_desc d = two_quads();
    tc_mesh_free(mesh_ok(&d));
    double xy[12];
    memcpy(xy, Q_XY, sizeof xy);
    xy[8] = 0.3, xy[9] = 0.3; /* vertex 4 inside quad 0's corner: reflex there */
    d.xy = xy;
    FAILS(&d, "quads[0]", "non-convex quad: it turns the other way at vertex 4 (corner 2)");
    xy[8] = 1, xy[9] = 1e-17; /* vertex 4 onto the line 1-... : no turn at vertex 1's neighbour */
    memcpy(xy, Q_XY, sizeof xy);
    xy[6] = 0.5, xy[7] = 0; /* vertex 3 on the edge 0-1 of quad 0 (0, 3, 1 collinear) */
    FAILS(&d, "quads[0]", "degenerate quad");
    d = two_quads();
    int32_t bowtie[] = {0, 1, 3, 4, 1, 2, 5, 4};
    d.quads = bowtie;
    FAILS(&d, "quads[0]", "non-convex quad: its sides cross");
    int32_t twice[] = {0, 1, 1, 3, 1, 2, 5, 4};
    d.quads = twice;
    FAILS(&d, "quads[0]", "degenerate quad: a vertex appears twice in [0, 1, 1, 3]");
    int32_t range[] = {0, 1, 9, 3, 1, 2, 5, 4};
    d.quads = range;
    FAILS(&d, "quads[0][2]", "vertex index 9 out of range (6 vertices)");
    int32_t repeat[] = {0, 1, 4, 3, 4, 3, 0, 1};
    d.quads = repeat;
    FAILS(&d, "quads[1]", "repeats quads[0] (same four vertices)");
    d = two_quads();
    static const int32_t tri[] = {0, 1, 4};
    d.ntris = 1, d.tris = tri;
    FAILS(&d, "quads", "give either triangles or quads, not both");
    d = two_quads();
    d.nquads = 0;
    FAILS(&d, "triangles", "no triangles (nor quads)");
}

/* Errors the triangle machinery finds on the split triangles name the quads. */
TEST(quads_validation_split_errors_name_quads) {
    /* quad 1 folds back over quad 0 across their shared edge 1-4 */
    static const double xy[] = {0, 0, 1, 0, 0, 1, 1, 1, 0.5, 0.8, 0.5, 0.2};
    static const int32_t quads[] = {0, 1, 3, 2, 1, 3, 4, 5};
    static const double val[] = {1, 2, 3, 4, 5, 6};
    tc_mesh_desc d;
    memset(&d, 0, sizeof d);
    d.nverts = 6, d.xy = xy, d.nquads = 2, d.quads = quads, d.nchan = 1, d.values = val;
    FAILS(&d, "quads[1]", "overlaps quads[0]: both lie on the same side of their shared edge");
    /* a C0 line along a quad's diagonal: not an edge of the quad mesh */
    d = two_quads();
    int32_t start[2] = {0, 2}, verts[2] = {0, 4};
    d.c0 = (tc_polylines){1, start, verts};
    FAILS(&d, "discontinuities.c0[0][0]", "segment [0, 4] is the diagonal of quads[0]");
    verts[0] = 1, verts[1] = 4; /* a quad edge: fine */
    tc_mesh_free(mesh_ok(&d));
    /* values that disagree across a C1 edge, from a per-quad entry */
    d = two_quads();
    int32_t cvq[1] = {0};
    double cv[4] = {1, 2.5, 5, 4};
    d.ncorner_values = 1, d.corner_values_tri = cvq, d.corner_values = cv;
    FAILS(&d, "corner_values[0]", "(quad 0)");
    /* tangents "given" with a corner missing: the reconstruction names the quad */
    d = two_quads();
    double g[12] = {0};
    uint8_t mask[6] = {1, 1, 1, 1, 0, 1};
    d.gradients = g, d.gradients_mask = mask;
    tc_mesh *m = mesh_ok(&d);
    tc_options o;
    tc_options_default(&o);
    o.tangents = TC_TANGENTS_GIVEN;
    tc_recon *r = NULL;
    tc_diags dg;
    tc_diags_init(&dg);
    CHECK(m && tc_recon_new(m, &o, &r, &dg) == TC_EINVAL);
    check_first(__FILE__, __LINE__, &dg, "quads[0]", "corner 2 (vertex 4) has no gradient");
    for (int i = 0; i < dg.count; i++) CHECK_MSG(strncmp(dg.items[i].path, "triangles", 9), "%s", dg.items[i].path);
    tc_diags_free(&dg);
    tc_mesh_free(m);
}

/* Per-quad corner entries: 4 corners each, quad indices checked, and their
 * data lands on both split triangles at the shared corners a and c. */
TEST(quads_per_quad_corner_entries) {
    tc_mesh_desc d = two_quads();
    int32_t cvq[2] = {1, 0};
    double cv[8] = {2, 3, 6, 5, 1, 2, 5, 4}; /* equal to the vertex values: no disagreement */
    d.ncorner_values = 2, d.corner_values_tri = cvq, d.corner_values = cv;
    int32_t cgq[1] = {1};
    double cg[8] = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8};
    uint8_t cgmask[4] = {1, 1, 0, 1};
    d.ncorner_gradients = 1, d.corner_gradients_tri = cgq, d.corner_gradients = cg, d.corner_gradients_mask = cgmask;
    int32_t mide[4] = {1, 4, 0, 4}, midq[2] = {1, 0};
    double midv[2] = {3.5, 3};
    d.nmidpoints = 2, d.midpoint_edge = mide, d.midpoint_tri = midq, d.midpoint_values = midv;
    tc_mesh *m = mesh_ok(&d);
    if (m) {
        CHECK(tc_mesh_quad_count(m) == 2 && tc_mesh_triangle_count(m) == 4);
        CHECK(!memcmp(tc_mesh_quads(m), Q_QUADS, sizeof Q_QUADS));
        static const int32_t split[] = {0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4};
        CHECK(!memcmp(tc_mesh_triangles(m), split, sizeof split));
        CHECK(*tc_mesh_corner_value(m, 3, 2) == 5 && *tc_mesh_corner_value(m, 2, 2) == 6); /* quad 1's d, c */
        /* quad 1's corner gradients: corner c (vertex 5) was masked out; with
         * tangents "given" every other corner of quad 1 has its own plane */
        tc_options o;
        tc_options_default(&o);
        o.method = TC_METHOD_LINEAR;
        tc_recon *r = NULL;
        CHECK(tc_recon_new(m, &o, &r, NULL) == TC_OK);
        tc_recon_free(r);
    }
    tc_mesh_free(m);
    cvq[1] = 2;
    FAILS(&d, "corner_values[1].quad", "quad index 2 out of range (2 quads)");
    cvq[1] = 1;
    FAILS(&d, "corner_values[1].quad", "quad 1 already has corner values (corner_values[0])");
    cvq[1] = 0;
    cgq[0] = -1;
    FAILS(&d, "corner_gradients[0].quad", "quad index -1 out of range (2 quads)");
    cgq[0] = 1;
    cg[6] = INFINITY;
    FAILS(&d, "corner_gradients[0].gradients[3]", "not finite");
    cg[6] = 0.7;
    midq[1] = 1; /* edge [0, 4] is quad 0's diagonal, not quad 1's */
    FAILS(&d, "midpoints[1].quad", "quad 1 does not have edge [0, 4]");
    midq[1] = 5;
    FAILS(&d, "midpoints[1].quad", "quad 5 does not have edge [0, 4]");
    midq[1] = 0;
    tc_mesh_free(mesh_ok(&d));
}

TEST(quads_hessians_checked) {
    tc_mesh_desc d = two_quads();
    double h[18] = {0};
    uint8_t mask[6] = {1, 1, 1, 1, 1, 0};
    h[7] = NAN; /* vertex 2 */
    d.hessians = h;
    FAILS(&d, "hessians[2]", "not finite");
    h[7] = 0, h[16] = INFINITY; /* vertex 5, masked out: not read */
    d.hessians_mask = mask;
    tc_mesh_free(mesh_ok(&d));
}

/* ---- the split: every triangle method sees the same mesh ------------------------- */

static void smooth_qf(const void *ctx, double x, double y, int ch, double *v, double g[2], double h[3]) {
    (void)ctx;
    double a = 1.0 + 0.3 * ch;
    *v = sin(2 * a * x + 1) * cos(3 * y - 0.5 * a) + 0.5 * x * y;
    g[0] = g[1] = h[0] = h[1] = h[2] = 0;
}

/* A quad mesh with every kind of per-corner data and flags, and the same data
 * written by hand for its explicit split into triangles. */
typedef struct {
    qmesh q;
    int32_t c0s[2], c0v[8], cm1s[2], cm1v[8];
    int32_t ncv, cvq[32];
    double cv[32 * 4 * 2];
    int32_t ncg, cgq[32];
    double cg[32 * 4 * 2 * 2];
    uint8_t cgm[32 * 4];
    int32_t nmid, mide[128 * 2], midq[128];
    double midv[128 * 2];
    /* the split's version */
    int32_t tris[64 * 3], tcvq[64], tcgq[64], tmidt[128];
    double tcv[64 * 3 * 2], tcg[64 * 3 * 2 * 2];
    uint8_t tcgm[64 * 3];
} both;

static void add_mid(both *b, int32_t a, int32_t c, int32_t side) {
    const double *p = b->q.xy + 2 * a, *r = b->q.xy + 2 * c;
    for (int ch = 0; ch < 2; ch++) {
        double v, g[2], h[3];
        smooth_qf(NULL, 0.5 * (p[0] + r[0]), 0.5 * (p[1] + r[1]), ch, &v, g, h);
        b->midv[2 * b->nmid + ch] = v + (side >= 0 ? 0.01 * side : 0);
    }
    b->mide[2 * b->nmid] = a, b->mide[2 * b->nmid + 1] = c, b->midq[b->nmid] = side;
    b->nmid++;
}

/* The split triangle of quad qi that has edge (a, c): 2qi or 2qi+1. */
static int32_t half_with(const both *b, int32_t qi, int32_t a, int32_t c) {
    const int32_t *v = b->q.quad + 4 * qi;
    int32_t t0[3] = {v[0], v[1], v[2]};
    int has_a = 0, has_c = 0;
    for (int k = 0; k < 3; k++) has_a |= t0[k] == a, has_c |= t0[k] == c;
    return has_a && has_c ? 2 * qi : 2 * qi + 1;
}

static void build_both(both *b, trng *rng) {
    memset(b, 0, sizeof *b);
    qgrid_opts o = {0.2, 0, {0, 0, 0, 0}, {0, 0}};
    qmesh_grid(&b->q, 4, 3, &o, rng); /* 20 vertices, 12 quads, 31 edges */
    qmesh_sample(&b->q, 2, smooth_qf, NULL);
    int nx = 4;
    /* C-1 along grid row j = 1 (vertices 5..9), C0 along column i = 2 (2, 7, 12, 17) */
    for (int i = 0; i <= nx; i++) b->cm1v[i] = 1 * (nx + 1) + i;
    for (int j = 0; j <= 3; j++) b->c0v[j] = j * (nx + 1) + 2;
    b->cm1s[1] = nx + 1, b->c0s[1] = 4;
    /* per-quad corner values: quads below row 1 take a jump of 0.5 at corners on it */
    for (int32_t qi = 0; qi < b->q.nq; qi++) {
        const int32_t *v = b->q.quad + 4 * qi;
        int below = qi / nx == 0, touches = 0;
        for (int k = 0; k < 4; k++) touches |= v[k] / (nx + 1) == 1;
        if (!touches) continue;
        b->cvq[b->ncv] = qi;
        for (int k = 0; k < 4; k++)
            for (int ch = 0; ch < 2; ch++)
                b->cv[(4 * b->ncv + k) * 2 + ch] = b->q.values[2 * v[k] + ch] + (below && v[k] / (nx + 1) == 1 ? 0.5 : 0);
        b->ncv++;
    }
    /* per-quad corner gradients on every other quad, some corners masked */
    for (int32_t qi = 0; qi < b->q.nq; qi += 2) {
        b->cgq[b->ncg] = qi;
        for (int k = 0; k < 4; k++) {
            b->cgm[4 * b->ncg + k] = (qi + k) % 3 != 0;
            for (int i = 0; i < 4; i++) b->cg[(4 * b->ncg + k) * 4 + i] = 0.1 * (qi + 1) - 0.05 * k + 0.02 * i;
        }
        b->ncg++;
    }
    /* midpoints: every diagonal, every quad edge once, but per side on the C-1 row */
    int32_t seen[64][2], nseen = 0;
    for (int32_t qi = 0; qi < b->q.nq; qi++) {
        const int32_t *v = b->q.quad + 4 * qi;
        add_mid(b, v[0], v[2], -1);
        for (int k = 0; k < 4; k++) {
            int32_t a = v[k], c = v[(k + 1) % 4], lo = a < c ? a : c, hi = a < c ? c : a, dup = 0;
            if (a / (nx + 1) == 1 && c / (nx + 1) == 1) {
                add_mid(b, a, c, qi);
                continue;
            }
            for (int i = 0; i < nseen; i++) dup |= seen[i][0] == lo && seen[i][1] == hi;
            if (dup) continue;
            seen[nseen][0] = lo, seen[nseen][1] = hi, nseen++;
            add_mid(b, a, c, -1);
        }
    }
    /* the split, by hand */
    for (int32_t qi = 0; qi < b->q.nq; qi++) {
        const int32_t *v = b->q.quad + 4 * qi;
        int32_t *t = b->tris + 6 * qi;
        t[0] = v[0], t[1] = v[1], t[2] = v[2], t[3] = v[0], t[4] = v[2], t[5] = v[3];
    }
    static const int half_corner[2][3] = {{0, 1, 2}, {0, 2, 3}};
    for (int32_t i = 0; i < b->ncv; i++)
        for (int h = 0; h < 2; h++) {
            b->tcvq[2 * i + h] = 2 * b->cvq[i] + h;
            for (int k = 0; k < 3; k++)
                for (int ch = 0; ch < 2; ch++)
                    b->tcv[((2 * i + h) * 3 + k) * 2 + ch] = b->cv[(4 * i + half_corner[h][k]) * 2 + ch];
        }
    for (int32_t i = 0; i < b->ncg; i++)
        for (int h = 0; h < 2; h++) {
            b->tcgq[2 * i + h] = 2 * b->cgq[i] + h;
            for (int k = 0; k < 3; k++) {
                b->tcgm[(2 * i + h) * 3 + k] = b->cgm[4 * i + half_corner[h][k]];
                memcpy(b->tcg + ((2 * i + h) * 3 + k) * 4, b->cg + (4 * i + half_corner[h][k]) * 4, 4 * sizeof(double));
            }
        }
    for (int32_t i = 0; i < b->nmid; i++)
        b->tmidt[i] = b->midq[i] < 0 ? -1 : half_with(b, b->midq[i], b->mide[2 * i], b->mide[2 * i + 1]);
}

static void both_descs(const both *b, tc_mesh_desc *dq, tc_mesh_desc *dt) {
    qmesh_desc(&b->q, 0, 0, dq);
    dq->c0 = (tc_polylines){1, b->c0s, b->c0v};
    dq->cm1 = (tc_polylines){1, b->cm1s, b->cm1v};
    dq->ncorner_values = b->ncv, dq->corner_values_tri = b->cvq, dq->corner_values = b->cv;
    dq->ncorner_gradients = b->ncg, dq->corner_gradients_tri = b->cgq, dq->corner_gradients = b->cg;
    dq->corner_gradients_mask = b->cgm;
    dq->nmidpoints = b->nmid, dq->midpoint_edge = b->mide, dq->midpoint_tri = b->midq, dq->midpoint_values = b->midv;
    *dt = *dq;
    dt->nquads = 0, dt->quads = NULL, dt->ntris = 2 * b->q.nq, dt->tris = b->tris;
    dt->ncorner_values = 2 * b->ncv, dt->corner_values_tri = b->tcvq, dt->corner_values = b->tcv;
    dt->ncorner_gradients = 2 * b->ncg, dt->corner_gradients_tri = b->tcgq, dt->corner_gradients = b->tcg;
    dt->corner_gradients_mask = b->tcgm;
    dt->midpoint_tri = b->tmidt;
}

/* Builds method o on both meshes and compares everything bit for bit. */
static void compare_method(const tc_mesh *mq, const tc_mesh *mt, const tc_locator *L, tc_options o, trng *rng) {
    tc_recon *rq = NULL, *rt = NULL;
    int sq = tc_recon_new(mq, &o, &rq, NULL), st = tc_recon_new(mt, &o, &rt, NULL);
    const char *name = tc_method_name(o.method);
    CHECK_MSG(sq == st, "%s: status %d on the quads, %d on the split", name, sq, st);
    if (rq && rt) {
        size_t nc = (size_t)tc_mesh_channel_count(mt), n = (size_t)tc_mesh_triangle_count(mt) * nc * (size_t)tc_recon_coef_count(rt);
        CHECK_MSG(tc_recon_coef_count(rq) == tc_recon_coef_count(rt) && !memcmp(tc_recon_coefs(rq), tc_recon_coefs(rt), n * sizeof(double)),
                  "%s (%s, %s, %s): coefficients differ", name, tc_cross_name(o.cross_boundary),
                  tc_wedges_name(o.wedges), tc_tangents_name(o.tangents));
        const double *gq = tc_recon_corner_gradients(rq), *gt = tc_recon_corner_gradients(rt);
        CHECK((!gq && !gt) || (gq && gt && !memcmp(gq, gt, (size_t)tc_mesh_triangle_count(mt) * 3 * nc * 2 * sizeof *gq)));
        enum { NP = 200 };
        double xy[2 * NP], vq[NP * 2], vt[NP * 2], dq[NP * 4], dt[NP * 4];
        for (int i = 0; i < 2 * NP; i++) xy[i] = 1.1 * trng_uniform(rng) - 0.05;
        tc_eval_points(rq, L, NP, xy, vq, dq, NULL);
        tc_eval_points(rt, L, NP, xy, vt, dt, NULL);
        CHECK_MSG(!memcmp(vq, vt, NP * nc * sizeof *vq) && !memcmp(dq, dt, 2 * NP * nc * sizeof *dq),
                  "%s: evaluations differ", name);
    }
    tc_recon_free(rq);
    tc_recon_free(rt);
}

TEST(quads_triangle_methods_equal_split) {
    trng rng;
    trng_seed(&rng, tc_test_seed() + 401);
    both *b = malloc(sizeof *b);
    if (!b) return;
    build_both(b, &rng);
    tc_mesh_desc dq, dt;
    both_descs(b, &dq, &dt);
    tc_mesh *mq = mesh_ok(&dq), *mt = mesh_ok(&dt);
    tc_locator *L = NULL;
    if (mt) CHECK(tc_locator_new(mt, &L) == TC_OK);
    const tc_tangents tangents[] = {TC_TANGENTS_AUTO, TC_TANGENTS_MIDPOINTS, TC_TANGENTS_ESTIMATE};
    for (int mi = 0; mq && mt && L && mi < tc_method_count(); mi++) /* every triangle method (the table) */
        for (int ci = 0; ci < 3 && !tc_method_quads_only((tc_method)mi); ci++)
            for (int wi = 0; wi < 2; wi++)
                for (int ti = 0; ti < 3; ti++) {
                    int cubic = (tc_method_reads((tc_method)mi) & TC_READS_CROSS_BOUNDARY) != 0;
                    if (!cubic && (ci || wi || ti)) continue;
                    tc_options o;
                    tc_options_default(&o);
                    o.method = (tc_method)mi, o.cross_boundary = (tc_cross)ci, o.wedges = (tc_wedges)wi;
                    o.tangents = tangents[ti];
                    compare_method(mq, mt, L, o, &rng);
                }
    tc_locator_free(L);
    tc_mesh_free(mq);
    tc_mesh_free(mt);
    qmesh_free(&b->q);
    free(b);
}

/* ---- the request format ------------------------------------------------------------ */

#define QUADS_JSON                                                                                     \
    "\"vertices\": [[0,0],[1,0],[2,0],[0,1],[1,1],[2,1]], \"quads\": [[0,1,4,3],[1,2,5,4]]"

static int parse(const char *json, tc_request **r, tc_diags *d) {
    tc_diags_init(d);
    return tc_request_parse(json, strlen(json), TC_REQ_MESH, r, d);
}

static void parse_fails(const char *file, int line, const char *json, int status, const char *path,
                        const char *needle) {
    tc_request *r = NULL;
    tc_diags d;
    int st = parse(json, &r, &d);
    if (st != status) tc_test_fail(file, line, "status %d, expected %d", st, status);
    check_first(file, line, &d, path, needle);
    tc_request_free(r);
    tc_diags_free(&d);
}
#define PARSE_FAILS(json, status, path, needle) parse_fails(__FILE__, __LINE__, json, status, path, needle)

TEST(quads_request_read_and_written) {
    const char *json = "{" QUADS_JSON ", \"values\": [1,2,3,4,5,6],"
                       " \"corner_values\": [{\"quad\": 1, \"values\": [2, 3, 6, 5]}],"
                       " \"corner_gradients\": [{\"quad\": 0, \"gradients\": [[1,2], null, [3,4], [5,6]]}],"
                       " \"midpoints\": [{\"edge\": [1, 4], \"value\": 3.5, \"quad\": 1}, {\"edge\": [0, 4], \"value\": 3}],"
                       " \"hessians\": [[1,2,3], null, [4,5,6], [7,8,9], [1,1,1], [2,2,2]],"
                       " \"method\": \"hermite\", \"twist\": \"zero\","
                       " \"methods\": [{\"method\": \"hermite\", \"twist\": \"estimate\"}, \"linear\"]}";
    tc_request *r = NULL;
    tc_diags d;
    CHECK(parse(json, &r, &d) == TC_REQ_OK);
    CHECK_MSG(d.count == 0, "%d findings (%s: %s)", d.count, d.count ? d.items[0].path : "", d.count ? d.items[0].message : "");
    if (r) {
        const tc_mesh_desc *q = &r->desc;
        CHECK(q->ntris == 0 && q->nquads == 2 && q->quads[4] == 1 && q->quads[7] == 4);
        CHECK(q->ncorner_values == 1 && q->corner_values_tri[0] == 1 && q->corner_values[3] == 5);
        CHECK(q->ncorner_gradients == 1 && q->corner_gradients_mask && q->corner_gradients_mask[1] == 0);
        CHECK(q->corner_gradients[7] == 6);
        CHECK(q->nmidpoints == 2 && q->midpoint_tri[0] == 1 && q->midpoint_tri[1] == -1);
        CHECK(q->hessians && q->hessians_mask && !q->hessians_mask[1] && q->hessians[8] == 6);
        CHECK(r->opt.method == TC_METHOD_HERMITE && r->opt.twist == TC_TWIST_ZERO);
        CHECK(r->nmethods == 2 && r->methods[0].twist == TC_TWIST_ESTIMATE && r->methods[1].twist == TC_TWIST_ZERO);
        tc_mesh *m = mesh_ok(q);
        tc_mesh_free(m);
        /* written back and read again: the same description */
        tc_strbuf b;
        tc_strbuf_init(&b);
        tc_json_request(&b, q, &r->opt);
        tc_request *r2 = NULL;
        tc_diags d2;
        tc_diags_init(&d2);
        CHECK(tc_request_parse(b.buf, b.len, TC_REQ_MESH, &r2, &d2) == TC_REQ_OK);
        CHECK_MSG(d2.count == 0, "written request: %s: %s", d2.count ? d2.items[0].path : "",
                  d2.count ? d2.items[0].message : "");
        if (r2) {
            const tc_mesh_desc *q2 = &r2->desc;
            CHECK(q2->nquads == 2 && !memcmp(q2->quads, q->quads, 8 * sizeof *q->quads) && q2->ntris == 0);
            CHECK(q2->ncorner_values == 1 && !memcmp(q2->corner_values, q->corner_values, 4 * sizeof(double)));
            CHECK(q2->ncorner_gradients == 1 && q2->corner_gradients_mask && q2->corner_gradients_mask[1] == 0);
            CHECK(!memcmp(q2->corner_gradients + 4, q->corner_gradients + 4, 4 * sizeof(double)));
            CHECK(q2->nmidpoints == 2 && q2->midpoint_tri[0] == 1 && q2->midpoint_tri[1] == -1);
            CHECK(q2->hessians && q2->hessians_mask && !q2->hessians_mask[1] && q2->hessians[17] == 2);
            CHECK(r2->opt.method == TC_METHOD_HERMITE && r2->opt.twist == TC_TWIST_ZERO);
        }
        tc_request_free(r2);
        tc_diags_free(&d2);
        tc_strbuf_free(&b);
    }
    tc_request_free(r);
    tc_diags_free(&d);
}

TEST(quads_request_errors) {
    PARSE_FAILS("{" QUADS_JSON ", \"values\": [1,2,3,4,5,6], \"corner_values\": [{\"triangle\": 1, \"values\": [2, 3, 6, 5]}]}",
                TC_REQ_INVALID, "corner_values[0].triangle", "this mesh is given as quads: name the quad");
    PARSE_FAILS("{" QUADS_JSON ", \"values\": [1,2,3,4,5,6], \"corner_values\": [{\"values\": [2, 3, 6, 5]}]}",
                TC_REQ_MALFORMED, "corner_values[0].quad", "missing required field 'quad' (a quad index)");
    PARSE_FAILS("{" QUADS_JSON ", \"values\": [1,2,3,4,5,6], \"corner_values\": [{\"quad\": 0, \"values\": [2, 3, 6]}]}",
                TC_REQ_MALFORMED, "corner_values[0].values", "expected an array of 4 corner values");
    PARSE_FAILS("{" QUADS_JSON ", \"values\": [1,2,3,4,5,6], \"corner_gradients\": [{\"quad\": 0, \"gradients\": [[1,2],[1,2],[1,2]]}]}",
                TC_REQ_MALFORMED, "corner_gradients[0].gradients", "expected an array of 4 corner gradients");
    PARSE_FAILS("{\"vertices\": [[0,0],[1,0],[1,1]], \"triangles\": [[0,1,2]], \"values\": [1,2,3],"
                " \"midpoints\": [{\"edge\": [0, 1], \"value\": 1, \"quad\": 0}]}",
                TC_REQ_INVALID, "midpoints[0].quad", "this mesh is given as triangles");
    PARSE_FAILS("{" QUADS_JSON ", \"values\": [1,2,3,4,5,6], \"hessians\": [[1,2], null, null, null, null, null]}",
                TC_REQ_MALFORMED, "hessians[0]", "expected an array of 3 numbers [fxx, fxy, fyy]");
    PARSE_FAILS("{" QUADS_JSON ", \"values\": [1,2,3,4,5,6], \"hessians\": [null]}", TC_REQ_INVALID, "hessians",
                "1 entries, expected 6");
    PARSE_FAILS("{" QUADS_JSON ", \"values\": [1,2,3,4,5,6], \"twist\": \"bessel\"}", TC_REQ_INVALID, "twist",
                "unknown twist 'bessel'; expected one of: estimate, zero");
    PARSE_FAILS("{" QUADS_JSON ", \"values\": [1,2,3,4,5,6], \"methods\": [{\"twist\": 0}]}", TC_REQ_MALFORMED,
                "methods[0].twist", "expected a string");
    PARSE_FAILS("{" QUADS_JSON ", \"values\": [1,2,3,4,5,6], \"quads\": [[0,1,4]]}", TC_REQ_MALFORMED, "quads",
                "given more than once");
    PARSE_FAILS("{\"vertices\": [[0,0],[1,0],[1,1],[0,1]], \"quads\": [[0,1,2]], \"values\": [1,2,3,4]}",
                TC_REQ_MALFORMED, "quads[0]", "expected an array of 4 vertex indices [a, b, c, d]");
    PARSE_FAILS("{\"vertices\": [[0,0],[1,0],[1,1],[0,1]], \"values\": [1,2,3,4]}", TC_REQ_MALFORMED, "triangles",
                "missing required field 'triangles'");
}

/* ---- scenes ---------------------------------------------------------------------- */

/* Disc and uniform scene meshes as quads: the same cells, split the same way,
 * so every triangle method gives the same answer on both; adaptive cannot. */
TEST(quads_scene_meshes) {
    tc_scene s;
    tc_scene_init(&s, TC_SCENE_PENUMBRA);
    const tc_scene_mesh_kind kinds[] = {TC_SCENE_MESH_DISC, TC_SCENE_MESH_UNIFORM};
    trng rng;
    trng_seed(&rng, tc_test_seed() + 402);
    for (int ki = 0; ki < 2; ki++) {
        tc_scene_mesh_opts o;
        tc_scene_mesh_opts_default(&o);
        o.kind = kinds[ki], o.density = 4;
        tc_scene_mesh *tm = NULL, *qm = NULL;
        CHECK(tc_scene_mesh_new(&s, &o, &tm) == TC_OK);
        o.quads = 1;
        CHECK(tc_scene_mesh_new(&s, &o, &qm) == TC_OK);
        if (!tm || !qm) {
            tc_scene_mesh_free(tm), tc_scene_mesh_free(qm);
            continue;
        }
        CHECK(qm->desc.ntris == 0 && qm->desc.nquads * 2 == tm->desc.ntris && qm->desc.tris == NULL);
        CHECK(qm->desc.nmidpoints == tm->desc.nmidpoints && qm->samples == tm->samples);
        tc_mesh *mq = mesh_ok(&qm->desc), *mt = mesh_ok(&tm->desc);
        tc_locator *L = NULL;
        if (mt) CHECK(tc_locator_new(mt, &L) == TC_OK);
        if (mq && mt && L) {
            CHECK(!memcmp(tc_mesh_triangles(mq), tc_mesh_triangles(mt), 3 * (size_t)tm->desc.ntris * sizeof(int32_t)));
            const tc_method methods[] = {TC_METHOD_CLOUGH_TOCHER, TC_METHOD_LINEAR4, TC_METHOD_CLOUGH_TOCHER_C1};
            for (int mi = 0; mi < 3; mi++) {
                tc_options opt;
                tc_options_default(&opt);
                opt.method = methods[mi], opt.tangents = TC_TANGENTS_MIDPOINTS;
                compare_method(mq, mt, L, opt, &rng);
            }
            tc_options opt;
            tc_options_default(&opt);
            opt.method = TC_METHOD_HERMITE, opt.tangents = TC_TANGENTS_MIDPOINTS;
            tc_recon *r = NULL;
            CHECK(tc_recon_new(mq, &opt, &r, NULL) == TC_OK);
            tc_recon_free(r);
        }
        tc_locator_free(L);
        tc_mesh_free(mq);
        tc_mesh_free(mt);
        tc_scene_mesh_free(tm);
        tc_scene_mesh_free(qm);
    }
    tc_scene_mesh_opts o;
    tc_scene_mesh_opts_default(&o);
    o.kind = TC_SCENE_MESH_ADAPTIVE, o.quads = 1;
    tc_scene_mesh *am = (tc_scene_mesh *)&am;
    CHECK(tc_scene_mesh_new(&s, &o, &am) == TC_EINVAL && am == NULL);
    CHECK_STR_CONTAINS(tc_scene_mesh_opts_check(&o), "hanging vertices");
}

/* Per-quad corner gradients of a scene: taken along the quad's own edges. */
TEST(quads_scene_gradients) {
    tc_scene s;
    tc_scene_init(&s, TC_SCENE_SQUARE_LIGHT);
    tc_scene_mesh_opts o;
    tc_scene_mesh_opts_default(&o);
    o.kind = TC_SCENE_MESH_UNIFORM, o.density = 4, o.gradients = 1, o.quads = 1;
    tc_scene_mesh *qm = NULL;
    CHECK(tc_scene_mesh_new(&s, &o, &qm) == TC_OK);
    if (!qm) return;
    CHECK(qm->desc.ncorner_gradients == qm->desc.nquads);
    double worst = 0, gmax = 0;
    for (int32_t i = 0; i < qm->desc.ncorner_gradients; i++)
        for (int k = 0; k < 4; k++) {
            const double *p = qm->desc.xy + 2 * qm->desc.quads[4 * qm->desc.corner_gradients_tri[i] + k];
            const double *g = qm->desc.corner_gradients + 8 * (size_t)i + 2 * k;
            double h = 1e-6, gx = (tc_scene_value(&s, p[0] + h, p[1]) - tc_scene_value(&s, p[0] - h, p[1])) / (2 * h);
            double gy = (tc_scene_value(&s, p[0], p[1] + h) - tc_scene_value(&s, p[0], p[1] - h)) / (2 * h);
            if (p[0] <= s.domain[0] || p[0] >= s.domain[2] || p[1] <= s.domain[1] || p[1] >= s.domain[3]) continue;
            worst = fmax(worst, hypot(g[0] - gx, g[1] - gy)), gmax = fmax(gmax, hypot(gx, gy));
        }
    CHECK_MSG(worst <= 1e-6 * fmax(gmax, 1), "quad corner gradients off by %.3g (max |grad| %.3g)", worst, gmax);
    tc_mesh_free(mesh_ok(&qm->desc));
    tc_scene_mesh_free(qm);
}

/* ---- through the API ------------------------------------------------------------- */

/* /v1/ordinates of a quad mesh: hermite's 22 coefficients per split triangle;
 * hermite on triangles is a 422 naming "triangles"; a quad counts as two
 * triangles against the server's limit (413 naming "quads"). */
TEST(quads_api_ordinates_and_limits) {
    const char *body = "{" QUADS_JSON ", \"values\": [1,2,3,4,5,6], \"method\": \"hermite\", \"twist\": \"zero\"}";
    tc_strbuf out;
    tc_api_result res;
    tc_strbuf_init(&out);
    tc_api_result_init(&res);
    CHECK(tc_api_ordinates(body, strlen(body), NULL, &out, &res) == 200);
    CHECK_STR_CONTAINS(out.buf, "\"method\":\"hermite\",\"twist\":\"zero\"");
    CHECK_STR_CONTAINS(out.buf, "\"labels\":[\"b00\",\"b01\"");
    CHECK_STR_CONTAINS(out.buf, "\"xd\",\"yd\"]");
    CHECK(res.triangles == 4);
    tc_api_result_free(&res);
    tc_strbuf_free(&out);

    const char *tris = "{\"vertices\": [[0,0],[1,0],[1,1]], \"triangles\": [[0,1,2]], \"values\": [1,2,3],"
                       " \"method\": \"hermite\"}";
    tc_strbuf_init(&out);
    tc_api_result_init(&res);
    CHECK(tc_api_ordinates(tris, strlen(tris), NULL, &out, &res) == 422);
    check_first(__FILE__, __LINE__, &res.diags, "triangles", "hermite needs quads");
    tc_api_result_free(&res);
    tc_strbuf_free(&out);

    tc_api_limits lim = {.max_vertices = 100, .max_triangles = 3, .max_points = 100, .max_pixels = 100, .render_threads = 1};
    tc_strbuf_init(&out);
    tc_api_result_init(&res);
    CHECK(tc_api_ordinates(body, strlen(body), &lim, &out, &res) == 413);
    check_first(__FILE__, __LINE__, &res.diags, "quads", "4 triangles (2 per quad)");
    tc_api_result_free(&res);
    tc_strbuf_free(&out);
}

/* ---- gaps found by mutation testing ------------------------------------------------------ */

/* Quad-specific refusals at their edges: an index equal to the vertex count is
 * out of range, and a first corner repeated as the last is a repeated vertex
 * (not reported as some geometric degeneracy). */
TEST(quads_validation_index_bounds_and_last_corner) {
    tc_mesh_desc d = two_quads();
    int32_t range[] = {0, 1, 6, 3, 1, 2, 5, 4};
    d.quads = range;
    FAILS(&d, "quads[0][2]", "vertex index 6 out of range (6 vertices)");
    int32_t last[] = {0, 1, 4, 0, 1, 2, 5, 4};
    d.quads = last;
    FAILS(&d, "quads[0]", "degenerate quad: a vertex appears twice in [0, 1, 4, 0]");
}

/* Errors found on the triangles a quad is split into name the quad: the second
 * half of quads[0] (triangle 1) folded onto by quads[1] across their shared
 * edge [2, 3] is "quads[0]", and a polyline along the diagonal of quads[1]
 * (triangles 2 and 3) names quads[1]. */
TEST(quads_findings_name_the_quad_of_either_half) {
    const double xy[12] = {0, 0, 1, 0, 1, 1, 0, 1, 0, 0.5, 1, 0.5};
    const int32_t quads[8] = {0, 1, 2, 3, 3, 2, 5, 4}; /* quads[1] lies on quads[0], clockwise */
    const double v[6] = {1, 2, 3, 4, 5, 6};
    tc_mesh_desc d = two_quads();
    d.xy = xy, d.quads = quads, d.values = v;
    FAILS(&d, "quads[1]", "overlaps quads[0]: both lie on the same side of their shared edge");
    d = two_quads();
    int32_t start[2] = {0, 2};
    const int32_t diag[2] = {1, 5};
    d.cm1 = (tc_polylines){1, start, diag};
    FAILS(&d, "discontinuities.c-1[0][0]", "segment [1, 5] is the diagonal of quads[1]");
}

/* An unused vertex of a quad mesh is warned about in the mesh's own words. */
TEST(quads_unused_vertex_says_quad) {
    const double xy[14] = {0, 0, 1, 0, 2, 0, 0, 1, 1, 1, 2, 1, 9, 9};
    const double v[7] = {1, 2, 3, 4, 5, 6, 7};
    tc_mesh_desc d = two_quads();
    d.nverts = 7, d.xy = xy, d.values = v;
    tc_diags dg;
    tc_diags_init(&dg);
    tc_mesh *m = NULL;
    CHECK(tc_mesh_new(&d, &m, &dg) == TC_OK && dg.errors == 0 && dg.count == 1);
    if (dg.count) {
        CHECK_MSG(!strcmp(dg.items[0].path, "vertices[6]"), "path '%s'", dg.items[0].path);
        CHECK_STR_CONTAINS(dg.items[0].message, "vertex 6 is used by no quad");
    }
    tc_mesh_free(m);
    tc_diags_free(&dg);
}
