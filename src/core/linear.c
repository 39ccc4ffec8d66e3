/* linear.c — the baselines tocher is measured against: constant (one value per
 * triangle), linear (Gouraud) and linear4 (the paper's 4-split through midpoint samples). */
#include <string.h>

#include "core/recon.h"

const char *const tc__constant_labels[1] = {"mean"};
const char *const tc__linear_labels[3] = {"u", "v", "w"};
const char *const tc__linear4_labels[6] = {"u", "v", "w", "uv", "vw", "wu"};

int tc__constant_build(struct tc_recon *r, tc_diags *dg) {
    const struct tc_mesh *m = r->m;
    double *coef = r->coef;
    int nc = m->nc;
    (void)dg;
    for (int32_t t = 0; t < m->nt; t++)
        for (int ch = 0; ch < nc; ch++) {
            const double *z = m->cz + 3 * (size_t)t * nc + ch;
            coef[(size_t)t * nc + ch] = z[0] + ((z[nc] - z[0]) + (z[2 * nc] - z[0])) / 3; /* exact when equal; no overflow */
        }
    return TC_OK;
}

int tc__linear_build(struct tc_recon *r, tc_diags *dg) {
    const struct tc_mesh *m = r->m;
    int nc = m->nc;
    (void)dg;
    for (int32_t t = 0; t < m->nt; t++)
        for (int ch = 0; ch < nc; ch++)
            for (int k = 0; k < 3; k++)
                r->coef[((size_t)t * nc + ch) * 3 + k] = m->cz[(3 * (size_t)t + k) * nc + ch];
    return TC_OK;
}

/* Corner values then the midpoint samples of edges 0 (uv), 1 (vw), 2 (wu). An
 * edge without a sample gets the mean of its ends: linear along that edge. */
int tc__linear4_build(struct tc_recon *r, tc_diags *dg) {
    const struct tc_mesh *m = r->m;
    double *coef = r->coef;
    int nc = m->nc;
    int32_t missing = 0;
    for (int32_t t = 0; t < m->nt; t++)
        for (int ch = 0; ch < nc; ch++) {
            double *o = coef + ((size_t)t * nc + ch) * 6;
            for (int k = 0; k < 3; k++) o[k] = m->cz[(3 * (size_t)t + k) * nc + ch];
            for (int k = 0; k < 3; k++) {
                size_t e = 3 * (size_t)t + k;
                if (m->mid_has && m->mid_has[e]) {
                    o[3 + k] = m->mid[e * nc + ch];
                } else {
                    o[3 + k] = 0.5 * (o[k] + o[(k + 1) % 3]);
                    missing += ch == 0;
                }
            }
        }
    if (missing)
        tc_diags_add(dg, TC_SEV_WARNING, "midpoints",
                     "%d triangle edge sides have no midpoint sample; linear4 is linear along them", (int)missing);
    return TC_OK;
}

void tc__constant_eval(const double *o, const tc_at *at, double *value, double *grad) {
    (void)at;
    *value = o[0];
    if (grad) grad[0] = grad[1] = 0;
}

static void grad_from(const double D[3], const double dl1[2], const double dl2[2], double *grad) {
    grad[0] = (D[1] - D[0]) * dl1[0] + (D[2] - D[0]) * dl2[0];
    grad[1] = (D[1] - D[0]) * dl1[1] + (D[2] - D[0]) * dl2[1];
}

/* Corner i with the largest weight: the reference of the difference form. */
static int heaviest(const double lam[3]) {
    return lam[0] >= lam[1] ? (lam[0] >= lam[2] ? 0 : 2) : (lam[1] >= lam[2] ? 1 : 2);
}

void tc__linear_eval(const double *o, const tc_at *at, double *value, double *grad) {
    const double *lam = at->lam;
    /* About the heaviest corner: exact at corners and for constant data. */
    double ref = o[heaviest(lam)];
    *value = ref + (lam[0] * (o[0] - ref) + lam[1] * (o[1] - ref) + lam[2] * (o[2] - ref));
    if (grad) grad_from(o, at->dl1, at->dl2, grad);
}

/* The 4-split: the corner triangle of corner i where lam[i] >= 1/2, else the
 * middle triangle of the three midpoints. */
void tc__linear4_eval(const double *o, const tc_at *at, double *value, double *grad) {
    const double *lam = at->lam, *mid = o + 3; /* mid[k] on edge k = (k, k+1) */
    double D[3];
    int i = lam[0] >= 0.5 ? 0 : lam[1] >= 0.5 ? 1 : lam[2] >= 0.5 ? 2 : -1;
    if (i >= 0) {
        int j = (i + 1) % 3, k = (i + 2) % 3;
        /* About the corner value: its weight 2 lam[i] - 1 plus the others is 1. */
        *value = o[i] + (2 * lam[j] * (mid[i] - o[i]) + 2 * lam[k] * (mid[k] - o[i]));
        D[i] = 2 * o[i];
        D[j] = 2 * mid[i];
        D[k] = 2 * mid[k];
    } else {
        double w[3] = {1 - 2 * lam[2], 1 - 2 * lam[0], 1 - 2 * lam[1]}; /* of mid[0], mid[1], mid[2] */
        double ref = mid[heaviest(w)];
        *value = ref + (w[0] * (mid[0] - ref) + w[1] * (mid[1] - ref) + w[2] * (mid[2] - ref));
        D[0] = -2 * mid[1];
        D[1] = -2 * mid[2];
        D[2] = -2 * mid[0];
    }
    if (grad) grad_from(D, at->dl1, at->dl2, grad);
}
