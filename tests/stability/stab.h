/* stab.h — shared pieces of the numerical stability suite (tests named stab_*): method variants,
 * owned mesh descriptions to move, scale and rebuild, per-variant figures, and the TSV summary. */
#ifndef TC_TEST_STAB_H
#define TC_TEST_STAB_H

#include <stddef.h>
#include <stdint.h>

#include "meshgen.h"
#include "tocher.h"

#define STAB_PI 3.14159265358979323846

/* ---- method variants: every method, and every cross/wedges option of clough-tocher ---- */

typedef struct {
    const char *name;  /* in the table: "clough-tocher/salesin/literal" */
    const char *brief; /* on stderr: "ct-salesin-lit" */
    tc_method method;
    tc_cross cross;
    tc_wedges wedges;
} stab_variant;

enum { STAB_NVAR = 11, STAB_HERMITE = 10 };
extern const stab_variant stab_var[STAB_NVAR];

void stab_options(int v, tc_tangents tangents, tc_options *o);
int stab_literal(int v);
/* Methods with tangent planes (everything but constant, linear, linear4: the method table says). */
int stab_has_planes(int v);

/* ---- owned mesh descriptions ---- */

/* A tc_mesh_desc whose arrays it owns, so a case can transform it and build it again. */
typedef struct {
    tc_mesh_desc d;
    void *own[40];
    int nown;
} sdesc;

void sdesc_copy(sdesc *s, const tc_mesh_desc *d);
void sdesc_free(sdesc *s);
/* x -> scale x + (dx, dy); gradients, normals and hessians follow (gradients / scale). */
void sdesc_move(sdesc *s, double scale, double dx, double dy);
/* Every value, sample, gradient and hessian times k (normals: their slopes times k). */
void sdesc_scale_values(sdesc *s, double k);
/* Adds a shared midpoint sample of f on every edge (quad diagonals included). */
void sdesc_add_midpoints(sdesc *s, tfunc f, const void *ctx);
/* Replaces the discontinuity polylines (c0 and c-1 lists of 2-vertex segments, -1 ended). */
void sdesc_set_lines(sdesc *s, const int32_t *c0, const int32_t *cm1);

/* ---- hand-built and generated meshes ---- */

/* A tmesh over the given vertices and triangles, adjacency and flags (boundary -1, else 1) set. */
void stab_tmesh(tmesh *g, int32_t nv, const double *xy, int32_t nt, const int32_t *tri);
/* Rounds every coordinate to a multiple of 2^-bits. */
void stab_dyadic(tmesh *g, int bits);

/* ---- running one variant ---- */

typedef struct {
    tc_mesh *m;
    tc_recon *r;
    tc_locator *L;
    tc_diags dg;
    int stage; /* 0 built, 1 refused by tc_mesh_new, 2 by tc_recon_new, 3 locator failed */
} srun;

int srun_start(srun *x, const tc_mesh_desc *d, const tc_options *o);
void srun_end(srun *x);
/* The first error, or NULL. */
const tc_diag *srun_error(const srun *x);
/* A finding names an element: a JSON path with an index ("triangles[4]",
 * "normals[3]") or, for path-level findings, a message that names one ("edge [2, 5]"). */
int stab_names_element(const tc_diag *d);
/* Some warning whose path starts with `path` mentions `word` and a number within
 * a factor 2 of `figure` (figure <= 0: any number). */
int stab_has_warning(const tc_diags *dg, const char *path, const char *word, double figure);
/* Coefficients and corner planes all finite. */
int stab_recon_finite(const tc_recon *r);

/* ---- per-variant figures and the report ---- */

typedef struct {
    double worst;
    int runs, refused, unnamed, nonfinite;
    char where[96];    /* the sub-case of the worst figure */
    char refusal[160]; /* the first refusal, "path: message" */
} stab_acc;

void stab_acc_init(stab_acc *a, int n);
void stab_acc_fig(stab_acc *a, double fig, const char *where);
/* Records a refusal (x->stage != 0), checking it names an element. */
void stab_acc_refusal(stab_acc *a, const srun *x);

enum {
    STAB_NO_REFUSAL = 1,  /* a refusal fails even when it names the element (the issue allows
                           * refusals naming the element in every case but these) */
    STAB_INFO = 2,        /* the figure is measured and reported, not bounded */
    STAB_EXEMPT_LITERAL = 4 /* literal wedges: reported, not bounded */
};

/* Prints a case's figures (stderr), writes its TSV lines (TC_STABILITY_TABLE),
 * and fails for every variant over the bound, non-finite, refused without
 * naming the element, or refused under STAB_NO_REFUSAL. */
void stab_report(const char *file, int line, const char *case_name, const char *measure, const stab_acc *acc,
                 double bound, int flags);
#define STAB_REPORT(c, m, acc, bound, flags) stab_report(__FILE__, __LINE__, c, m, acc, bound, flags)
/* The same with a separate bound for the literal wedges variants (the paper's
 * construction as printed, whose stated bound is wider). */
void stab_report_lit(const char *file, int line, const char *case_name, const char *measure, const stab_acc *acc,
                     double bound, double lit_bound, int flags);
#define STAB_REPORT_LIT(c, m, acc, bound, lit, flags) stab_report_lit(__FILE__, __LINE__, c, m, acc, bound, lit, flags)

/* One TSV line: case, method, measure, worst, bound, verdict, detail (worst < 0: none
 * measured, bound < 0: not bounded; both printed "-"). */
void stab_table(const char *case_name, const char *method, const char *measure, double worst, double bound,
                const char *verdict, const char *detail);

/* ---- properties of a reconstruction, for every method ---- */

/* Relative residuals of what the variant promises (scales local to the
 * triangles involved): interpolation, C0, C1 across edges, C1 at C1
 * vertices, C1 across the cubic split's internal edges. */
typedef struct {
    double corner, c0, c1, vertex, internal;
    double aspect; /* worst triangle aspect ratio, longest edge^2 / (2 area) */
} stab_cont;
void stab_continuity(const tc_recon *r, stab_cont *c);
double stab_cont_worst(const stab_cont *c);
/* The C1 residuals (edges, vertices, split edges) over their stated bound
 * max(1e-9, STAB_C1_ULPS * eps * aspect): a gradient read across a triangle of
 * width h from ordinates of size |z| + |g| L carries rounding of eps (|z| + |g| L) / h,
 * eps * aspect relative to |g|; no double-precision representation of the cubic
 * avoids it (docs/stability.md). <= 1 holds the bound. */
#define STAB_C1_ULPS 100.0
double stab_c1_over_bound(const stab_cont *c);
/* Which of the five is the worst ("C1 edge", ...). */
const char *stab_cont_which(const stab_cont *c);

/* Dense sampling of a reconstruction: per_tri random points in every triangle
 * plus corners and edge points, each in its own triangle's piece. */
typedef struct {
    double zmin, zmax;  /* data range: corner values and midpoint samples */
    double vmin, vmax;  /* reconstruction range */
    double gmax;        /* largest |gradient| */
    long nonfinite;
} stab_range;
void stab_sample(const tc_recon *r, int per_tri, uint64_t seed, stab_range *s);
/* (how far the values leave the data range) / (data range). */
double stab_overshoot(const stab_range *s);
/* The measurement most cases take: continuity (c) and a dense sample (s, per_tri
 * random points per triangle). 1 if the coefficients and every sample are finite. */
int stab_measure(const tc_recon *r, int per_tri, uint64_t seed, stab_cont *c, stab_range *s);
/* Largest |given gradient| of the description (gradients, normals, corner gradients). */
double stab_given_gradient(const tc_mesh_desc *d);

#endif
