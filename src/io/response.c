/* response.c — JSON writers for the core's results. Numbers go through
 * tc_strbuf_double so every double parses back to itself. */
#include "io/response.h"
#include "io/jsonout.h"
#include "core/alloc.h"

static void member(tc_strbuf *b, const char *name) { tc_json_key(b, ",", name); }

void tc_json_ordinates(tc_strbuf *b, const tc_recon *r) {
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

void tc_json_points(tc_strbuf *b, int nc, size_t n, const double *values, const double *grads,
                    const int32_t *tri, int plain) {
    member(b, "values");
    tc_strbuf_putc(b, '[');
    for (size_t i = 0; i < n; i++) {
        if (i) tc_strbuf_putc(b, ',');
        point_entry(b, values + i * (size_t)nc, nc, 1, plain, tri && tri[i] < 0);
    }
    tc_strbuf_putc(b, ']');
    if (grads) {
        member(b, "gradients");
        tc_strbuf_putc(b, '[');
        for (size_t i = 0; i < n; i++) {
            if (i) tc_strbuf_putc(b, ',');
            point_entry(b, grads + 2 * i * (size_t)nc, nc, 2, plain, tri && tri[i] < 0);
        }
        tc_strbuf_putc(b, ']');
    }
    member(b, "outside");
    tc_strbuf_putc(b, '[');
    for (size_t i = 0, k = 0; tri && i < n; i++)
        if (tri[i] < 0) {
            if (k++) tc_strbuf_putc(b, ',');
            tc_strbuf_int(b, (long long)i);
        }
    tc_strbuf_putc(b, ']');
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
