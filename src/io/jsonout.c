/* jsonout.c — JSON output primitives shared by the response writers, the
 * request writer and /v1/compare; numbers go through the exact printer. */
#include "io/base64.h"
#include "io/jsonout.h"
#include "io/options.h"

void tc_json_key(tc_strbuf *b, const char *sep, const char *name) {
    if (b->len && b->buf[b->len - 1] != '{') tc_strbuf_puts(b, sep);
    tc_strbuf_json_string(b, name);
    tc_strbuf_putc(b, ':');
}

void tc_json_numbers(tc_strbuf *b, const double *x, int n) {
    tc_strbuf_putc(b, '[');
    for (int i = 0; i < n; i++) {
        if (i) tc_strbuf_putc(b, ',');
        tc_strbuf_double(b, x[i]);
    }
    tc_strbuf_putc(b, ']');
}

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
#error "typed arrays carry the host's doubles as little-endian bytes"
#endif

void tc_json_typed_open(tc_strbuf *b, const size_t *shape, int ndim) {
    tc_strbuf_puts(b, "{\"dtype\":\"float64\",\"shape\":[");
    for (int k = 0; k < ndim; k++) {
        if (k) tc_strbuf_putc(b, ',');
        tc_strbuf_int(b, (long long)shape[k]);
    }
    tc_strbuf_puts(b, "],\"data\":\"");
}

void tc_json_typed_close(tc_strbuf *b) { tc_strbuf_puts(b, "\"}"); }

void tc_json_typed(tc_strbuf *b, const double *x, const size_t *shape, int ndim) {
    size_t count = 1;
    for (int k = 0; k < ndim; k++) count *= shape[k];
    tc_json_typed_open(b, shape, ndim);
    tc_base64_append(b, x, count * sizeof *x);
    tc_json_typed_close(b);
}

void tc_json_ints(tc_strbuf *b, const int32_t *x, int n) {
    tc_strbuf_putc(b, '[');
    for (int i = 0; i < n; i++) {
        if (i) tc_strbuf_putc(b, ',');
        tc_strbuf_int(b, x[i]);
    }
    tc_strbuf_putc(b, ']');
}

void tc_json_options(tc_strbuf *b, const tc_options *o) {
    for (int i = 0; i < tc_opt_count(); i++) { /* the method, then only the options it reads */
        const tc_opt *row = tc_opt_at(i);
        if (tc_opt_read_by(row, o->method)) tc_opt_write(b, ",", row, o);
    }
}
