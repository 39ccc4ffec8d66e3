/* linear.c — the baselines tocher is measured against: constant (one value per
 * triangle), linear (Gouraud) and linear4 (the paper's 4-split through midpoint samples). */
#include <stdio.h>
#include <string.h>

#include "core/alloc.h"
#include "core/linear.h"
#include "core/mesh.h"
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
            const double *z = m->cz + 3 * (size_t)t * (size_t)nc + ch;
            coef[tc__ix(t, nc, ch)] = z[0] + ((z[nc] - z[0]) + (z[2 * nc] - z[0])) / 3; /* exact when equal; no overflow */
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
                r->coef[tc__ix(t, nc, ch) * 3 + (size_t)k] = m->cz[tc__ix(3 * t + k, nc, ch)];
    return TC_OK;
}

/* The edges linear4 had to make linear: how many, and the first few to name. */
#define MISSING_LIST 3
typedef struct {
    int32_t count, nlist, t;
    int32_t edge[MISSING_LIST][2];
} missing_mids;

static void note_missing(const struct tc_mesh *m, missing_mids *mm, int32_t t, int k) {
    if (mm->count++ == 0) mm->t = t;
    if (mm->nlist == MISSING_LIST) return;
    mm->edge[mm->nlist][0] = m->tri[3 * (size_t)t + (size_t)k];
    mm->edge[mm->nlist++][1] = m->tri[3 * (size_t)t + (size_t)(k + 1) % 3];
}

/* One warning at the first triangle concerned, naming the first edges. */
static void warn_missing(const struct tc_mesh *m, const missing_mids *mm, tc_diags *dg) {
    if (!mm->count) return;
    char path[48], edges[MISSING_LIST * 28 + 16] = "";
    size_t len = 0;
    for (int i = 0; i < mm->nlist; i++)
        len += (size_t)snprintf(edges + len, sizeof edges - len, "%s[%d, %d]", i ? ", " : "", (int)mm->edge[i][0],
                                (int)mm->edge[i][1]);
    if (mm->count > mm->nlist) snprintf(edges + len, sizeof edges - len, ", ...");
    tc__elem_path(m, mm->t, path, sizeof path);
    tc_diags_add(dg, TC_SEV_WARNING, path,
                 "%d triangle edge side%s no midpoint sample (edges %s); linear4 is linear along them: send "
                 "their samples in \"midpoints\", or use linear",
                 (int)mm->count, mm->count > 1 ? "s have" : " has", edges);
}

/* Corner values then the midpoint samples of edges 0 (uv), 1 (vw), 2 (wu). An
 * edge without a sample gets the mean of its ends: linear along that edge. */
int tc__linear4_build(struct tc_recon *r, tc_diags *dg) {
    const struct tc_mesh *m = r->m;
    double *coef = r->coef;
    int nc = m->nc;
    missing_mids mm;
    memset(&mm, 0, sizeof mm);
    for (int32_t t = 0; t < m->nt; t++)
        for (int ch = 0; ch < nc; ch++) {
            double *o = coef + tc__ix(t, nc, ch) * 6;
            for (int k = 0; k < 3; k++) o[k] = m->cz[tc__ix(3 * t + k, nc, ch)];
            for (int k = 0; k < 3; k++) {
                size_t e = 3 * (size_t)t + (size_t)k;
                if (m->mid_has && m->mid_has[e]) {
                    o[3 + k] = m->mid[e * (size_t)nc + (size_t)ch];
                } else {
                    o[3 + k] = 0.5 * (o[k] + o[(k + 1) % 3]);
                    if (ch == 0) note_missing(m, &mm, t, k);
                }
            }
        }
    warn_missing(m, &mm, dg);
    return TC_OK;
}

void tc__constant_eval(const double *o, const tc__eval_point *at, double *value, double *grad) {
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

void tc__linear_eval(const double *o, const tc__eval_point *at, double *value, double *grad) {
    const double *lam = at->lam;
    /* About the heaviest corner: exact at corners and for constant data. */
    double ref = o[heaviest(lam)];
    *value = ref + (lam[0] * (o[0] - ref) + lam[1] * (o[1] - ref) + lam[2] * (o[2] - ref));
    if (grad) grad_from(o, at->dl1, at->dl2, grad);
}

/* The 4-split: the corner triangle of corner i where lam[i] >= 1/2, else the
 * middle triangle of the three midpoints. */
void tc__linear4_eval(const double *o, const tc__eval_point *at, double *value, double *grad) {
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
