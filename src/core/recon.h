/* recon.h — struct tc_recon and the per-method pieces the method table
 * (method.c) points to: each method's build and the evaluator of its pieces. */
#ifndef TC_CORE_RECON_H
#define TC_CORE_RECON_H

#include "core/geom.h"
#include "core/method.h"
#include "core/range.h"
#include "core/wedge.h"

struct tc_recon {
    const struct tc_mesh *m;
    tc_options opt;
    const tc__method *method;  /* the row of opt.method; ncoef, labels, eval are its */
    int ncoef;
    const char *const *labels; /* [ncoef] */
    tc_piece_eval eval;
    double *coef;              /* [nt][nc][ncoef] */
    double *cgrad;             /* [3nt][nc][2] corner planes used, or NULL */
    /* Per channel: its data are all >= 0 and the range is restricted, so its
     * ordinates are >= 0 to within rounding (range.h); the evaluators return
     * the few values a rounding puts below 0 as 0 (never more than ~1e-12 of
     * the channel's scale: the limiter, not this, keeps the function up). */
    uint8_t floor0[TC_MAX_CHANNELS];
};

/* Value v of channel ch as a point or a pixel of r gets it. */
static inline double tc__floored(const struct tc_recon *r, int ch, double v) {
    return r->floor0[ch] && v < 0 ? 0 : v;
}

/* Every build below is a tc_method_build: it fills r->coef (allocated by
 * tc_recon_new for the method's ncoef) and reads its row as r->method. */

/* linear.c: the baselines. */
extern const char *const tc__constant_labels[1];
extern const char *const tc__linear_labels[3];
extern const char *const tc__linear4_labels[6];
int tc__constant_build(struct tc_recon *r, tc_diags *dg);
int tc__linear_build(struct tc_recon *r, tc_diags *dg);
int tc__linear4_build(struct tc_recon *r, tc_diags *dg);
void tc__constant_eval(const double *o, const tc_at *at, double *value, double *grad);
void tc__linear_eval(const double *o, const tc_at *at, double *value, double *grad);
void tc__linear4_eval(const double *o, const tc_at *at, double *value, double *grad);

/* recon.c: the cubic methods (clough-tocher, clough-tocher-c1). */
int tc__ct_build(struct tc_recon *r, tc_diags *dg);

/* powell_sabin.c and hermite.c. */
enum { TC_PS_COEFS = 25, TC_PS_ORDINATES = 19 /* the rest is the split geometry */ };
extern const char *const tc__ps_labels[TC_PS_COEFS];
int tc__ps_build(struct tc_recon *r, tc_diags *dg);
void tc__ps_eval(const double *o, const tc_at *at, double *value, double *grad);
int tc__hermite_build(struct tc_recon *r, tc_diags *dg);

/* How a method's ordinates depend on its corner planes, for the range
 * limiter (range.h): the directions per corner, and whether a piece spans a
 * quad (its bound is the quad's). NULL dirs: the planes are not limited. */
typedef struct {
    tc_plane_dirs_fn dirs;
    const void *ctx;
    int per_quad;
} tc_plane_use;

/* recon.c: the cubic methods' tangent-plane pipeline (wedges delimited per
 * the method's `honour` -> corner inputs per r->opt.tangents -> wedge planes)
 * for other methods: fills r->cgrad (allocating it), then, unless
 * r->opt.range is free, limits the planes for `use`. Corner values are the
 * mesh's, so the method must not have honour TC_HONOR_NONE on C-1 data. */
int tc__recon_planes(struct tc_recon *r, const tc_plane_use *use, tc_diags *dg);

/* powell_sabin.c: TC_PS_COEFS coefficients per triangle and channel (layout
 * there), and piece p (0..5) of the 6-split extended to any point, for tests:
 * piece 2k + h lies on edge k, next to its corner k (h = 0) or k+1 (h = 1). */
void tc__ps_eval_piece(const double *coef, int piece, const double lam[3], const double dl1[2], const double dl2[2],
                       double *value, double *grad);

/* Tests: the mesh size from which tc_eval_points visits batches in Z order
 * (default 32768 triangles), so the sorted path can be checked on small meshes. */
void tc__eval_sort_min_triangles(int32_t nt);

#endif
