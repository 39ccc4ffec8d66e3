/* numfmt_cascade.c — the baseline of bench/perf/numfmt.c: tc_fmt_double as it was before
 * Schubfach (issue 17), the first of %.15g/%.16g/%.17g that round-trips, kept to time it. */

/* How a candidate of p significant digits is obtained, fastest first:
 *  1. x an integer below 2^53: its digits are the answer (or, for 16-digit
 *     multiples of 10, its 15-digit exponent form).
 *  2. 2^-19 <= |x| < 2^49: exact 128-bit integer arithmetic rounds x to p
 *     digits (round half to even, as glibc printf does) and decides whether
 *     strtod would read them back as x — no printf, strtod or floating point.
 *  3. anything else: one snprintf("%.16e") gives 17 correct digits, from which
 *     the 15- and 16-digit roundings are derived unless that could be a double
 *     rounding; then snprintf is asked for exactly p digits. Such a candidate is
 *     checked by converting it back: with one IEEE multiply or divide when that
 *     is exactly strtod's answer (Clinger's fast path), else with strtod. 17
 *     digits always round-trip for binary64, so that candidate is not checked.
 *
 * Assumptions, all true for this program: the "C" locale (it never calls
 * setlocale) — though nothing here depends on it: printf output is read only
 * for its digits, and strtod only gets radix-free text like "123e-4"; the
 * default round-to-nearest mode (nothing calls fesetround); IEEE binary64
 * doubles. Not compiled with -ffast-math (checked below). */
#include "numfmt_cascade.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Clinger's fast path needs every double operation rounded once, to double. */
#if FLT_EVAL_METHOD == 0 && !defined(__FAST_MATH__)
#define TC_CLINGER 1
#else
#define TC_CLINGER 0
#endif

#if defined(__SIZEOF_INT128__)
__extension__ typedef unsigned __int128 u128;
#define TC_EXACT 1
#else
#define TC_EXACT 0
#endif

/* A candidate: q has exactly p digits (10^(p-1) <= q < 10^p) and stands for
 * d.ddd...e<e>, i.e. the value q * 10^(e - p + 1); e is what %e would print. */
typedef struct {
    uint64_t q;
    int p, e;
} dec;

static const uint64_t pow10_u64[20] = {
    1ULL, 10ULL, 100ULL, 1000ULL, 10000ULL, 100000ULL, 1000000ULL, 10000000ULL,
    100000000ULL, 1000000000ULL, 10000000000ULL, 100000000000ULL,
    1000000000000ULL, 10000000000000ULL, 100000000000000ULL,
    1000000000000000ULL, 10000000000000000ULL, 100000000000000000ULL,
    1000000000000000000ULL, 10000000000000000000ULL};

#if TC_CLINGER
/* 10^0 .. 10^22 are all exactly representable as doubles. */
static const double pow10_dbl[23] = {
    1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
    1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
#endif

/* ---- output ---------------------------------------------------------------- */

/* Writes the decimal digits of q (no NUL); returns how many. Two digits per
 * division: the digit loop is most of the cost of a short number. */
static size_t put_digits(char *out, uint64_t q) {
    static const char pairs[201] =
        "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
        "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
        "8081828384858687888990919293949596979899";
    char tmp[20];
    size_t i = sizeof tmp;
    for (; q >= 100; q /= 100) {
        i -= 2;
        memcpy(tmp + i, pairs + 2 * (q % 100), 2);
    }
    if (q >= 10) {
        i -= 2;
        memcpy(tmp + i, pairs + 2 * q, 2);
    } else {
        tmp[--i] = (char)('0' + q);
    }
    memcpy(out, tmp + i, sizeof tmp - i);
    return sizeof tmp - i;
}

/* q without its trailing decimal zeros (q > 0). After the loop fewer than 8
 * remain, and 4 + 2 + 1 covers those. */
static uint64_t strip_zeros(uint64_t q) {
    while (q % 100000000 == 0) q /= 100000000;
    if (q % 10000 == 0) q /= 10000;
    if (q % 100 == 0) q /= 100;
    if (q % 10 == 0) q /= 10;
    return q;
}

/* %e style of the nd significant digits dig: d[.ddd]e{+|-}XX (>= 2 exponent digits). */
static size_t put_exp_style(char *out, const char *dig, size_t nd, int e) {
    size_t n = 0;
    out[n++] = dig[0];
    if (nd > 1) {
        out[n++] = '.';
        memcpy(out + n, dig + 1, nd - 1);
        n += nd - 1;
    }
    out[n++] = 'e';
    out[n++] = e < 0 ? '-' : '+';
    unsigned ae = (unsigned)(e < 0 ? -e : e);
    if (ae < 10) out[n++] = '0';
    return n + put_digits(out + n, ae);
}

/* %f style of the nd significant digits dig with decimal exponent e, -4 <= e < 17.
 * A point is written only with digits on both sides of it. */
static size_t put_fixed_style(char *out, const char *dig, size_t nd, int e) {
    size_t n = 0;
    if (e < 0) {
        out[n++] = '0';
        out[n++] = '.';
        for (int i = -1; i > e; i--) out[n++] = '0';
        memcpy(out + n, dig, nd);
        return n + nd;
    }
    size_t nint = (size_t)e + 1;
    for (size_t i = 0; i < nint; i++) out[n++] = i < nd ? dig[i] : '0';
    if (nd > nint) {
        out[n++] = '.';
        memcpy(out + n, dig + nint, nd - nint);
        n += nd - nint;
    }
    return n;
}

/* What printf("%.*g", d.p, value) writes: trailing zeros dropped, %e style when
 * the exponent is < -4 or >= the precision (C11 7.21.6.1). */
static size_t put_g(char *out, dec d) {
    char dig[20];
    size_t nd = put_digits(dig, strip_zeros(d.q));
    if (d.e < -4 || d.e >= d.p) return put_exp_style(out, dig, nd, d.e);
    return put_fixed_style(out, dig, nd, d.e);
}

/* Fast path 1: n < 2^53 is an exact integer. Below 10^15 its 15-digit rounding is
 * n itself and %.15g prints it in full. From 10^15 on, %.15g drops the last digit,
 * which round-trips iff that digit is 0 (n/10 * 10 == n; otherwise the rounded
 * value is an even integer <= 2^53 + 8, hence exact, hence != n), and then it is
 * printed as d.dddde+15; else %.16g prints all 16 digits. */
static size_t put_integer(char *out, uint64_t n) {
    if (n >= pow10_u64[15] && n % 10 == 0) return put_g(out, (dec){n / 10, 15, 15});
    return put_digits(out, n);
}

/* ---- checking a candidate ------------------------------------------------------ */

/* Whether strtod(candidate) == ax. For q <= 2^53 and |exponent| <= 22 both
 * operands are exact doubles, so one correctly rounded * or / gives exactly the
 * nearest double (ties to even), which is what strtod returns. */
static int round_trips(dec d, double ax) {
    int e10 = d.e - d.p + 1;
#if TC_CLINGER
    if (d.q <= (UINT64_C(1) << 53) && e10 >= -22 && e10 <= 22) {
        double m = (double)d.q;
        return (e10 >= 0 ? m * pow10_dbl[e10] : m / pow10_dbl[-e10]) == ax;
    }
#endif
    char s[48];
    snprintf(s, sizeof s, "%llue%d", (unsigned long long)d.q, e10);
    return strtod(s, NULL) == ax;
}

/* ---- path 2: exact integer arithmetic ------------------------------------------ */

#if TC_EXACT
/* 10^s for 0 <= s <= 22 (< 2^74). */
static u128 pow10_u128(int s) {
    return s <= 19 ? (u128)pow10_u64[s] : (u128)pow10_u64[19] * pow10_u64[s - 19];
}

/* floor(log10(x)) for x = f * 2^-j in [2^e2, 2^(e2+1)), -19 <= e2 <= 48.
 * est = floor(e2 * log10 2) (1233/4096 is close enough over this range; C division
 * truncates, hence the correction for e2 < 0), and since the binade spans less
 * than one decade the answer is est or est + 1: it is est + 1 iff x >= 10^(est+1). */
static int decimal_exponent(uint64_t f, int j, int e2) {
    int est = e2 * 1233 / 4096 - (e2 < 0);
    int t = est + 1;
    int above = t >= 0 ? (u128)f >= (u128)pow10_u64[t] << j
                       : f * pow10_u128(-t) >= (u128)1 << j;
    return above ? t : est;
}

/* x = f * 2^-j (2^52 <= f < 2^53) with decimal exponent e, rounded to p digits,
 * half to even (as printf does), into *d. With s = p - 1 - e in [0, 22]:
 *   n = x * 10^s * 2^j = f * 10^s exactly (< 2^127), q = n >> j, r = n mod 2^j.
 * In these units one ulp of x is 10^s and |candidate - x| is r (rounded down) or
 * 2^j - r (rounded up). strtod gives x back iff that distance is under half the
 * gap to x's neighbour on that side, or equal with f even (ties go to even). The
 * gap is one ulp, but half an ulp below a power of two (f == 2^52).
 * Returns 1 if *d round-trips, 0 if not, -1 (d unset) if q did not come out with
 * p digits — i.e. e was wrong, so a mistake there costs speed, never a digit. */
static int exact_round(uint64_t f, int j, int e, int p, dec *d) {
    u128 ulp = pow10_u128(p - 1 - e), n = f * ulp, one = (u128)1 << j;
    uint64_t q = (uint64_t)(n >> j);
    u128 r = n & (one - 1);
    if (q < pow10_u64[p - 1] || q >= pow10_u64[p]) return -1;
    int up = 2 * r > one || (2 * r == one && (q & 1));
    u128 dist = up ? one - r : r;
    u128 scaled = dist * (!up && f == (UINT64_C(1) << 52) ? 4 : 2);
    q += (uint64_t)up;
    *d = q == pow10_u64[p] ? (dec){pow10_u64[p - 1], p, e + 1} : (dec){q, p, e};
    return scaled < ulp || (scaled == ulp && !(f & 1));
}

/* The cascade for 2^-19 <= ax < 2^49 (then e is in [-6, 14], so 0 <= s <= 22),
 * without printf, strtod or floating point. Returns 0 if ax is outside that
 * range, or if even 17 digits failed the check (impossible; printf decides then). */
static int shortest_exact(double ax, dec *d) {
    uint64_t bits;
    memcpy(&bits, &ax, sizeof bits);
    int e2 = (int)(bits >> 52) - 1023;      /* ax >= 0, so no sign bit */
    if (e2 < -19 || e2 > 48) return 0;
    uint64_t f = (bits & ((UINT64_C(1) << 52) - 1)) | (UINT64_C(1) << 52);
    int j = 52 - e2;                        /* ax = f * 2^-j, 4 <= j <= 71 */
    int e = decimal_exponent(f, j, e2);
    for (int p = 15; p <= 17; p++) {
        int rt = exact_round(f, j, e, p, d);
        if (rt < 0) return 0;
        if (rt) return 1;
    }
    return 0;
}
#endif

/* ---- path 3: printf for the digits ----------------------------------------------- */

/* The p-digit rounding of ax from snprintf("%.*e"), reading only its digits and
 * exponent, so whatever radix character the locale uses is skipped. */
static dec printf_digits(double ax, int p) {
    char s[40];
    dec d = {0, p, 0};
    snprintf(s, sizeof s, "%.*e", p - 1, ax);
    const char *c = s;
    for (; *c && *c != 'e'; c++)
        if (*c >= '0' && *c <= '9') d.q = d.q * 10 + (uint64_t)(*c - '0');
    if (*c == 'e') d.e = (int)strtol(c + 1, NULL, 10);
    return d;
}

/* The p-digit rounding (p = 15, 16) derived from the correctly rounded 17 digits.
 * Let t in [0, 1) be x's exact tail below digit p, in units of digit p, and
 * k = 17 - p. The 17-digit text shows t rounded to k digits, t', so
 * |t - t'| <= 10^-k / 2 (a carry out of the tail is already in the leading
 * digits, tail "00", and t >= 1 - 10^-k/2 > 1/2 means "round up" too). Hence
 * t' < 1/2 implies t < 1/2 and t' > 1/2 implies t > 1/2: only t' == 1/2 ("5" or
 * "50") leaves the direction unknown; then return 0 and let printf round. */
static int derive_round(dec d17, int p, dec *d) {
    uint64_t div = pow10_u64[17 - p], half = div / 2;
    uint64_t q = d17.q / div, tail = d17.q % div;
    if (tail == half) return 0;
    if (tail > half) q++;
    *d = q == pow10_u64[p] ? (dec){pow10_u64[p - 1], p, d17.e + 1} : (dec){q, p, d17.e};
    return 1;
}

/* The cascade for any finite ax > 0, with one snprintf in the common case. */
static dec shortest_printf(double ax) {
    dec d17 = printf_digits(ax, 17), d;
    for (int p = 15; p <= 16; p++) {
        if (!derive_round(d17, p, &d)) d = printf_digits(ax, p);
        if (round_trips(d, ax)) return d;
    }
    return d17;
}

/* ---- entry point -------------------------------------------------------------- */

size_t tc_fmt_double_cascade(char out[TC_FMT_DOUBLE_SIZE], double x) {
    if (!isfinite(x)) {
        memcpy(out, "null", 5);
        return 4;
    }
    size_t n = 0;
    if (signbit(x)) out[n++] = '-';         /* also -0.0, which %g prints as "-0" */
    double ax = fabs(x);
    if (ax < 0x1p53 && (double)(uint64_t)ax == ax) {
        n += put_integer(out + n, (uint64_t)ax);
    } else {
        dec d;
#if TC_EXACT
        if (!shortest_exact(ax, &d)) d = shortest_printf(ax);
#else
        d = shortest_printf(ax);
#endif
        n += put_g(out + n, d);
    }
    out[n] = '\0';
    return n;
}
