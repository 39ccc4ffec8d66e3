/* jsonout.c — JSON output primitives shared by the response writers, the
 * request writer and /v1/compare; numbers go through the exact printer. */
#include "io/jsonout.h"

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

void tc_json_ints(tc_strbuf *b, const int32_t *x, int n) {
    tc_strbuf_putc(b, '[');
    for (int i = 0; i < n; i++) {
        if (i) tc_strbuf_putc(b, ',');
        tc_strbuf_int(b, x[i]);
    }
    tc_strbuf_putc(b, ']');
}

void tc_json_options(tc_strbuf *b, const tc_options *o) {
    tc_json_key(b, ",", "method");
    tc_strbuf_json_string(b, tc_method_name(o->method));
    unsigned reads = tc_method_reads(o->method); /* only the options the method reads */
    if (reads & TC_READS_CROSS_BOUNDARY) {
        tc_json_key(b, ",", "cross_boundary");
        tc_strbuf_json_string(b, tc_cross_name(o->cross_boundary));
    }
    if (reads & TC_READS_TWIST) {
        tc_json_key(b, ",", "twist");
        tc_strbuf_json_string(b, tc_twist_name(o->twist));
    }
    if (reads & TC_READS_WEDGES) {
        tc_json_key(b, ",", "wedges");
        tc_strbuf_json_string(b, tc_wedges_name(o->wedges));
    }
    if (reads & TC_READS_TANGENTS) {
        tc_json_key(b, ",", "tangents");
        tc_strbuf_json_string(b, tc_tangents_name(o->tangents));
    }
    if (reads & TC_READS_AVERAGE) {
        tc_json_key(b, ",", "average");
        tc_strbuf_json_string(b, tc_average_name(o->average));
    }
}
