/* tiles.c — tile URLs to tile requests (404 for tiles that do not exist, 400
 * naming a bad query parameter) and tile requests to viewports. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image/format.h"
#include "server/tiles.h"

/* A decimal integer of digits only (no sign, no spaces), at most 18 digits. */
static int parse_index(const char *s, size_t n, long long *out) {
    if (n == 0 || n > 18) return -1;
    long long v = 0;
    for (size_t i = 0; i < n; i++) {
        if (s[i] < '0' || s[i] > '9') return -1;
        v = v * 10 + (s[i] - '0');
    }
    *out = v;
    return 0;
}

static int format_named(const char *name) {
    for (int f = 0; f < TC_IMG_NFORMATS; f++)
        if (!strcmp(tc_img_format_name((tc_img_format)f), name)) return f;
    return -1;
}

static int parse_path(const tc_path_params *p, tc_tile_req *t, char *detail, size_t n) {
    long long z;
    const char *last = p->seg[3], *dot = strchr(last, '.');
    if (parse_index(p->seg[1], strlen(p->seg[1]), &z) || parse_index(p->seg[2], strlen(p->seg[2]), &t->x) || !dot ||
        parse_index(last, (size_t)(dot - last), &t->y))
        return snprintf(detail, n, "no such tile: expected /tiles/{z}/{x}/{y}.{format} with whole numbers"), 404;
    if (z > TC_TILE_MAX_Z) return snprintf(detail, n, "no such tile: z = %lld; the pyramid ends at z = 24", z), 404;
    t->z = (int)z;
    long long side = 1LL << z;
    if (t->x >= side || t->y >= side)
        return snprintf(detail, n, "no such tile: x and y run from 0 to %lld at z = %d", side - 1, t->z), 404;
    if ((t->format = format_named(dot + 1)) < 0)
        return snprintf(detail, n, "no such tile format '%.32s' (png, png16, exr, exr-half, tiff, raw)", dot + 1), 404;
    return 0;
}

static int parse_bool(const char *s, int *out) {
    if (!strcmp(s, "true") || !strcmp(s, "1")) return *out = 1, 0;
    if (!strcmp(s, "false") || !strcmp(s, "0")) return *out = 0, 0;
    return -1;
}

static int parse_double(const char *s, double *out) {
    char *end;
    errno = 0;
    *out = strtod(s, &end);
    return end == s || *end || errno == ERANGE || !isfinite(*out) ? -1 : 0;
}

/* "v" or "v1,v2,...": one value for every channel, or one per channel (the
 * count is checked against the mesh's channels by the caller). */
static int parse_background(const char *s, tc_tile_req *t) {
    char buf[1024];
    if (strlen(s) >= sizeof buf) return -1;
    strcpy(buf, s);
    t->nbackground = 0;
    for (char *save = NULL, *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
        if (t->nbackground == TC_MAX_CHANNELS || parse_double(tok, &t->background[t->nbackground])) return -1;
        t->nbackground++;
    }
    return t->nbackground ? 0 : -1;
}

static int parse_query(const tc_query *q, tc_tile_req *t, char *detail, size_t n) {
    if (q->overflow) return snprintf(detail, n, "more than %d query parameters", TC_QUERY_MAX), 400;
    for (int i = 0; i < q->n; i++) {
        const char *k = q->key[i], *v = q->value[i];
        long long size;
        if (!strcmp(k, "size")) {
            if (parse_index(v, strlen(v), &size) || size < 1 || size > TC_TILE_MAX_SIZE)
                return snprintf(detail, n, "size: expected whole pixels from 1 to %d, got '%.32s'", TC_TILE_MAX_SIZE,
                                v), 400;
            t->size = (int)size;
        } else if (!strcmp(k, "exposure")) {
            if (parse_double(v, &t->exposure) || t->exposure < -64 || t->exposure > 64)
                return snprintf(detail, n, "exposure: expected stops from -64 to 64, got '%.32s'", v), 400;
        } else if (!strcmp(k, "overlay") || !strcmp(k, "linear")) {
            if (parse_bool(v, !strcmp(k, "overlay") ? &t->overlay : &t->linear))
                return snprintf(detail, n, "%s: expected true or false, got '%.32s'", k, v), 400;
        } else if (!strcmp(k, "background")) {
            if (parse_background(v, t))
                return snprintf(detail, n, "background: expected a number or one per channel, comma-separated, "
                                "got '%.32s'", v), 400;
        } else {
            return snprintf(detail, n, "%.32s: unknown query parameter (size, exposure, overlay, linear, background)",
                            k), 400;
        }
    }
    return 0;
}

int tc_tile_parse(const tc_path_params *p, const tc_query *q, tc_tile_req *t, char *detail, size_t n) {
    memset(t, 0, sizeof *t);
    t->size = TC_TILE_DEFAULT_SIZE;
    if (p->n != 4) return snprintf(detail, n, "no such tile"), 404;
    int rc = parse_path(p, t, detail, n);
    return rc ? rc : parse_query(q, t, detail, n);
}

void tc_tile_meaning(const tc_tile_req *t, char *out, size_t n) {
    int k = snprintf(out, n, "tile %d/%lld/%lld.%s size=%d exposure=%.17g overlay=%d linear=%d background=", t->z,
                     t->x, t->y, tc_img_format_name((tc_img_format)t->format), t->size, t->exposure, t->overlay,
                     t->linear);
    for (int i = 0; i < t->nbackground && k > 0 && (size_t)k < n; i++)
        k += snprintf(out + k, n - (size_t)k, "%s%.17g", i ? "," : "", t->background[i]);
}

void tc_tile_viewport(const tc_tile_req *t, const double bbox[4], tc_viewport *vp) {
    double x0 = bbox[0], y0 = bbox[1], w = bbox[2] - bbox[0], h = bbox[3] - bbox[1];
    double s = w > h ? w : h;
    double ts = s / (double)(1LL << t->z); /* exact: a power of two */
    vp->x0 = x0 + (double)t->x * ts;
    vp->x1 = x0 + (double)(t->x + 1) * ts;
    vp->y0 = y0 + s - (double)(t->y + 1) * ts;
    vp->y1 = y0 + s - (double)t->y * ts;
    vp->width = vp->height = t->size;
}
