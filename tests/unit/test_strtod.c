/* test_strtod.c — io/strtod_fast.h against the C library's strtod, bit for bit: a million and
 * more random decimal strings, the classic hard cases, and JSON's number grammar. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "io/strtod_fast.h"

static uint64_t xs(uint64_t *s) {
    *s ^= *s << 13, *s ^= *s >> 7, *s ^= *s << 17;
    return *s;
}

/* tc_strtod_fast reads all of s and gives strtod's bits. */
static int same_as_strtod(const char *s) {
    double a = 0, b = strtod(s, NULL);
    size_t n = tc_strtod_fast(s, strlen(s), &a);
    if (n != strlen(s) || memcmp(&a, &b, sizeof a)) {
        tc_test_fail(__FILE__, __LINE__, "'%.80s': length %zu of %zu, %.17g, strtod %.17g", s, n, strlen(s), a, b);
        return 0;
    }
    return 1;
}

/* A random JSON number: sign, 1-40 digits with the point anywhere (JSON's leading-zero
 * rule kept), an exponent in -350..350 half the time. */
static void random_number(uint64_t *st, char *buf) {
    int n = 1 + (int)(xs(st) % 40), p = 0, point = (int)(xs(st) % (uint64_t)(n + 1));
    if (xs(st) & 1) buf[p++] = '-';
    for (int j = 0; j < n; j++) {
        if (j == point && j > 0) buf[p++] = '.';
        int lead = j == 0 && point != 1 && n > 1; /* a first digit followed by more integer digits */
        buf[p++] = (char)(lead ? '1' + (int)(xs(st) % 9) : '0' + (int)(xs(st) % 10));
    }
    if (xs(st) & 1) {
        int e = (int)(xs(st) % 701) - 350;
        p += sprintf(buf + p, "%c%s%d", xs(st) & 1 ? 'e' : 'E', e >= 0 && (xs(st) & 1) ? "+" : "", e);
    }
    buf[p] = '\0';
}

TEST(strtod_fast_random_million) {
    uint64_t st = 0x9E3779B97F4A7C15u ^ tc_test_seed();
    char buf[96];
    long bad = 0;
    unsigned long fb0 = tc__strtod_fallbacks();
    for (long k = 0; k < 1200000 && bad < 5; k++) {
        random_number(&st, buf);
        bad += !same_as_strtod(buf);
    }
    /* the fast algorithms decide most of them (a test of the fast path, not only of strtod) */
    unsigned long fb = tc__strtod_fallbacks() - fb0;
    CHECK_MSG(fb < 120000, "%lu of 1.2e6 went to strtod", fb);
}

TEST(strtod_fast_random_doubles_round_trip) {
    /* %.17g and %.16g of random bit patterns: near-halfway texts of every exponent */
    uint64_t st = 0xD1B54A32D192ED03u ^ tc_test_seed();
    char buf[64];
    long bad = 0;
    for (long k = 0; k < 300000 && bad < 5; k++) {
        uint64_t bits = xs(&st) & ~(UINT64_C(1) << 63);
        double d;
        memcpy(&d, &bits, sizeof d);
        if (!isfinite(d)) continue;
        snprintf(buf, sizeof buf, k & 1 ? "%.17g" : "%.16g", d);
        if (strchr(buf, 'e') || strchr(buf, '.') || 1) bad += !same_as_strtod(buf);
    }
}

TEST(strtod_fast_hard_cases) {
    static const char *const cases[] = {
        "2.2250738585072011e-308", "2.2250738585072012e-308", "4.9406564584124654e-324",
        "2.4703282292062327e-324", "2.4703282292062328e-324", /* half the least subnormal: 0 / 5e-324 */
        "1.7976931348623157e308", "1.7976931348623158e308", "1.7976931348623159e308", "1e309", "-1e400",
        "9007199254740993", "9007199254740992", "9007199254740994", "9007199254740995",
        "1.00000000000000011102230246251565404236316680908203125",  /* exactly halfway: to even (1) */
        "1.00000000000000011102230246251565404236316680908203124",
        "1.00000000000000011102230246251565404236316680908203126",
        "1.00000000000000033306690738754696212708950042724609375", /* halfway, rounds up to even */
        "0", "-0", "0.0", "-0.0", "0e0", "-0e-999", "0.000000000000000000000000000001", "1e-400", "-1e-400",
        "1e22", "1e23", "9e22", "1.7e308", "123456789012345678901234567890", "0.1", "0.2", "0.3",
        "3.0517578125e-05", "2.2204460492503131e-16", "4503599627370496.5", "4503599627370497.5",
        "7.2057594037927933e16", "1e-22", "1e-23", "8.98846567431158e307", "5e-324", "1e-325",
        "12345678901234567890", "18446744073709551615", "18446744073709551616", "99999999999999999999e-20",
        "1.4e-45", "3.4028234663852886e38", "2.225073858507201e-308", "6.631236846766476e-316",
        "1e-1000000000000", "1e1000000000000", "1E+2", "1e-0", "0.5e1",
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) same_as_strtod(cases[k]);
    double d = 0;
    CHECK(tc_strtod_fast("-0", 2, &d) == 2 && d == 0 && signbit(d));
    CHECK(tc_strtod_fast("1.7976931348623159e308", 22, &d) == 22 && isinf(d));
    CHECK(tc_strtod_fast("2.4703282292062328e-324", 23, &d) == 23 && d == 4.9406564584124654e-324);
}

TEST(strtod_fast_long_digit_strings) {
    /* 800 digits: the halfway point 1 + 2^-53 written out, then nudged by a last digit far away */
    char buf[1000];
    uint64_t st = 42 ^ tc_test_seed();
    strcpy(buf, "1.00000000000000011102230246251565404236316680908203125");
    size_t n = strlen(buf);
    while (n < 800) buf[n++] = '0';
    buf[n] = '\0';
    same_as_strtod(buf); /* still exactly halfway: 1 */
    buf[n - 1] = '1';
    same_as_strtod(buf); /* just above: 1 + 2^-52 */
    for (int k = 0; k < 2000; k++) { /* random 100..800-digit numbers with exponents */
        int len = 100 + (int)(xs(&st) % 700), p = 0;
        buf[p++] = (char)('1' + (int)(xs(&st) % 9));
        for (int j = 1; j < len; j++) buf[p++] = (char)('0' + (int)(xs(&st) % 10));
        sprintf(buf + p, "e%d", (int)(xs(&st) % 1400) - 1100);
        same_as_strtod(buf);
    }
    memset(buf, '9', 800); /* 999...9e-800 ~ 1 */
    strcpy(buf + 800, "e-800");
    same_as_strtod(buf);
}

TEST(strtod_fast_json_grammar) {
    static const char *const not_numbers[] = {"", "-", "+1", ".5", "-.5", "1.", "1.e5", "1e", "1e+", "e5", "x", "-x"};
    double d = 7;
    for (size_t k = 0; k < sizeof not_numbers / sizeof not_numbers[0]; k++)
        CHECK_MSG(tc_strtod_fast(not_numbers[k], strlen(not_numbers[k]), &d) == 0, "'%s' read", not_numbers[k]);
    /* only the JSON number at the start counts: "01" is 0 then "1"; the length says where it ends */
    CHECK(tc_strtod_fast("01", 2, &d) == 1 && d == 0);
    CHECK(tc_strtod_fast("1.5,2", 5, &d) == 3 && d == 1.5);
    CHECK(tc_strtod_fast("12345", 3, &d) == 3 && d == 123); /* not NUL-terminated: stops at len */
    CHECK(tc_strtod_fast("-12]", 4, &d) == 3 && d == -12);
}

/* Long exponents against many digits: the exponent's digits are accumulated up to a cap (the
 * value is 0 or inf beyond it anyway), but the cap must be far above any digit count a body
 * can carry. "0.<999 zeros>1e10000" is 10^9000 (inf) and "1<1000 zeros>e-10000" is 10^-9000
 * (0); an exponent cut short at four digits (1000) would make both exactly 1.0. */
TEST(strtod_fast_long_exponent_against_many_digits) {
    enum { Z = 1000 };
    char *buf = malloc(Z + 64);
    if (!buf) return;
    strcpy(buf, "0.");
    memset(buf + 2, '0', Z - 1);
    strcpy(buf + 2 + Z - 1, "1e10000");
    double d = 0;
    CHECK(tc_strtod_fast(buf, strlen(buf), &d) == strlen(buf) && d == INFINITY);
    same_as_strtod(buf);
    buf[0] = '1';
    memset(buf + 1, '0', Z);
    strcpy(buf + 1 + Z, "e-10000");
    d = 1;
    CHECK(tc_strtod_fast(buf, strlen(buf), &d) == strlen(buf) && d == 0 && !signbit(d));
    same_as_strtod(buf);
    strcpy(buf + 1 + Z, "e-1000"); /* exactly 1: the same digits, the exponent they balance */
    CHECK(tc_strtod_fast(buf, strlen(buf), &d) == strlen(buf) && d == 1);
    free(buf);
}
