/* format.c — the table of image formats and what reads it: names, media types,
 * extensions, the channel counts and alpha each holds, and lists for messages. */
#include <float.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>

#include "image/format.h"

/* One row per tc_img_format; see tc_img_traits for what each field means. */
static const tc_img_traits formats[TC_IMG_NFORMATS] = {
    [TC_IMG_PNG] = {"png", "image/png", NULL, {".png"}, TC_IMG_CH(1) | TC_IMG_CH(3), TC_IMG_ALPHA_ALWAYS, 1, 1, 0, 1},
    [TC_IMG_PNG16] = {"png16", "image/png", NULL, {NULL}, TC_IMG_CH(1) | TC_IMG_CH(3), TC_IMG_ALPHA_ALWAYS, 1, 1, 0, 2},
    [TC_IMG_EXR] = {"exr", "image/x-exr", "image/exr", {".exr"}, TC_IMG_CH_ANY, TC_IMG_ALPHA_ALWAYS, 0, 1, FLT_MAX, 4},
    [TC_IMG_EXR_HALF] = {"exr-half", "image/x-exr", NULL, {NULL}, TC_IMG_CH_ANY, TC_IMG_ALPHA_ALWAYS, 0, 1, 65504, 2},
    [TC_IMG_TIFF] = {"tiff", "image/tiff", NULL, {".tif", ".tiff"}, TC_IMG_CH_ANY, TC_IMG_ALPHA_UNLESS_2, 0, 1, FLT_MAX, 4},
    [TC_IMG_RAW] = {"raw", "application/octet-stream", NULL, {".raw"}, TC_IMG_CH_ANY, TC_IMG_ALPHA_NONE, 0, 0, FLT_MAX, 4},
};

const tc_img_traits *tc_img_traits_of(tc_img_format f) {
    return (int)f >= 0 && f < TC_IMG_NFORMATS && formats[f].name ? &formats[f] : NULL;
}

/* NULL for a value outside the enum. */
const char *tc_img_format_name(tc_img_format f) {
    const tc_img_traits *t = tc_img_traits_of(f);
    return t ? t->name : NULL;
}

const char *tc_img_mime(tc_img_format f) {
    const tc_img_traits *t = tc_img_traits_of(f);
    return t ? t->mime : NULL;
}

/* Case-insensitive, since names come from people typing requests. */
int tc_img_format_parse(const char *name, tc_img_format *out) {
    for (int f = 0; name && f < TC_IMG_NFORMATS; f++) {
        if (formats[f].name && strcasecmp(name, formats[f].name) == 0) {
            if (out) *out = (tc_img_format)f;
            return 0;
        }
    }
    return -1;
}

/* Exact (case-sensitive) extensions, as the CLI always matched them. */
int tc_img_format_of_path(const char *path) {
    const char *dot = path ? strrchr(path, '.') : NULL;
    for (int f = 0; dot && f < TC_IMG_NFORMATS; f++)
        for (int i = 0; i < 3 && formats[f].ext[i]; i++)
            if (strcmp(dot, formats[f].ext[i]) == 0) return f;
    return -1;
}

int tc_img_primary(tc_img_format f) {
    const tc_img_traits *t = tc_img_traits_of(f);
    for (int g = 0; t && g < (int)f; g++)
        if (formats[g].mime && strcmp(formats[g].mime, t->mime) == 0) return g;
    return t ? (int)f : -1;
}

int tc_img_holds(tc_img_format f, int nc) {
    const tc_img_traits *t = tc_img_traits_of(f);
    return t && nc >= 1 && nc <= 16 && (t->channels & TC_IMG_CH(nc)) != 0;
}

int tc_img_has_alpha(tc_img_format f, int nc) {
    const tc_img_traits *t = tc_img_traits_of(f);
    if (!t) return 0;
    return t->alpha == TC_IMG_ALPHA_ALWAYS || (t->alpha == TC_IMG_ALPHA_UNLESS_2 && nc != 2);
}

/* ---- lists for messages ---- */

/* Appends item `k` of a list of n: "a", ", b", ..., and with `last` (" or ")
 * before the final one; the text stops at cap. */
static void list_add(char *buf, size_t cap, size_t *len, int k, int n, const char *last, const char *fmt, ...) {
    if (*len + 1 >= cap) return;
    const char *sep = k == 0 ? "" : k == n - 1 && last ? last : ", ";
    int w = snprintf(buf + *len, cap - *len, "%s", sep);
    if (w > 0) *len += (size_t)w < cap - *len ? (size_t)w : cap - *len - 1;
    va_list ap;
    va_start(ap, fmt);
    w = vsnprintf(buf + *len, cap - *len, fmt, ap);
    va_end(ap);
    if (w > 0) *len += (size_t)w < cap - *len ? (size_t)w : cap - *len - 1;
}

const char *tc_img_list_names(char *buf, size_t cap) {
    size_t len = 0;
    buf[0] = '\0';
    for (int f = 0; f < TC_IMG_NFORMATS; f++) list_add(buf, cap, &len, f, TC_IMG_NFORMATS, NULL, "%s", formats[f].name);
    return buf;
}

const char *tc_img_list_channels(tc_img_format f, char *buf, size_t cap) {
    size_t len = 0;
    int n = 0, k = 0;
    buf[0] = '\0';
    for (int nc = 1; nc <= 16; nc++) n += tc_img_holds(f, nc);
    for (int nc = 1; nc <= 16; nc++)
        if (tc_img_holds(f, nc)) list_add(buf, cap, &len, k++, n, " or ", "%d", nc);
    return buf;
}

/* The primaries only: a variant (png16, exr-half) is the same suggestion again. */
static int suggested(tc_img_format f, int nc, int with_alpha) {
    return tc_img_primary(f) == (int)f && tc_img_holds(f, nc) && (!with_alpha || tc_img_has_alpha(f, nc));
}

const char *tc_img_list_holding(int nc, int with_alpha, char *buf, size_t cap) {
    size_t len = 0;
    int n = 0, k = 0;
    buf[0] = '\0';
    for (int f = 0; f < TC_IMG_NFORMATS; f++) n += suggested((tc_img_format)f, nc, with_alpha);
    for (int f = 0; f < TC_IMG_NFORMATS; f++)
        if (suggested((tc_img_format)f, nc, with_alpha))
            list_add(buf, cap, &len, k++, n, " or ", "%s", formats[f].name);
    return buf;
}
