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

/* Checks everything both encoders rely on, so a bad request fails here without
 * loading OpenImageIO. */
static int check_image(const tc_img *im, tc_img_format f, char *err, size_t errlen) {
    if (!tc_img_traits_of(f)) return set_err(err, errlen, "unknown image format %d", (int)f), -1;
    if (!im || !im->pixels) return set_err(err, errlen, "no pixels to encode"), -1;
    if (im->width < 1 || im->height < 1)
        return set_err(err, errlen, "image size %dx%d is empty", im->width, im->height), -1;
    if (im->channels < 1 || im->channels > TC_IMG_MAX_CHANNELS)
        return set_err(err, errlen, "an image has 1 to %d channels, not %d", TC_IMG_MAX_CHANNELS, im->channels), -1;
    size_t per_pixel = ((size_t)im->channels + 1) * sizeof(float);
    if ((size_t)im->width > SIZE_MAX / per_pixel / (size_t)im->height)
        return set_err(err, errlen, "image size %dx%d is too large", im->width, im->height), -1;
    return check_traits(im, f, err, errlen);
}

static void put_le32(unsigned char *p, float v) {
    uint32_t u;
    memcpy(&u, &v, sizeof u);
    p[0] = (unsigned char)u, p[1] = (unsigned char)(u >> 8);
    p[2] = (unsigned char)(u >> 16), p[3] = (unsigned char)(u >> 24);
}

/* Little-endian float32 samples, [height][width][channels], no alpha, no header:
 * the one format written without the plugin (its row's `plugin` is 0). */
static int encode_raw(const tc_img *im, unsigned char **out, size_t *len, char *err, size_t errlen) {
    size_t n = (size_t)im->width * (size_t)im->height * (size_t)im->channels;
    unsigned char *buf = malloc(n * 4);
    if (!buf) return set_err(err, errlen, "out of memory for a %dx%d raw image", im->width, im->height), -1;
    for (size_t i = 0; i < n; i++) put_le32(buf + 4 * i, im->pixels[i]);
    *out = buf;
    *len = n * 4;
    return 0;
}

int tc_img_encode(const tc_img *im, tc_img_format f, unsigned char **out, size_t *len, char *err, size_t errlen) {
    if (!out || !len) return set_err(err, errlen, "no output buffer"), -1;
    *out = NULL;
    *len = 0;
    if (check_image(im, f, err, errlen) != 0) return -1;
    if (!tc_img_traits_of(f)->plugin) return encode_raw(im, out, len, err, errlen);
    tc_img_encode_impl_fn encode;
    if (tc__img_plugin(&encode, NULL, err, errlen) != 0) return -1;
    return encode(im, f, out, len, err, errlen);
}

/* Both encoders hand out malloc()ed memory. */
void tc_img_free(unsigned char *p) { free(p); }

/* ---- decoding (tests) ------------------------------------------------------------- */

int tc_img_decode(const unsigned char *data, size_t len, tc_img_decoded *out, char *err, size_t errlen) {
    if (!out) return set_err(err, errlen, "no output"), -1;
    memset(out, 0, sizeof *out);
    tc_img_decode_impl_fn decode;
    if (tc__img_plugin(NULL, &decode, err, errlen) != 0) return -1;
    return decode(data, len, out, err, errlen);
}

void tc_img_decoded_free(tc_img_decoded *d) {
    if (!d) return;
    free(d->pixels);
    d->pixels = NULL;
}
