/* lsq.h — small dense least squares (Householder QR) for tangent estimation.
 * Fixed maximum sizes so callers can keep everything on the stack. */
#ifndef TC_CORE_LSQ_H
#define TC_CORE_LSQ_H

#include "tocher.h"

#define TC_LSQ_MAXROWS 64
#define TC_LSQ_MAXCOLS 5
#define TC_LSQ_MAXRHS TC_MAX_CHANNELS

/* Minimizes |A X - B| column by column. A and B are overwritten. Returns 0, or
 * -1 if the sizes are out of range or A is rank deficient relative to rtol. */
int tc__lsq_solve(double A[][TC_LSQ_MAXCOLS], int rows, int cols, double B[][TC_LSQ_MAXRHS], int nrhs,
                  double rtol, double X[][TC_LSQ_MAXRHS]);

#endif
