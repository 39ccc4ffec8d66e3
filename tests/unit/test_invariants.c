/* test_invariants.c — the checkers of mesh.h's and wedge.h's invariants (invariants.c):
 * they pass on built meshes and name what a corrupted copy breaks; TC_ASSERT aborts (TC_DEBUG). */
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "check.h"
#include "core/assert.h"
#include "core/mesh.h"
#include "core/wedge.h"
#include "meshgen.h"

static void plane_f(const void *ctx, double x, double y, int ch, double *v, double g[2]) {
    (void)ctx, (void)ch;
    *v = 0.3 + 0.5 * x - 0.2 * y + 0.1 * x * y;
    g[0] = 0.5 + 0.1 * y;
    g[1] = -0.2 + 0.1 * x;
}

/* A jittered 6x6 grid with C0 lines meeting at a vertex and a C-1 line (corner
 * values jump across it): every kind of edge, overridden corners, and wedges
 * with C0 and C-1 sides. */
static tc_mesh *sample_mesh(tmesh *g) {
    trng r;
    trng_seed(&r, tc_test_seed() + 13);
    tmesh_grid(g, 6, 6, 0.2, -1, &r);
    int32_t c0[4] = {tmesh_gv(6, 1, 2), tmesh_gv(6, 2, 2), tmesh_gv(6, 3, 2), tmesh_gv(6, 4, 2)};
    int32_t branch[3] = {tmesh_gv(6, 2, 2), tmesh_gv(6, 2, 3), tmesh_gv(6, 2, 4)}; /* (2, 2): a C0 vertex */
    int32_t cm1[3] = {tmesh_gv(6, 3, 3), tmesh_gv(6, 3, 4), tmesh_gv(6, 3, 5)};
    tmesh_add_line(g, TC_C0, c0, 4);
    tmesh_add_line(g, TC_C0, branch, 3);
    tmesh_add_line(g, TC_CM1, cm1, 3);
    tmesh_sample(g, 1, plane_f, NULL, 1, 0, 0.25);
    return tmesh_build(g);
}

/* An interior edge of m whose flag is `flag`, or -1. */
static int32_t interior_edge(const struct tc_mesh *m, int flag) {
    for (int32_t e = 0; e < 3 * m->nt; e++)
        if (m->nbr[e] >= 0 && m->flag[e] == flag) return e;
    return -1;
}

TEST(invariants_hold_on_built_meshes) {
    tmesh g;
    tc_mesh *m = sample_mesh(&g);
    char why[256] = "x";
    if (m) {
        CHECK_MSG(tc__mesh_check(m, why, sizeof why) == 0, "mesh: %s", why);
        CHECK(why[0] == '\0');
        CHECK(m->nflagged > 0 && m->ncorner_overrides > 0);
        for (int honor = TC_HONOR_NONE; honor <= TC_HONOR_CM1; honor++) {
            tc__wedge_set ws;
            CHECK(tc__wedges_build(m, honor, &ws) == TC_OK);
            CHECK_MSG(tc__wedges_check(m, &ws, why, sizeof why) == 0, "wedges (honor %d): %s", honor, why);
            tc__wedges_free(&ws);
        }
    }
    tc_mesh_free(m);
    tmesh_free(&g);
}

/* Small meshes of random triangles over vertices drawn from a few coordinates, among them
 * offsets of 1e-300 and subnormals (1.1e-319) off the lines through the others, each triangle's
 * corners in random order: whatever tc_mesh_new accepts keeps every invariant of the mesh and
 * of its wedges. The fuzzer found two folded triangles, running their shared edge the same way
 * with a third vertex a subnormal off its line, accepted and linked (the wedges inconsistent:
 * a TC_ASSERT in the debug build, and in a release build whatever the wedges then gave). */
TEST(invariants_hold_on_accepted_near_degenerate_meshes) {
    static const double coord[] = {0, 1, 2, 0.5, 1e-300, 1.1e-319, -1.1e-319, 1 + 0x1p-52};
    trng r;
    trng_seed(&r, tc_test_seed() + 14);
    int accepted = 0;
    for (int it = 0; it < 4000; it++) {
        double xy[12], v[6];
        int32_t tri[15];
        int nv = 4 + trng_int(&r, 3), nt = 2 + trng_int(&r, 4);
        for (int i = 0; i < 2 * nv; i++) xy[i] = coord[trng_int(&r, 8)];
        for (int i = 0; i < nv; i++) v[i] = trng_uniform(&r);
        for (int i = 0; i < 3 * nt; i++) tri[i] = trng_int(&r, nv);
        tc_mesh_desc d;
        tc_mesh_desc_init(&d);
        d.nverts = nv, d.xy = xy, d.values = v, d.nchan = 1, d.ntris = nt, d.tris = tri;
        d.degenerate = TC_DEGENERATE_DROP;
        tc_diags dg;
        tc_diags_init(&dg);
        tc_mesh *m = NULL;
        if (tc_mesh_new(&d, &m, &dg) == TC_OK) {
            char why[256];
            accepted++;
            CHECK_MSG(tc__mesh_check(m, why, sizeof why) == 0, "mesh %d: %s", it, why);
            for (int honor = TC_HONOR_NONE; honor <= TC_HONOR_CM1; honor++) {
                tc__wedge_set ws;
                if (tc__wedges_build(m, honor, &ws) != TC_OK) continue;
                CHECK_MSG(tc__wedges_check(m, &ws, why, sizeof why) == 0, "mesh %d, wedges (honor %d): %s", it, honor,
                          why);
                tc__wedges_free(&ws);
            }
        }
        tc_mesh_free(m);
        tc_diags_free(&dg);
    }
    CHECK_MSG(accepted > 400, "only %d meshes accepted", accepted);
}

/* Each corruption goes into a copy of one array, swapped in for the check and out again. */
TEST(invariants_mesh_check_names_the_broken_invariant) {
    tmesh g;
    tc_mesh *m = sample_mesh(&g);
    char why[256];
    size_t nc = 3 * (size_t)(m ? m->nt : 0);
    int32_t e = m ? interior_edge(m, TC_C1) : -1;
    CHECK(e >= 0);
    if (!m || e < 0) {
        tc_mesh_free(m);
        tmesh_free(&g);
        return;
    }
    int32_t *nbr = malloc(nc * sizeof *nbr), *own_nbr = m->nbr;
    memcpy(nbr, m->nbr, nc * sizeof *nbr);
    nbr[e] = (m->nbr[e] + 1) % m->nt == e / 3 ? (m->nbr[e] + 2) % m->nt : (m->nbr[e] + 1) % m->nt;
    m->nbr = nbr;
    CHECK(tc__mesh_check(m, why, sizeof why) != 0);
    CHECK_STR_CONTAINS(why, "not mutual");
    CHECK(tc__mesh_check(m, NULL, 0) != 0); /* no message wanted */
    m->nbr = own_nbr;
    free(nbr);

    int8_t *flag = malloc(nc), *own_flag = m->flag;
    memcpy(flag, m->flag, nc);
    flag[e] = TC_C0; /* one side only */
    m->flag = flag;
    CHECK(tc__mesh_check(m, why, sizeof why) != 0);
    CHECK_STR_CONTAINS(why, "flags not symmetric");
    m->flag = own_flag;
    free(flag);

    double *cz = malloc(nc * sizeof *cz), *own_cz = m->cz;
    memcpy(cz, m->cz, nc * sizeof *cz);
    cz[e] += 1e-9; /* corner e is an end of edge e, which is C1 */
    m->cz = cz;
    CHECK(tc__mesh_check(m, why, sizeof why) != 0);
    CHECK_STR_CONTAINS(why, "corner values differ across the C"); /* the first C0/C1 edge at that corner */
    m->cz = own_cz;
    free(cz);

    m->max_valence++; /* the wedges and edge sides size their scratch by it */
    CHECK(tc__mesh_check(m, why, sizeof why) != 0);
    CHECK_STR_CONTAINS(why, "max_valence");
    m->max_valence--;

    double kept = m->cz_hi[0];
    m->cz_hi[0] += 1; /* the bounds and the tangent clamps read it for the corner values' range */
    CHECK(tc__mesh_check(m, why, sizeof why) != 0);
    CHECK_STR_CONTAINS(why, "kept range of channel 0");
    m->cz_hi[0] = kept;

    CHECK_MSG(tc__mesh_check(m, why, sizeof why) == 0, "restored: %s", why);
    tc_mesh_free(m);
    tmesh_free(&g);
}

TEST(invariants_wedges_check_names_the_broken_invariant) {
    tmesh g;
    tc_mesh *m = sample_mesh(&g);
    tc__wedge_set ws;
    char why[256];
    if (!m || tc__wedges_build(m, TC_HONOR_ALL, &ws) != TC_OK) {
        CHECK(0);
        tc_mesh_free(m);
        tmesh_free(&g);
        return;
    }
    size_t nc = 3 * (size_t)m->nt;
    int32_t *of = malloc(nc * sizeof *of), *own_of = ws.of_corner;
    memcpy(of, ws.of_corner, nc * sizeof *of);
    of[ws.corners[0]] = 1; /* the first corner claimed by the second wedge */
    ws.of_corner = of;
    CHECK(tc__wedges_check(m, &ws, why, sizeof why) != 0);
    CHECK_STR_CONTAINS(why, "whose of_corner is 1");
    ws.of_corner = own_of;
    free(of);

    int32_t w = -1; /* a wedge of three or more faces: swapping two breaks its fan's order */
    for (int32_t i = 0; i < ws.nw && w < 0; i++)
        if (ws.w[i].count >= 3) w = i;
    CHECK(w >= 0);
    if (w >= 0) {
        int32_t *corners = malloc(nc * sizeof *corners), *own_corners = ws.corners, f = ws.w[w].first;
        memcpy(corners, ws.corners, nc * sizeof *corners);
        corners[f] = ws.corners[f + 1], corners[f + 1] = ws.corners[f];
        ws.corners = corners;
        CHECK(tc__wedges_check(m, &ws, why, sizeof why) != 0);
        CHECK_STR_CONTAINS(why, "not counter-clockwise neighbours");
        ws.corners = own_corners;
        free(corners);
    }
    int32_t c0 = -1; /* a wedge with a C0 side: its `across` dropped */
    int side = 0;
    for (int32_t i = 0; i < ws.nw && c0 < 0; i++)
        for (int sd = 0; sd < 2 && c0 < 0; sd++)
            if (ws.w[i].across[sd] >= 0) c0 = i, side = sd;
    CHECK(c0 >= 0);
    if (c0 >= 0) {
        int32_t keep = ws.w[c0].across[side];
        ws.w[c0].across[side] = -1;
        CHECK(tc__wedges_check(m, &ws, why, sizeof why) != 0);
        CHECK_STR_CONTAINS(why, "across"); /* its own side, or a wedge before it not across back */
        ws.w[c0].across[side] = keep;
    }
    CHECK_MSG(tc__wedges_check(m, &ws, why, sizeof why) == 0, "restored: %s", why);
    tc__wedges_free(&ws);
    tc_mesh_free(m);
    tmesh_free(&g);
}

static int counted;
static int count_check(int x, char *why, size_t n) {
    (void)why, (void)n;
    counted++;
    return x;
}

#ifdef TC_DEBUG
/* In a child, the builders' TC_ASSERT_CHECK on a corrupted mesh: it must
 * abort, saying where and what. */
TEST(invariants_assert_aborts_on_a_broken_mesh) {
    int calls = 0;
    TC_ASSERT(++calls > 0);
    CHECK(calls == 1);
    TC_ASSERT_CHECK(count_check, 0);
    CHECK(counted == 1);
    tmesh g;
    tc_mesh *m = sample_mesh(&g);
    int32_t e = m ? interior_edge(m, TC_C1) : -1;
    int fd[2];
    CHECK(e >= 0 && pipe(fd) == 0);
    if (e < 0) {
        tc_mesh_free(m);
        tmesh_free(&g);
        return;
    }
    fflush(NULL);
    pid_t pid = fork();
    if (pid == 0) {
        alarm(20); /* never hang the suite */
        dup2(fd[1], 2);
        close(fd[0]);
        m->nbr[e] = -1; /* the other side still names this one */
        TC_ASSERT_CHECK(tc__mesh_check, m);
        _exit(0);
    }
    close(fd[1]);
    int status = 0;
    CHECK(pid > 0 && waitpid(pid, &status, 0) == pid);
    CHECK_MSG(WIFSIGNALED(status) && WTERMSIG(status) == SIGABRT, "child status %#x", status);
    char msg[512] = "";
    ssize_t got = read(fd[0], msg, sizeof msg - 1);
    msg[got > 0 ? got : 0] = '\0';
    close(fd[0]);
    CHECK_STR_CONTAINS(msg, "test_invariants.c:");
    CHECK_STR_CONTAINS(msg, "TC_ASSERT(tc__mesh_check(m)) failed");
    CHECK_STR_CONTAINS(msg, "boundary edge");
    tc_mesh_free(m);
    tmesh_free(&g);
}
#else
/* Release: TC_ASSERT and TC_ASSERT_CHECK are compiled out, their arguments never evaluated. */
TEST(invariants_asserts_compiled_out) {
    int calls = 0;
    TC_ASSERT(++calls > 0);
    TC_ASSERT_CHECK(count_check, 1);
    CHECK(calls == 0 && counted == 0);
}
#endif

/* An interior edge flagged twice (by two c0 polylines, one running it each
 * way) is still one flagged edge: the mesh's count of flagged interior edges
 * agrees with its flags (tc__mesh_check). */
TEST(invariants_edge_flagged_twice_counted_once) {
    static const double xy[8] = {0, 0, 1, 0, 1, 1, 0, 1};
    static const int32_t tri[6] = {0, 1, 2, 0, 2, 3};
    static const double val[4] = {1, 2, 3, 4};
    int32_t start[3] = {0, 2, 4};
    static const int32_t verts[4] = {0, 2, 2, 0};
    tc_mesh_desc d;
    tc_mesh_desc_init(&d);
    d.nverts = 4, d.xy = xy, d.ntris = 2, d.tris = tri, d.nchan = 1, d.values = val;
    d.c0 = (tc_polylines){2, start, verts};
    tc_diags dg;
    tc_diags_init(&dg);
    tc_mesh *m = NULL;
    CHECK(tc_mesh_new(&d, &m, &dg) == TC_OK);
    if (m) {
        char why[256] = "";
        CHECK(m->nflagged == 1);
        CHECK_MSG(tc__mesh_check(m, why, sizeof why) == 0, "mesh: %s", why);
    }
    tc_mesh_free(m);
    tc_diags_free(&dg);
}
