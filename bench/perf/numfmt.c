/* numfmt.c — `make bench`'s number printing figure (issue 17: >= 25 M doubles/s): doubles/s of
 * tc_fmt_double, of the old cascade it replaced, and of snprintf("%.17g"), as one JSON object.
 *
 *     build/bench_numfmt [N]      (N doubles, default 10^7; each figure the best of 3 passes,
 *                                  in doubles per second of the thread's CPU time)
 *
 * Inputs: random bit patterns over all finite doubles (the worst case: 16-17 digits,
 * every exponent), and values as the API prints them (ordinates: arithmetic results
 * in [-10, 10]); both sets are generated once, outside the timing. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "io/numfmt.h"
#include "numfmt_cascade.h"
#include "benchio.h"

/* This thread's CPU time, not the wall clock: the bench machines are shared, and time
 * spent descheduled is not the printer's (each figure is still the best of 3 passes). */
static double now_s(void) {
    return bench_clock_s(CLOCK_THREAD_CPUTIME_ID);
}

static uint64_t rng_state = 0x9E3779B97F4A7C15ULL;

static uint64_t rng(void) {
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return rng_state;
}

static size_t fmt_printf(char out[TC_FMT_DOUBLE_SIZE], double x) {
    return (size_t)snprintf(out, TC_FMT_DOUBLE_SIZE, "%.17g", x);
}

typedef size_t (*fmt_fn)(char out[TC_FMT_DOUBLE_SIZE], double x);

/* Doubles per second, best of 3 passes over v. The byte count goes into *sink so
 * the compiler cannot drop the calls. */
static double rate(fmt_fn f, const double *v, size_t n, size_t *sink) {
    double best = 0;
    for (int pass = 0; pass < 3; pass++) {
        char out[TC_FMT_DOUBLE_SIZE];
        size_t bytes = 0;
        double t0 = now_s();
        for (size_t i = 0; i < n; i++) bytes += f(out, v[i]);
        double r = (double)n / (now_s() - t0);
        if (r > best) best = r;
        *sink += bytes;
    }
    return best;
}

int main(int argc, char **argv) {
    size_t n = argc > 1 ? (size_t)strtoull(argv[1], NULL, 10) : 10000000;
    double *bits = malloc(n * sizeof *bits), *ords = malloc(n * sizeof *ords);
    if (!n || !bits || !ords) return 1;
    for (size_t i = 0; i < n;) {
        uint64_t u = rng();
        memcpy(&bits[i], &u, sizeof u);
        if (isfinite(bits[i])) i++;
    }
    for (size_t i = 0; i < n; i++) {
        double t = (double)(rng() >> 11) * 0x1p-53;
        ords[i] = 10 * sin(7 * t) * exp(-t) + t * t / 3;
    }
    size_t sink = 0;
    const struct { const char *name; fmt_fn f; } fns[] = {
        {"schubfach", tc_fmt_double}, {"cascade", tc_fmt_double_cascade}, {"printf17", fmt_printf}};
    printf("{\"n\": %zu", n);
    for (size_t k = 0; k < sizeof fns / sizeof *fns; k++) {
        /* printf, and the cascade outside its exact range, are 10-40x slower: a tenth
         * of the inputs is plenty for their figures */
        int fast = fns[k].f == tc_fmt_double;
        size_t m = fast ? n : n / 10 + 1;
        printf(", \"%s_random_bits_per_s\": %.0f", fns[k].name, rate(fns[k].f, bits, m, &sink));
        m = fns[k].f != fmt_printf ? n : n / 10 + 1;
        printf(", \"%s_ordinates_per_s\": %.0f", fns[k].name, rate(fns[k].f, ords, m, &sink));
        fflush(stdout);
    }
    printf(", \"sink\": %zu}\n", sink % 10);
    free(bits);
    free(ords);
    return 0;
}
