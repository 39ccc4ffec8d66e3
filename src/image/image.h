/* image.h — encoding rendered tiles into image files in memory (codec.c; OpenImageIO
 * behind a C interface, loaded only when first used: plugin.c, encode.cpp). */
#ifndef TC_IMAGE_H
#define TC_IMAGE_H

#include <stddef.h>

#include "image/format.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    int width, height;
    int channels;         /* data channels, 1 .. 16 */
    const float *pixels;  /* [height][width][channels], row 0 = top of the image */
    const float *alpha;   /* [height][width] coverage 0 or 1, or NULL: no alpha channel */
    double exposure;      /* stops: PNG values are v * 2^exposure before the transfer */
    int linear;           /* PNG only: 1 = no sRGB transfer (default 0: sRGB) */
} tc_img;

/* Encodes the image in memory as format f (format.h). On success returns 0 and
 * *out (free with tc_img_free) holds *len bytes. On failure returns -1 with a
 * message in err (e.g. PNG with 2 data channels, the image library not
 * installed). Thread-safe. */
int tc_img_encode(const tc_img *im, tc_img_format f, unsigned char **out, size_t *len, char *err, size_t errlen);
void tc_img_free(unsigned char *p);

/* ---- Writing an image band by band ----
 * A tile that is rendered and encoded a band of rows at a time never holds
 * all its samples at once: memory is the encoded bytes (grown in place) plus
 * one band. tc_img_encode is this with a single band of every row.
 *
 *   tc_img_writer_open(header, f, &w, ...)     header: size, channels, exposure,
 *                                              linear, and alpha != NULL when the
 *                                              image has an alpha channel (pixels unused)
 *   tc_img_writer_rows(w, pixels, alpha, n...) the next n rows, top to bottom,
 *                                              [n][width][channels] (+ [n][width] alpha)
 *   tc_img_writer_finish(w, &bytes, &len, &cap, ...) after every row: the file,
 *                                              malloc()ed, cap > len bytes allocated
 *   tc_img_writer_free(w)                      always, finished or not
 *   tc_img_writer_place(w, n)                  where the next n rows are stored as they
 *                                              are, for the caller to render into (then
 *                                              _rows with that pointer copies nothing);
 *                                              NULL where the writer converts them: every
 *                                              format but raw, and raw on a big-endian host
 *   tc_img_places(f, nc)                       1 when a writer of f for nc channels gives
 *                                              such places (the caller can plan for it
 *                                              before opening one), else 0
 * Each returns 0, or -1 with a message in err; after a failure only _free is
 * meaningful. The bytes equal tc_img_encode's whatever the bands. */
typedef struct tc_img_writer tc_img_writer;
int tc_img_writer_open(const tc_img *header, tc_img_format f, tc_img_writer **w, char *err, size_t errlen);
int tc_img_writer_rows(tc_img_writer *w, const float *pixels, const float *alpha, int rows, char *err,
                       size_t errlen);
int tc_img_writer_finish(tc_img_writer *w, unsigned char **out, size_t *len, size_t *cap, char *err, size_t errlen);
void tc_img_writer_free(tc_img_writer *w);
float *tc_img_writer_place(tc_img_writer *w, int rows);
int tc_img_places(tc_img_format f, int nc);

/* Loads the OpenImageIO part now (it is loaded on the first encode otherwise).
 * Returns 0, or -1 with the reason in err. */
int tc_img_load(char *err, size_t errlen);
/* 1 once the OpenImageIO part is loaded in this process. */
int tc_img_loaded(void);

/* ---- For tests: decoding an encoded PNG, EXR or TIFF back with OpenImageIO ---- */

typedef struct {
    int width, height;
    int channels;          /* all of them, alpha included */
    int alpha_channel;     /* its index, or -1 */
    float *pixels;         /* [height][width][channels], row 0 first; tc_img_decoded_free */
    char format[16];       /* OpenImageIO's reader name: "png", "openexr", "tiff" */
    char type[16];         /* the stored sample type: "uint8", "uint16", "half", "float" */
    char names[256];       /* channel names, comma-separated */
    char colorspace[32];   /* the "oiio:ColorSpace" read back, or "" */
    char compression[32];  /* the "compression" read back, or "" */
} tc_img_decoded;

/* Loads the plugin like tc_img_encode. Returns 0, or -1 with a message in err.
 * Samples come back as float (an 8-bit 255 reads as 1.0); alpha unassociated. */
int tc_img_decode(const unsigned char *data, size_t len, tc_img_decoded *out, char *err, size_t errlen);
void tc_img_decoded_free(tc_img_decoded *d);

/* ---- The contract between codec.c / plugin.c and the plugin built from encode.cpp ---- */

/* The plugin's tc_img_plugin_abi() must return this: bump it whenever tc_img,
 * tc_img_decoded or the signatures below change, so a stale installed plugin is
 * refused instead of misreading the structs. */
#define TC_IMG_PLUGIN_ABI 2

/* Resolved with dlsym (plugin.c). Inputs are already validated by codec.c
 * (dimensions, channel counts, formats the plugin writes, the rows' count), so
 * the plugin only streams: open a writer for a header (pixels unused), write
 * bands (a tc_img whose height is the band's rows), finish (the file malloc()ed,
 * cap > len, so tc_img_free is free() whichever side produced it), free. */
typedef int (*tc_img_plugin_abi_fn)(void);
typedef void *(*tc_img_stream_open_fn)(const tc_img *header, tc_img_format f, char *err, size_t errlen);
typedef int (*tc_img_stream_rows_fn)(void *s, const tc_img *band, char *err, size_t errlen);
typedef int (*tc_img_stream_finish_fn)(void *s, unsigned char **out, size_t *len, size_t *cap, char *err,
                                       size_t errlen);
typedef void (*tc_img_stream_free_fn)(void *s);
typedef int (*tc_img_decode_impl_fn)(const unsigned char *data, size_t len, tc_img_decoded *out, char *err,
                                     size_t errlen);

/* The plugin's entry points, resolved together. */
typedef struct {
    tc_img_stream_open_fn open;
    tc_img_stream_rows_fn rows;
    tc_img_stream_finish_fn finish;
    tc_img_stream_free_fn free;
    tc_img_decode_impl_fn decode;
} tc_img_plugin_fns;

#ifdef __cplusplus
}
#endif
#endif
