/* minmax.h — fmax and fmin as inline comparisons, the same results as glibc's for every
 * input but a signaling NaN (which no arithmetic makes), without a call into libm (gcc keeps
 * them calls unless NaNs are ruled out). tests/unit/test_minmax.c compares them. */
#ifndef TC_CORE_MINMAX_H
#define TC_CORE_MINMAX_H

/* C99's fmax: the larger operand, or the one that is not a NaN. Equal operands (+0 and -0
 * among them) give b, as glibc's x86-64 fmax does (maxsd), so results stay bit for bit; on
 * every architecture (aarch64's glibc gives +0 for fmax(-0, +0) and fmax(+0, -0)). */
static inline double tc__fmax(double a, double b) {
    return a > b || b != b ? a : b;
}

/* C99's fmin, likewise: the smaller operand, or the one that is not a NaN; b when equal. */
static inline double tc__fmin(double a, double b) {
    return a < b || b != b ? a : b;
}

#endif
