/* fhypot.h — sqrt(x^2 + y^2) without libm's hypot where no scaling is needed.
 * glibc's hypot, careful at every magnitude, took a quarter of the ordinates'
 * time (least squares norms, weights, validation); inside [1e-150, 1e150] the
 * squares cannot overflow or lose the larger term, so the plain form is used
 * (within an ulp of hypot), and hypot only outside. */
#ifndef TC_CORE_FHYPOT_H
#define TC_CORE_FHYPOT_H

#include <math.h>

#include "core/minmax.h"

static inline double tc__hypot(double x, double y) {
    double m = tc__fmax(fabs(x), fabs(y));
    return m > 1e-150 && m < 1e150 ? sqrt(x * x + y * y) : hypot(x, y);
}

#endif
