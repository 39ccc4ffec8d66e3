/* response.c — JSON writers for the core's results. Numbers go through
 * tc_strbuf_double so every double parses back to itself. */
#include "io/response.h"
#include "io/base64.h"
#include "io/jsonout.h"
#include "io/numfmt.h"
#include "io/textpar.h"
#include "core/alloc.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static void member(tc_strbuf *b, const char *name) { tc_json_key(b, ",", name); }

void tc_json_ordinates(tc_strbuf *b, const tc_recon *r) { tc_json_ordinates_enc(b, r, 0); }

/* Rows (triangles) staged per base64 chunk: a multiple of 3, so that every chunk but the
 * last is a whole number of 3-byte groups and the chunks' texts join into the one text. */
enum { STAGE_ROWS = 3 * 128 };

/* The rows of given triangles [i0, i1) as the typed array's bytes: each kept triangle's
 * coefficients, NaN for a dropped one. */
static void stage_rows(const tc_recon *r, size_t i0, size_t i1, size_t row, double *x) {
    const tc_mesh *m = tc_recon_mesh(r);
    const double *coef = tc_recon_coefs(r);
    for (size_t i = i0; i < i1; i++, x += row) {
        int32_t t = tc_mesh_triangle_of_given(m, (int32_t)i);
        if (t < 0) {
            for (size_t k = 0; k < row; k++) x[k] = NAN;
        } else {
            memcpy(x, coef + (size_t)t * row, row * sizeof *x); /* row t: [C][K], tc__ix's layout */
        }
    }
}

/* 1 when given triangle i is kept triangle i for every i: the coefficient array is then
 * the typed array's bytes as they are. */
static int identity_numbering(const tc_mesh *m, size_t ngiven) {
    for (size_t i = 0; i < ngiven; i++)
        if (tc_mesh_triangle_of_given(m, (int32_t)i) != (int32_t)i) return 0;
    return 1;
}

/* "ordinates" as one typed array [T][C][K] in the request's numbering, encoded straight
 * into b (its exact size reserved first): no copy of the coefficients is made, except a
 * small staging block per chunk when triangles were dropped or renumbered. */
static void typed_ordinates(tc_strbuf *b, const tc_recon *r) {
    const tc_mesh *m = tc_recon_mesh(r);
    size_t nc = (size_t)tc_mesh_channel_count(m), nk = (size_t)tc_recon_coef_count(r);
    size_t ngiven = (size_t)tc_mesh_given_triangle_count(m), row = nc * nk;
    const size_t shape[3] = {ngiven, nc, nk};
    size_t bytes = ngiven * row * sizeof(double), text = tc_base64_encoded_len(bytes);
    if (text == SIZE_MAX || tc_strbuf_reserve(b, text + 128)) { /* + the typed array's frame */
        b->oom = 1;
        return;
    }
    tc_json_typed_open(b, shape, 3);
    if (identity_numbering(m, ngiven)) {
        tc__base64_append_parallel(b, tc_recon_coefs(r), bytes, tc_recon_options(r)->threads);
    } else {
        double *x = malloc(STAGE_ROWS * row * sizeof *x);
        if (!x) {
            b->oom = 1;
            return;
        }
        for (size_t i = 0; i < ngiven && !b->oom; i += STAGE_ROWS) {
            size_t n = ngiven - i < STAGE_ROWS ? ngiven - i : STAGE_ROWS;
            stage_rows(r, i, i + n, row, x);
            tc_base64_append(b, x, n * row * sizeof *x);
        }
        free(x);
    }
    tc_json_typed_close(b);
}

/* Bytes the JSON form of the ordinates takes at most: per given triangle ",\n[" "]" and
 * per channel "[" "]" "," and per number its text (TC_FMT_DOUBLE_SIZE bounds it) and ",".
 * Reserving it first saves the doublings of a growing buffer (each a fresh block whose
 * pages fault in, and a copy); the untouched tail of an over-estimate costs no memory. */
static size_t json_ordinates_bound(size_t ngiven, size_t nc, size_t nk) {
    size_t per_row = 4 + nc * (3 + nk * TC_FMT_DOUBLE_SIZE);
    return ngiven > (SIZE_MAX - 16) / per_row ? SIZE_MAX : ngiven * per_row + 16;
}

/* Rows (given triangles) per part of the threaded printing: a part's thread costs tens of
 * microseconds to wake, a row's text about one microsecond to print. */
enum { ORDS_MIN_PART = 2048 };

typedef struct {
    const tc_recon *r;
    const double *coef;
    int nc, nk;
} ords_ctx;

/* Given triangles [lo, hi) of the JSON "ordinates", in the request's numbering: each
 * row's text depends on its triangle alone (and on whether it is row 0), so the parts
 * join into the text one thread prints (tc__text_parallel's rule). */
static void json_rows(tc_strbuf *b, void *ctx, int32_t lo, int32_t hi) {
    const ords_ctx *c = ctx;
    const tc_mesh *m = tc_recon_mesh(c->r);
    for (int32_t i = lo; i < hi && !b->oom; i++) { /* null where dropped */
        int32_t t = tc_mesh_triangle_of_given(m, i);
        tc_strbuf_puts(b, i ? ",\n" : "\n");
        if (t < 0) {
            tc_strbuf_puts(b, "null");
            continue;
        }
        tc_strbuf_putc(b, '[');
        for (int ch = 0; ch < c->nc; ch++) {
            if (ch) tc_strbuf_putc(b, ',');
            tc_json_numbers(b, c->coef + tc__ix(t, c->nc, ch) * (size_t)c->nk, c->nk);
        }
        tc_strbuf_putc(b, ']');
    }
}

void tc_json_ordinates_enc(tc_strbuf *b, const tc_recon *r, int base64) {
    const tc_mesh *m = tc_recon_mesh(r);
    int nc = tc_mesh_channel_count(m), nk = tc_recon_coef_count(r);
    int32_t ngiven = tc_mesh_given_triangle_count(m);
    /* All of it at once, the small members before the numbers included (typed_ordinates
     * reserves its exact size itself). */
    if (!base64 && tc_strbuf_reserve(b, 4096 + json_ordinates_bound((size_t)ngiven, (size_t)nc, (size_t)nk))) return;
    tc_json_options(b, tc_recon_options(r));
    member(b, "channels");
    tc_strbuf_int(b, nc);
    member(b, "labels");
    tc_strbuf_putc(b, '[');
    for (int i = 0; i < nk; i++) {
        if (i) tc_strbuf_putc(b, ',');
        tc_strbuf_json_string(b, tc_recon_coef_label(r, i));
    }
    tc_strbuf_putc(b, ']');
    member(b, "ordinates");
    if (base64) {
        typed_ordinates(b, r);
        return;
    }
    tc_strbuf_putc(b, '[');
    ords_ctx c = {r, tc_recon_coefs(r), nc, nk};
    size_t per_row = json_ordinates_bound(1, (size_t)nc, (size_t)nk);
    tc__text_parallel(b, ngiven, tc_recon_options(r)->threads, ORDS_MIN_PART, per_row, json_rows, &c);
    tc_strbuf_puts(b, "\n]");
}

/* One point's values or gradients: a number or array per channel, or null. */
static void point_entry(tc_strbuf *b, const double *x, int nc, int width, int plain, int outside) {
    if (outside) {
        tc_strbuf_puts(b, "null");
    } else if (plain && nc == 1) {
        if (width == 1) tc_strbuf_double(b, x[0]);
        else tc_json_numbers(b, x, width);
    } else {
        tc_strbuf_putc(b, '[');
        for (int ch = 0; ch < nc; ch++) {
            if (ch) tc_strbuf_putc(b, ',');
            if (width == 1) tc_strbuf_double(b, x[ch]);
            else tc_json_numbers(b, x + (size_t)ch * (size_t)width, width);
        }
        tc_strbuf_putc(b, ']');
    }
}

/* width numbers per channel per point as one typed array, NaN for points outside. */
static void typed_points(tc_strbuf *b, int nc, size_t n, const double *x, int width, const int32_t *tri, int plain) {
    size_t per = (size_t)nc * (size_t)width, shape[3] = {n, (size_t)nc, (size_t)width};
    int ndim = 0;
    const size_t *sh = shape;
    if (plain && nc == 1) shape[1] = (size_t)width, ndim = width == 1 ? 1 : 2; /* [n] or [n][2] */
    else ndim = width == 1 ? 2 : 3;                                            /* [n][C] or [n][C][2] */
    size_t nout = 0;
    for (size_t i = 0; tri && i < n; i++) nout += tri[i] < 0;
    if (!nout) {
        tc_json_typed(b, x, sh, ndim);
        return;
    }
    double *y = malloc(n * per * sizeof *y); /* a copy with NaN where the JSON form has null */
    if (!y) {
        b->oom = 1;
        return;
    }
    memcpy(y, x, n * per * sizeof *y);
    for (size_t i = 0; i < n; i++)
        for (size_t k = 0; tri[i] < 0 && k < per; k++) y[i * per + k] = NAN;
    tc_json_typed(b, y, sh, ndim);
    free(y);
}

void tc_json_points(tc_strbuf *b, int nc, size_t n, const double *values, const double *grads,
                    const int32_t *tri, int plain) {
    tc_json_points_enc(b, nc, n, values, grads, tri, plain, 0);
}

/* "outside": the indices of the points outside the mesh. */
static void outside(tc_strbuf *b, size_t n, const int32_t *tri) {
    member(b, "outside");
    tc_strbuf_putc(b, '[');
    for (size_t i = 0, k = 0; tri && i < n; i++)
        if (tri[i] < 0) {
            if (k++) tc_strbuf_putc(b, ',');
            tc_strbuf_int(b, (long long)i);
        }
    tc_strbuf_putc(b, ']');
}

/* Points written between two calls of the stop check. */
#define STOP_EVERY 8192

int tc_json_points_enc_until(tc_strbuf *b, int nc, size_t n, const double *values, const double *grads,
                             const int32_t *tri, int plain, int base64, int (*stop)(void *), void *ctx) {
    if (base64) {
        member(b, "values");
        typed_points(b, nc, n, values, 1, tri, plain);
        if (grads) member(b, "gradients"), typed_points(b, nc, n, grads, 2, tri, plain);
        outside(b, n, tri);
        return 0;
    }
    member(b, "values");
    tc_strbuf_putc(b, '[');
    for (size_t i = 0; i < n; i++) {
        if (stop && i % STOP_EVERY == STOP_EVERY - 1 && stop(ctx)) return -1;
        if (i) tc_strbuf_putc(b, ',');
        point_entry(b, values + i * (size_t)nc, nc, 1, plain, tri && tri[i] < 0);
    }
    tc_strbuf_putc(b, ']');
    if (grads) {
        member(b, "gradients");
        tc_strbuf_putc(b, '[');
        for (size_t i = 0; i < n; i++) {
            if (stop && i % STOP_EVERY == STOP_EVERY - 1 && stop(ctx)) return -1;
            if (i) tc_strbuf_putc(b, ',');
            point_entry(b, grads + 2 * i * (size_t)nc, nc, 2, plain, tri && tri[i] < 0);
        }
        tc_strbuf_putc(b, ']');
    }
    outside(b, n, tri);
    return 0;
}

void tc_json_points_enc(tc_strbuf *b, int nc, size_t n, const double *values, const double *grads,
                        const int32_t *tri, int plain, int base64) {
    (void)tc_json_points_enc_until(b, nc, n, values, grads, tri, plain, base64, NULL, NULL);
}

void tc_json_diags(tc_strbuf *b, const char *name, const tc_diags *d, tc_severity sev) {
    member(b, name);
    tc_strbuf_putc(b, '[');
    int k = 0;
    for (int i = 0; d && i < d->count; i++) {
        if (d->items[i].severity != sev) continue;
        tc_strbuf_puts(b, k++ ? ",{\"path\":" : "{\"path\":");
        tc_strbuf_json_string(b, d->items[i].path);
        tc_strbuf_puts(b, ",\"message\":");
        tc_strbuf_json_string(b, d->items[i].message);
        tc_strbuf_putc(b, '}');
    }
    tc_strbuf_putc(b, ']');
}
