/* tocher.h — public API of the tocher reconstruction core.
 * Clough-Tocher C1 cubic reconstruction of illumination functions on planar
 * triangulations, keeping the C0 / C-1 discontinuities the caller flags
 * (Salesin, Lischinski & DeRose 1992), plus the baselines it is measured against.
 *
 * Life cycle: describe a mesh (tc_mesh_desc, caller-owned arrays) -> tc_mesh_new
 * copies and validates it and builds its topology -> tc_recon_new computes one
 * reconstruction (ordinates) of that mesh -> tc_locator_new indexes the mesh for
 * point queries -> tc_eval_points / tc_eval_triangle evaluate.
 * A tc_mesh must outlive every tc_recon and tc_locator made from it.
 * All objects are immutable once built, so any number of threads may evaluate
 * the same reconstruction at once. Every _free(NULL) is a no-op.
 */
#ifndef TOCHER_H
#define TOCHER_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define TC_VERSION "0.1.0"
#define TC_MAX_CHANNELS 16
#define TC_CT_ORDINATES 19 /* Bézier ordinates per triangle and channel */

/* ---- status and diagnostics ------------------------------------------------ */

typedef enum {
    TC_OK = 0,
    TC_EINVAL = 1, /* the input failed validation; the diagnostics say where */
    TC_ENOMEM = 2, /* an allocation failed */
    TC_ELIMIT = 3,  /* the input is larger than this build can index */
    TC_ETIMEOUT = 4 /* the deadline passed before the work was done */
} tc_status;

typedef enum { TC_SEV_ERROR = 0, TC_SEV_WARNING = 1 } tc_severity;

/* One finding about the input. `path` is the JSON path of the offending element
 * in the JSON request format (README.md, api/openapi.yaml: "triangles[5]", "discontinuities.c0[2][3]"),
 * so a caller that built the description from JSON can report it verbatim. */
typedef struct {
    tc_severity severity;
    char path[96];
    char message[224];
} tc_diag;

/* A bounded list of findings. Keeps the first TC_DIAGS_KEEP; counts the rest. */
#define TC_DIAGS_KEEP 64
typedef struct {
    tc_diag *items;
    int count;     /* entries kept in items */
    int errors;    /* all errors seen, kept or not */
    int warnings;  /* all warnings seen, kept or not */
} tc_diags;

void tc_diags_init(tc_diags *d);
void tc_diags_free(tc_diags *d);
void tc_diags_clear(tc_diags *d);
/* printf-style; path may be NULL. Returns TC_EINVAL for errors, TC_OK for warnings. */
int tc_diags_add(tc_diags *d, tc_severity sev, const char *path, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;

/* ---- the mesh description (as in the JSON request) ------------------------ */

/* A set of polylines over vertex indices; polyline i is
 * verts[start[i] .. start[i+1]), and each consecutive pair must be a mesh edge. */
typedef struct {
    int32_t count;
    const int32_t *start; /* [count + 1] */
    const int32_t *verts;
} tc_polylines;

/* What tc_mesh_new does with a zero-area or repeated-vertex triangle ([3, 3, 5]). */
typedef enum {
    TC_DEGENERATE_REFUSE = 0, /* an error naming it */
    TC_DEGENERATE_DROP        /* left out before the topology is built, with one warning
                               * listing them; the other triangles keep their index as given
                               * (tc_mesh_triangle_of_given). Non-manifold edges and overlaps
                               * stay errors. No effect on a quad mesh: a degenerate quad is
                               * refused (dropping it would cut a hole in the patch grid). */
} tc_degenerate;

/* Everything a front-end sends. All arrays are caller-owned and only read during
 * tc_mesh_new. Optional arrays are NULL (and their counts 0) when absent.
 * "C" below is nchan; per-corner data follows the triangle's vertex order as given.
 *
 * Quad meshes: give nquads/quads instead of ntris/tris (both at once is an
 * error). Quad q = (a, b, c, d) becomes triangles 2q = (a, b, c) and
 * 2q+1 = (a, c, d), split along the diagonal a-c, so every triangle method
 * runs on it unchanged. On a quad mesh the per-corner entries name quads, not
 * triangles: corner_values_tri[i] and corner_gradients_tri[i] are quad indices
 * with corner_values [n][4][C], corner_gradients [n][4][C][2] and
 * corner_gradients_mask [n][4] in the quad's corner order, and midpoint_tri[i]
 * names the quad whose side the sample belongs to. Midpoint samples may lie on
 * a diagonal (the triangle methods use them there); discontinuity polylines may
 * not (the diagonal is not an edge of the quad mesh). */
typedef struct {
    int32_t nverts;
    const double *xy;             /* [nverts][2] */
    int32_t ntris;
    const int32_t *tris;          /* [ntris][3], either orientation */
    int32_t nquads;               /* instead of triangles: quads, corners in order */
    const int32_t *quads;         /*   around each (either orientation), [nquads][4] */
    int32_t nchan;                /* 1 .. TC_MAX_CHANNELS */
    const double *values;         /* [nverts][C] */

    int32_t ncorner_values;       /* per-corner value overrides (C-1 edges) */
    const int32_t *corner_values_tri;   /* [n] triangle (quad on a quad mesh) */
    const double *corner_values;        /* [n][3][C] ([n][4][C] on a quad mesh) */

    const double *gradients;      /* [nverts][C][2] or NULL */
    const uint8_t *gradients_mask;/* [nverts], 0 = not given; NULL = all given */
    const double *normals;        /* [nverts][C][3], N.z > 0, or NULL */
    const uint8_t *normals_mask;  /* [nverts] or NULL */
    const double *hessians;       /* [nverts][C][3] (fxx, fxy, fyy), or NULL: Hermite twists */
    const uint8_t *hessians_mask; /* [nverts] or NULL */

    int32_t ncorner_gradients;
    const int32_t *corner_gradients_tri; /* [n] triangle (quad on a quad mesh) */
    const double *corner_gradients;      /* [n][3][C][2] ([n][4][C][2] on a quad mesh) */
    const uint8_t *corner_gradients_mask;/* [n][3] ([n][4]), 0 = corner not given; NULL = all */

    int32_t nmidpoints;           /* extra samples at edge midpoints */
    const int32_t *midpoint_edge; /* [n][2] vertex indices */
    const int32_t *midpoint_tri;  /* [n]: the side it belongs to (a triangle, or a quad on a
                                   * quad mesh), -1 = both; NULL = all -1 */
    const double *midpoint_values;/* [n][C] */

    tc_polylines c0;              /* derivative discontinuities (kinks) */
    tc_polylines cm1;             /* value discontinuities (jumps) */

    /* How closely values that must agree have to agree: corner values at a
     * vertex joined through C0/C1 edges (not parted by C-1 edges or the
     * boundary), and midpoint samples given for both sides of a C0/C1 edge.
     * Relative to the channel's scale, the largest |corner value| of that
     * channel over the mesh. Differences within it are averaged away (the
     * reconstruction is then exactly continuous there; a warning says how many
     * vertices and the largest difference), beyond it the mesh is refused
     * naming the edge. Below 1e-12 (0 in a zero-filled description) it is
     * 1e-12: rounding only. tc_mesh_desc_init sets TC_VALUE_TOLERANCE_DEFAULT. */
    double value_tolerance;
    tc_degenerate degenerate;
    /* Threads tc_mesh_new may use for its per-vertex and per-triangle checks;
     * <= 1 checks on the caller's thread. The mesh and every finding (their
     * order included) are the same whatever the count. */
    int threads;
} tc_mesh_desc;

/* The default value_tolerance: printing to 6 significant digits (differences
 * up to 1e-5 of the scale) passes; far below one 8-bit grey level. */
#define TC_VALUE_TOLERANCE_DEFAULT 1e-4

/* Zero-fills d and sets the defaults a front-end wants (value_tolerance).
 * A description only zero-filled keeps the strictest checks instead. */
void tc_mesh_desc_init(tc_mesh_desc *d);

/* ---- the mesh ------------------------------------------------------------ */

typedef struct tc_mesh tc_mesh;

/* Copies, validates and builds the topology of a mesh. On TC_EINVAL *out is NULL
 * and diags holds the errors (each naming the element); warnings may be added on
 * success too. diags may be NULL. */
int tc_mesh_new(const tc_mesh_desc *desc, tc_mesh **out, tc_diags *diags);
void tc_mesh_free(tc_mesh *m);

int32_t tc_mesh_vertex_count(const tc_mesh *m);
/* On a quad mesh: 2 x the quad count (the split triangles, see tc_mesh_desc).
 * Without the triangles dropped as degenerate: every per-triangle array of
 * the core (tc_mesh_triangles, tc_recon_coefs, owners) counts these. */
int32_t tc_mesh_triangle_count(const tc_mesh *m);
/* Triangles as given, dropped ones included (tc_mesh_triangle_count when none
 * was dropped), the triangle of given index i (-1 if it was dropped), and the
 * given index of triangle t. */
int32_t tc_mesh_given_triangle_count(const tc_mesh *m);
int32_t tc_mesh_triangle_of_given(const tc_mesh *m, int32_t i);
int32_t tc_mesh_given_triangle(const tc_mesh *m, int32_t t);
/* The quads as given ([count][4]); 0 and NULL for a mesh given as triangles.
 * Quad q is triangles 2q and 2q+1 of tc_mesh_triangles. */
int32_t tc_mesh_quad_count(const tc_mesh *m);
const int32_t *tc_mesh_quads(const tc_mesh *m);
int tc_mesh_channel_count(const tc_mesh *m);
const double *tc_mesh_xy(const tc_mesh *m);        /* [nverts][2] */
const int32_t *tc_mesh_triangles(const tc_mesh *m);/* [ntris][3] as given */
/* Value of corner k of triangle t (vertex value unless overridden): [C]. */
const double *tc_mesh_corner_value(const tc_mesh *m, int32_t t, int k);

/* Edge k of a triangle joins its corners k and (k+1)%3. */
typedef enum { TC_CM1 = -1, TC_C0 = 0, TC_C1 = 1 } tc_continuity;
/* The continuity flag of an edge; mesh-boundary edges report TC_CM1. */
tc_continuity tc_mesh_edge_flag(const tc_mesh *m, int32_t t, int k);
/* The triangle across edge k (-1 on the boundary); *nk receives its edge index. */
int32_t tc_mesh_neighbor(const tc_mesh *m, int32_t t, int k, int *nk);

/* ---- reconstructions ----------------------------------------------------- */

typedef enum {
    TC_METHOD_CLOUGH_TOCHER = 0, /* cubic, C1 except where flagged (the paper) */
    TC_METHOD_CLOUGH_TOCHER_C1,  /* cubic, C1 everywhere: flags ignored */
    TC_METHOD_LINEAR,            /* piecewise linear on the mesh (Gouraud) */
    TC_METHOD_LINEAR4,           /* linear on the 4-split through the midpoint samples */
    TC_METHOD_CONSTANT,          /* one value per triangle: the corner mean */
    TC_METHOD_POWELL_SABIN,      /* C1 quadratic on the 6-split (incenter); C-1 cuts, C0 not honoured */
    TC_METHOD_HERMITE,           /* bicubic Hermite patches over quads (bilinear map) */
    TC_METHOD_COUNT              /* not a method: how many there are (tc_method_count()) */
} tc_method;

typedef enum {
    TC_CROSS_NORMAL = 0, /* derivative normal to the edge linear (reduced HCT) */
    TC_CROSS_SALESIN,    /* the paper's averaged, projected normal */
    TC_CROSS_AFFINE      /* derivative towards the neighbour's centroid linear (scipy) */
} tc_cross;

typedef enum {
    TC_WEDGES_CORRECTED = 0, /* Figure 6 with both its defects fixed (src/core/wedgeplane.c) */
    TC_WEDGES_LITERAL        /* Figure 6 as printed */
} tc_wedges;

typedef enum {
    TC_TANGENTS_AUTO = 0, /* per corner: given, else midpoints, else estimate */
    TC_TANGENTS_GIVEN,    /* every corner must have a gradient or normal */
    TC_TANGENTS_MIDPOINTS,/* every edge must have a midpoint sample */
    TC_TANGENTS_ESTIMATE  /* least squares within each wedge, inputs ignored */
} tc_tangents;

/* Hermite patches: the cross derivative f_st = x_s' H x_t + g . x_st at each
 * quad corner (x the quad's bilinear map, g the corner's tangent plane) when the
 * request gives no second derivatives H ("hessians", which always win). */
typedef enum {
    TC_TWIST_ESTIMATE = 0, /* H per wedge from the neighbouring corners' tangent planes
                            * (least squares; limited where the mesh does not resolve it) */
    TC_TWIST_ZERO          /* H = 0: f_st = g . x_st, zero on parallelograms */
} tc_twist;

/* How a wedge's faces' planes are averaged into one (Figure 6 step 1, and the
 * coupling of two wedges across a C0 edge). */
typedef enum {
    TC_AVERAGE_AREA = 0, /* area-weighted mean of the gradients: linear in the data,
                          * slivers cannot tilt it */
    TC_AVERAGE_NORMALS   /* the paper's normalized sum of unit normals (always with
                          * wedges "literal") */
} tc_average;

/* How far the cubic and quadratic methods may leave the range of their data. */
typedef enum {
    TC_RANGE_LOCAL = 0, /* each triangle within [min, max] of its own corner values, widened by a
                         * small margin of its own spread, never below 0 where they are >= 0 */
    TC_RANGE_POSITIVE,  /* never below 0 where a triangle's corner values are all >= 0 */
    TC_RANGE_FREE       /* the paper's cubic as it comes (equal to matplotlib's and scipy's) */
} tc_range;

/* Invariant: every default is the enum's 0, so a zero-filled tc_options is
 * tc_options_default's. `threads` and `deadline_ms` are no options of the
 * method: the threads tc_recon_new may use for its per-vertex and per-triangle
 * work (<= 1: the caller's thread only; the ordinates and every finding are the
 * same bit for bit whatever the count), and the tc_now_ms() time after which it
 * stops with TC_ETIMEOUT at its next check (between the stages of its build, and
 * every few hundred wedges in the longest one; 0: none; a build that returns TC_OK
 * is the same whatever the deadline). */
typedef struct {
    tc_method method;
    tc_cross cross_boundary;
    tc_wedges wedges;
    tc_tangents tangents;
    tc_twist twist;
    tc_average average;
    tc_range range;
    int threads;
    double deadline_ms;
} tc_options;

void tc_options_default(tc_options *o);

/* The options of tc_options a method reads, one bit each (tc_method_reads);
 * the options it does not read change nothing in its result. */
enum {
    TC_READS_CROSS_BOUNDARY = 1u << 0,
    TC_READS_WEDGES = 1u << 1,
    TC_READS_TANGENTS = 1u << 2,
    TC_READS_TWIST = 1u << 3,
    TC_READS_AVERAGE = 1u << 4,
    TC_READS_RANGE = 1u << 5
};

/* The methods are tc_method 0 .. tc_method_count() - 1. */
int tc_method_count(void);
/* TC_READS_* bits of the options method m reads; 0 for an unknown m. */
unsigned tc_method_reads(tc_method m);
/* 1 if m needs a mesh given as quads (hermite), else 0. */
int tc_method_quads_only(tc_method m);

/* Names as used in requests ("clough-tocher", "normal", ...); NULL if unknown. */
const char *tc_method_name(tc_method m);
const char *tc_cross_name(tc_cross c);
const char *tc_wedges_name(tc_wedges w);
const char *tc_tangents_name(tc_tangents t);
const char *tc_twist_name(tc_twist t);
const char *tc_average_name(tc_average a);
const char *tc_range_name(tc_range r);
const char *tc_degenerate_name(tc_degenerate d);
/* Parse a name; returns 0 and sets *out, or -1 if the name is unknown. */
int tc_method_parse(const char *s, tc_method *out);
int tc_cross_parse(const char *s, tc_cross *out);
int tc_wedges_parse(const char *s, tc_wedges *out);
int tc_tangents_parse(const char *s, tc_tangents *out);
int tc_twist_parse(const char *s, tc_twist *out);
int tc_average_parse(const char *s, tc_average *out);
int tc_range_parse(const char *s, tc_range *out);
int tc_degenerate_parse(const char *s, tc_degenerate *out);

/* The options of tc_options but the method, generically: option i of
 * 0 .. tc_option_count() - 1 has a request name ("cross_boundary"), a TC_READS_*
 * bit, values named by tc_option_value_name (NULL past the last; value 0 is the
 * default), and a value in a tc_options. Unknown i: NULL, 0, or no effect. */
int tc_option_count(void);
const char *tc_option_name(int i);
unsigned tc_option_bit(int i);
const char *tc_option_value_name(int i, int v);
int tc_option_get(const tc_options *o, int i);
void tc_option_set(tc_options *o, int i, int v);

typedef struct tc_recon tc_recon;

int tc_recon_new(const tc_mesh *m, const tc_options *o, tc_recon **out, tc_diags *diags);
void tc_recon_free(tc_recon *r);

const tc_mesh *tc_recon_mesh(const tc_recon *r);
const tc_options *tc_recon_options(const tc_recon *r);
/* Coefficients per triangle and channel: 19 Bézier ordinates for the cubic
 * methods (labels uuu vvv www uuv uuw uvv uww vvw vww cuu cvv cww ccu ccv ccw cuv
 * cuw cvw ccc, u = the triangle's first vertex as given), 3 corner values for
 * linear (u v w), 6 for linear4 (u v w, then the midpoints uv vw wu), 1 for
 * constant (mean). hermite: 22 per split triangle, the same for both triangles
 * of a quad (a, b, c, d): the bicubic Bézier ordinates b00 .. b33 of its patch
 * (b_ij at index 4i + j, label "bij"; i counts along s from a to b, j along t
 * from a to d; b00 = f(a), b30 = f(b), b33 = f(c), b03 = f(d)), then the
 * corners b, c, d relative to a, the triangle's first corner (xb yb xc yc xd yd),
 * which define the bilinear map x(s, t) = a + s(b-a) + t(d-a) + st(a-b+c-d).
 * powell-sabin: 25 — u v w; u:uv v:uv v:vw w:vw w:wu u:wu (the quadratic Bézier
 * ordinates halfway from a corner to an edge's split point); uv vw wu (the split
 * points); u:z v:z w:z and z:uv z:vw z:wu (halfway to the incenter z); z; then the
 * split geometry: zeta_u zeta_v zeta_w (z's barycentrics) and alpha_uv alpha_vw
 * alpha_wu (each split point's position along its edge, wu running from w to u). */
int tc_recon_coef_count(const tc_recon *r);
const char *tc_recon_coef_label(const tc_recon *r, int i);
const double *tc_recon_coefs(const tc_recon *r); /* [ntris][C][count] */
/* The tangent plane used at each corner, [ntris][3][C][2] (dz/dx, dz/dy), or
 * NULL for methods without tangent planes. */
const double *tc_recon_corner_gradients(const tc_recon *r);

/* ---- point location and evaluation ---------------------------------------- */

typedef struct tc_locator tc_locator;

int tc_locator_new(const tc_mesh *m, tc_locator **out);
void tc_locator_free(tc_locator *L);
/* The triangle that owns (x, y), or -1 outside the mesh. Every point of the
 * mesh has exactly one owner, also on shared edges and vertices (a top-left
 * rule on exactly computed edge tests); points on the mesh boundary belong to
 * the triangle they touch. Cost O(log T) for well-spread meshes. */
int32_t tc_locate(const tc_locator *L, double x, double y);

/* Value [C] and, if grad is not NULL, gradient [C][2] of triangle t's piece at
 * (x, y) — the polynomial extended if the point lies outside t. */
void tc_eval_triangle(const tc_recon *r, int32_t t, double x, double y,
                      double *value, double *grad);

/* Evaluates n points xy[n][2]: values[n][C], grads[n][C][2] (may be NULL),
 * tri[n] (may be NULL) = owning triangle or -1. Points outside the mesh get
 * value 0 and gradient 0 and tri -1: never NaN. */
void tc_eval_points(const tc_recon *r, const tc_locator *L, size_t n, const double *xy,
                    double *values, double *grads, int32_t *tri);
/* The same on up to `threads` threads (fewer for small batches; < 1 means 1):
 * every result is bit for bit tc_eval_points', whatever the thread count. */
void tc_eval_points_mt(const tc_recon *r, const tc_locator *L, size_t n, const double *xy,
                       double *values, double *grads, int32_t *tri, int threads);

/* ---- rendering tiles ------------------------------------------------------ */

/* A world rectangle sampled by width x height pixels. Pixel (i, j), j = 0 the
 * TOP row, has its centre at
 *     x = x0 + (x1 - x0) * ((i + 0.5) / width)
 *     y = y1 - (y1 - y0) * ((j + 0.5) / height)
 * computed in exactly that order, so any program can reproduce it bit for bit. */
typedef struct {
    double x0, y0, x1, y1;
    int32_t width, height;
} tc_viewport;

void tc_viewport_pixel_center(const tc_viewport *vp, int32_t i, int32_t j, double *x, double *y);

typedef struct {
    const double *background; /* [C] value of pixels outside the mesh; NULL = 0 */
    int threads;              /* worker threads; <= 1 renders on the caller's thread */
    double deadline_ms;       /* tc_now_ms() after which rendering stops with
                               * TC_ETIMEOUT; 0 = none */
    int32_t row0, rows;       /* only rows [row0, row0 + rows) of the viewport (rows 0: to
                               * the last row), stored from row 0 of values and owner; each
                               * pixel as the whole tile's, so a tile may be rendered in bands */
    double limit;             /* > 0: every sample of magnitude >= limit (rounded to float) is
                               * stored as +-limit (an image format's largest sample: half's
                               * 65504, float's FLT_MAX) and counted; 0: none is */
    int64_t *limited;         /* not NULL: the count of such samples is added to *limited */
} tc_render_options;

/* tc_render's unit of work for its threads, in rows: a caller that renders a tile in bands
 * (row0/rows) wastes least with bands of a multiple of it. On several threads the last units
 * of a call shrink (to 8 rows) so that the threads end together. */
#define TC_RENDER_BAND_ROWS 32

/* Milliseconds of CLOCK_MONOTONIC: the clock of deadline_ms (and of every timing). */
double tc_now_ms(void);

/* Renders r over vp into values[height][width][C] (each pixel the double that
 * tc_eval_points gives at its centre — for the Clough-Tocher cubic on a triangle
 * of aspect <= 64 and at least four pixels of area, a double within 1e-12 of the channel's
 * data scale of it, from the renderer's fast form, where fused multiply-add is an
 * instruction (x86-64 with AVX2 and FMA, aarch64; elsewhere that double itself) — rounded once to float; beyond the float
 * range, +-FLT_MAX: never an infinity) and, if owner is
 * not NULL, owner[height][width] (the owning triangle, -1 outside the mesh).
 * Visits only the triangles that overlap the tile. The result is the same bit
 * for bit whatever the number of threads. o may be NULL. */
int tc_render(const tc_recon *r, const tc_locator *L, const tc_viewport *vp, const tc_render_options *o,
              float *values, int32_t *owner);

/* Draws the mesh's edges over a rendered tile, one pixel wide, coloured by the
 * continuity the reconstruction has across them: C1 grey, C0 yellow, C-1 red,
 * boundary white (3 channels; other channel counts get 0.35 / 0.7 / 1.0 / 1.0 in
 * every channel), all times `scale`. That is each edge's flag as the method
 * honours it, capped by what the method reaches: clough-tocher and hermite keep
 * every flag; clough-tocher-c1 none (all grey); powell-sabin C-1 only (C0 edges
 * grey); linear and linear4 are C0 across every unflagged or C0 edge (yellow)
 * and keep C-1; constant is C-1 across every edge (red). Hermite does not draw
 * the quads' diagonals (inside a patch). */
void tc_render_overlay(const tc_recon *r, const tc_viewport *vp, double scale, float *values);
/* The same over rows [row0, row0 + rows) of the viewport only, values holding those
 * rows from its row 0 (a band rendered with tc_render_options.row0/rows). */
void tc_render_overlay_rows(const tc_recon *r, const tc_viewport *vp, double scale, int32_t row0, int32_t rows,
                            float *values);

/* ---- error against a reference -------------------------------------------- */

/* Errors of a reconstruction against reference values, pooled over channels. */
typedef struct {
    double max_abs;   /* max |ref - rec| */
    double rms;       /* sqrt(mean (ref - rec)^2) */
    double mean_rel;  /* Bastos & Oliveira's: mean of |ref - rec| / scale */
    double scale;     /* the full-scale value mean_rel divides by */
    int64_t n;        /* points compared (those inside the mesh) */
    int64_t outside;  /* points outside the mesh: not compared */
} tc_error_stats;

/* Compares r with ref[n][C] at xy[n][2]. scale is the largest value the
 * function can take (the full scale of an image); <= 0 means max |ref|. */
int tc_compare(const tc_recon *r, const tc_locator *L, size_t n, const double *xy, const double *ref, double scale,
               tc_error_stats *out);

/* ---- overshoot: how far a rendered tile leaves the data --------------------- */

/* One channel of a tile against the mesh's own data. R = hi - lo is the
 * channel's data range over every triangle's corner values (per-corner values
 * included). The pixel owned by triangle t, of value v, leaves t's data by
 *     e = max(0, v - max_t, min_t - v) / unit,   unit = R
 * (max(|lo|, |hi|) when R = 0, and 1 when that is 0 too), min_t and max_t the
 * smallest and largest of t's corner values rounded to float as pixels are, so
 * a pixel equal to a corner value has e = 0 and a linear reconstruction leaves
 * nothing. A non-finite pixel has e = infinity. */
typedef struct {
    double lo, hi;           /* the channel's smallest and largest corner value */
    double unit;             /* what e is measured in (R unless R = 0) */
    int64_t pixels;          /* pixels inside the mesh (owner >= 0) */
    int64_t negative;        /* pixels below 0 when no data is (lo >= 0); else 0 */
    int64_t beyond;          /* pixels with e > the threshold asked for */
    double beyond_fraction;  /* beyond / pixels (0 without pixels) */
    double worst;            /* the largest e */
    int32_t worst_tri;       /* its pixel's owner; -1 when worst is 0 */
    int32_t worst_i, worst_j;/* its pixel: column, row from the top; -1 when worst is 0 */
    double worst_value;      /* that pixel's value */
    double min_value, max_value; /* over the pixels inside the mesh (0 without any) */
} tc_overshoot_stats;

/* Measures a tile rendered from a reconstruction on m (tc_render's values
 * [height][width][C] and owner [height][width]) into out[C]. TC_EINVAL when an
 * owner is not a triangle of m or -1, or a size is negative. */
int tc_overshoot(const tc_mesh *m, const float *values, const int32_t *owner, int32_t width, int32_t height,
                 double threshold, tc_overshoot_stats *out);

#ifdef __cplusplus
}
#endif
#endif /* TOCHER_H */
