/* strbuf.c — tc_strbuf: growable output buffer with sticky allocation failure.
 * Every append goes through room(), which reserves its bytes plus the NUL. */
#include "io/strbuf.h"

#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/hugemem.h"
#include "io/numfmt.h"

#define TC_STRBUF_MIN_CAP 64

static _Thread_local long grows; /* test hook: reallocations so far in this thread */

long tc_strbuf__grows(void) { return grows; }

void tc_strbuf_init(tc_strbuf *b) {
    b->buf = NULL;
    b->len = b->cap = 0;
    b->oom = 0;
}

void tc_strbuf_free(tc_strbuf *b) {
    free(b->buf);
    tc_strbuf_init(b);
}

void tc_strbuf_reset(tc_strbuf *b) {
    b->len = 0;
    if (b->cap) b->buf[0] = '\0';
}

/* Grows cap so that len + n + 1 <= cap: at least doubling, so a sequence of
 * appends copies each byte O(1) times on average. On failure sets oom and leaves
 * buf as it was. */
static int grow(tc_strbuf *b, size_t n) {
    if (n >= SIZE_MAX - b->len) goto fail;
    size_t need = b->len + n + 1;
    size_t cap = b->cap ? b->cap : TC_STRBUF_MIN_CAP;
    while (cap < need) cap = cap > SIZE_MAX / 2 ? need : 2 * cap;
    char *p = tc__huge_realloc(b->buf, cap); /* a big answer: huge pages, few faults */
    if (!p) goto fail;
    if (!b->cap) p[0] = '\0';
    b->buf = p;
    b->cap = cap;
    grows++;
    return 0;
fail:
    b->oom = 1;
    return -1;
}

/* 1 if n more bytes plus the NUL fit (growing if needed), 0 if b is or goes oom.
 * `cap - len > n` cannot overflow: len < cap, or both are 0. */
static inline int room(tc_strbuf *b, size_t n) {
    if (b->oom) return 0;
    return b->cap - b->len > n || grow(b, n) == 0;
}

int tc_strbuf_reserve(tc_strbuf *b, size_t extra) {
    return room(b, extra) ? 0 : -1;
}

void tc_strbuf_append(tc_strbuf *b, const char *s, size_t n) {
    if (!room(b, n)) return;
    memcpy(b->buf + b->len, s, n);
    b->len += n;
    b->buf[b->len] = '\0';
}

void tc_strbuf_puts(tc_strbuf *b, const char *s) {
    tc_strbuf_append(b, s, strlen(s));
}

void tc_strbuf_putc(tc_strbuf *b, char c) {
    if (!room(b, 1)) return;
    b->buf[b->len++] = c;
    b->buf[b->len] = '\0';
}

/* Formats into the spare space; if that was too small, grows to the exact size
 * vsnprintf reported and formats again. */
void tc_strbuf_printf(tc_strbuf *b, const char *fmt, ...) {
    va_list ap, ap2;
    if (!room(b, 0)) return;
    va_start(ap, fmt);
    va_copy(ap2, ap);
    int n = vsnprintf(b->buf + b->len, b->cap - b->len, fmt, ap);
    va_end(ap);
    if (n >= 0 && (size_t)n >= b->cap - b->len && room(b, (size_t)n))
        n = vsnprintf(b->buf + b->len, b->cap - b->len, fmt, ap2);
    va_end(ap2);
    if (b->oom) {
        b->buf[b->len] = '\0';              /* undo a truncated first attempt */
    } else if (n < 0) {
        b->buf[b->len] = '\0';
        b->oom = 1;
    } else {
        b->len += (size_t)n;
    }
}

/* Formats straight into the spare space: room() guarantees 32 bytes + NUL. */
void tc_strbuf_double(tc_strbuf *b, double x) {
    if (!room(b, TC_FMT_DOUBLE_SIZE)) return;
    b->len += tc_fmt_double(b->buf + b->len, x);
}

/* Counts the digits first so they can be written in place, last one first.
 * The magnitude is taken in unsigned arithmetic, so LLONG_MIN is fine. */
void tc_strbuf_int(tc_strbuf *b, long long x) {
    unsigned long long u = x < 0 ? 0ULL - (unsigned long long)x : (unsigned long long)x;
    size_t nd = 1;
    for (unsigned long long t = u; t >= 10; t /= 10) nd++;
    size_t n = nd + (x < 0);
    if (!room(b, n)) return;
    char *end = b->buf + b->len + n;
    do {
        *--end = (char)('0' + u % 10);
        u /= 10;
    } while (u);
    if (x < 0) *--end = '-';
    b->len += n;
    b->buf[b->len] = '\0';
}

/* The escape of byte c, or NULL if c is copied as is. `u` receives \u00XX. */
static const char *json_escape(unsigned char c, char u[7]) {
    static const char hex[] = "0123456789abcdef";
    switch (c) {
    case '"': return "\\\"";
    case '\\': return "\\\\";
    case '\b': return "\\b";
    case '\f': return "\\f";
    case '\n': return "\\n";
    case '\r': return "\\r";
    case '\t': return "\\t";
    default:
        if (c >= 0x20) return NULL;
        memcpy(u, "\\u00", 4);
        u[4] = hex[c >> 4];
        u[5] = hex[c & 15];
        u[6] = '\0';
        return u;
    }
}

/* Copies runs of plain bytes with one append each; escapes in between. */
void tc_strbuf_json_string(tc_strbuf *b, const char *s) {
    if (!s) {
        tc_strbuf_append(b, "null", 4);
        return;
    }
    char u[7];
    tc_strbuf_putc(b, '"');
    const char *run = s;
    for (; *s; s++) {
        const char *esc = json_escape((unsigned char)*s, u);
        if (!esc) continue;
        tc_strbuf_append(b, run, (size_t)(s - run));
        tc_strbuf_puts(b, esc);
        run = s + 1;
    }
    tc_strbuf_append(b, run, (size_t)(s - run));
    tc_strbuf_putc(b, '"');
}

char *tc_strbuf_detach(tc_strbuf *b, size_t *len) {
    if (!b->oom) room(b, 0);                /* an empty buffer still yields "" */
    char *s = b->oom ? NULL : b->buf;
    if (len) *len = s ? b->len : 0;
    if (!s) free(b->buf);
    tc_strbuf_init(b);
    return s;
}

void tc_strbuf_adopt(tc_strbuf *b, char *buf, size_t len, size_t cap) {
    tc_strbuf_free(b);
    if (!buf || cap <= len) {
        free(buf);
        b->oom = 1;
        return;
    }
    buf[len] = '\0';
    b->buf = buf, b->len = len, b->cap = cap;
}
