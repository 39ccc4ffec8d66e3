/* test_image.c — unit tests of src/image: the format table, the lazy plugin loader, and
 * every format encoded in memory then decoded back with OpenImageIO. */
#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "check.h"
#include "image/image.h"

/* The tests run in file order, and the order matters here: the tests before
 * image_png8 must not load the plugin (they check that it stays unloaded). */

/* ---- helpers ------------------------------------------------------------------- */

#define W 7
#define H 5
#define MAXCH 16

/* Sample values: negative, zero, the sRGB knee, mid-grey, one, HDR, and between. */
static const float values[] = {-0.25f, 0.0f, 0.5f, 1.0f, 3.7f, 0.0031308f, 0.002f, 0.18f,
                               0.75f, 0.999f, 1e-3f, 0.0404f, 2.0f, 0.3333f, 0.9f, 0.05f};
#define NVALUES (int)(sizeof values / sizeof values[0])

typedef struct {
    float px[H * W * MAXCH];
    float alpha[H * W];
    tc_img im;
} test_img;

/* A W x H image whose samples differ between neighbours, so a flipped, shifted or
 * transposed decode fails; alpha (0 or 1) when with_alpha. */
static void make_img(test_img *t, int nch, int with_alpha) {
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            for (int c = 0; c < nch; c++) t->px[(y * W + x) * nch + c] = values[(x + 3 * y + 5 * c) % NVALUES];
            t->alpha[y * W + x] = (x + y) % 3 ? 1.0f : 0.0f;
        }
    t->im = (tc_img){.width = W, .height = H, .channels = nch, .pixels = t->px,
                     .alpha = with_alpha ? t->alpha : NULL, .exposure = 0, .linear = 0};
}

static int encode(const tc_img *im, tc_img_format f, unsigned char **out, size_t *len) {
    char err[512] = "";
    int rc = tc_img_encode(im, f, out, len, err, sizeof err);
    CHECK_MSG(rc == 0, "encoding %s failed: %s", tc_img_format_name(f), err);
    return rc;
}

/* Encodes then decodes; 0 on success (d then holds the pixels to free). */
static int round_trip(const tc_img *im, tc_img_format f, tc_img_decoded *d) {
    unsigned char *bytes = NULL;
    size_t len = 0;
    if (encode(im, f, &bytes, &len) != 0) return -1;
    char err[512] = "";
    int rc = tc_img_decode(bytes, len, d, err, sizeof err);
    CHECK_MSG(rc == 0, "decoding %s failed: %s", tc_img_format_name(f), err);
    tc_img_free(bytes);
    return rc;
}

/* The channel names the encoder promises for EXR: Y; R,G,B; ch0.. (zero-padded past
 * 10 channels); then A. Writes them comma-separated into out. */
static void expected_names(int nch, int with_alpha, char *out, size_t cap) {
    static const char *const rgb[] = {"R", "G", "B"};
    size_t len = 0;
    out[0] = '\0';
    for (int c = 0; c < nch; c++) {
        const char *sep = c ? "," : "";
        if (nch == 1) len += (size_t)snprintf(out + len, cap - len, "Y");
        else if (nch == 3) len += (size_t)snprintf(out + len, cap - len, "%s%s", sep, rgb[c]);
        else len += (size_t)snprintf(out + len, cap - len, "%sch%0*d", sep, nch > 10 ? 2 : 1, c);
    }
    if (with_alpha) snprintf(out + len, cap - len, ",A");
}

/* The index in the encoder's input (nch = alpha) of decoded channel i, found by name
 * since OpenEXR may store channels in another order. -1 if unknown. */
static int source_channel(const tc_img_decoded *d, int i, const char *expected) {
    char want[256], got[256];
    snprintf(got, sizeof got, "%s", d->names);
    char *save = NULL, *name = strtok_r(got, ",", &save);
    for (int k = 0; k < i && name; k++) name = strtok_r(NULL, ",", &save);
    if (!name) return -1;
    snprintf(want, sizeof want, "%s", expected);
    int idx = 0;
    for (char *s2 = NULL, *w = strtok_r(want, ",", &s2); w; w = strtok_r(NULL, ",", &s2), idx++)
        if (strcmp(w, name) == 0) return idx;
    return -1;
}

/* The input sample that decoded channel src (an index from source_channel) came from. */
static float input_sample(const tc_img *im, int p, int src) {
    return src == im->channels ? im->alpha[p] : im->pixels[p * im->channels + src];
}

/* Checks a decoded float format (EXR, TIFF) against the input: names (by_name: the
 * EXR names; else just the count), alpha, and every sample within rel_tol (0 = exact). */
static void check_float_decode(const tc_img *im, const tc_img_decoded *d, int by_name, double rel_tol) {
    int with_alpha = im->alpha != NULL, total = im->channels + with_alpha;
    char names[256];
    expected_names(im->channels, with_alpha, names, sizeof names);
    CHECK(d->width == W && d->height == H);
    CHECK_MSG(d->channels == total, "%d channels decoded, %d written", d->channels, total);
    if (d->channels != total) return;
    int src[MAXCH + 1];
    for (int i = 0; i < total; i++) {
        src[i] = by_name ? source_channel(d, i, names) : i;
        CHECK_MSG(src[i] >= 0, "decoded channel %d (%s) unexpected; want %s", i, d->names, names);
        if (src[i] < 0) return;
    }
    if (with_alpha)
        CHECK_MSG(d->alpha_channel >= 0 && src[d->alpha_channel] == im->channels, "alpha channel %d of %s",
                  d->alpha_channel, d->names);
    else
        CHECK_MSG(d->alpha_channel == -1, "alpha channel %d without alpha", d->alpha_channel);
    for (int p = 0; p < W * H; p++)
        for (int i = 0; i < total; i++) {
            double want = input_sample(im, p, src[i]), got = d->pixels[p * total + i];
            double tol = rel_tol > 0 ? fmax(fabs(want) * rel_tol, ldexp(1, -24)) : 0;
            CHECK_MSG(fabs(got - want) <= tol, "pixel %d channel %d: %.9g decoded, %.9g written", p, i, got,
                      want);
        }
}

/* The PNG conversion as specified: v * 2^exposure, sRGB unless linear, clamp (NaN
 * -> 0), round to nearest of 0..maxval. */
static long png_reference(double v, double exposure, int linear, double maxval) {
    double x = v * exp2(exposure);
    if (!linear) x = x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055;
    if (!(x > 0)) x = 0;
    if (x > 1) x = 1;
    return (long)floor(x * maxval + 0.5);
}

static void check_png(int nch, int with_alpha, int sixteen, int linear, double exposure) {
    test_img t;
    make_img(&t, nch, with_alpha);
    t.px[1] = NAN;        /* clamps to 0 */
    t.px[2 * nch] = 1e30f; /* clamps to 1 */
    t.im.exposure = exposure;
    t.im.linear = linear;
    tc_img_decoded d;
    if (round_trip(&t.im, sixteen ? TC_IMG_PNG16 : TC_IMG_PNG, &d) != 0) return;
    int total = nch + with_alpha;
    double maxval = sixteen ? 65535 : 255;
    CHECK_MSG(strcmp(d.format, "png") == 0 && strcmp(d.type, sixteen ? "uint16" : "uint8") == 0,
              "decoded as %s %s", d.format, d.type);
    CHECK_MSG(d.channels == total && d.alpha_channel == (with_alpha ? nch : -1), "%d channels, alpha %d",
              d.channels, d.alpha_channel);
    CHECK_MSG(strcmp(d.colorspace, linear ? "Linear" : "sRGB") == 0, "colorspace '%s'", d.colorspace);
    for (int p = 0; d.channels == total && p < W * H; p++)
        for (int c = 0; c < total; c++) {
            long want = c < nch ? png_reference(t.px[p * nch + c], exposure, linear, maxval)
                                : png_reference(t.alpha[p], 0, 1, maxval);
            long got = lround(d.pixels[p * total + c] * maxval);
            CHECK_MSG(got == want, "png%s %dch pixel %d channel %d: %ld decoded, %ld expected",
                      sixteen ? "16" : "", nch, p, c, got, want);
        }
    tc_img_decoded_free(&d);
}

/* Every level's boundary: the encoder quantizes by thresholds found on the formula (encode.cpp's
 * Quantizer), so a sample a few floats either side of where each level begins, and random ones,
 * must all decode to png_reference's level. One grey channel, 1024 samples a row. */
static void check_png_boundaries(int sixteen, int linear, double exposure) {
    double maxval = sixteen ? 65535 : 255, scale = exp2(exposure);
    size_t n = 0, cap = (size_t)maxval * 7 + 4096;
    float *v = malloc(cap * sizeof *v);
    if (!v) return;
    for (int k = 1; k <= (int)maxval; k++) {
        double y = (k - 0.5) / maxval, x = linear ? y : y <= 12.92 * 0.0031308 ? y / 12.92 : pow((y + 0.055) / 1.055, 2.4);
        float f = (float)(x / scale);
        for (int i = 0; i < 3; i++) f = nextafterf(f, 0);
        for (int i = 0; i < 7; i++, f = nextafterf(f, INFINITY)) v[n++] = f;
    }
    unsigned r = 12345;
    while (n < cap) { /* random floats in [0, 1.25 / scale) */
        r = r * 1103515245u + 12345u;
        v[n++] = (float)((r >> 8) / 16777216.0 * 1.25 / scale);
    }
    int width = 1024, height = (int)((n + 1023) / 1024);
    float *px = calloc((size_t)width * (size_t)height, sizeof *px);
    if (!px) return free(v);
    memcpy(px, v, n * sizeof *v);
    tc_img im = {.width = width, .height = height, .channels = 1, .pixels = px, .exposure = exposure, .linear = linear};
    tc_img_decoded d;
    if (round_trip(&im, sixteen ? TC_IMG_PNG16 : TC_IMG_PNG, &d) == 0) {
        long bad = 0, first = -1;
        for (size_t p = 0; p < (size_t)width * (size_t)height; p++)
            if (lround(d.pixels[p] * maxval) != png_reference(px[p], exposure, linear, maxval)) bad++, first = first < 0 ? (long)p : first;
        CHECK_MSG(bad == 0, "png%s linear %d exposure %g: %ld of %zu samples at other levels (first %ld: %.9g)",
                  sixteen ? "16" : "", linear, exposure, bad, n, first, first >= 0 ? px[first] : 0.0);
        tc_img_decoded_free(&d);
    }
    free(v), free(px);
}

/* ---- names (no plugin) -------------------------------------------------------------- */

TEST(image_format_names) {
    for (int f = 0; f < TC_IMG_NFORMATS; f++) {
        tc_img_format back = TC_IMG_NFORMATS;
        const char *name = tc_img_format_name((tc_img_format)f);
        CHECK(name && tc_img_format_parse(name, &back) == 0 && back == (tc_img_format)f);
        CHECK(tc_img_mime((tc_img_format)f) != NULL);
    }
    tc_img_format f = TC_IMG_NFORMATS;
    CHECK(tc_img_format_parse("EXR-Half", &f) == 0 && f == TC_IMG_EXR_HALF);
    CHECK(tc_img_format_parse("jpeg", &f) == -1);
    CHECK(tc_img_format_parse("", &f) == -1);
    CHECK(tc_img_format_parse(NULL, &f) == -1);
    CHECK(tc_img_format_name(TC_IMG_NFORMATS) == NULL);
    CHECK(strcmp(tc_img_format_name(TC_IMG_PNG16), "png16") == 0);
    CHECK(strcmp(tc_img_mime(TC_IMG_PNG), "image/png") == 0);
    CHECK(strcmp(tc_img_mime(TC_IMG_PNG16), "image/png") == 0);
    CHECK(strcmp(tc_img_mime(TC_IMG_EXR_HALF), "image/x-exr") == 0);
    CHECK(strcmp(tc_img_mime(TC_IMG_TIFF), "image/tiff") == 0);
    CHECK(strcmp(tc_img_mime(TC_IMG_RAW), "application/octet-stream") == 0);
}

/* ---- checks and raw output: still no plugin ------------------------------------------ */

TEST(image_invalid_inputs_fail_without_loading) {
    test_img t;
    unsigned char *out = NULL;
    size_t len = 0;
    char err[256];
    make_img(&t, 2, 0);
    for (int f = TC_IMG_PNG; f <= TC_IMG_PNG16; f++) {
        err[0] = '\0';
        CHECK(tc_img_encode(&t.im, (tc_img_format)f, &out, &len, err, sizeof err) == -1 && out == NULL);
        CHECK_STR_CONTAINS(err, "png holds 1 or 3 channels; this mesh has 2");
        CHECK_STR_CONTAINS(err, "use exr, tiff or raw");
    }
    make_img(&t, 3, 0);
    t.im.channels = 17; /* refused before any sample is read */
    CHECK(tc_img_encode(&t.im, TC_IMG_EXR, &out, &len, err, sizeof err) == -1);
    CHECK_STR_CONTAINS(err, "not 17");
    make_img(&t, 3, 0);
    t.im.width = 0;
    CHECK(tc_img_encode(&t.im, TC_IMG_TIFF, &out, &len, err, sizeof err) == -1);
    t.im.width = W;
    t.im.exposure = INFINITY;
    CHECK(tc_img_encode(&t.im, TC_IMG_PNG, &out, &len, err, sizeof err) == -1);
    CHECK(tc_img_encode(&t.im, (tc_img_format)99, &out, &len, err, sizeof err) == -1);
    CHECK(tc_img_encode(NULL, TC_IMG_EXR, &out, &len, err, sizeof err) == -1);
    make_img(&t, 2, 1); /* OpenImageIO would write these 3 samples as RGB, alpha untagged */
    CHECK(tc_img_encode(&t.im, TC_IMG_TIFF, &out, &len, err, sizeof err) == -1);
    CHECK_STR_CONTAINS(err, "tiff cannot mark alpha on 2 channels");
    CHECK(!tc_img_loaded());
}

TEST(image_raw_without_plugin) {
    CHECK(!tc_img_loaded());
    test_img t;
    make_img(&t, 3, 1); /* alpha is not written to raw */
    unsigned char *out = NULL;
    size_t len = 0;
    if (encode(&t.im, TC_IMG_RAW, &out, &len) != 0) return;
    CHECK(len == (size_t)W * H * 3 * 4);
    for (size_t i = 0; len == (size_t)W * H * 3 * 4 && i < (size_t)W * H * 3; i++) {
        const unsigned char *b = out + 4 * i;
        uint32_t u = (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
        float v;
        memcpy(&v, &u, sizeof v);
        CHECK_MSG(memcmp(&v, &t.px[i], sizeof v) == 0, "raw sample %zu: %g, wrote %g", i, v, t.px[i]);
    }
    tc_img_free(out);
    CHECK_MSG(!tc_img_loaded(), "a raw encode loaded OpenImageIO");
}

/* In a child process (loading happens once per process): sets TOCHER_IMAGE_LIB to lib,
 * encodes a PNG, and sends back the error. Returns the child's exit status: 0 if the
 * encode failed without loading anything. */
static int encode_in_child(const char *lib, char *msg, size_t cap) {
    int fd[2];
    msg[0] = '\0';
    if (pipe(fd) != 0) return -1;
    fflush(NULL);
    pid_t pid = fork();
    if (pid == 0) {
        close(fd[0]);
        setenv("TOCHER_IMAGE_LIB", lib, 1);
        test_img t;
        make_img(&t, 3, 0);
        unsigned char *out = NULL;
        size_t len = 0;
        char err[2048] = "";
        int rc = tc_img_encode(&t.im, TC_IMG_PNG, &out, &len, err, sizeof err);
        ssize_t wrote = write(fd[1], err, strlen(err));
        _exit(rc == -1 && !tc_img_loaded() && wrote >= 0 ? 0 : 1);
    }
    close(fd[1]);
    size_t n = 0;
    for (ssize_t r; pid > 0 && n + 1 < cap && (r = read(fd[0], msg + n, cap - 1 - n)) > 0;) n += (size_t)r;
    msg[n] = '\0';
    close(fd[0]);
    int status = -1;
    if (pid < 0 || waitpid(pid, &status, 0) != pid) return -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(image_loader_reports_bad_library) {
    char msg[2048];
    const char *missing = "/nonexistent/tocher/libtocher_image.so";
    CHECK(encode_in_child(missing, msg, sizeof msg) == 0);
    CHECK_STR_CONTAINS(msg, "cannot load the image plugin");
    CHECK_STR_CONTAINS(msg, "TOCHER_IMAGE_LIB");
    CHECK_STR_CONTAINS(msg, missing);
    CHECK_STR_CONTAINS(msg, "No such file");
    /* A real shared library that is not the plugin. */
    CHECK(encode_in_child("libm.so.6", msg, sizeof msg) == 0);
    CHECK_STR_CONTAINS(msg, "libm.so.6: not a tocher image plugin");
    CHECK(!tc_img_loaded());
}

/* ---- PNG: the first tests to load the plugin -------------------------------------------- */

TEST(image_png8) {
    CHECK(!tc_img_loaded());
    check_png(3, 0, 0, 0, 0.0); /* the first non-raw encode loads the plugin */
    CHECK(tc_img_loaded());
    char err[1024] = "";
    CHECK_MSG(tc_img_load(err, sizeof err) == 0, "%s", err);
    for (int linear = 0; linear <= 1; linear++)
        for (int a = 0; a <= 1; a++) {
            check_png(1, a, 0, linear, 0.0);
            check_png(3, a, 0, linear, 0.5);
            check_png(3, a, 0, linear, -1.25);
        }
}

TEST(image_png_levels_at_every_boundary) {
    check_png_boundaries(0, 0, 0.0);
    check_png_boundaries(0, 1, 0.5);
    check_png_boundaries(0, 0, -1.25);
    check_png_boundaries(1, 0, 0.0);
    check_png_boundaries(1, 1, 1.0);
    check_png_boundaries(1, 0, -2.5);
}

TEST(image_png16) {
    for (int linear = 0; linear <= 1; linear++)
        for (int a = 0; a <= 1; a++) {
            check_png(1, a, 1, linear, 1.0);
            check_png(3, a, 1, linear, 0.0);
            check_png(3, a, 1, linear, -2.5);
        }
}

/* ---- float formats ------------------------------------------------------------------ */

static const int float_channel_counts[] = {1, 2, 3, 5, 12, 16};
#define NCOUNTS (int)(sizeof float_channel_counts / sizeof float_channel_counts[0])

static void check_float_format(tc_img_format f, const char *reader, const char *type, const char *compression,
                               double rel_tol) {
    for (int k = 0; k < NCOUNTS; k++)
        for (int a = 0; a <= 1; a++) {
            int nch = float_channel_counts[k];
            if (f == TC_IMG_TIFF && nch == 2 && a) continue; /* refused, see above */
            test_img t;
            make_img(&t, nch, a);
            t.im.exposure = 3; /* ignored by the float formats */
            tc_img_decoded d;
            if (round_trip(&t.im, f, &d) != 0) continue;
            CHECK_MSG(strcmp(d.format, reader) == 0 && strcmp(d.type, type) == 0, "%s %dch: decoded as %s %s",
                      tc_img_format_name(f), nch, d.format, d.type);
            CHECK_MSG(strcmp(d.compression, compression) == 0, "compression '%s'", d.compression);
            check_float_decode(&t.im, &d, f != TC_IMG_TIFF, rel_tol);
            tc_img_decoded_free(&d);
        }
}

TEST(image_exr_float) { check_float_format(TC_IMG_EXR, "openexr", "float", "piz", 0); }

/* Half keeps 11 significant bits: relative error at most 2^-11 after rounding. */
TEST(image_exr_half) { check_float_format(TC_IMG_EXR_HALF, "openexr", "half", "zip", ldexp(1, -11)); }

TEST(image_tiff_float) { check_float_format(TC_IMG_TIFF, "tiff", "float", "zip", 0); }

TEST(image_exr_channel_names) {
    static const struct {
        int nch, alpha;
        const char *names;
    } cases[] = {{1, 0, "Y"}, {1, 1, "Y,A"}, {3, 1, "R,G,B,A"}, {2, 0, "ch0,ch1"}, {12, 0, "ch00,"}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char names[256];
        expected_names(cases[i].nch, cases[i].alpha, names, sizeof names);
        CHECK_MSG(strncmp(names, cases[i].names, strlen(cases[i].names)) == 0, "%s", names);
        test_img t;
        make_img(&t, cases[i].nch, cases[i].alpha);
        tc_img_decoded d;
        if (round_trip(&t.im, TC_IMG_EXR, &d) != 0) continue;
        /* The same set of names, whatever order the file keeps them in. */
        for (int c = 0; c < d.channels; c++) CHECK(source_channel(&d, c, names) >= 0);
        CHECK(d.channels == cases[i].nch + cases[i].alpha);
        tc_img_decoded_free(&d);
    }
}

/* ---- robustness --------------------------------------------------------------------- */

TEST(image_decode_rejects_garbage) {
    char err[256] = "";
    tc_img_decoded d;
    static const unsigned char junk[] = "this is not an image";
    CHECK(tc_img_decode(junk, sizeof junk, &d, err, sizeof err) == -1 && d.pixels == NULL);
    CHECK_STR_CONTAINS(err, "not a PNG, OpenEXR or TIFF");
    /* A truncated EXR (a truncated PNG fails too, but libpng prints to stderr). */
    test_img t;
    make_img(&t, 3, 0);
    unsigned char *bytes = NULL;
    size_t len = 0;
    if (encode(&t.im, TC_IMG_EXR, &bytes, &len) != 0) return;
    err[0] = '\0';
    CHECK(tc_img_decode(bytes, len / 2, &d, err, sizeof err) == -1 && d.pixels == NULL);
    CHECK(strlen(err) > 0);
    tc_img_free(bytes);
}

/* Encodes in several threads at once; every result must equal the serial one. */
typedef struct {
    const tc_img *im;
    const unsigned char *want[TC_IMG_NFORMATS];
    size_t want_len[TC_IMG_NFORMATS];
    int mismatches;
} thread_job;

static void *encode_all(void *arg) {
    thread_job *job = arg;
    for (int rep = 0; rep < 4; rep++)
        for (int f = 0; f < TC_IMG_NFORMATS; f++) {
            unsigned char *out = NULL;
            size_t len = 0;
            if (tc_img_encode(job->im, (tc_img_format)f, &out, &len, NULL, 0) != 0 || len != job->want_len[f] ||
                memcmp(out, job->want[f], len) != 0)
                job->mismatches++;
            tc_img_free(out);
        }
    return NULL;
}

TEST(image_encode_concurrently) {
    test_img t;
    make_img(&t, 3, 1);
    thread_job jobs[4];
    unsigned char *want[TC_IMG_NFORMATS] = {0};
    size_t want_len[TC_IMG_NFORMATS] = {0};
    for (int f = 0; f < TC_IMG_NFORMATS; f++)
        if (encode(&t.im, (tc_img_format)f, &want[f], &want_len[f]) != 0) return;
    pthread_t th[4];
    for (int i = 0; i < 4; i++) {
        jobs[i] = (thread_job){.im = &t.im, .mismatches = 0};
        memcpy(jobs[i].want, want, sizeof want);
        memcpy(jobs[i].want_len, want_len, sizeof want_len);
        CHECK(pthread_create(&th[i], NULL, encode_all, &jobs[i]) == 0);
    }
    for (int i = 0; i < 4; i++) {
        pthread_join(th[i], NULL);
        CHECK_MSG(jobs[i].mismatches == 0, "thread %d: %d encodes differ from the serial ones", i,
                  jobs[i].mismatches);
    }
    for (int f = 0; f < TC_IMG_NFORMATS; f++) tc_img_free(want[f]);
}

/* The same tile gives the same bytes, even a clock second later (writers like to
 * stamp the time). */
TEST(image_encode_is_deterministic) {
    test_img t;
    make_img(&t, 3, 1);
    unsigned char *first[TC_IMG_NFORMATS] = {0};
    size_t first_len[TC_IMG_NFORMATS] = {0};
    for (int f = 0; f < TC_IMG_NFORMATS; f++) encode(&t.im, (tc_img_format)f, &first[f], &first_len[f]);
    for (time_t start = time(NULL); time(NULL) == start;) nanosleep(&(struct timespec){0, 20000000}, NULL);
    for (int f = 0; f < TC_IMG_NFORMATS; f++) {
        unsigned char *again = NULL;
        size_t len = 0;
        if (first[f] && encode(&t.im, (tc_img_format)f, &again, &len) == 0)
            CHECK_MSG(len == first_len[f] && memcmp(again, first[f], len) == 0, "%s differs a second later",
                      tc_img_format_name((tc_img_format)f));
        tc_img_free(again);
        tc_img_free(first[f]);
    }
}

/* Written band by band (1, 2 and 3 rows at a time, one band of all rows), every
 * format gives the bytes tc_img_encode gives; rows past the end, a missing alpha
 * and finishing early are refused with a message. */
TEST(image_writer_bands_give_the_same_bytes) {
    test_img t;
    make_img(&t, 3, 1);
    for (int f = 0; f < TC_IMG_NFORMATS; f++) {
        tc_img im = t.im;
        if (!tc_img_has_alpha((tc_img_format)f, 3)) im.alpha = NULL;
        unsigned char *want = NULL;
        size_t want_len = 0;
        if (encode(&im, (tc_img_format)f, &want, &want_len) != 0) continue;
        for (int step = 1; step <= H; step++) {
            char err[256] = "";
            tc_img_writer *w = NULL;
            unsigned char *got = NULL;
            size_t len = 0, cap = 0;
            int rc = tc_img_writer_open(&im, (tc_img_format)f, &w, err, sizeof err);
            for (int y = 0; rc == 0 && y < H; y += step) {
                int rows = H - y < step ? H - y : step;
                rc = tc_img_writer_rows(w, im.pixels + (size_t)y * W * 3, im.alpha ? im.alpha + y * W : NULL, rows,
                                        err, sizeof err);
            }
            if (rc == 0) rc = tc_img_writer_finish(w, &got, &len, &cap, err, sizeof err);
            CHECK_MSG(rc == 0, "%s in bands of %d: %s", tc_img_format_name((tc_img_format)f), step, err);
            CHECK_MSG(rc != 0 || (len == want_len && cap > len && memcmp(got, want, len) == 0),
                      "%s in bands of %d rows: %zu bytes differ from tc_img_encode's %zu",
                      tc_img_format_name((tc_img_format)f), step, len, want_len);
            tc_img_free(got);
            tc_img_writer_free(w);
        }
        tc_img_free(want);
    }
    char err[256] = "";
    tc_img_writer *w = NULL;
    unsigned char *got = NULL;
    size_t len, cap;
    int opened = tc_img_writer_open(&t.im, TC_IMG_PNG, &w, err, sizeof err) == 0;
    CHECK_MSG(opened, "png writer: %s", err);
    if (!opened) return; /* no writer to misuse (the plugin could not be loaded) */
    CHECK(tc_img_writer_rows(w, t.px, NULL, 1, err, sizeof err) == -1 && strstr(err, "alpha expected"));
    CHECK(tc_img_writer_rows(w, t.px, t.alpha, H + 1, err, sizeof err) == -1);
    CHECK(tc_img_writer_rows(w, t.px, t.alpha, 2, err, sizeof err) == 0);
    CHECK(tc_img_writer_finish(w, &got, &len, &cap, err, sizeof err) == -1 && strstr(err, "only 2 of 5 rows"));
    CHECK(got == NULL);
    tc_img_writer_free(w);
    tc_img_writer_free(NULL);
}

/* A raw image's rows written in place (tc_img_writer_place, two rows at a time; what the
 * daemon renders into) give tc_img_encode's bytes; no place past the last row, for no rows,
 * or for a format the writer converts (PNG). tc_img_places says so before a writer opens
 * (the daemon's memory reservation reads it). */
TEST(image_writer_place_raw) {
    test_img t;
    make_img(&t, 3, 0);
    unsigned char *want = NULL, *got = NULL;
    size_t want_len = 0, len = 0, cap = 0;
    if (encode(&t.im, TC_IMG_RAW, &want, &want_len) != 0) return;
    char err[256] = "";
    tc_img_writer *w = NULL;
    int rc = tc_img_writer_open(&t.im, TC_IMG_RAW, &w, err, sizeof err), placed = 0;
    CHECK(rc == 0 && tc_img_writer_place(w, 0) == NULL && tc_img_writer_place(w, H + 1) == NULL);
    for (int y = 0; rc == 0 && y < H; y += 2) {
        int rows = H - y < 2 ? H - y : 2;
        float *at = tc_img_writer_place(w, rows);
        if (!at) break;
        memcpy(at, t.px + (size_t)y * W * 3, (size_t)rows * W * 3 * sizeof *at);
        rc = tc_img_writer_rows(w, at, NULL, rows, err, sizeof err), placed += rows;
    }
    CHECK_MSG(placed == H && tc_img_writer_place(w, 1) == NULL, "%d rows placed", placed);
    if (rc == 0 && placed == H) rc = tc_img_writer_finish(w, &got, &len, &cap, err, sizeof err);
    CHECK_MSG(rc == 0 && len == want_len && memcmp(got, want, len) == 0, "raw in place: %s", err);
    tc_img_free(got), tc_img_free(want);
    tc_img_writer_free(w);
    w = NULL;
    if (tc_img_writer_open(&t.im, TC_IMG_PNG, &w, err, sizeof err) == 0) CHECK(tc_img_writer_place(w, 1) == NULL);
    tc_img_writer_free(w);
    CHECK(tc_img_places(TC_IMG_RAW, 3) == 1 && tc_img_places(TC_IMG_RAW, 16) == 1); /* as placed above */
    for (int f = 0; f < TC_IMG_NFORMATS; f++)
        if (f != TC_IMG_RAW) CHECK_MSG(tc_img_places((tc_img_format)f, 1) == 0, "%s in place", tc_img_format_name((tc_img_format)f));
    CHECK(tc_img_places((tc_img_format)-1, 1) == 0);
}

/* ---- the format table as a whole ----------------------------------------------------- */

/* What adding a row must keep true: the name and each extension lead back to
 * the row; a format with extensions is the primary of its MIME type; and for
 * every channel count, with and without coverage, encoding either succeeds as
 * the row says (decoding back to as many channels, alpha where the row's rule
 * writes it) or is refused with a message, before the plugin is involved. */
TEST(image_format_table_round_trips) {
    for (int f = 0; f < TC_IMG_NFORMATS; f++) {
        const tc_img_traits *t = tc_img_traits_of((tc_img_format)f);
        tc_img_format back = TC_IMG_NFORMATS;
        CHECK_MSG(t && t->name && t->mime && strchr(t->mime, '/'), "format %d has no row", f);
        if (!t) continue;
        CHECK(tc_img_format_parse(t->name, &back) == 0 && back == (tc_img_format)f);
        CHECK_MSG(!t->ext[0] || tc_img_primary((tc_img_format)f) == f, "%s: extensions on a variant", t->name);
        for (int i = 0; i < 3 && t->ext[i]; i++) {
            char path[64];
            snprintf(path, sizeof path, "dir.x/tile%s", t->ext[i]);
            CHECK_MSG(tc_img_format_of_path(path) == f, "%s: extension %s", t->name, t->ext[i]);
        }
        for (int nc = 1; nc <= MAXCH; nc++)
            for (int with_alpha = 0; with_alpha <= 1; with_alpha++) {
                test_img im;
                make_img(&im, nc, with_alpha);
                unsigned char *out = NULL;
                size_t len = 0;
                char err[256] = "";
                int refused_alpha = with_alpha && t->alpha != TC_IMG_ALPHA_NONE && !tc_img_has_alpha((tc_img_format)f, nc);
                int want = tc_img_holds((tc_img_format)f, nc) && !refused_alpha;
                int rc = tc_img_encode(&im.im, (tc_img_format)f, &out, &len, err, sizeof err);
                CHECK_MSG((rc == 0) == want && (rc == 0 || (err[0] && !out)), "%s, %d channels%s: %s", t->name, nc,
                          with_alpha ? " + alpha" : "", rc ? err : "encoded");
                if (rc == 0 && !t->plugin) CHECK(len == (size_t)W * H * (size_t)nc * 4);
                tc_img_decoded d;
                if (rc == 0 && t->plugin && tc_img_decode(out, len, &d, err, sizeof err) == 0) {
                    int alpha = with_alpha && tc_img_has_alpha((tc_img_format)f, nc);
                    CHECK_MSG(d.channels == nc + alpha && (d.alpha_channel >= 0) == alpha,
                              "%s, %d channels%s: %d decoded, alpha at %d", t->name, nc, with_alpha ? " + alpha" : "",
                              d.channels, d.alpha_channel);
                    tc_img_decoded_free(&d);
                }
                tc_img_free(out);
            }
    }
}

/* api/openapi.yaml, read next to this source file: the render request's
 * "format" enum is the table's names in order, and every primary MIME type is
 * among the render responses' content types. */
TEST(image_format_table_matches_the_contract) {
    const char *me = __FILE__, *cut = strstr(me, "tests/unit/test_image.c");
    char path[1024], line[512], names[256], want_enum[300] = "";
    snprintf(path, sizeof path, "%.*sapi/openapi.yaml", (int)(cut ? cut - me : 0), me);
    FILE *fp = fopen(path, "r");
    CHECK_MSG(fp != NULL, "cannot read %s", path);
    if (!fp) return;
    snprintf(want_enum, sizeof want_enum, "enum: [%s]", tc_img_list_names(names, sizeof names));
    int in_format = 0, enum_ok = 0, mime_seen[TC_IMG_NFORMATS] = {0};
    while (fgets(line, sizeof line, fp)) {
        const char *s = line + strspn(line, " ");
        if (in_format && !strncmp(s, "enum:", 5)) enum_ok = !strncmp(s, want_enum, strlen(want_enum)), in_format = 0;
        if (!strncmp(s, "format:", 7) && s[7] == '\n') in_format = 1;
        for (int f = 0; f < TC_IMG_NFORMATS; f++) {
            const char *mime = tc_img_mime((tc_img_format)f);
            if (mime && !strncmp(s, mime, strlen(mime)) && !strncmp(s + strlen(mime), ": {schema", 9)) mime_seen[f] = 1;
        }
    }
    fclose(fp);
    CHECK_MSG(enum_ok, "api/openapi.yaml: the render format enum is not \"%s\"", want_enum);
    for (int f = 0; f < TC_IMG_NFORMATS; f++)
        if (tc_img_primary((tc_img_format)f) == f)
            CHECK_MSG(mime_seen[f], "api/openapi.yaml: /v1/render answers no %s", tc_img_mime((tc_img_format)f));
}
