/* qp.c — the primal active-set method for small dense convex QPs (Nocedal &
 * Wright, Algorithm 16.3): every iterate is feasible, so stopping early is safe. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/minmax.h"
#include "core/qp.h"

/* A pivot below this fraction of the matrix's largest entry is rounding of a
 * singular KKT system (a working row dependent on the others): ~100 ulps, far
 * below the entries' real spread in these small, scaled problems. */
#define PIVOT_MIN 1e-14
/* A constraint row c blocks a step p only when c.p > this times |c| |p| (the
 * cosine of their angle): rows dependent on the working rows have c.p = 0 but for
 * rounding, about 1e-16 |c| |p| per term. */
#define BLOCK_MIN_COS 1e-12
/* A step below this fraction of y's scale (the data's plus y's size) is none:
 * the iterate has converged to rounding, and the multipliers decide what next. */
#define STEP_NEGLIGIBLE 1e-11

/* Solves the k x k system M x = r in place by Gaussian elimination with
 * partial pivoting (M is overwritten). -1 if a pivot is negligible against
 * the matrix's largest entry. */
static int solve_dense(int k, double *M, double *r) {
    double big = 0;
    for (int i = 0; i < k * k; i++) big = tc__fmax(big, fabs(M[i]));
    for (int c = 0; c < k; c++) {
        int p = c;
        for (int i = c + 1; i < k; i++)
            if (fabs(M[i * k + c]) > fabs(M[p * k + c])) p = i;
        if (!(fabs(M[p * k + c]) > PIVOT_MIN * big)) return -1;
        if (p != c) {
            for (int j = 0; j < k; j++) {
                double t = M[c * k + j];
                M[c * k + j] = M[p * k + j], M[p * k + j] = t;
            }
            double t = r[c];
            r[c] = r[p], r[p] = t;
        }
        for (int i = c + 1; i < k; i++) {
            double f = M[i * k + c] / M[c * k + c];
            if (f == 0) continue;
            for (int j = c; j < k; j++) M[i * k + j] -= f * M[c * k + j];
            r[i] -= f * r[c];
        }
    }
    for (int c = k - 1; c >= 0; c--) {
        double s = r[c];
        for (int j = c + 1; j < k; j++) s -= M[c * k + j] * r[j];
        r[c] = s / M[c * k + c];
    }
    return 0;
}

typedef struct {
    int n, neq, m;
    const double *H, *f, *Aeq, *C, *b;
    int work[TC_QP_MAXN]; /* inequality rows held active */
    int nwork;
    int last;             /* the row added last, or -1 */
    unsigned char banned[TC_QP_MAXM]; /* rows that made the working set singular: not to block until a drop */
} problem;

static double dot(const double *a, const double *x, int n) {
    double s = 0;
    for (int i = 0; i < n; i++) s += a[i] * x[i];
    return s;
}

/* The step p to the minimizer on the working set from y, and the multipliers
 * mu of the working rows (equalities first): [H A'; A 0] [p; mu] = [-(Hy+f); 0]. */
static int kkt_step(const problem *q, const double *y, double *M, double *p, double *mu) {
    int n = q->n, k = n + q->neq + q->nwork;
    double r[TC_QP_MAXN + TC_QP_MAXEQ + TC_QP_MAXN];
    memset(M, 0, (size_t)k * (size_t)k * sizeof *M);
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < n; j++) M[i * k + j] = q->H[i * n + j];
        r[i] = -(dot(q->H + i * n, y, n) + q->f[i]);
    }
    for (int a = 0; a < q->neq + q->nwork; a++) {
        const double *row = a < q->neq ? q->Aeq + a * n : q->C + q->work[a - q->neq] * n;
        for (int j = 0; j < n; j++) M[(n + a) * k + j] = M[j * k + n + a] = row[j];
        r[n + a] = 0;
    }
    if (solve_dense(k, M, r)) return -1;
    memcpy(p, r, (size_t)n * sizeof *p);
    memcpy(mu, r + n, (size_t)(q->neq + q->nwork) * sizeof *mu);
    return 0;
}

/* Drops the working inequality with the most negative multiplier; 0 if none
 * is negative (y is optimal). */
static int drop_negative(problem *q, const double *mu) {
    int worst = -1;
    for (int a = 0; a < q->nwork; a++)
        if (mu[q->neq + a] < 0 && (worst < 0 || mu[q->neq + a] < mu[q->neq + worst])) worst = a;
    if (worst < 0) return 0;
    q->work[worst] = q->work[--q->nwork];
    memset(q->banned, 0, sizeof q->banned);
    q->last = -1;
    return 1;
}

/* Moves y along p as far as the inactive rows allow (at most to y + p) and
 * adds the row that blocked, if any. */
static void advance(problem *q, double *y, const double *p) {
    double alpha = 1, pn = sqrt(dot(p, p, q->n));
    int block = -1;
    for (int i = 0; i < q->m; i++) {
        int active = 0;
        for (int a = 0; a < q->nwork; a++) active |= q->work[a] == i;
        const double *c = q->C + i * q->n;
        /* A row that depends on the working rows has c.p = 0 exactly but for
         * rounding; it must not block (adding it would make the KKT system singular). */
        double cp = active || q->banned[i] ? 0 : dot(c, p, q->n);
        if (!(cp > BLOCK_MIN_COS * sqrt(dot(c, c, q->n)) * pn)) continue;
        double slack = tc__fmax(0, q->b[i] - dot(q->C + i * q->n, y, q->n)), a = slack / cp;
        if (a < alpha) alpha = a, block = i;
    }
    for (int j = 0; j < q->n; j++) y[j] += alpha * p[j];
    if (block >= 0 && q->nwork < q->n) q->work[q->nwork++] = block, q->last = block;
}

static int solve_scaled(int n, const double *H, const double *f, int neq, const double *Aeq, int m, const double *C,
                        const double *b, double *y) {
    problem q = {n, neq, m, H, f, Aeq, C, b, {0}, 0, -1, {0}};
    int kmax = n + neq + n;
    double *M = malloc((size_t)kmax * (size_t)kmax * sizeof *M);
    if (!M) return -1;
    double p[TC_QP_MAXN], mu[TC_QP_MAXEQ + TC_QP_MAXN], scale = 0;
    for (int i = 0; i < n; i++) scale = tc__fmax(scale, fabs(f[i]) / H[i * n + i]);
    int rc = 1;
    for (int it = 0; it < 8 * (m + n); it++) {
        if (kkt_step(&q, y, M, p, mu)) {
            /* The row added last depends on the working rows up to rounding
             * (nearly parallel to them): take it out and let it not block. */
            if (q.last < 0 || q.work[q.nwork - 1] != q.last) {
                rc = -1;
                break;
            }
            q.banned[q.last] = 1;
            q.nwork--, q.last = -1;
            continue;
        }
        /* With as many working rows as variables y is a vertex and p is 0 but
         * for rounding; otherwise a step below rounding of y's scale is none. */
        double pn = 0, yn = 0;
        for (int j = 0; j < n; j++) pn = tc__fmax(pn, fabs(p[j])), yn = tc__fmax(yn, fabs(y[j]));
        if (q.neq + q.nwork >= n || pn <= STEP_NEGLIGIBLE * (scale + yn)) {
            if (!drop_negative(&q, mu)) {
                rc = 0;
                break;
            }
            continue;
        }
        advance(&q, y, p);
    }
    free(M);
    return rc;
}

/* Unit scaling: variables by 1/sqrt(H_ii), so H has a unit diagonal, and every
 * constraint row to unit length, so the KKT systems are well scaled whatever
 * the units of the problem (pivots are judged against the largest entry). */
typedef struct {
    double H[TC_QP_MAXN * TC_QP_MAXN], f[TC_QP_MAXN], d[TC_QP_MAXN];
    double Aeq[TC_QP_MAXEQ * TC_QP_MAXN], C[TC_QP_MAXM * TC_QP_MAXN], b[TC_QP_MAXM];
} scaled;

static double unit_row(double *row, int n) {
    double s = sqrt(dot(row, row, n));
    for (int j = 0; s > 0 && j < n; j++) row[j] /= s;
    return s > 0 ? s : 1;
}

int tc__qp_solve(int n, const double *H, const double *f, int neq, const double *Aeq, int m, const double *C,
                 const double *b, double *y) {
    memset(y, 0, (size_t)n * sizeof *y);
    if (n < 1 || n > TC_QP_MAXN || neq > TC_QP_MAXEQ || m > TC_QP_MAXM) return -1;
    scaled *S = malloc(sizeof *S);
    if (!S) return -1;
    for (int i = 0; i < n; i++) S->d[i] = H[i * n + i] > 0 ? 1 / sqrt(H[i * n + i]) : 1;
    for (int i = 0; i < n; i++) {
        S->f[i] = f[i] * S->d[i];
        for (int j = 0; j < n; j++) S->H[i * n + j] = H[i * n + j] * S->d[i] * S->d[j];
    }
    for (int a = 0; a < neq; a++) {
        for (int j = 0; j < n; j++) S->Aeq[a * n + j] = Aeq[a * n + j] * S->d[j];
        unit_row(S->Aeq + a * n, n);
    }
    for (int i = 0; i < m; i++) {
        for (int j = 0; j < n; j++) S->C[i * n + j] = C[i * n + j] * S->d[j];
        S->b[i] = b[i] / unit_row(S->C + i * n, n);
    }
    int rc = solve_scaled(n, S->H, S->f, neq, S->Aeq, m, S->C, S->b, y);
    for (int i = 0; i < n; i++) y[i] *= S->d[i];
    free(S);
    return rc;
}
