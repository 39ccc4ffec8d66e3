/* qp.h — small dense convex quadratic programs (a few dozen variables), solved
 * exactly by the primal active-set method from the feasible point y = 0. */
#ifndef TC_CORE_QP_H
#define TC_CORE_QP_H

enum { TC_QP_MAXN = 32, TC_QP_MAXEQ = 32, TC_QP_MAXM = 192 };

/* Minimizes 1/2 y'Hy + f'y subject to Aeq y = 0 (neq rows) and C y <= b (m
 * rows), H [n][n] symmetric positive definite, all row-major. y = 0 must be
 * feasible (every b_i >= 0), and every iterate stays feasible, so y is usable
 * even when the solver stops early. Returns 0 at the optimum, 1 when it
 * stopped at the iteration cap (y feasible, not optimal), -1 when a linear
 * system was singular (y is the last feasible iterate). */
int tc__qp_solve(int n, const double *H, const double *f, int neq, const double *Aeq, int m, const double *C,
                 const double *b, double *y);

#endif
