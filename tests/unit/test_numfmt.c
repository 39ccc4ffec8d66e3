/* test_numfmt.c — tests of tc_fmt_double (round trip, shortest digits, layout, JSON
 * syntax) and of tc_strbuf (growth, escaping, detach, sticky oom). */
#include <float.h>
#include <limits.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "io/numfmt.h"
#include "io/strbuf.h"

/* ---- helpers ------------------------------------------------------------------- */

static uint64_t rng_state;

static void rng_seed(unsigned long salt) {
    rng_state = ((uint64_t)tc_test_seed() + salt) * 0x9E3779B97F4A7C15ULL | 1;
}

/* xorshift64: fixed sequence for a fixed seed, never 0 from a non-zero state. */
static uint64_t rng(void) {
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return rng_state;
}

static double bits_to_double(uint64_t u) {
    double x;
    memcpy(&x, &u, sizeof x);
    return x;
}

static int same_bits(double a, double b) {
    return memcmp(&a, &b, sizeof a) == 0;
}

static int is_digit(char c) {
    return c >= '0' && c <= '9';
}

/* RFC 8259 number: -? (0 | [1-9][0-9]*) (. [0-9]+)? ([eE] [+-]? [0-9]+)? */
static int is_json_number(const char *s) {
    if (*s == '-') s++;
    if (*s == '0') s++;
    else if (*s >= '1' && *s <= '9') while (is_digit(*s)) s++;
    else return 0;
    if (*s == '.') {
        if (!is_digit(*++s)) return 0;
        while (is_digit(*s)) s++;
    }
    if (*s == 'e' || *s == 'E') {
        s++;
        if (*s == '+' || *s == '-') s++;
        if (!is_digit(*s)) return 0;
        while (is_digit(*s)) s++;
    }
    return *s == '\0';
}

/* The old definition, which tc_fmt_double still matches byte for byte on every
 * normal double whose significand is not 2^52 (numfmt.c's header says why): the
 * first of %.15g/%.16g/%.17g that strtod reads back to the same bits. */
static void cascade_fmt(char out[64], double x) {
    for (int p = 15; p <= 17; p++) {
        snprintf(out, 64, "%.*g", p, x);
        if (same_bits(strtod(out, NULL), x)) return;
    }
}

/* The shortest round trip, from printf and strtod alone: for p = 1, 2, ... the
 * p-digit decimals around |x| are its correct rounding r ("%.*e") and the
 * neighbour of r on x's other side; the first p where one reads back to x gives
 * the answer, r if it does (it is the nearer: Ryu/Schubfach's tie-break), else the
 * neighbour (possible only where the interval is lopsided, at c = 2^52). A p-digit
 * decimal in x's rounding interval makes the one of them on its side of x be in it
 * too, so none is missed. Writes the digits (no zeros at the end) into dig and
 * returns the decimal exponent. */
static int shortest_ref(double x, char dig[20]) {
    double ax = fabs(x);
    for (int p = 1; p <= 17; p++) {
        char s[48];
        snprintf(s, sizeof s, "%.*e", p - 1, ax);
        unsigned long long m = 0;
        const char *c = s;
        for (; *c != 'e'; c++)
            if (is_digit(*c)) m = m * 10 + (unsigned long long)(*c - '0');
        int e = atoi(c + 1), e10 = e - (p - 1);
        if (!same_bits(strtod(s, NULL), ax)) {
            double r = strtod(s, NULL);
            unsigned long long low = 1;        /* 10^(p-1): r = 1.00..e: the one below */
            for (int i = 1; i < p; i++) low *= 10;  /* is 9.99..9 with an exponent less */
            if (r < ax) m++;
            else if (m != low) m--;
            else m = low * 10 - 1, e10--;
            snprintf(s, sizeof s, "%llue%d", m, e10);
            if (!same_bits(strtod(s, NULL), ax)) continue;
        }
        int nd = snprintf(dig, 20, "%llu", m);
        e = e10 + nd - 1;
        while (nd > 1 && dig[nd - 1] == '0') dig[--nd] = '\0';
        return e;
    }
    CHECK_MSG(0, "%a: 17 digits did not round-trip", x);
    dig[0] = '\0';
    return 0;
}

/* The layout numfmt.h promises for digits dig, exponent e: "%.<P>g" with
 * P = max(15, digits), as C11 7.21.6.1 describes %g. */
static void layout(char out[64], int neg, const char *dig, int e) {
    int nd = (int)strlen(dig), p = nd < 15 ? 15 : nd, n = 0;
    if (neg) out[n++] = '-';
    if (e < -4 || e >= p) {
        n += snprintf(out + n, 64, "%c%s%se%c%02d", dig[0], nd > 1 ? "." : "", dig + 1,
                      e < 0 ? '-' : '+', abs(e));
    } else if (e < 0) {
        out[n++] = '0';
        out[n++] = '.';
        for (int i = -1; i > e; i--) out[n++] = '0';
        snprintf(out + n, 64, "%s", dig);
    } else {
        for (int i = 0; i <= e; i++) out[n++] = i < nd ? dig[i] : '0';
        if (nd > e + 1) n += snprintf(out + n, 64, ".%s", dig + e + 1);
        out[n] = '\0';
    }
}

static int is_lopsided_or_subnormal(double x) {
    uint64_t u;
    memcpy(&u, &x, sizeof u);
    int be = (int)(u >> 52 & 0x7ff);
    return be == 0 || (u & ((UINT64_C(1) << 52) - 1)) == 0;
}

/* Formats x, checks length, JSON syntax and round trip; with want_ref also that
 * the digits are shortest_ref's and the text its layout, and (outside lopsided
 * binade bottoms and subnormals) the old cascade's text. Returns 1 if all held. */
static int check_value(double x, int want_ref) {
    char out[TC_FMT_DOUBLE_SIZE + 8];
    memset(out, 'X', sizeof out);
    size_t n = tc_fmt_double(out, x);
    int ok = n < TC_FMT_DOUBLE_SIZE && out[n] == '\0' && strlen(out) == n &&
             memcmp(out + TC_FMT_DOUBLE_SIZE, "XXXXXXXX", 8) == 0;
    CHECK_MSG(ok, "%a: bad length %zu, or wrote past TC_FMT_DOUBLE_SIZE", x, n);
    if (!ok) return 0;
    ok = is_json_number(out) && same_bits(strtod(out, NULL), x);
    CHECK_MSG(ok, "%a: \"%s\" is not JSON or does not round-trip", x, out);
    if (ok && want_ref) {
        char dig[20], want[64];
        int e = shortest_ref(x, dig);
        if (x == 0) strcpy(want, signbit(x) ? "-0" : "0");
        else layout(want, signbit(x) != 0, dig, e);
        ok = strcmp(out, want) == 0;
        CHECK_MSG(ok, "%a: \"%s\", the shortest is \"%s\"", x, out, want);
        if (ok && !is_lopsided_or_subnormal(x)) {
            cascade_fmt(want, x);
            ok = strcmp(out, want) == 0;
            CHECK_MSG(ok, "%a: \"%s\", the cascade gives \"%s\"", x, out, want);
        }
    }
    return ok;
}

static void check_both_signs(double x) {
    check_value(x, 1);
    check_value(-x, 1);
}

/* TC_NUMFMT_FULL=1 (make numfmt-full) scales the random tests to the issue's
 * 10^7 round trips and 2 * 10^5 shortest references; the default run is ~1/10. */
static long scaled(long n) {
    const char *s = getenv("TC_NUMFMT_FULL");
    return s && *s == '1' ? n * 10 : n;
}

/* ---- tc_fmt_double --------------------------------------------------------------- */

TEST(numfmt_json_checker_works) {
    const char *good[] = {"0", "-0", "1", "10", "0.5", "-1.25", "1e+20", "1E-3", "5e-324", "12e3"};
    const char *bad[] = {"", "-", ".5", "5.", "01", "+1", "1e", "1e+", "1.e5", "inf", "nan",
                         "-inf", "0x1p3", "1,5", " 1", "1 ", "--1", "1.5.2"};
    for (size_t i = 0; i < sizeof good / sizeof *good; i++)
        CHECK_MSG(is_json_number(good[i]), "rejects \"%s\"", good[i]);
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++)
        CHECK_MSG(!is_json_number(bad[i]), "accepts \"%s\"", bad[i]);
}

/* The oracles themselves: shortest_ref and layout on values whose answer is known. */
TEST(numfmt_reference_works) {
    static const struct { double x; const char *want; } t[] = {
        {0.1, "0.1"}, {-2.5, "-2.5"}, {5e-324, "5e-324"}, {1e-5, "1e-05"}, {0.001, "0.001"},
        {1e15, "1e+15"}, {1e15 + 1, "1000000000000001"}, {123.456, "123.456"},
        {0.1 + 0.2, "0.30000000000000004"}, {DBL_MAX, "1.7976931348623157e+308"},
        {9007199254740994.0, "9007199254740994"}, {1.5e17, "1.5e+17"},
    };
    for (size_t i = 0; i < sizeof t / sizeof *t; i++) {
        char dig[20], got[64];
        int e = shortest_ref(t[i].x, dig);
        layout(got, t[i].x < 0, dig, e);
        CHECK_MSG(strcmp(got, t[i].want) == 0, "reference: %a gave \"%s\", want \"%s\"",
                  t[i].x, got, t[i].want);
    }
}

TEST(numfmt_nonfinite_is_null) {
    double v[] = {INFINITY, -INFINITY, NAN, -NAN, bits_to_double(0x7ff0000000000001ULL)};
    for (size_t i = 0; i < sizeof v / sizeof *v; i++) {
        char out[TC_FMT_DOUBLE_SIZE];
        size_t n = tc_fmt_double(out, v[i]);
        CHECK_MSG(n == 4 && strcmp(out, "null") == 0, "non-finite #%zu gave \"%s\"", i, out);
    }
}

/* Expected texts checked against glibc's %.Ng and Python's repr() (also shortest,
 * nearest). The subnormals are where the text differs from the old cascade. */
TEST(numfmt_known_values) {
    static const struct { double x; const char *want; } t[] = {
        {0.0, "0"}, {-0.0, "-0"}, {1.0, "1"}, {-1.0, "-1"}, {100.0, "100"},
        {0.1, "0.1"}, {0.5, "0.5"}, {-2.5, "-2.5"}, {0.3, "0.3"}, {123.456, "123.456"},
        {0.1 + 0.2, "0.30000000000000004"}, {1 / 3.0, "0.3333333333333333"},
        {100.0 / 3, "33.333333333333336"}, {1e300, "1e+300"}, {-1e-300, "-1e-300"},
        {1e-4, "0.0001"}, {1e-5, "1e-05"}, {5e-7, "5e-07"}, {1e21, "1e+21"},
        {1e22, "1e+22"}, {1e23, "1e+23"}, {1e15, "1e+15"}, {1e15 + 1, "1000000000000001"},
        {1234567890123450.0, "1.23456789012345e+15"}, {-1e16, "-1e+16"},
        {9007199254740992.0, "9007199254740992"}, {9007199254740994.0, "9007199254740994"},
        {4503599627370495.5, "4503599627370495.5"},
        {123456789012345678.0, "1.2345678901234568e+17"},
        {12345678901234567890.0, "1.2345678901234567e+19"},
        {1.00000762939453125, "1.0000076293945312"}, /* exact tie: half to even */
        {DBL_MAX, "1.7976931348623157e+308"}, {DBL_MIN, "2.2250738585072014e-308"},
        {5e-324, "5e-324"}, {DBL_TRUE_MIN, "5e-324"}, {-DBL_TRUE_MIN, "-5e-324"},
        {1e-323, "1e-323"}, {1.5e-323, "1.5e-323"}, {2.5e-323, "2.5e-323"},
        {0x0.fffffffffffffp-1022, "2.225073858507201e-308"}, /* largest subnormal */
        {0x1p-1000, "9.332636185032189e-302"},
        {0x1p-1067, "6.3e-322"}, {0x1p-1073, "1e-323"},
        {0x1p+1023, "8.98846567431158e+307"}, {0x1p-60, "8.673617379884035e-19"},
    };
    for (size_t i = 0; i < sizeof t / sizeof *t; i++) {
        char out[TC_FMT_DOUBLE_SIZE];
        size_t n = tc_fmt_double(out, t[i].x);
        CHECK_MSG(strcmp(out, t[i].want) == 0 && n == strlen(t[i].want),
                  "%a gave \"%s\", want \"%s\"", t[i].x, out, t[i].want);
        check_value(t[i].x, 1);
    }
}

/* The double nearest 10^e is printed as 10^e ("1e+300", "0.0001", "100"),
 * subnormal ones too, now that the shortest form is asked for. */
TEST(numfmt_powers_of_ten) {
    for (int e = -323; e <= 308; e++) {
        char src[16], want[16], out[TC_FMT_DOUBLE_SIZE];
        snprintf(src, sizeof src, "1e%d", e);
        double x = strtod(src, NULL);
        check_both_signs(x);
        if (e >= -4 && e < 15) {
            if (e < 0) snprintf(want, sizeof want, "0.%0*d", -e, 1);
            else snprintf(want, sizeof want, "1%0*d", e, 0);
            if (e == 0) strcpy(want, "1");
        } else {
            snprintf(want, sizeof want, "1e%c%02d", e < 0 ? '-' : '+', abs(e));
        }
        tc_fmt_double(out, x);
        CHECK_MSG(strcmp(out, want) == 0, "10^%d gave \"%s\", want \"%s\"", e, out, want);
    }
}

/* Every binade edge (where k's estimate and the lopsided interval change), the
 * neighbours of each power of 10, and the first and last subnormals. */
TEST(numfmt_binade_and_decade_edges) {
    for (int e = -1074; e <= 1023; e++) {
        double x = ldexp(1.0, e);
        check_both_signs(x);
        check_both_signs(nextafter(x, 0));
        check_both_signs(nextafter(x, INFINITY));
        check_value(nextafter(nextafter(x, INFINITY), INFINITY), 1);
    }
    for (int e = -323; e <= 308; e++) {
        char src[16];
        snprintf(src, sizeof src, "1e%d", e);
        double x = strtod(src, NULL);
        check_both_signs(nextafter(x, 0));
        check_both_signs(nextafter(x, INFINITY));
    }
    for (uint64_t c = 1; c <= 3000; c++) {
        check_value(bits_to_double(c), 1);
        check_value(bits_to_double((UINT64_C(1) << 52) - c), 1);
    }
    check_both_signs(DBL_MAX);
    check_both_signs(nextafter(DBL_MAX, 0));
    check_both_signs(DBL_TRUE_MIN);
}

TEST(numfmt_integers_match_reference) {
    rng_seed(1);
    for (int i = 0; i < 20000; i++) {
        uint64_t r = rng();
        check_both_signs((double)(r >> 11));                     /* [0, 2^53) */
        check_both_signs((double)((r >> 14) % 100000000000000ULL * 10 + 1000000000000000ULL));
        check_both_signs((double)(r % 2000) + 1e15 - 1000);      /* around 10^15 */
        check_both_signs((double)(r >> (11 + r % 53)));          /* all magnitudes */
        check_value((double)(r >> 1), 1);                        /* above 2^53 */
    }
    for (int d = -64; d <= 64; d++) check_both_signs(9007199254740992.0 + 2 * d);
    /* the integer test reads the bits after the point: in each binade up to 2^53 the
     * values one fraction bit, one ulp and one half away from an integer */
    for (int e = 0; e <= 54; e++) {
        double x = ldexp(1.0, e);
        check_both_signs(x + 0.5), check_both_signs(x - 0.5), check_both_signs(x - 1), check_both_signs(x + 1);
        check_both_signs(nextafter(x, INFINITY)), check_both_signs(nextafter(x + 1, INFINITY));
        check_both_signs(nextafter(x, 0)), check_both_signs(nextafter(x - 1, 0));
    }
    check_both_signs(0.0), check_both_signs(0.25), check_both_signs(1e-300);
}

/* Results of arithmetic, short ("nice") decimals, and exact ties at each precision. */
TEST(numfmt_typical_values_match_reference) {
    rng_seed(2);
    for (int i = 0; i < 20000; i++) {
        check_value(i * 0.1 / 3, 1);
        check_value(i / 7.0 + 0.01, 1);
        check_value(sqrt((double)i) * 1e-3, 1);
    }
    for (int i = 0; i < 20000; i++) {
        char s[40];
        uint64_t r = rng();
        snprintf(s, sizeof s, "%llue%d", (unsigned long long)(r >> 20) % 100000000ULL,
                 (int)(r % 620) - 330);
        check_both_signs(strtod(s, NULL));                      /* short decimals, any scale */
        check_value(exp2((double)(r >> 11) / 9007199254740992.0 * 120 - 60), 1);
    }
    for (int i = 0; i < 10000; i++) {
        uint64_t r = rng();
        double k = (double)(r % 40000000000000ULL + 100000000000000ULL); /* 15 digits */
        check_value(k + 0.5, 1);
        check_value(k + 0.25, 1);
        check_value(k / 10 + 0.125, 1);
        check_value(1 + (double)(r >> 11 & 0xfffff) * 0x1p-20, 1);
        check_value(ldexp(1 + (double)(r >> 40) * 0x1p-24, (int)(r % 160) - 80), 1);
    }
}

/* Random bit patterns over all finite doubles, and random subnormals, against the
 * shortest reference (slow: up to 17 printf + strtod each). */
TEST(numfmt_random_bits_match_reference) {
    rng_seed(5);
    long n = scaled(20000);
    for (long i = 0; i < n;) {
        double x = bits_to_double(rng());
        if (!isfinite(x)) continue;
        i++;
        if (!check_value(x, 1)) break;
        if (!check_value(bits_to_double(rng() >> 12), 1)) break;   /* subnormal */
    }
}

/* The property for arbitrary doubles: valid JSON and the same bits back, for
 * 10^6 (10^7 with TC_NUMFMT_FULL=1) random bit patterns. */
TEST(numfmt_roundtrips_random_bits) {
    rng_seed(3);
    long tested = 0, n = scaled(1000000);
    for (long i = 0; tested < n; i++) {
        double x = bits_to_double(rng());
        if (!isfinite(x)) continue;
        tested++;
        if (!check_value(x, 0)) break;                       /* one report is enough */
    }
    CHECK(tested == n);
}

/* ---- tc_strbuf -------------------------------------------------------------------- */

static int invariant_holds(const tc_strbuf *b) {
    if (b->cap == 0) return b->buf == NULL && b->len == 0;
    return b->buf && b->len < b->cap && b->buf[b->len] == '\0';
}

TEST(strbuf_init_free_reset) {
    tc_strbuf b;
    tc_strbuf_init(&b);
    CHECK(b.buf == NULL && b.len == 0 && b.cap == 0 && b.oom == 0);
    tc_strbuf_free(&b);                                       /* free of empty is fine */
    CHECK(invariant_holds(&b));
    tc_strbuf_puts(&b, "hello");
    size_t cap = b.cap;
    tc_strbuf_reset(&b);
    CHECK(b.len == 0 && b.cap == cap && b.buf && b.buf[0] == '\0');
    tc_strbuf_free(&b);
    CHECK(b.buf == NULL && b.cap == 0);
}

TEST(strbuf_grows_geometrically) {
    tc_strbuf b;
    tc_strbuf_init(&b);
    int growths = 0;
    size_t cap = 0;
    for (int i = 0; i < 200000; i++) {
        tc_strbuf_append(&b, "abc", (size_t)(i % 4)); /* 0..3 bytes */
        tc_strbuf_putc(&b, (char)('a' + i % 26));
        if (b.cap != cap) growths++, cap = b.cap;
        if (!invariant_holds(&b)) break;
    }
    CHECK(invariant_holds(&b));
    CHECK(!b.oom && b.len == 200000 / 4 * 6 + 200000);
    CHECK_MSG(growths <= 20, "%d reallocations for %zu bytes", growths, b.len);
    size_t at = 0;
    int ok = 1;
    for (int i = 0; i < 200000 && ok; i++) {
        ok = memcmp(b.buf + at, "abc", (size_t)(i % 4)) == 0;
        at += (size_t)(i % 4);
        ok = ok && b.buf[at++] == 'a' + i % 26;
    }
    CHECK_MSG(ok, "content differs at byte %zu", at);
    tc_strbuf_free(&b);
}

TEST(strbuf_numbers) {
    tc_strbuf b;
    tc_strbuf_init(&b);
    tc_strbuf_int(&b, 0);
    tc_strbuf_putc(&b, ' ');
    tc_strbuf_int(&b, -42);
    tc_strbuf_putc(&b, ' ');
    tc_strbuf_int(&b, LLONG_MAX);
    tc_strbuf_putc(&b, ' ');
    tc_strbuf_int(&b, LLONG_MIN);
    tc_strbuf_putc(&b, ' ');
    tc_strbuf_double(&b, 0.1);
    tc_strbuf_putc(&b, ' ');
    tc_strbuf_double(&b, -0.0);
    tc_strbuf_putc(&b, ' ');
    tc_strbuf_double(&b, NAN);
    CHECK_MSG(strcmp(b.buf, "0 -42 9223372036854775807 -9223372036854775808 0.1 -0 null") == 0,
              "got \"%s\"", b.buf);
    CHECK(invariant_holds(&b) && b.len == strlen(b.buf));
    /* Many doubles in a row, read back: each lands exactly at len. */
    tc_strbuf_reset(&b);
    rng_seed(4);
    double v[5000];
    for (int i = 0; i < 5000; i++) {
        do v[i] = bits_to_double(rng()); while (!isfinite(v[i]));
        tc_strbuf_double(&b, v[i]);
        tc_strbuf_putc(&b, ',');
    }
    char *p = b.buf;
    int ok = invariant_holds(&b);
    for (int i = 0; i < 5000 && ok; i++) {
        char *end;
        ok = same_bits(strtod(p, &end), v[i]) && *end == ',';
        p = end + 1;
    }
    CHECK(ok && p == b.buf + b.len);
    tc_strbuf_free(&b);
}

TEST(strbuf_printf_grows) {
    tc_strbuf b;
    tc_strbuf_init(&b);
    tc_strbuf_printf(&b, "%s-%d", "x", 7);
    tc_strbuf_printf(&b, "[%0500d]", 5);                      /* longer than the spare room */
    CHECK(!b.oom && b.len == 3 + 502 && invariant_holds(&b));
    CHECK(strncmp(b.buf, "x-7[000", 7) == 0 && strcmp(b.buf + b.len - 2, "5]") == 0);
    tc_strbuf_printf(&b, "%s", "");
    CHECK(b.len == 505);
    tc_strbuf_free(&b);
}

TEST(strbuf_json_string_escapes) {
    tc_strbuf b;
    tc_strbuf_init(&b);
    tc_strbuf_json_string(&b, "a\"b\\c\nd\te\x01" "f\x1f\r\b\f/\x7f");
    CHECK_MSG(strcmp(b.buf, "\"a\\\"b\\\\c\\nd\\te\\u0001f\\u001f\\r\\b\\f/\x7f\"") == 0,
              "got %s", b.buf);
    tc_strbuf_reset(&b);
    const char *utf8 = "h\xc3\xa9llo \xe2\x82\xac \xf0\x9f\x98\x80"; /* héllo € 😀 */
    tc_strbuf_json_string(&b, utf8);
    CHECK(b.len == strlen(utf8) + 2 && b.buf[0] == '"' && b.buf[b.len - 1] == '"' &&
          memcmp(b.buf + 1, utf8, strlen(utf8)) == 0);
    tc_strbuf_reset(&b);
    tc_strbuf_json_string(&b, "");
    tc_strbuf_json_string(&b, NULL);
    CHECK(strcmp(b.buf, "\"\"null") == 0);
    tc_strbuf_free(&b);
}

TEST(strbuf_detach) {
    tc_strbuf b;
    size_t len = 99;
    tc_strbuf_init(&b);
    tc_strbuf_puts(&b, "payload");
    char *s = tc_strbuf_detach(&b, &len);
    CHECK(s && strcmp(s, "payload") == 0 && len == 7);
    CHECK(b.buf == NULL && b.len == 0 && b.cap == 0 && !b.oom);
    free(s);
    s = tc_strbuf_detach(&b, &len);                           /* empty gives "" */
    CHECK(s && s[0] == '\0' && len == 0);
    free(s);
    tc_strbuf_puts(&b, "x");
    b.oom = 1;
    s = tc_strbuf_detach(&b, &len);                           /* failed gives NULL */
    CHECK(s == NULL && len == 0 && b.buf == NULL && !b.oom);
}

TEST(strbuf_oom_is_sticky) {
    tc_strbuf b;
    tc_strbuf_init(&b);
    tc_strbuf_puts(&b, "kept");
    CHECK(tc_strbuf_reserve(&b, SIZE_MAX) == -1 && b.oom);   /* a real failure: overflow */
    CHECK(strcmp(b.buf, "kept") == 0 && invariant_holds(&b));
    size_t cap = b.cap;
    tc_strbuf_append(&b, "xy", 2);
    tc_strbuf_puts(&b, "xy");
    tc_strbuf_putc(&b, 'x');
    tc_strbuf_printf(&b, "%d", 12);
    tc_strbuf_double(&b, 1.5);
    tc_strbuf_int(&b, 12);
    tc_strbuf_json_string(&b, "q");
    CHECK(tc_strbuf_reserve(&b, 1) == -1);
    CHECK(b.oom && b.len == 4 && b.cap == cap && strcmp(b.buf, "kept") == 0);
    tc_strbuf_free(&b);
    /* Set by hand on an empty buffer: nothing is allocated either. */
    tc_strbuf_init(&b);
    b.oom = 1;
    tc_strbuf_putc(&b, 'x');
    tc_strbuf_double(&b, 2.0);
    CHECK(b.buf == NULL && b.len == 0 && b.cap == 0);
}
