/* load.c — the C side of src/image: format names and Accept headers, raw output, and
 * opening the OpenImageIO plugin (libtocher_image.so, from encode.cpp) on first use. */

/* Why a plugin: OpenImageIO and the libraries it pulls in cost every process that links
 * them load time and memory, whether it writes an image or not. Measured here (Debian 12,
 * OpenImageIO 2.4.7, 2 cores; a small program calling tc_img_load, then one 64x64 PNG
 * encode, reading VmRSS from /proc/self/status): loading takes 0.20-0.29 s warm (median
 * 0.25 s; 0.64 s with a cold page cache) and adds 122 MB of resident memory, 125 MB after
 * the first encode, against 0 s and 0.1 MB without. So commands and requests that produce
 * no image never load it, and raw float output is written here without it. Loading
 * happens once per process (pthread_once); the plugin is never unloaded, since
 * OpenImageIO keeps threads and static state.
 *
 * Where the plugin is looked for: $TOCHER_IMAGE_LIB if set (and then only there, so a
 * wrong setting is an error rather than a silent fallback), else libtocher_image.so next
 * to the running executable (the build tree), ../lib/libtocher_image.so relative to it
 * (an installed layout), and finally plain "libtocher_image.so" (dlopen's search path). */
#include "image/image.h"

#include <dlfcn.h>
#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#define TC_IMG_MAX_CHANNELS 16
#define TC_IMG_PLUGIN_NAME "libtocher_image.so"

/* ---- errors ------------------------------------------------------------------- */

static void set_err(char *err, size_t errlen, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

static void set_err(char *err, size_t errlen, const char *fmt, ...) {
    if (!err || !errlen) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, errlen, fmt, ap);
    va_end(ap);
}

/* ---- names ------------------------------------------------------------------- */

static const struct {
    const char *name, *mime;
} formats[TC_IMG_NFORMATS] = {
    [TC_IMG_PNG] = {"png", "image/png"},
    [TC_IMG_PNG16] = {"png16", "image/png"},
    [TC_IMG_EXR] = {"exr", "image/x-exr"},
    [TC_IMG_EXR_HALF] = {"exr-half", "image/x-exr"},
    [TC_IMG_TIFF] = {"tiff", "image/tiff"},
    [TC_IMG_RAW] = {"raw", "application/octet-stream"},
};

static int valid_format(tc_img_format f) { return (int)f >= 0 && f < TC_IMG_NFORMATS; }

/* NULL for a value outside the enum. */
const char *tc_img_format_name(tc_img_format f) { return valid_format(f) ? formats[f].name : NULL; }

const char *tc_img_mime(tc_img_format f) { return valid_format(f) ? formats[f].mime : NULL; }

/* Case-insensitive, since names come from people typing requests. */
int tc_img_format_parse(const char *name, tc_img_format *out) {
    for (int f = 0; name && f < TC_IMG_NFORMATS; f++) {
        if (strcasecmp(name, formats[f].name) == 0) {
            if (out) *out = (tc_img_format)f;
            return 0;
        }
    }
    return -1;
}

/* ---- Accept headers ---------------------------------------------------------------- */
// (Line comments here, since the wildcards contain the characters that open a block comment.)
// Each format we can serve gets the q of the most specific media range that matches it
// (exact type > "image/*" > "*/*"), as RFC 9110 12.5.1 says. The answer is the explicitly
// named format with the highest q (> 0; the earliest on ties), unless a wildcard gives some
// format a strictly higher q: then -1, "no preference", and the caller uses its default
// (png). One consequence: "image/png;q=0, image/*" also gives -1. PNG16 and EXR_HALF share
// their MIME types with PNG and EXR, so an Accept header never selects them: only the
// request's "format" field does.

enum { ACC_PNG, ACC_EXR, ACC_TIFF, ACC_RAW, ACC_N };
static const tc_img_format acc_format[ACC_N] = {TC_IMG_PNG, TC_IMG_EXR, TC_IMG_TIFF, TC_IMG_RAW};
static const char *const acc_major[ACC_N] = {"image", "image", "image", "application"};

typedef struct {
    int level[ACC_N]; // 0 unmatched, 1 by "*/*", 2 by "image/*" (or "application/*"), 3 by name
    int q[ACC_N];     // thousandths, from the range at that level
    int pos[ACC_N];   // where that range was in the header
} acc_state;

typedef struct {
    const char *s;
    size_t n;
} span;

static int is_ows(char c) { return c == ' ' || c == '\t'; }

static span trim(const char *s, size_t n) {
    while (n && is_ows(*s)) s++, n--;
    while (n && is_ows(s[n - 1])) n--;
    return (span){s, n};
}

static int span_is(span a, const char *lit) { return a.n == strlen(lit) && strncasecmp(a.s, lit, a.n) == 0; }

/* Length up to the first `stop` character outside double quotes, at most n: bounded,
 * so that parsing stays linear in the header's length whatever it holds. */
static size_t until_unquoted(const char *s, size_t n, char stop) {
    size_t i = 0;
    for (int quoted = 0; i < n && (quoted || s[i] != stop); i++) {
        if (s[i] == '\\' && quoted && i + 1 < n) i++;
        else if (s[i] == '"') quoted = !quoted;
    }
    return i;
}

/* A qvalue ("0", "0.5", "1.000") in thousandths, or -1 if malformed. */
static int parse_qvalue(span v) {
    if (v.n == 0 || (v.s[0] != '0' && v.s[0] != '1') || v.n > 5) return -1;
    int q = (v.s[0] - '0') * 1000;
    if (v.n == 1) return q;
    if (v.s[1] != '.') return -1;
    for (size_t i = 2, scale = 100; i < v.n; i++, scale /= 10) {
        if (v.s[i] < '0' || v.s[i] > '9') return -1;
        q += (v.s[i] - '0') * (int)scale;
    }
    return q > 1000 ? -1 : q;
}

/* The q parameter among the ";"-separated parameters of one element (1000 when
 * absent, -1 when malformed). */
static int element_q(const char *p, size_t n) {
    while (n) {
        size_t k = until_unquoted(p, n, ';');
        span param = trim(p, k);
        const char *eq = memchr(param.s, '=', param.n);
        if (eq && span_is(trim(param.s, (size_t)(eq - param.s)), "q"))
            return parse_qvalue(trim(eq + 1, param.n - (size_t)(eq + 1 - param.s)));
        p += k < n ? k + 1 : k;
        n -= k < n ? k + 1 : k;
    }
    return 1000;
}

/* How specifically the media range names format a: 3, 2, 1, or 0 (not at all). */
static int match_level(span range, int a) {
    if (span_is(range, "*/*")) return 1;
    size_t major = strlen(acc_major[a]);
    if (range.n == major + 2 && strncasecmp(range.s, acc_major[a], major) == 0 && range.s[major] == '/' &&
        range.s[major + 1] == '*')
        return 2;
    if (span_is(range, tc_img_mime(acc_format[a]))) return 3;
    return a == ACC_EXR && span_is(range, "image/exr") ? 3 : 0;
}

/* Records one element of the header ("type/subtype; params"). */
static void accept_element(acc_state *acc, const char *p, size_t n, int pos) {
    size_t k = until_unquoted(p, n, ';');
    span range = trim(p, k);
    int q = element_q(p + k, n - k);
    if (range.n == 0 || q < 0) return; /* malformed: ignored */
    for (int a = 0; a < ACC_N; a++) {
        int lv = match_level(range, a);
        if (lv > acc->level[a]) acc->level[a] = lv, acc->q[a] = q, acc->pos[a] = pos;
    }
}

static int accept_choice(const acc_state *acc) {
    int best = -1, wild_q = 0;
    for (int a = 0; a < ACC_N; a++) {
        if (acc->level[a] < 3) {
            if (acc->level[a] && acc->q[a] > wild_q) wild_q = acc->q[a];
        } else if (acc->q[a] > 0 &&
                   (best < 0 || acc->q[a] > acc->q[best] || (acc->q[a] == acc->q[best] && acc->pos[a] < acc->pos[best]))) {
            best = a;
        }
    }
    return best >= 0 && acc->q[best] >= wild_q ? (int)acc_format[best] : -1;
}

int tc_img_format_from_accept(const char *accept) {
    if (!accept) return -1;
    acc_state acc = {{0}, {0}, {0}};
    const char *p = accept;
    size_t left = strlen(accept);
    for (int pos = 0; left; pos++) {
        size_t n = until_unquoted(p, left, ',');
        accept_element(&acc, p, n, pos);
        size_t step = n < left ? n + 1 : n; /* past the comma */
        p += step, left -= step;
    }
    return accept_choice(&acc);
}

/* ---- the plugin ------------------------------------------------------------------ */

static pthread_once_t plugin_once = PTHREAD_ONCE_INIT;
static tc_img_encode_impl_fn plugin_encode;
static tc_img_decode_impl_fn plugin_decode;
static atomic_int plugin_ok;
static char plugin_error[4096]; /* why loading failed; written once under plugin_once */

/* Appends "; path: reason" to the report (dlerror() usually starts with the path
 * itself, which is not repeated). */
static void note_failure(char *report, size_t cap, const char *path, const char *reason) {
    size_t len = strlen(report), plen = strlen(path);
    if (!reason) reason = "unknown error";
    if (strncmp(reason, path, plen) == 0 && reason[plen] == ':') reason += plen + 1;
    while (*reason == ' ') reason++;
    if (len < cap) snprintf(report + len, cap - len, "%s%s: %s", len ? "; " : "", path, reason);
}

/* Opens one candidate and resolves its entry points; on failure appends the reason. */
static int try_plugin(const char *path, char *report, size_t cap) {
    void *h = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!h) {
        note_failure(report, cap, path, dlerror());
        return -1;
    }
    tc_img_plugin_abi_fn abi = (tc_img_plugin_abi_fn)dlsym(h, "tc_img_plugin_abi");
    tc_img_encode_impl_fn enc = (tc_img_encode_impl_fn)dlsym(h, "tc_img_encode_impl");
    tc_img_decode_impl_fn dec = (tc_img_decode_impl_fn)dlsym(h, "tc_img_decode_impl");
    if (!abi || !enc || !dec || abi() != TC_IMG_PLUGIN_ABI) {
        note_failure(report, cap, path, abi && enc && dec ? "built for another version of tocher (ABI mismatch)"
                                                          : "not a tocher image plugin (entry points missing)");
        dlclose(h);
        return -1;
    }
    plugin_encode = enc;
    plugin_decode = dec;
    return 0;
}

/* The directory of the running executable, without the trailing '/'; 0 on success. */
static int exe_dir(char *dir, size_t cap) {
    ssize_t n = readlink("/proc/self/exe", dir, cap - 1);
    if (n <= 0 || (size_t)n >= cap - 1) return -1;
    dir[n] = '\0';
    char *slash = strrchr(dir, '/');
    if (!slash) return -1;
    *slash = '\0';
    return 0;
}

static int try_default_places(char *report, size_t cap) {
    char dir[4096], path[4096 + 64];
    if (exe_dir(dir, sizeof dir) == 0) {
        snprintf(path, sizeof path, "%s/" TC_IMG_PLUGIN_NAME, dir);
        if (try_plugin(path, report, cap) == 0) return 0;
        snprintf(path, sizeof path, "%s/../lib/" TC_IMG_PLUGIN_NAME, dir);
        if (try_plugin(path, report, cap) == 0) return 0;
    }
    return try_plugin(TC_IMG_PLUGIN_NAME, report, cap);
}

static void load_plugin(void) {
    char report[sizeof plugin_error - 128] = "";
    const char *env = getenv("TOCHER_IMAGE_LIB");
    int rc = env && *env ? try_plugin(env, report, sizeof report) : try_default_places(report, sizeof report);
    if (rc == 0) {
        atomic_store(&plugin_ok, 1);
        return;
    }
    snprintf(plugin_error, sizeof plugin_error, "cannot load the image plugin (OpenImageIO)%s: tried %s",
             env && *env ? " named by TOCHER_IMAGE_LIB" : "", report);
}

int tc_img_load(char *err, size_t errlen) {
    pthread_once(&plugin_once, load_plugin);
    if (atomic_load(&plugin_ok)) return 0;
    set_err(err, errlen, "%s", plugin_error);
    return -1;
}

int tc_img_loaded(void) { return atomic_load(&plugin_ok); }

/* ---- encoding ---------------------------------------------------------------------- */

/* Checks everything both encoders rely on, so a bad request fails here without
 * loading OpenImageIO. */
static int check_image(const tc_img *im, tc_img_format f, char *err, size_t errlen) {
    if (!valid_format(f)) return set_err(err, errlen, "unknown image format %d", (int)f), -1;
    if (!im || !im->pixels) return set_err(err, errlen, "no pixels to encode"), -1;
    if (im->width < 1 || im->height < 1)
        return set_err(err, errlen, "image size %dx%d is empty", im->width, im->height), -1;
    if (im->channels < 1 || im->channels > TC_IMG_MAX_CHANNELS)
        return set_err(err, errlen, "an image has 1 to %d channels, not %d", TC_IMG_MAX_CHANNELS, im->channels), -1;
    size_t per_pixel = ((size_t)im->channels + 1) * sizeof(float);
    if ((size_t)im->width > SIZE_MAX / per_pixel / (size_t)im->height)
        return set_err(err, errlen, "image size %dx%d is too large", im->width, im->height), -1;
    if (f == TC_IMG_TIFF && im->channels == 2 && im->alpha)
        return set_err(err, errlen, "tiff cannot mark alpha on 2 channels (3 samples read as RGB) — use exr, "
                                    "or no alpha"), -1;
    if (f == TC_IMG_PNG || f == TC_IMG_PNG16) {
        if (im->channels != 1 && im->channels != 3)
            return set_err(err, errlen, "png holds 1 or 3 channels; this mesh has %d — use exr, tiff or raw",
                           im->channels), -1;
        if (!isfinite(im->exposure)) return set_err(err, errlen, "exposure must be a finite number of stops"), -1;
    }
    return 0;
}

static void put_le32(unsigned char *p, float v) {
    uint32_t u;
    memcpy(&u, &v, sizeof u);
    p[0] = (unsigned char)u, p[1] = (unsigned char)(u >> 8);
    p[2] = (unsigned char)(u >> 16), p[3] = (unsigned char)(u >> 24);
}

/* Little-endian float32 samples, [height][width][channels], no alpha, no header. */
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
    if (f == TC_IMG_RAW) return encode_raw(im, out, len, err, errlen);
    if (tc_img_load(err, errlen) != 0) return -1;
    return plugin_encode(im, f, out, len, err, errlen);
}

/* Both encoders hand out malloc()ed memory. */
void tc_img_free(unsigned char *p) { free(p); }

/* ---- decoding (tests) ------------------------------------------------------------- */

int tc_img_decode(const unsigned char *data, size_t len, tc_img_decoded *out, char *err, size_t errlen) {
    if (!out) return set_err(err, errlen, "no output"), -1;
    memset(out, 0, sizeof *out);
    if (tc_img_load(err, errlen) != 0) return -1;
    return plugin_decode(data, len, out, err, errlen);
}

void tc_img_decoded_free(tc_img_decoded *d) {
    if (!d) return;
    free(d->pixels);
    d->pixels = NULL;
}
