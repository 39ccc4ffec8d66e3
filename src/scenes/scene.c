/* scene.c — the reference scenes: their geometry, exact radiosity (visible-part
 * form factors) and the discontinuity events derived from the geometry. */
#include "scenes/scene.h"

#include <math.h>
#include <string.h>

#include "scenes/formfactor.h"

static const double PI = 3.14159265358979323846;

/* Where the box is clipped for occlusion. A box point at height z and
 * horizontal distance r from the receiver point projects to distance r H / z
 * from it on the light's plane, so the sliver z < BOX_CLIP only matters for
 * receiver points within about BOX_CLIP of the footprint. Even there the rays
 * that enter the sliver go on through the box above it (the box is solid), so
 * clipping changes nothing, except for rays grazing a vertical edge from
 * points within ~BOX_CLIP of a footprint corner. On the contact line itself the
 * face's vertices project exactly onto the face's line in the light plane,
 * which is what makes tc_scene_value_from exact there. */
#define BOX_CLIP 1e-9

/* The side of a C-1 line a nudged point falls on; see tc_scene_value_from. */
#define NUDGE 1e-9

typedef struct {
    const char *name, *summary;
    int point_light;
    double light[4], light_z;
    tc_occluder_kind occluder;
    double occ[4], occ_z0, occ_z1;
} scene_def;

static const scene_def defs[TC_SCENE_COUNT] = {
    [TC_SCENE_SQUARE_LIGHT] = {"square-light", "square light, side 0.5 at height 0.4, nothing in the way (smooth)",
                               0, {0.25, 0.25, 0.75, 0.75}, 0.4,
                               TC_OCCLUDER_NONE, {0, 0, 0, 0}, 0, 0},
    [TC_SCENE_PENUMBRA] = {"penumbra", "square light (side 0.3, H 1), square occluder (side 0.3, h 0.5): C0 edges",
                           0, {0.35, 0.35, 0.65, 0.65}, 1.0,
                           TC_OCCLUDER_SQUARE, {0.32, 0.37, 0.62, 0.67}, 0.5, 0.5},
    [TC_SCENE_POINT_SHADOW] = {"point-shadow", "point light at height 1, square occluder (side 0.3, h 0.5): C-1 shadow",
                               1, {0.5, 0.5, 0.5, 0.5}, 1.0,
                               TC_OCCLUDER_SQUARE, {0.35, 0.35, 0.65, 0.65}, 0.5, 0.5},
    [TC_SCENE_BOX] = {"box", "box [0.4,0.6]^2 x [0,0.15] on the receiver under a square light: C-1 contact, C0 shadow",
                      0, {0.35, 0.35, 0.65, 0.65}, 1.0,
                      TC_OCCLUDER_BOX, {0.4, 0.4, 0.6, 0.6}, 0.0, 0.15},
    [TC_SCENE_STIFF] = {"stiff", "as penumbra with the occluder at h 1e-4: penumbrae 3e-5 wide, steep slivers",
                        0, {0.35, 0.35, 0.65, 0.65}, 1.0,
                        TC_OCCLUDER_SQUARE, {0.32, 0.37, 0.62, 0.67}, 1e-4, 1e-4},
};

const char *tc_scene_name(tc_scene_id id) {
    return (int)id >= 0 && id < TC_SCENE_COUNT ? defs[id].name : NULL;
}

const char *tc_scene_summary(tc_scene_id id) {
    return (int)id >= 0 && id < TC_SCENE_COUNT ? defs[id].summary : NULL;
}

int tc_scene_parse(const char *name, tc_scene_id *out) {
    for (int i = 0; name && i < TC_SCENE_COUNT; i++)
        if (strcmp(defs[i].name, name) == 0) {
            *out = (tc_scene_id)i;
            return 0;
        }
    return -1;
}

/* ---- geometry ---------------------------------------------------------------- */

static void rect_poly(const double r[4], tc__poly *p) {
    const double v[4][2] = {{r[0], r[1]}, {r[2], r[1]}, {r[2], r[3]}, {r[0], r[3]}};
    p->n = 4;
    memcpy(p->v, v, sizeof v);
}

/* The occluder seen from (x, y, 0), projected onto the light's plane: the hull
 * of its projected vertices (a convex body between the receiver and the light
 * projects to a convex set). The box is clipped to z >= box_clip first, since
 * vertices at the receiver's height would project to infinity. */
static void occluder_shadow(const tc_scene *s, double x, double y, tc__poly *out) {
    double pts[8][2];
    int n = 0;
    double z[2] = {s->occluder == TC_OCCLUDER_BOX ? s->box_clip : s->occ_z0, s->occ_z1};
    int levels = s->occluder == TC_OCCLUDER_BOX ? 2 : 1;
    for (int l = 0; l < levels; l++)
        for (int c = 0; c < 4; c++) {
            double q[3] = {s->occ[c == 1 || c == 2 ? 2 : 0], s->occ[c >= 2 ? 3 : 1], z[l]};
            tc__project(x, y, q, s->light_z, pts[n++]);
        }
    tc__hull((const double (*)[2])pts, n, out);
}

static int in_footprint(const tc_scene *s, double x, double y) {
    return x >= s->occ[0] && x <= s->occ[2] && y >= s->occ[1] && y <= s->occ[3];
}

/* F of the light's visible part: F(light) - F(light ∩ shadow of the occluder). */
static double visible_form_factor(const tc_scene *s, double x, double y) {
    tc__poly light, shadow, hidden;
    rect_poly(s->light, &light);
    double f = tc__form_factor(&light, s->light_z, x, y);
    if (s->occluder == TC_OCCLUDER_NONE) return f;
    occluder_shadow(s, x, y, &shadow);
    tc__clip(&light, &shadow, &hidden);
    /* Fully hidden: the clip returns the light's own vertices, so f - f = 0 exactly. */
    if (hidden.n >= 3) f -= tc__form_factor(&hidden, s->light_z, x, y);
    return f > 0 ? f : 0;
}

static int point_visible(const tc_scene *s, double x, double y) {
    tc__poly shadow;
    if (s->occluder == TC_OCCLUDER_NONE) return 1;
    occluder_shadow(s, x, y, &shadow);
    return !tc__inside(&shadow, s->light[0], s->light[1]);
}

/* rho I cos(theta) / (pi r^2) with cos(theta) = H / r. */
static double point_radiosity(const tc_scene *s, double x, double y) {
    double dx = s->light[0] - x, dy = s->light[1] - y, h = s->light_z;
    double r2 = dx * dx + dy * dy + h * h;
    return s->rho * s->emit * h / (PI * r2 * sqrt(r2));
}

double tc_scene_visibility(const tc_scene *s, double x, double y) {
    if (s->point_light) return point_visible(s, x, y);
    if (s->occluder == TC_OCCLUDER_BOX && in_footprint(s, x, y)) return 0;
    return visible_form_factor(s, x, y);
}

double tc_scene_value(const tc_scene *s, double x, double y) {
    if (s->point_light) return point_visible(s, x, y) ? point_radiosity(s, x, y) : 0;
    return s->rho * s->emit * tc_scene_visibility(s, x, y);
}

double tc_scene_value_from(const tc_scene *s, double x, double y, double dx, double dy) {
    double len = hypot(dx, dy);
    if (!(len > 0) || (!s->point_light && s->occluder != TC_OCCLUDER_BOX)) return tc_scene_value(s, x, y);
    double eps = NUDGE * fmax(1, fmax(fabs(x), fabs(y))) / len;
    double qx = x + eps * dx, qy = y + eps * dy;
    if (s->point_light) return point_visible(s, qx, qy) ? point_radiosity(s, x, y) : 0;
    if (in_footprint(s, qx, qy)) return 0;
    return s->rho * s->emit * visible_form_factor(s, x, y);
}

/* ---- events ------------------------------------------------------------------ */

/* Where, seen from the receiver, an occluder edge at coordinate o and height h
 * lines up with a light edge (or the point light) at coordinate l and height H:
 * the receiver coordinate c with c + (o - c) H / h = l. */
static double shadow_line(double o, double h, double l, double H) {
    return (o * H - l * h) / (H - h);
}

/* The shadow lines along one axis (2 occluder edges x 1 or 2 light edges, at
 * height h) and their range [*lo, *hi]. Returns the count. */
static int shadow_lines(const tc_scene *s, int axis, double h, double c[4], double *lo, double *hi) {
    int n = 0, nl = s->point_light ? 1 : 2;
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < nl; j++)
            c[n++] = shadow_line(s->occ[axis + 2 * i], h, s->light[axis + 2 * j], s->light_z);
    *lo = *hi = c[0];
    for (int i = 1; i < n; i++) *lo = fmin(*lo, c[i]), *hi = fmax(*hi, c[i]);
    return n;
}

static void add_event(tc_scene *s, tc_continuity kind, int axis, double at, double lo, double hi) {
    const double *d = s->domain;
    lo = fmax(lo, d[1 - axis]);
    hi = fmin(hi, d[3 - axis]);
    if (!(at > d[axis] && at < d[axis + 2] && lo < hi)) return; /* off the domain */
    for (int i = 0; i < s->nevents; i++) {
        const tc_scene_event *e = &s->events[i];
        if (e->axis == axis && e->at == at && e->lo == lo && e->hi == hi && e->kind == kind) return;
    }
    if (s->nevents == TC_SCENE_MAX_EVENTS) return; /* the scenes need at most 16 */
    s->events[s->nevents++] = (tc_scene_event){kind, axis, at, lo, hi};
}

/* A flat occluder parallel to the light: with everything axis-aligned the
 * hidden part of the light is the rectangle light ∩ projected occluder, whose
 * sides switch between light edges and projected occluder edges exactly on the
 * shadow lines (EV and EE events coincide: the edges are parallel). Each line
 * matters where the projected occluder overlaps the light along the other
 * axis: between the extreme shadow lines of that axis (the outer penumbra).
 * A point light makes the shadow hard: the same lines are jumps. */
static void flat_occluder_events(tc_scene *s) {
    double c[2][4], lo[2], hi[2];
    int n[2];
    for (int a = 0; a < 2; a++) n[a] = shadow_lines(s, a, s->occ_z0, c[a], &lo[a], &hi[a]);
    for (int a = 0; a < 2; a++)
        for (int i = 0; i < n[a]; i++)
            add_event(s, s->point_light ? TC_CM1 : TC_C0, a, c[a][i], lo[1 - a], hi[1 - a]);
}

/* The box on the receiver:
 * - its footprint's boundary is the contact line: B jumps to 0 under the box;
 * - its top edges give shadow lines as a flat occluder at the top's height
 *   would, but only outside the footprint's range on that axis: a top edge is
 *   a silhouette edge only for receiver points on the outer side of its face;
 * - the plane of each side face meets the receiver in the contact line's
 *   prolongation. From a point on it the face is seen edge-on and projects to
 *   the fixed line x = face on the light's plane; crossing the plane swaps the
 *   silhouette (top edge + far vertical edge on one side, near vertical edge on
 *   the other), whose projections sweep the light at different rates: a kink,
 *   where that line crosses the light (light x-range contains the face) between
 *   the footprint and the outermost shadow line;
 * - each vertical edge with each light vertex gives a D2 ray from a footprint
 *   corner (a corner of the light being covered): C1, not listed. */
static void box_events(tc_scene *s) {
    double c[2][4], lo[2], hi[2];
    for (int a = 0; a < 2; a++) shadow_lines(s, a, s->occ_z1, c[a], &lo[a], &hi[a]);
    for (int a = 0; a < 2; a++) {
        int b = 1 - a;
        double f0 = s->occ[a], f1 = s->occ[a + 2];
        add_event(s, TC_CM1, a, f0, s->occ[b], s->occ[b + 2]);
        add_event(s, TC_CM1, a, f1, s->occ[b], s->occ[b + 2]);
        for (int i = 0; i < 4; i++)
            if (c[a][i] < f0 || c[a][i] > f1) add_event(s, TC_C0, a, c[a][i], lo[b], hi[b]);
        for (int k = 0; k < 2; k++) {
            double f = s->occ[a + 2 * k];
            if (!(s->light[a] < f && f < s->light[a + 2])) continue;
            add_event(s, TC_C0, a, f, lo[b], s->occ[b]);
            add_event(s, TC_C0, a, f, s->occ[b + 2], hi[b]);
        }
    }
}

int tc_scene_init(tc_scene *s, tc_scene_id id) {
    static const double unit[4] = {0, 0, 1, 1};
    return tc_scene_init_domain(s, id, unit);
}

int tc_scene_init_domain(tc_scene *s, tc_scene_id id, const double domain[4]) {
    if ((int)id < 0 || id >= TC_SCENE_COUNT || !(domain[0] < domain[2] && domain[1] < domain[3])) return TC_EINVAL;
    const scene_def *d = &defs[id];
    memset(s, 0, sizeof *s);
    s->id = id;
    memcpy(s->domain, domain, sizeof s->domain);
    s->rho = 0.8;
    s->emit = 1;
    s->point_light = d->point_light;
    memcpy(s->light, d->light, sizeof s->light);
    s->light_z = d->light_z;
    s->occluder = d->occluder;
    memcpy(s->occ, d->occ, sizeof s->occ);
    s->occ_z0 = d->occ_z0;
    s->occ_z1 = d->occ_z1;
    s->box_clip = BOX_CLIP;
    /* Without an occluder B peaks below the light's centre (a symmetric light). */
    double cx = 0.5 * (s->light[0] + s->light[2]), cy = 0.5 * (s->light[1] + s->light[3]);
    tc_scene bare = *s;
    bare.occluder = TC_OCCLUDER_NONE;
    s->scale = tc_scene_value(&bare, cx, cy);
    if (s->occluder == TC_OCCLUDER_SQUARE) flat_occluder_events(s);
    if (s->occluder == TC_OCCLUDER_BOX) box_events(s);
    return TC_OK;
}
