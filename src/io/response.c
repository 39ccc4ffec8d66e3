/* response.c — JSON writers for the core's results. Numbers go through
 * tc_strbuf_double so every double parses back to itself. */
#include "io/response.h"
#include "io/jsonout.h"
#include "core/alloc.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void member(tc_strbuf *b, const char *name) { tc_json_key(b, ",", name); }

void tc_json_ordinates(tc_strbuf *b, const tc_recon *r) { tc_json_ordinates_enc(b, r, 0); }

/* "ordinates" as one typed array [T][C][K] in the request's numbering. */
static void typed_ordinates(tc_strbuf *b, const tc_recon *r) {
    const tc_mesh *m = tc_recon_mesh(r);
    size_t nc = (size_t)tc_mesh_channel_count(m), nk = (size_t)tc_recon_coef_count(r);
    size_t ngiven = (size_t)tc_mesh_given_triangle_count(m), row = nc * nk;
    double *x = malloc((ngiven ? ngiven : 1) * row * sizeof *x);
    if (!x) {
        b->oom = 1;
        return;
    }
    const double *coef = tc_recon_coefs(r);
    for (size_t i = 0; i < ngiven; i++) {
        int32_t t = tc_mesh_triangle_of_given(m, (int32_t)i);
        for (size_t ch = 0; ch < nc; ch++)
            for (size_t k = 0; k < nk; k++)
                x[i * row + ch * nk + k] = t < 0 ? NAN : coef[tc__ix(t, (long)nc, (long)ch) * nk + k];
    }
    const size_t shape[3] = {ngiven, nc, nk};
    tc_json_typed(b, x, shape, 3);
    free(x);
}

void tc_json_ordinates_enc(tc_strbuf *b, const tc_recon *r, int base64) {
    const tc_mesh *m = tc_recon_mesh(r);
    int nc = tc_mesh_channel_count(m), nk = tc_recon_coef_count(r);
    int32_t ngiven = tc_mesh_given_triangle_count(m);
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
    const double *coef = tc_recon_coefs(r);
    for (int32_t i = 0; i < ngiven && !b->oom; i++) { /* the request's numbering: null where dropped */
        int32_t t = tc_mesh_triangle_of_given(m, i);
        tc_strbuf_puts(b, i ? ",\n" : "\n");
        if (t < 0) {
            tc_strbuf_puts(b, "null");
            continue;
        }
        tc_strbuf_putc(b, '[');
        for (int ch = 0; ch < nc; ch++) {
            if (ch) tc_strbuf_putc(b, ',');
            tc_json_numbers(b, coef + tc__ix(t, nc, ch) * (size_t)nk, nk);
        }
        tc_strbuf_putc(b, ']');
    }
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
