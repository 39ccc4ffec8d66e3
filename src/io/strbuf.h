/* strbuf.h — tc_strbuf, a growable NUL-terminated output buffer for the writers
 * (JSON, text). Allocation failure is sticky, so callers check `oom` once, at the end. */
#ifndef TC_IO_STRBUF_H
#define TC_IO_STRBUF_H

#include <stddef.h>

/* Invariants:
 *  - len < cap and buf[len] == '\0' whenever cap > 0; buf == NULL iff cap == 0;
 *  - once oom is set (an allocation failed, or a size overflowed) every append
 *    and reserve is a no-op until tc_strbuf_free / tc_strbuf_detach, and the
 *    content is whatever was there before the failure (still NUL-terminated);
 *  - capacity at least doubles on each growth, so appending is amortized O(1).
 * The fields may be read directly; change them only through these functions. */
typedef struct {
    char *buf;
    size_t len, cap;
    int oom;
} tc_strbuf;

void tc_strbuf_init(tc_strbuf *b);      /* empty, allocates nothing */
void tc_strbuf_free(tc_strbuf *b);      /* frees and re-inits; fine on an empty one */
void tc_strbuf_reset(tc_strbuf *b);     /* len = 0, keeps capacity, keeps oom */
/* Makes room for `extra` more bytes (plus the NUL). 0 on success, -1 if oom. */
int tc_strbuf_reserve(tc_strbuf *b, size_t extra);

/* s must not point into b->buf: growing may move it. */
void tc_strbuf_append(tc_strbuf *b, const char *s, size_t n);
void tc_strbuf_puts(tc_strbuf *b, const char *s);
void tc_strbuf_putc(tc_strbuf *b, char c);
/* An output error of vsnprintf (never seen with a valid format) also sets oom. */
void tc_strbuf_printf(tc_strbuf *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
void tc_strbuf_double(tc_strbuf *b, double x);  /* tc_fmt_double's text */
void tc_strbuf_int(tc_strbuf *b, long long x);
/* s as a quoted JSON string: '"' and '\\' escaped, \b \f \n \r \t, other bytes
 * below 0x20 as \u00XX, all else (UTF-8 included) copied as is. NULL gives null. */
void tc_strbuf_json_string(tc_strbuf *b, const char *s);

/* Hands the buffer to the caller (free() it) and re-inits b; *len (if len is not
 * NULL) gets its length. Returns "" (allocated) for an empty buffer, and NULL if
 * oom was set — the partial content is freed then. */
char *tc_strbuf_detach(tc_strbuf *b, size_t *len);

/* The inverse: b (freed first) takes over buf, a malloc()ed block of cap > len
 * bytes holding len bytes of content; buf[len] becomes the NUL. So an answer
 * produced elsewhere (an encoded image) becomes the response without a copy. */
void tc_strbuf_adopt(tc_strbuf *b, char *buf, size_t len, size_t cap);

/* Test hook: how many times a buffer grew (a reallocation) in this thread so far. */
long tc_strbuf__grows(void);

#endif
