/* request_render.c — the request's fields for what is answered: with_gradients
 * (/v1/evaluate), viewport, format, exposure, overlay, linear, background (render), reference (compare). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "image/format.h"
#include "io/reader.h"
#include "io/request_fields.h"
#include "io/typed.h"

void tc__parse_with_gradients(tc__reader *rd, const cJSON *v, const tc__jpath *p) {
    tc__rd_bool(rd, v, p, &rd->r->with_gradients);
}

/* ---- fields: rendering ------------------------------------------------------------- */

static const tc__field viewport_fields[] = {
    {"x0", NULL, 0, "x"}, {"y0", NULL, 0, "y"}, {"x1", NULL, 0, "x"},
    {"y1", NULL, 0, "y"}, {"width", NULL, 0, "pixels"}, {"height", NULL, 0, "pixels"},
};
#define NVIEWPORT ((int)(sizeof viewport_fields / sizeof viewport_fields[0]))

/* One required member of the viewport: a number, or a pixel count 1 .. 2^20. */
static int viewport_member(tc__reader *rd, const cJSON *v, const tc__jpath *obj, int i, double *num, int32_t *count) {
    tc__jpath p = tc__jpath_key(obj, viewport_fields[i].name);
    if (!v) {
        tc__rd_shape_error(rd, &p, "missing required field '%s'", viewport_fields[i].name);
        return -1;
    }
    if (!count) return tc__rd_number(rd, v, &p, num);
    if (tc__rd_int(rd, v, &p, count)) return -1;
    if (*count < 1 || *count > (1 << 20)) {
        tc__rd_value_error(rd, &p, "%s must be 1 to %d pixels, got %d", viewport_fields[i].name, 1 << 20, (int)*count);
        return -1;
    }
    return 0;
}

void tc__parse_viewport(tc__reader *rd, const cJSON *v, const tc__jpath *p) {
    const cJSON *found[NVIEWPORT];
    if (tc__rd_members(rd, v, p, viewport_fields, NVIEWPORT, found, "an object {x0, y0, x1, y1, width, height}"))
        return;
    tc_viewport *vp = &rd->r->viewport;
    double *num[4] = {&vp->x0, &vp->y0, &vp->x1, &vp->y1};
    int bad = 0;
    for (int i = 0; i < 4; i++) bad |= viewport_member(rd, found[i], p, i, num[i], NULL) != 0;
    bad |= viewport_member(rd, found[4], p, 4, NULL, &vp->width) != 0;
    bad |= viewport_member(rd, found[5], p, 5, NULL, &vp->height) != 0;
    if (bad) return;
    for (int axis = 0; axis < 2; axis++) {
        double lo = axis ? vp->y0 : vp->x0, hi = axis ? vp->y1 : vp->x1;
        tc__jpath ph = tc__jpath_key(p, axis ? "y1" : "x1");
        if (!(hi > lo)) {
            tc__rd_value_error(rd, &ph, "%s = %g must be greater than %s = %g", axis ? "y1" : "x1", hi,
                               axis ? "y0" : "x0", lo);
            bad = 1;
        }
    }
    rd->r->has_viewport = !bad;
}

void tc__parse_format(tc__reader *rd, const cJSON *v, const tc__jpath *p) {
    tc_img_format f;
    char names[160];
    if (!tc__json_is(v, cJSON_String) || !v->valuestring) {
        tc__rd_shape_error(rd, p, "expected a string (%s), got %s", tc_img_list_names(names, sizeof names),
                           tc__json_kind(v));
        return;
    }
    if (tc_img_format_parse(v->valuestring, &f)) {
        tc__rd_value_error(rd, p, "unknown format '%.40s'; expected one of: %s", v->valuestring,
                           tc_img_list_names(names, sizeof names));
        return;
    }
    rd->r->format = (int)f;
}

void tc__parse_exposure(tc__reader *rd, const cJSON *v, const tc__jpath *p) {
    double e;
    if (tc__rd_number(rd, v, p, &e)) return;
    if (fabs(e) > 64) {
        tc__rd_value_error(rd, p, "exposure %g stops is out of range (-64 to 64)", e);
        return;
    }
    rd->r->exposure = e;
}

/* "encoding": "json" (the default) or "base64" (the answer's big arrays as typed arrays). */
void tc__parse_encoding(tc__reader *rd, const cJSON *v, const tc__jpath *p) {
    if (!tc__json_is(v, cJSON_String) || !v->valuestring) {
        tc__rd_shape_error(rd, p, "expected a string (\"json\" or \"base64\"), got %s", tc__json_kind(v));
        return;
    }
    if (strcmp(v->valuestring, "json") && strcmp(v->valuestring, "base64")) {
        tc__rd_value_error(rd, p, "unknown encoding '%.40s'; expected \"json\" or \"base64\"", v->valuestring);
        return;
    }
    rd->r->encoding_base64 = !strcmp(v->valuestring, "base64");
}

void tc__parse_overlay(tc__reader *rd, const cJSON *v, const tc__jpath *p) { tc__rd_bool(rd, v, p, &rd->r->overlay); }
void tc__parse_linear(tc__reader *rd, const cJSON *v, const tc__jpath *p) { tc__rd_bool(rd, v, p, &rd->r->linear); }

/* ---- fields: comparison ------------------------------------------------------------ */

static const tc__field reference_fields[] = {
    {"points", NULL, 0, "[[x, y], ...]"},
    {"values", NULL, 0, "[z, ...] or [[z1, ..., zC], ...]"},
    {"scale", NULL, 0, "the full-scale value"},
};
enum { REF_POINTS, REF_VALUES, REF_SCALE, REF_NFIELDS };

/* Typed reference values: [n] (one channel) or [n, C]. */
static void typed_reference_values(tc__reader *rd, const cJSON *v, const tc__jpath *p, size_t n) {
    tc__typed t;
    size_t C = (size_t)rd->nchan, d2[2] = {0, C}, d1[1] = {0};
    char expected[48];
    snprintf(expected, sizeof expected, C == 1 ? "[n] or [n, 1]" : "[n, %zu] (channels, as values)", C);
    if (tc__rd_typed(rd, v, p, 0, &t) ||
        tc__typed_dims(rd, &t, p, C == 1 && t.ndim == 1 ? 1 : 2, C == 1 && t.ndim == 1 ? d1 : d2, expected))
        return;
    if (t.shape[0] != n) {
        tc__rd_value_error(rd, p, "%zu values for %zu points", t.shape[0], n);
        return;
    }
    double *z = tc__rd_alloc(rd, t.count, sizeof *z);
    if (t.count && !z) return;
    tc__typed_doubles(rd, &t, p, z);
    rd->r->reference_values = z;
}

/* The reference values: one per point, C channels each. */
static void read_reference_values(tc__reader *rd, const cJSON *v, const tc__jpath *p, size_t n) {
    size_t m, i = 0;
    if (tc__is_typed(v)) {
        typed_reference_values(rd, v, p, n);
        return;
    }
    if (tc__rd_array(rd, v, p, "an array of reference values [z, ...] or [[z1, ..., zC], ...]", SIZE_MAX / 16, &m))
        return;
    if (m != n) {
        tc__rd_value_error(rd, p, "%zu values for %zu points", m, n);
        return;
    }
    double *z = tc__rd_alloc(rd, n, (size_t)rd->nchan * sizeof *z);
    if (n && !z) return;
    for (const cJSON *e = v->child; e; e = e->next, i++) {
        tc__jpath pi = tc__jpath_index(p, i);
        tc__rd_channels(rd, e, &pi, z + i * (size_t)rd->nchan);
    }
    rd->r->reference_values = z;
}

void tc__parse_reference(tc__reader *rd, const cJSON *v, const tc__jpath *p) {
    const cJSON *found[REF_NFIELDS];
    if (!rd->nchan || tc__rd_members(rd, v, p, reference_fields, REF_NFIELDS, found, "an object {points, values}"))
        return;
    tc__jpath pp = tc__jpath_key(p, "points"), pv = tc__jpath_key(p, "values"), ps = tc__jpath_key(p, "scale");
    if (!found[REF_POINTS] || !found[REF_VALUES]) {
        tc__rd_shape_error(rd, found[REF_POINTS] ? &pv : &pp, "missing required field '%s'",
                           found[REF_POINTS] ? "values" : "points");
        return;
    }
    size_t n;
    double *xy;
    if (tc__rd_xy_list(rd, found[REF_POINTS], &pp, SIZE_MAX / 2 / sizeof(double), &n, &xy)) return;
    rd->r->nreference = n;
    rd->r->reference_points = xy;
    read_reference_values(rd, found[REF_VALUES], &pv, n);
    if (found[REF_SCALE] && !tc__rd_number(rd, found[REF_SCALE], &ps, &rd->r->reference_scale) &&
        !(rd->r->reference_scale > 0))
        tc__rd_value_error(rd, &ps, "scale must be positive, got %g", rd->r->reference_scale);
}

/* A number (every channel) or one number per channel. */
void tc__parse_background(tc__reader *rd, const cJSON *v, const tc__jpath *p) {
    if (!rd->nchan) return; /* values unreadable: already reported */
    if (!tc__json_is(v, cJSON_Array)) {
        double z;
        if (tc__rd_number(rd, v, p, &z)) return;
        for (int ch = 0; ch < rd->nchan; ch++) rd->r->background[ch] = z;
    } else if (tc__rd_numbers(rd, v, p, rd->nchan, rd->r->background, "(one per channel)")) {
        return;
    }
    rd->r->has_background = 1;
}
