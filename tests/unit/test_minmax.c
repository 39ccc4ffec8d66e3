/* test_minmax.c — tc__fmax and tc__fmin give libm's fmax and fmin bit for bit (but +0 against -0,
 * where glibc differs by architecture): infinities, quiet NaNs on either side, random doubles. */
#include <stdint.h>
#include <string.h>

#include "check.h"
#include "core/minmax.h"

static uint64_t bits(double v) {
    uint64_t u;
    memcpy(&u, &v, sizeof u);
    return u;
}

/* Same bits, or both NaN (which NaN libm returns when both are is not specified). */
static int same(double a, double b) {
    return bits(a) == bits(b) || (a != a && b != b);
}

/* fmax and fmin through a volatile pointer: the libm calls, not a folded constant. */
static double (*volatile libm_max)(double, double) = fmax;
static double (*volatile libm_min)(double, double) = fmin;

/* libm's answer, but for two zeros: C leaves the sign of fmax(+0, -0) open and glibc's differs
 * by architecture (x86-64's maxsd gives the second operand, aarch64's fmaxnm +0 for fmax and -0
 * for fmin). tocher gives the second operand on every machine, so its bytes do not depend on it. */
static double want(double (*libm)(double, double), double a, double b) {
    return a == 0 && b == 0 ? b : libm(a, b);
}

static void check_pair(double a, double b) {
    double wmax = want(libm_max, a, b), wmin = want(libm_min, a, b);
    CHECK_MSG(same(tc__fmax(a, b), wmax), "fmax(%a, %a): %a, want %a", a, b, tc__fmax(a, b), wmax);
    CHECK_MSG(same(tc__fmin(a, b), wmin), "fmin(%a, %a): %a, want %a", a, b, tc__fmin(a, b), wmin);
}

TEST(minmax_special_values_as_libm) {
    const double v[] = {0.0, -0.0, 1.0, -1.0, 0x1p-1074, -0x1p-1074, 1e308, -1e308, INFINITY, -INFINITY, NAN, -NAN};
    const int n = (int)(sizeof v / sizeof v[0]);
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) check_pair(v[i], v[j]);
    CHECK(tc__fmax(NAN, 2.0) == 2.0 && tc__fmax(2.0, NAN) == 2.0); /* a NaN is ignored */
    CHECK(tc__fmin(NAN, 2.0) == 2.0 && tc__fmin(2.0, NAN) == 2.0);
}

TEST(minmax_random_doubles_as_libm) {
    uint64_t s = tc_test_seed() | 1u;
    for (int i = 0; i < 200000; i++) {
        double d[2];
        for (int k = 0; k < 2; k++) { /* xorshift64: every bit pattern, NaNs and subnormals included */
            s ^= s << 13, s ^= s >> 7, s ^= s << 17;
            /* a NaN made quiet: glibc answers NaN for a signaling one (IEEE 754-2008), which
             * no arithmetic makes and no parser of tocher's gives */
            uint64_t u = (s & 0x7ff0000000000000u) == 0x7ff0000000000000u && (s << 12) ? s | 1ull << 51 : s;
            memcpy(&d[k], &u, sizeof d[k]);
        }
        if (i % 4 == 1) d[1] = d[0];  /* equal operands */
        if (i % 4 == 2) d[1] = -d[0]; /* opposite signs */
        check_pair(d[0], d[1]);
    }
}
