/* test_dm.c — the discontinuity mesher (scenes/dm.c) and the realistic surfaces: valid,
 * conforming fans; real output's triangle shapes; values exact or as printed; the flags. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "scenes/meshing.h"
#include "scenes/scene.h"
#include "scenes/surfaces.h"

static const double PI = 3.14159265358979323846;

static tc_scene_mesh *dm_mesh(const tc_scene *s, const tc_scene_mesh_opts *o) {
    tc_scene_mesh *m = NULL;
    int st = tc_scene_mesh_new(s, o, &m);
    CHECK_MSG(st == TC_OK && m, "%s dm N=%d rotation %g: status %d", tc_scene_name(s->id), o->density, o->rotation, st);
    return m;
}

static tc_scene_mesh *surface_mesh(const tc_dm_surface *f, int no_c0, tc_scene *s) {
    tc_scene_mesh_opts o;
    CHECK(tc_dm_surface_setup(f, no_c0, s, &o) == TC_OK);
    return dm_mesh(s, &o);
}

static tc_mesh *core_mesh(const tc_scene_mesh *m) {
    tc_mesh *cm = NULL;
    tc_diags dg;
    tc_diags_init(&dg);
    int st = tc_mesh_new(&m->desc, &cm, &dg);
    CHECK_MSG(st == TC_OK, "tc_mesh_new: %s: %s", dg.count ? dg.items[0].path : "", dg.count ? dg.items[0].message : "");
    tc_diags_free(&dg);
    return cm;
}

static const double *vxy(const tc_scene_mesh *m, int32_t t, int k) { return m->desc.xy + 2 * m->desc.tris[3 * t + k]; }

/* ---- validity ---------------------------------------------------------------------- */

/* A mesh of the rectangle d: counter-clockwise triangles that tile it (areas sum
 * to its area) with no T-vertices (every edge with one triangle lies on d's
 * boundary, exactly: the mesher snaps turned vertices back onto the sides). */
static void check_tiles(const tc_scene_mesh *m, const tc_mesh *cm, const double d[4], const char *what) {
    double area = 0;
    int cw = 0, stray = 0;
    for (int32_t t = 0; t < m->desc.ntris; t++) {
        const double *a = vxy(m, t, 0), *b = vxy(m, t, 1), *c = vxy(m, t, 2);
        double a2 = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        cw += !(a2 > 0);
        area += a2 / 2;
        for (int k = 0; k < 3; k++) {
            int nk;
            if (tc_mesh_neighbor(cm, t, k, &nk) >= 0) continue;
            const double *p = vxy(m, t, k), *q = vxy(m, t, (k + 1) % 3);
            int on = (p[0] == q[0] && (p[0] == d[0] || p[0] == d[2])) || (p[1] == q[1] && (p[1] == d[1] || p[1] == d[3]));
            stray += !on;
        }
    }
    double want = (d[2] - d[0]) * (d[3] - d[1]);
    CHECK_MSG(cw == 0 && stray == 0 && fabs(area - want) <= 1e-12 * want,
              "%s: %d clockwise triangles, %d boundary edges inside (T-vertices), area %.17g of %.17g", what, cw, stray,
              area, want);
}

static void check_valid(const tc_scene *s, const tc_scene_mesh *m, const char *what) {
    tc_mesh *cm = m ? core_mesh(m) : NULL;
    if (!cm) return;
    check_tiles(m, cm, s->domain, what);
    tc_options o;
    tc_options_default(&o);
    tc_recon *r = NULL;
    CHECK_MSG(tc_recon_new(cm, &o, &r, NULL) == TC_OK, "%s: the default reconstruction fails", what);
    tc_recon_free(r);
    tc_mesh_free(cm);
}

/* Every scene, at several densities and angles (0, odd, a quarter turn, negative). */
TEST(dm_every_scene_meshes_validly) {
    const int dens[] = {1, 4, 16};
    const double rot[] = {0, 17, 90, -45};
    for (int id = 0; id < TC_SCENE_COUNT; id++)
        for (int d = 0; d < 3; d++)
            for (int r = 0; r < 4; r++) {
                tc_scene s;
                tc_scene_mesh_opts o;
                tc_scene_init(&s, (tc_scene_id)id);
                tc_scene_mesh_opts_default(&o);
                o.kind = TC_SCENE_MESH_DM, o.density = dens[d], o.rotation = rot[r], o.gradients = d == 1;
                tc_scene_mesh *m = dm_mesh(&s, &o);
                char what[96];
                snprintf(what, sizeof what, "%s dm N=%d rotation %g", tc_scene_name(s.id), dens[d], rot[r]);
                check_valid(&s, m, what);
                tc_scene_mesh_free(m);
            }
}

TEST(dm_every_surface_meshes_validly) {
    for (int i = 0; i < tc_dm_surface_count(); i++)
        for (int no_c0 = 0; no_c0 < 2; no_c0++) {
            const tc_dm_surface *f = tc_dm_surface_get(i);
            tc_scene s;
            tc_scene_mesh *m = surface_mesh(f, no_c0, &s);
            char what[96];
            snprintf(what, sizeof what, "surface %s%s", f->name, no_c0 ? " (no C0)" : "");
            check_valid(&s, m, what);
            tc_scene_mesh_free(m);
        }
    CHECK(tc_dm_surface_get(-1) == NULL && tc_dm_surface_get(tc_dm_surface_count()) == NULL);
}

TEST(dm_options_are_checked) {
    tc_scene_mesh_opts o;
    tc_scene_mesh_opts_default(&o);
    CHECK(tc_scene_mesh_opts_check(&o) == NULL && o.no_c0 == 0 && o.digits == 0 && o.rotation == 0);
    o.rotation = 10;
    CHECK_STR_CONTAINS(tc_scene_mesh_opts_check(&o), "only dm");
    o.kind = TC_SCENE_MESH_DM;
    CHECK(tc_scene_mesh_opts_check(&o) == NULL);
    o.quads = 1;
    CHECK_STR_CONTAINS(tc_scene_mesh_opts_check(&o), "not quads");
    o.quads = 0, o.digits = 18;
    CHECK_STR_CONTAINS(tc_scene_mesh_opts_check(&o), "digits");
    o.digits = 6, o.rotation = NAN;
    CHECK_STR_CONTAINS(tc_scene_mesh_opts_check(&o), "rotation");
    tc_scene_mesh_kind k;
    CHECK(tc_scene_mesh_kind_parse("dm", &k) == 0 && k == TC_SCENE_MESH_DM && !strcmp(tc_scene_mesh_kind_name(k), "dm"));
    tc_scene s;
    const double bad[4] = {0, 0, 0, 1};
    CHECK(tc_scene_init_domain(&s, TC_SCENE_STIFF, bad) == TC_EINVAL);
}

/* ---- shapes ------------------------------------------------------------------------ */

/* Triangles of the kind real output overshoots on: aspect 470-825 with a
 * largest angle of 116-149 degrees (taken a little wider). */
static int real_kind(double aspect, double angle) { return aspect >= 300 && aspect <= 1500 && angle >= 110 && angle <= 155; }

typedef struct {
    int32_t tris, real_kind, max_fan;
    double worst_aspect, angle_of_worst, largest_angle;
} shape_stats;

static shape_stats shapes(const tc_scene_mesh *m) {
    shape_stats st = {m->desc.ntris, 0, 0, m->worst_aspect, m->worst_aspect_angle, m->largest_angle};
    int32_t *uses = calloc((size_t)m->desc.nverts, sizeof *uses);
    for (int32_t t = 0; t < m->desc.ntris; t++) {
        const double *a = vxy(m, t, 0), *b = vxy(m, t, 1), *c = vxy(m, t, 2);
        st.real_kind += real_kind(tc_scene_triangle_aspect(a, b, c), tc_scene_triangle_largest_angle(a, b, c));
        for (int k = 0; uses && k < 3; k++) uses[m->desc.tris[3 * t + k]]++;
    }
    for (int32_t v = 0; uses && v < m->desc.nverts; v++) st.max_fan = uses[v] > st.max_fan ? uses[v] : st.max_fan;
    free(uses);
    return st;
}

/* The patches on the stiff shadow have real output's shapes: their worst
 * triangles are long and obtuse as real ones are, and nothing is far beyond
 * (no 1e5 slivers). The whole scenes are printed: hundreds of triangles,
 * fans, and the stiff scene's 3e-5 strips, which make slivers of aspect 1e5. */
TEST(dm_surfaces_have_real_shapes) {
    for (int i = 0; i < tc_dm_surface_count(); i++) {
        const tc_dm_surface *f = tc_dm_surface_get(i);
        tc_scene s;
        tc_scene_mesh *m = surface_mesh(f, 1, &s);
        if (!m) continue;
        shape_stats st = shapes(m);
        printf("  [dm shapes] %-16s %4d triangles, worst aspect %7.4g (its largest angle %5.1f), largest angle %5.1f, "
               "%2d of the real kind, up to %2d triangles at a vertex\n",
               f->name, st.tris, st.worst_aspect, st.angle_of_worst, st.largest_angle, st.real_kind, st.max_fan);
        if (!strncmp(f->name, "stiff-", 6))
            CHECK_MSG(st.real_kind >= 1 && st.worst_aspect >= 400 && st.worst_aspect <= 1500 && st.largest_angle < 170,
                      "%s: %d triangles of the real kind, worst aspect %.4g, largest angle %.1f", f->name, st.real_kind,
                      st.worst_aspect, st.largest_angle);
        if (f->window[2] - f->window[0] == 1) /* the whole scenes: fans over hundreds of triangles */
            CHECK_MSG(st.tris >= 100 && st.max_fan >= 16, "%s: %d triangles, fans of %d", f->name, st.tris, st.max_fan);
        tc_scene_mesh_free(m);
    }
}

/* Edge p-q lies on event e's segment. */
static int on_event(const tc_scene_event *e, const double *p, const double *q) {
    return p[e->axis] == e->at && q[e->axis] == e->at && fmin(p[1 - e->axis], q[1 - e->axis]) >= e->lo &&
           fmax(p[1 - e->axis], q[1 - e->axis]) <= e->hi;
}

/* Mesh edges on the lines of s's events that lie on no event: prolongations. */
static int prolongations(const tc_scene *s, const tc_scene_mesh *m) {
    int n = 0;
    for (int32_t t = 0; t < m->desc.ntris; t++)
        for (int k = 0; k < 3; k++) {
            const double *p = vxy(m, t, k), *q = vxy(m, t, (k + 1) % 3);
            int on_line = 0, on_any = 0;
            for (int i = 0; i < s->nevents; i++) {
                const tc_scene_event *e = &s->events[i];
                on_line |= p[e->axis] == e->at && q[e->axis] == e->at;
                on_any |= on_event(e, p, q);
            }
            n += on_line && !on_any;
        }
    return n;
}

/* Not prolonged across the receiver: the disc mesher draws every event's line
 * from side to side (a grid); dm only prolongs an edge from a reflex corner to
 * the first edge it meets, so it has fewer vertices and fewer edges on the
 * events' lines beyond the events. */
TEST(dm_events_are_not_prolonged_across_the_receiver) {
    for (int id = 0; id < TC_SCENE_COUNT; id++) {
        tc_scene s;
        tc_scene_mesh_opts o;
        tc_scene_init(&s, (tc_scene_id)id);
        if (s.nevents == 0) continue;
        tc_scene_mesh_opts_default(&o);
        o.density = 1;
        tc_scene_mesh *disc = dm_mesh(&s, &o);
        o.kind = TC_SCENE_MESH_DM;
        tc_scene_mesh *dm = dm_mesh(&s, &o);
        if (!disc || !dm) continue;
        int pd = prolongations(&s, disc), pm = prolongations(&s, dm);
        CHECK_MSG(dm->desc.nverts < disc->desc.nverts && pm < pd,
                  "%s: dm %d vertices, %d prolongation edges; disc %d, %d", tc_scene_name(s.id), dm->desc.nverts, pm,
                  disc->desc.nverts, pd);
        tc_scene_mesh_free(disc);
        tc_scene_mesh_free(dm);
    }
}

/* Turned scenes: flagged edges that are not axis-parallel. */
TEST(dm_rotation_turns_the_events) {
    tc_scene s;
    tc_scene_mesh_opts o;
    tc_scene_init(&s, TC_SCENE_PENUMBRA);
    tc_scene_mesh_opts_default(&o);
    o.kind = TC_SCENE_MESH_DM, o.rotation = 30;
    tc_scene_mesh *m = dm_mesh(&s, &o);
    int oblique = 0;
    for (int32_t l = 0; m && l < m->desc.c0.count; l++)
        for (int32_t i = m->desc.c0.start[l]; i + 1 < m->desc.c0.start[l + 1]; i++) {
            const double *p = m->desc.xy + 2 * m->desc.c0.verts[i], *q = m->desc.xy + 2 * m->desc.c0.verts[i + 1];
            double a = fmod(atan2(q[1] - p[1], q[0] - p[0]) * 180 / PI + 360, 90);
            oblique += fabs(a - 30) < 1e-9 || fabs(a - 60) < 1e-9 ? 1 : 0;
        }
    CHECK_MSG(oblique > 0 && m && m->flagged_c0 > 0, "%d C0 edges at 30 or 120 degrees", oblique);
    tc_scene_mesh_free(m);
}

/* ---- values and flags ---------------------------------------------------------------- */

/* Mesh point p of a mesh turned by `rotation` about the centre of s's domain,
 * in the scene's frame. */
static void scene_point(const tc_scene *s, double rotation, const double p[2], double q[2]) {
    double c = cos(rotation * PI / 180), sn = sin(rotation * PI / 180);
    double o[2] = {0.5 * (s->domain[0] + s->domain[2]), 0.5 * (s->domain[1] + s->domain[3])};
    double x = p[0] - o[0], y = p[1] - o[1];
    q[0] = o[0] + c * x + sn * y;
    q[1] = o[1] - sn * x + c * y;
}

/* B at q, or its limit from one of 8 directions (a vertex on a C-1 line,
 * turned off it by rounding, may have its value from the other side). */
static double nearest_side(const tc_scene *s, const double q[2], double v) {
    double best = tc_scene_value(s, q[0], q[1]);
    for (int k = 0; k < 8; k++) {
        double z = tc_scene_value_from(s, q[0], q[1], cos(k * PI / 4), sin(k * PI / 4));
        if (fabs(z - v) < fabs(best - v)) best = z;
    }
    return best;
}

/* The vertex values are B at the vertices: exactly on unturned meshes, to
 * rounding of the turn on turned ones. */
TEST(dm_values_are_the_scenes) {
    const double rot[] = {0, 30};
    for (int id = 0; id < TC_SCENE_COUNT; id++)
        for (int r = 0; r < 2; r++) {
            tc_scene s;
            tc_scene_mesh_opts o;
            tc_scene_init(&s, (tc_scene_id)id);
            tc_scene_mesh_opts_default(&o);
            o.kind = TC_SCENE_MESH_DM, o.rotation = rot[r];
            tc_scene_mesh *m = dm_mesh(&s, &o);
            double worst = 0;
            for (int32_t v = 0; m && v < m->desc.nverts; v++) {
                const double *p = m->desc.xy + 2 * v;
                double q[2] = {p[0], p[1]}, z = m->desc.values[v];
                if (rot[r] != 0) scene_point(&s, rot[r], p, q);
                worst = fmax(worst, fabs(z - (rot[r] != 0 ? nearest_side(&s, q, z) : tc_scene_value(&s, q[0], q[1]))));
            }
            CHECK_MSG(r ? worst <= 1e-9 * s.scale : worst == 0, "%s rotation %g: values differ from B by %.3g",
                      tc_scene_name(s.id), rot[r], worst);
            tc_scene_mesh_free(m);
        }
}

/* v has at most `digits` significant digits. */
static int printed_to(double v, int digits) {
    char buf[40];
    snprintf(buf, sizeof buf, "%.*e", digits - 1, v);
    return strtod(buf, NULL) == v;
}

/* digits 6: every value (vertex, corner, midpoint) as printed with 6
 * significant digits, and within half a unit of the 6th digit of the exact one. */
TEST(dm_values_rounded_to_6_digits) {
    const tc_scene_id ids[] = {TC_SCENE_PENUMBRA, TC_SCENE_POINT_SHADOW, TC_SCENE_BOX};
    for (int i = 0; i < 3; i++) {
        tc_scene s;
        tc_scene_mesh_opts o;
        tc_scene_init(&s, ids[i]);
        tc_scene_mesh_opts_default(&o);
        o.kind = TC_SCENE_MESH_DM, o.density = 4;
        tc_scene_mesh *exact = dm_mesh(&s, &o);
        o.digits = 6;
        tc_scene_mesh *m = dm_mesh(&s, &o);
        if (!exact || !m) continue;
        const tc_mesh_desc *d = &m->desc, *e = &exact->desc;
        int bad = 0, changed = 0;
        CHECK(d->nverts == e->nverts && d->ncorner_values == e->ncorner_values && d->nmidpoints == e->nmidpoints);
        for (int32_t v = 0; v < d->nverts; v++) {
            bad += !printed_to(d->values[v], 6) || fabs(d->values[v] - e->values[v]) > 5.000001e-6 * fabs(e->values[v]);
            changed += d->values[v] != e->values[v];
        }
        for (int32_t j = 0; j < 3 * d->ncorner_values; j++) bad += !printed_to(d->corner_values[j], 6);
        for (int32_t j = 0; j < d->nmidpoints; j++) bad += !printed_to(d->midpoint_values[j], 6);
        CHECK_MSG(bad == 0 && changed > 0, "%s: %d values not as printed to 6 digits (%d changed)", tc_scene_name(ids[i]),
                  bad, changed);
        tc_scene_mesh_free(exact);
        tc_scene_mesh_free(m);
    }
}

/* no_c0: the same mesh, the C0 events left unflagged, the C-1 ones kept. */
TEST(dm_no_c0_leaves_only_the_jumps) {
    const tc_scene_id ids[] = {TC_SCENE_PENUMBRA, TC_SCENE_BOX, TC_SCENE_STIFF};
    for (int i = 0; i < 3; i++) {
        tc_scene s;
        tc_scene_mesh_opts o;
        tc_scene_init(&s, ids[i]);
        tc_scene_mesh_opts_default(&o);
        o.kind = TC_SCENE_MESH_DM, o.rotation = 20;
        tc_scene_mesh *with = dm_mesh(&s, &o);
        o.no_c0 = 1;
        tc_scene_mesh *without = dm_mesh(&s, &o);
        if (!with || !without) continue;
        const tc_mesh_desc *a = &with->desc, *b = &without->desc;
        int same = a->nverts == b->nverts && a->ntris == b->ntris &&
                   !memcmp(a->xy, b->xy, 2 * (size_t)a->nverts * sizeof *a->xy) &&
                   !memcmp(a->tris, b->tris, 3 * (size_t)a->ntris * sizeof *a->tris);
        CHECK_MSG(same && with->flagged_c0 > 0 && a->c0.count > 0, "%s: meshes differ or nothing flagged C0",
                  tc_scene_name(ids[i]));
        CHECK_MSG(without->flagged_c0 == 0 && b->c0.count == 0 && without->flagged_cm1 == with->flagged_cm1 &&
                      b->cm1.count == a->cm1.count,
                  "%s: no_c0 keeps %d C0 edges, %d of %d C-1 edges", tc_scene_name(ids[i]), without->flagged_c0,
                  without->flagged_cm1, with->flagged_cm1);
        tc_scene_mesh_free(with);
        tc_scene_mesh_free(without);
    }
}

/* Where the data jumps (the hard shadow, the box's contact line) the
 * triangles on each side carry their side's values at the shared corners:
 * across every interior C-1 edge the corner values differ by the jump. */
TEST(dm_jumps_carry_per_corner_values) {
    const tc_scene_id ids[] = {TC_SCENE_POINT_SHADOW, TC_SCENE_BOX};
    for (int i = 0; i < 2; i++) {
        tc_scene s;
        tc_scene_mesh_opts o;
        tc_scene_init(&s, ids[i]);
        tc_scene_mesh_opts_default(&o);
        o.kind = TC_SCENE_MESH_DM, o.rotation = 30, o.digits = 6;
        tc_scene_mesh *m = dm_mesh(&s, &o);
        tc_mesh *cm = m ? core_mesh(m) : NULL;
        int edges = 0, flat = 0;
        double smallest = INFINITY;
        for (int32_t t = 0; cm && t < m->desc.ntris; t++)
            for (int k = 0; k < 3; k++) {
                int nk;
                int32_t t2 = tc_mesh_neighbor(cm, t, k, &nk);
                if (t2 < t || tc_mesh_edge_flag(cm, t, k) != TC_CM1) continue;
                /* corner k of t is corner (nk + 1) % 3 of t2: the edge runs the other way there */
                double jump = fabs(tc_mesh_corner_value(cm, t, k)[0] - tc_mesh_corner_value(cm, t2, (nk + 1) % 3)[0]);
                smallest = fmin(smallest, jump / s.scale);
                flat += jump < 0.01 * s.scale;
                edges++;
            }
        CHECK_MSG(edges > 0 && m->desc.ncorner_values > 0 && flat == 0,
                  "%s: %d C-1 edges, %d corner-value entries, %d without a jump", tc_scene_name(ids[i]), edges,
                  m ? m->desc.ncorner_values : 0, flat);
        printf("  [dm jumps] %-12s %d interior C-1 edges, smallest corner jump %.3g x scale\n", tc_scene_name(ids[i]),
               edges, smallest);
        tc_mesh_free(cm);
        tc_scene_mesh_free(m);
    }
}
