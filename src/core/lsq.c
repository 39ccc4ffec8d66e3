/* lsq.c — small dense least squares by Householder QR (rows <= TC_LSQ_MAXROWS,
 * columns <= TC_LSQ_MAXCOLS), with several right-hand sides sharing one matrix. */
#include <math.h>
#include <string.h>

#include "core/fhypot.h"
#include "core/lsq.h"

/* |A[from..rows)[j]|: the plain sum of squares where it can neither overflow nor
 * lose the small terms (one sqrt instead of one per element: the fits run once
 * per wedge, and the per-element form was most of their time), else hypot steps. */
static double column_norm(double A[][TC_LSQ_MAXCOLS], int from, int rows, int j) {
    double s = 0;
    for (int i = from; i < rows; i++) s += A[i][j] * A[i][j];
    if (s > 1e-280 && s < 1e280) return sqrt(s);
    s = 0;
    for (int i = from; i < rows; i++) s = tc__hypot(s, A[i][j]);
    return s;
}

/* Reduces A (rows x cols, row-major, leading dimension TC_LSQ_MAXCOLS) to R in
 * place and applies the same reflections to B (rows x nrhs, leading dimension
 * TC_LSQ_MAXRHS). Returns 0, or -1 when a column is negligible against the
 * largest one (rank deficient within rtol), or when less than `indep` of its own
 * norm lies outside the span of the columns before it (|R_jj| is that part:
 * the sine of the column's angle to them, so the test is scale free per column). */
static int householder(double A[][TC_LSQ_MAXCOLS], int rows, int cols, double B[][TC_LSQ_MAXRHS], int nrhs,
                       double rtol, double indep) {
    double colmax = 0, own[TC_LSQ_MAXCOLS];
    for (int j = 0; j < cols; j++) {
        own[j] = column_norm(A, 0, rows, j);
        if (own[j] > colmax) colmax = own[j];
    }
    for (int j = 0; j < cols; j++) {
        double norm = column_norm(A, j, rows, j);
        if (!(norm > rtol * colmax) || !(norm > indep * own[j])) return -1;
        double alpha = A[j][j] > 0 ? -norm : norm;
        double v0 = A[j][j] - alpha; /* reflector v = (v0, A[j+1..][j]) */
        double vnorm2 = v0 * v0;
        for (int i = j + 1; i < rows; i++) vnorm2 += A[i][j] * A[i][j];
        A[j][j] = alpha;
        if (vnorm2 == 0) continue;
        for (int k = j + 1; k < cols; k++) {
            double s = v0 * A[j][k];
            for (int i = j + 1; i < rows; i++) s += A[i][j] * A[i][k];
            s = 2 * s / vnorm2;
            A[j][k] -= s * v0;
            for (int i = j + 1; i < rows; i++) A[i][k] -= s * A[i][j];
        }
        for (int k = 0; k < nrhs; k++) {
            double s = v0 * B[j][k];
            for (int i = j + 1; i < rows; i++) s += A[i][j] * B[i][k];
            s = 2 * s / vnorm2;
            B[j][k] -= s * v0;
            for (int i = j + 1; i < rows; i++) B[i][k] -= s * A[i][j];
        }
    }
    return 0;
}

int tc__lsq_solve(double A[][TC_LSQ_MAXCOLS], int rows, int cols, double B[][TC_LSQ_MAXRHS], int nrhs,
                  double rtol, double X[][TC_LSQ_MAXRHS]) {
    return tc__lsq_solve_indep(A, rows, cols, B, nrhs, rtol, 0, X);
}

int tc__lsq_solve_indep(double A[][TC_LSQ_MAXCOLS], int rows, int cols, double B[][TC_LSQ_MAXRHS], int nrhs,
                        double rtol, double indep, double X[][TC_LSQ_MAXRHS]) {
    if (rows < cols || cols > TC_LSQ_MAXCOLS || rows > TC_LSQ_MAXROWS || nrhs > TC_LSQ_MAXRHS) return -1;
    if (householder(A, rows, cols, B, nrhs, rtol, indep) < 0) return -1;
    for (int k = 0; k < nrhs; k++)
        for (int j = cols - 1; j >= 0; j--) {
            double s = B[j][k];
            for (int i = j + 1; i < cols; i++) s -= A[j][i] * X[i][k];
            X[j][k] = s / A[j][j];
        }
    return 0;
}
