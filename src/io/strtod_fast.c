/* strtod_fast.c — decimal text to double for the request reader's big arrays: Clinger's exact
 * fast path, then Eisel–Lemire with a 128-bit power of five, and libc strtod where undecided.
 *
 * The contract is strtod's result bit for bit (round to nearest, ties to even), so each
 * step answers only when it can prove its answer, and hands the rest to strtod:
 *
 * 1. The text is read into w, its first 19 significant digits (w < 10^19 < 2^64), and q, so
 *    that the value is w * 10^q, or lies strictly between w * 10^q and (w + 1) * 10^q when a
 *    nonzero digit was dropped ("truncated").
 * 2. Clinger (1990): when nothing was dropped, w <= 2^53 and |q| <= 22, both w and 10^|q| are
 *    exact doubles, so one IEEE multiplication or division rounds the exact value once:
 *    correctly rounded. (Needs FLT_EVAL_METHOD == 0: no extended-precision intermediates.)
 * 3. Eisel–Lemire (Lemire 2021, "Number Parsing at a Gigabyte per Second", section 5):
 *    w normalized to 64 bits times T ~ 5^q * 2^(127-e) (tools/gen_pow5.py, truncated, so
 *    T <= exact < T + 1) gives the top 128 bits of a 192-bit product P, with
 *    computed <= exact < computed + 2^64 in P's units, i.e. below one unit of the middle
 *    word. The 53 leading bits of P are the mantissa; rounding depends only on whether the
 *    rest is above or below one half. We answer only when the bits just below the mantissa
 *    are neither `half` nor `half - 1` (then the true rest is provably on the same side
 *    of one half as the computed one; exact ties are always among the refused). Results
 *    that would be subnormal or infinite are refused too (strtod handles the rare ones).
 *    For truncated input we convert w and w + 1: rounding is monotonic, so if both give
 *    the same double so does everything between them; otherwise strtod decides.
 * 4. Anything else: strtod on a NUL-terminated copy (halfway cases, 20+ digit ambiguity,
 *    |q| beyond the table, subnormals, overflow). */
#include <float.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "io/strtod_fast.h"
#include "io/pow5_table.h"

static _Thread_local unsigned long fallbacks;

unsigned long tc__strtod_fallbacks(void) { return fallbacks; }

/* libc strtod on s[0..n): 0 and *out set, or -1 when the copy could not be allocated. */
static int libc_strtod(const char *s, size_t n, double *out) {
    char small[128];
    char *buf = n < sizeof small ? small : malloc(n + 1);
    if (!buf) return -1;
    memcpy(buf, s, n);
    buf[n] = '\0';
    *out = strtod(buf, NULL);
    if (buf != small) free(buf);
    fallbacks++;
    return 0;
}

/* Eisel–Lemire for w * 10^q (w != 0, q within the table): the double's bits without the
 * sign, or -1 when the product cannot decide the rounding (see the top of the file). */
static int eisel_lemire(uint64_t w, int q, uint64_t *bits) {
    int lz = __builtin_clzll(w);
    uint64_t wn = w << lz;
    uint64_t thi = tc_pow5[q - TC_POW5_QMIN].hi, tlo = tc_pow5[q - TC_POW5_QMIN].lo;
    int e = tc_pow5[q - TC_POW5_QMIN].e;
    /* P = wn * (thi * 2^64 + tlo) < 2^192; top = P >> 64 cannot overflow 128 bits. */
    unsigned __int128 a = (unsigned __int128)wn * thi, b = (unsigned __int128)wn * tlo;
    unsigned __int128 top = a + (b >> 64);
    uint64_t hi = (uint64_t)(top >> 64);
    int upper = (int)(hi >> 63); /* P in [2^190, 2^192): hi's top bit is 62 or 63 */
    int sh = 10 + upper;         /* keeps 53 bits */
    uint64_t m = hi >> sh, r = hi & ((UINT64_C(1) << sh) - 1), half = UINT64_C(1) << (sh - 1);
    if (r == half || r == half - 1) return -1;
    m += r > half;
    /* value = P * 2^(q + e - 127 - lz) ~ m * 2^(sh + 128 + q + e - 127 - lz) */
    int E = sh + 1 + q + e - lz;
    if (m == UINT64_C(1) << 53) m >>= 1, E++;
    int biased = E + 52 + 1023;
    if (biased < 1 || biased > 2046) return -1; /* subnormal or overflow: strtod */
    *bits = (uint64_t)biased << 52 | (m & ((UINT64_C(1) << 52) - 1));
    return 0;
}

static const double exact_pow10[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                       1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

static int is_digit(char c) { return c >= '0' && c <= '9'; }

size_t tc_strtod_fast(const char *s, size_t len, double *out) {
    size_t i = 0;
    int neg = 0, nd = 0, truncated = 0;
    uint64_t w = 0;
    int64_t q = 0; /* decimal exponent adjustment from the digits */
    if (i < len && s[i] == '-') neg = 1, i++;
    if (i >= len || !is_digit(s[i])) return 0;
    if (s[i] == '0') i++; /* JSON: a leading zero stands alone ("01" is not a number) */
    else
        for (; i < len && is_digit(s[i]); i++) {
            if (nd < 19) w = w * 10 + (uint64_t)(s[i] - '0'), nd++;
            else q++, truncated |= s[i] != '0';
        }
    if (i < len && s[i] == '.') {
        i++;
        if (i >= len || !is_digit(s[i])) return 0;
        for (; i < len && is_digit(s[i]); i++) {
            if (nd == 0 && s[i] == '0') q--; /* leading zeros of 0.000123 */
            else if (nd < 19) w = w * 10 + (uint64_t)(s[i] - '0'), nd++, q--;
            else truncated |= s[i] != '0';
        }
    }
    if (i < len && (s[i] == 'e' || s[i] == 'E')) {
        i++;
        int eneg = 0;
        int64_t ev = 0;
        if (i < len && (s[i] == '+' || s[i] == '-')) eneg = s[i] == '-', i++;
        if (i >= len || !is_digit(s[i])) return 0;
        for (; i < len && is_digit(s[i]); i++)
            if (ev < 100000000) ev = ev * 10 + (s[i] - '0'); /* beyond: 0 or inf anyway */
        q += eneg ? -ev : ev;
    }
    if (w == 0) { /* all digits zero: strtod gives a signed zero whatever the exponent */
        *out = neg ? -0.0 : 0.0;
        return i;
    }
#if FLT_EVAL_METHOD == 0
    if (!truncated && w <= UINT64_C(1) << 53 && q >= -22 && q <= 22) {
        double d = (double)w;
        d = q >= 0 ? d * exact_pow10[q] : d / exact_pow10[-q];
        *out = neg ? -d : d;
        return i;
    }
#else
    (void)exact_pow10;
#endif
    uint64_t bits, bits1;
    if (q >= TC_POW5_QMIN && q <= TC_POW5_QMAX && !eisel_lemire(w, (int)q, &bits) &&
        (!truncated || (!eisel_lemire(w + 1, (int)q, &bits1) && bits1 == bits))) {
        bits |= (uint64_t)neg << 63;
        memcpy(out, &bits, sizeof *out);
        return i;
    }
    return libc_strtod(s, i, out) ? 0 : i;
}
