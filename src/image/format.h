/* format.h — the image formats a tile can be written in, one row of traits each
 * (format.c): the request reader, the JSON API, the CLI, content negotiation and
 * the encoders all read the table, so a format's facts live in one place. */
#ifndef TC_IMAGE_FORMAT_H
#define TC_IMAGE_FORMAT_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* To add a format: its enumerator here, its row in format.c, and its encoder
 * (a case in encode.cpp's switch, which fails to compile without it, or C code
 * in codec.c for a format written without the plugin); the tests walk the
 * table (names, types, extensions, channel counts, api/openapi.yaml). */
typedef enum {
    TC_IMG_PNG = 0,  /* 8-bit, exposure + sRGB transfer */
    TC_IMG_PNG16,    /* 16-bit, exposure + sRGB transfer */
    TC_IMG_EXR,      /* OpenEXR, 32-bit float, linear */
    TC_IMG_EXR_HALF, /* OpenEXR, 16-bit half, linear */
    TC_IMG_TIFF,     /* TIFF, 32-bit float, linear */
    TC_IMG_RAW,      /* little-endian float32, no header, linear */
    TC_IMG_NFORMATS
} tc_img_format;

/* What a request without "format" (and without a usable Accept header) gets. */
#define TC_IMG_DEFAULT TC_IMG_PNG

/* Whether the coverage of the pixels is written as an alpha channel. */
typedef enum {
    TC_IMG_ALPHA_NONE,     /* never (raw) */
    TC_IMG_ALPHA_ALWAYS,   /* always */
    TC_IMG_ALPHA_UNLESS_2  /* except with 2 data channels: TIFF writes 3 samples as RGB, so it
                            * cannot mark the third as alpha */
} tc_img_alpha;

/* Bit n of tc_img_traits.channels: n data channels can be written. */
#define TC_IMG_CH(n) (1u << (n))
#define TC_IMG_CH_ANY 0x1FFFEu /* 1 .. 16 */

/* Invariants (checked by the tests): names are distinct; the first row of a
 * MIME type is its primary, the one an Accept header and the suggestions name
 * (png16 and exr-half are variants of png and exr, chosen only by name); only
 * a primary has extensions, and they are distinct. */
typedef struct {
    const char *name;         /* the request's "format" */
    const char *mime;         /* Content-Type of the encoded tile */
    const char *mime_alias;   /* another media type an Accept header may name it by, or NULL */
    const char *ext[3];       /* output file extensions that choose it (".png"), NULL-terminated */
    uint32_t channels;        /* TC_IMG_CH bits of the data channel counts it holds */
    tc_img_alpha alpha;
    int display;              /* display-referred: values are v * 2^exposure through the sRGB transfer
                               * (unless "linear"), clamped and quantized; else the linear floats */
    int plugin;               /* encoded by the OpenImageIO plugin (else written in C, codec.c) */
    double max_sample;        /* linear formats: the largest |value| a sample holds (a value beyond is
                               * written as that, with a warning, api.c); 0 for display-referred ones */
    int sample_bytes;         /* bytes of one stored sample (uncompressed) */
} tc_img_traits;

/* The row of format f, or NULL if f is not a format. */
const tc_img_traits *tc_img_traits_of(tc_img_format f);

/* Names as in requests ("png", "png16", "exr", "exr-half", "tiff", "raw"). */
const char *tc_img_format_name(tc_img_format f);
int tc_img_format_parse(const char *name, tc_img_format *out); /* 0, or -1 if unknown (case-insensitive) */
const char *tc_img_mime(tc_img_format f);
/* The format whose extension ends path ("tile.exr"), or -1. */
int tc_img_format_of_path(const char *path);
/* The primary format of f's MIME type (f itself, or the format f is a variant of); -1 if f is not a format. */
int tc_img_primary(tc_img_format f);

/* 1 if f holds nc data channels. */
int tc_img_holds(tc_img_format f, int nc);
/* 1 if f writes coverage as alpha for an image of nc data channels. */
int tc_img_has_alpha(tc_img_format f, int nc);

/* Lists for messages: every format's name ("png, png16, ..., raw"); the channel
 * counts f holds ("1 or 3"); the primary formats that hold nc channels, and
 * write alpha for them if with_alpha ("exr, tiff or raw"). Each writes at most
 * cap bytes (NUL included) and returns buf. */
const char *tc_img_list_names(char *buf, size_t cap);
const char *tc_img_list_channels(tc_img_format f, char *buf, size_t cap);
const char *tc_img_list_holding(int nc, int with_alpha, char *buf, size_t cap);

#ifdef __cplusplus
}
#endif
#endif
