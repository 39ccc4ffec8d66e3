/* codec.c — tc_img_encode and tc_img_decode: every input checked against the format
 * table first (so a bad request fails without loading OpenImageIO), raw written
 * here, the other formats handed to the plugin (plugin.c, encode.cpp). */
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image/plugin.h"
#include "io/hugemem.h"

#define TC_IMG_MAX_CHANNELS 16

static void set_err(char *err, size_t errlen, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

static void set_err(char *err, size_t errlen, const char *fmt, ...) {
    if (!err || !errlen) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, errlen, fmt, ap);
    va_end(ap);
}

/* ---- encoding ---------------------------------------------------------------------- */

/* What the format's row says it can hold: its channel counts, alpha, and for a
 * display-referred format a finite exposure. */
static int check_traits(const tc_img *im, tc_img_format f, char *err, size_t errlen) {
    const tc_img_traits *t = tc_img_traits_of(f);
    char list[96], use[96];
    tc_img_format primary = (tc_img_format)tc_img_primary(f);
    if (im->alpha && !tc_img_has_alpha(f, im->channels) && t->alpha == TC_IMG_ALPHA_UNLESS_2)
        return set_err(err, errlen, "%s cannot mark alpha on 2 channels (3 samples read as RGB) — use %s, or no alpha",
                       t->name, tc_img_list_holding(im->channels, 1, use, sizeof use)), -1;
    if (!tc_img_holds(f, im->channels))
        return set_err(err, errlen, "%s holds %s channels; this mesh has %d — use %s", tc_img_format_name(primary),
                       tc_img_list_channels(f, list, sizeof list), im->channels,
                       tc_img_list_holding(im->channels, 0, use, sizeof use)), -1;
    if (t->display && !isfinite(im->exposure))
        return set_err(err, errlen, "exposure must be a finite number of stops"), -1;
    return 0;
}

/* Checks everything both encoders rely on but the samples, so a bad request
 * fails here without loading OpenImageIO. */
static int check_header(const tc_img *im, tc_img_format f, char *err, size_t errlen) {
    if (!tc_img_traits_of(f)) return set_err(err, errlen, "unknown image format %d", (int)f), -1;
    if (!im) return set_err(err, errlen, "no image"), -1;
    if (im->width < 1 || im->height < 1)
        return set_err(err, errlen, "image size %dx%d is empty", im->width, im->height), -1;
    if (im->channels < 1 || im->channels > TC_IMG_MAX_CHANNELS)
        return set_err(err, errlen, "an image has 1 to %d channels, not %d", TC_IMG_MAX_CHANNELS, im->channels), -1;
    size_t per_pixel = ((size_t)im->channels + 1) * sizeof(float);
    if ((size_t)im->width > SIZE_MAX / per_pixel / (size_t)im->height)
        return set_err(err, errlen, "image size %dx%d is too large", im->width, im->height), -1;
    return check_traits(im, f, err, errlen);
}

/* Raw samples are little-endian float32: a copy where the host is little-endian. */
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
#define RAW_IS_HOST 1
#else
#define RAW_IS_HOST 0
static void put_le32(unsigned char *p, float v) {
    uint32_t u;
    memcpy(&u, &v, sizeof u);
    p[0] = (unsigned char)u, p[1] = (unsigned char)(u >> 8);
    p[2] = (unsigned char)(u >> 16), p[3] = (unsigned char)(u >> 24);
}
#endif

/* Invariants: rows_done <= header.height; raw != NULL iff the format is raw
 * (written here, without the plugin: little-endian float32 samples,
 * [height][width][channels], no alpha, no header), else stream is the plugin's. */
struct tc_img_writer {
    tc_img header; /* pixels NULL; alpha non-NULL iff the image has an alpha channel */
    tc_img_format f;
    int rows_done;
    const tc_img_plugin_fns *fns;
    void *stream;
    unsigned char *raw; /* the whole file, allocated at open: it is the answer */
    size_t raw_len;
};

int tc_img_writer_open(const tc_img *header, tc_img_format f, tc_img_writer **wp, char *err, size_t errlen) {
    static const float has_alpha = 1;
    *wp = NULL;
    if (check_header(header, f, err, errlen) != 0) return -1;
    tc_img_writer *w = calloc(1, sizeof *w);
    if (!w) return set_err(err, errlen, "out of memory"), -1;
    w->header = *header;
    w->header.pixels = NULL;
    w->header.alpha = header->alpha ? &has_alpha : NULL;
    w->f = f;
    if (!tc_img_traits_of(f)->plugin) {
        w->raw_len = (size_t)header->width * (size_t)header->height * (size_t)header->channels * 4;
        /* The answer itself (the daemon frees it with tc__huge_free): a 4096² tile is 64 MiB, which
         * malloc maps afresh each time, and writing it then cost ~17k page faults, 4x the render. */
        w->raw = tc__huge_realloc(NULL, w->raw_len + 1);
        if (!w->raw) return free(w), set_err(err, errlen, "out of memory for a %dx%d raw image", header->width,
                                            header->height), -1;
    } else if (!(w->fns = tc__img_plugin(err, errlen)) ||
               !(w->stream = w->fns->open(&w->header, f, err, errlen))) {
        return free(w), -1;
    }
    *wp = w;
    return 0;
}

/* Where the raw answer's next row goes. */
static unsigned char *raw_next(const tc_img_writer *w) {
    const tc_img *h = &w->header;
    return w->raw + (size_t)w->rows_done * (size_t)h->width * (size_t)h->channels * 4;
}

int tc_img_writer_rows(tc_img_writer *w, const float *pixels, const float *alpha, int rows, char *err,
                       size_t errlen) {
    const tc_img *h = &w->header;
    if (!pixels || rows < 1 || rows > h->height - w->rows_done || (!alpha != !h->alpha))
        return set_err(err, errlen, "rows %d..%d of a %d-row image (alpha %s) cannot be written", w->rows_done,
                       w->rows_done + rows, h->height, h->alpha ? "expected" : "not expected"), -1;
    size_t n = (size_t)rows * (size_t)h->width * (size_t)h->channels;
    if (w->raw) {
        unsigned char *at = raw_next(w);
#if RAW_IS_HOST
        if ((const void *)pixels != (void *)at) memcpy(at, pixels, n * 4); /* put_le32's bytes; none from _place */
#else
        for (size_t i = 0; i < n; i++) put_le32(at + 4 * i, pixels[i]);
#endif
    } else {
        tc_img band = *h;
        band.height = rows, band.pixels = pixels, band.alpha = alpha;
        if (w->fns->rows(w->stream, &band, err, errlen) != 0) return -1;
    }
    w->rows_done += rows;
    return 0;
}

float *tc_img_writer_place(tc_img_writer *w, int rows) {
    const tc_img *h = &w->header;
    if (!tc_img_places(w->f, h->channels) || rows < 1 || rows > h->height - w->rows_done) return NULL;
    return (float *)(void *)raw_next(w);
}

int tc_img_places(tc_img_format f, int nc) {
    const tc_img_traits *t = tc_img_traits_of(f);
    return RAW_IS_HOST && t && !t->plugin && !tc_img_has_alpha(f, nc);
}

int tc_img_writer_finish(tc_img_writer *w, unsigned char **out, size_t *len, size_t *cap, char *err, size_t errlen) {
    *out = NULL, *len = *cap = 0;
    if (w->rows_done != w->header.height)
        return set_err(err, errlen, "only %d of %d rows written", w->rows_done, w->header.height), -1;
    if (!w->raw) return w->fns->finish(w->stream, out, len, cap, err, errlen);
    *out = w->raw, *len = w->raw_len, *cap = w->raw_len + 1;
    w->raw = NULL;
    return 0;
}

void tc_img_writer_free(tc_img_writer *w) {
    if (!w) return;
    if (w->stream) w->fns->free(w->stream);
    free(w->raw);
    free(w);
}

int tc_img_encode(const tc_img *im, tc_img_format f, unsigned char **out, size_t *len, char *err, size_t errlen) {
    if (!out || !len) return set_err(err, errlen, "no output buffer"), -1;
    *out = NULL;
    *len = 0;
    if (!im || !im->pixels) return set_err(err, errlen, "no pixels to encode"), -1;
    tc_img_writer *w;
    size_t cap;
    if (tc_img_writer_open(im, f, &w, err, errlen) != 0) return -1;
    int rc = tc_img_writer_rows(w, im->pixels, im->alpha, im->height, err, errlen);
    if (rc == 0) rc = tc_img_writer_finish(w, out, len, &cap, err, errlen);
    tc_img_writer_free(w);
    return rc;
}

/* Both encoders hand out malloc()ed memory. */
void tc_img_free(unsigned char *p) { free(p); }

/* ---- decoding (tests) ------------------------------------------------------------- */

int tc_img_decode(const unsigned char *data, size_t len, tc_img_decoded *out, char *err, size_t errlen) {
    if (!out) return set_err(err, errlen, "no output"), -1;
    memset(out, 0, sizeof *out);
    const tc_img_plugin_fns *fns = tc__img_plugin(err, errlen);
    return fns ? fns->decode(data, len, out, err, errlen) : -1;
}

void tc_img_decoded_free(tc_img_decoded *d) {
    if (!d) return;
    free(d->pixels);
    d->pixels = NULL;
}
