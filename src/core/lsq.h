/* lsq.h — small dense least squares (Householder QR) for tangent estimation.
 * Fixed maximum sizes so callers can keep everything on the stack. */
#ifndef TC_CORE_LSQ_H
#define TC_CORE_LSQ_H

#include "tocher.h"

#define TC_LSQ_MAXROWS 64
#define TC_LSQ_MAXCOLS 9 /* a cubic: 2 + 3 + 4 terms without the constant */
#define TC_LSQ_MAXRHS TC_MAX_CHANNELS

/* Minimizes |A X - B| column by column. A and B are overwritten. Returns 0, or
 * -1 if the sizes are out of range or A is rank deficient relative to rtol. */
int tc__lsq_solve(double A[][TC_LSQ_MAXCOLS], int rows, int cols, double B[][TC_LSQ_MAXRHS], int nrhs,
                  double rtol, double X[][TC_LSQ_MAXRHS]);

/* The same, and also -1 when some column has less than `indep` (0..1) of its
 * norm outside the span of the columns before it: columns ordered from the
 * terms that must be determined to those that may be dropped, a caller can fall
 * back to fewer terms instead of fitting an ill-determined one (a cubic term on
 * samples that lie on three lines, for example). */
int tc__lsq_solve_indep(double A[][TC_LSQ_MAXCOLS], int rows, int cols, double B[][TC_LSQ_MAXRHS], int nrhs,
                        double rtol, double indep, double X[][TC_LSQ_MAXRHS]);

#endif
