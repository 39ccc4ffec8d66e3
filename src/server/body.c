/* body.c — request bodies: header checks, accumulation under the limit (so a
 * client cannot make the server allocate more than --max-body), UTF-8. */
#include <limits.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "io/hugemem.h"
#include "server/body.h"

enum { FIRST_CHUNK = 64 * 1024 };

void tc_body_init(tc_body *b, size_t limit) {
    b->buf = NULL;
    b->len = b->cap = b->expect = 0;
    b->limit = limit;
}

void tc_body_free(tc_body *b) {
    free(b->buf);
    tc_body_init(b, b->limit);
}

/* Capacity for `need` bytes plus the NUL, growing geometrically up to the
 * declared length (when it covers need) or the limit, + 1. */
static int grow(tc_body *b, size_t need) {
    if (need < b->cap) return 0;
    size_t cap = b->cap ? b->cap : FIRST_CHUNK;
    while (cap <= need) cap = cap > SIZE_MAX / 2 ? SIZE_MAX : cap * 2;
    size_t most = b->expect >= need ? b->expect : b->limit;
    if (cap > most + 1) cap = most + 1;
    char *p = tc__huge_realloc(b->buf, cap); /* a big body: huge pages, few faults */
    if (!p) return -1;
    b->buf = p, b->cap = cap;
    return 0;
}

/* Nothing is allocated before bytes arrive: a client that declares 64 MiB and
 * sends nothing must not cost 64 MiB (300 such connections reserved 19.8 GB of
 * virtual memory). The declared length only caps the geometric growth. */
int tc_body_reserve(tc_body *b, size_t expect) {
    if (expect <= b->limit) b->expect = expect; /* larger: refused elsewhere */
    return 0;
}

int tc_body_append(tc_body *b, const char *data, size_t n) {
    if (n > b->limit - b->len) return 1;
    if (grow(b, b->len + n)) return -1;
    memcpy(b->buf + b->len, data, n);
    b->len += n;
    b->buf[b->len] = '\0';
    return 0;
}

static const char *skip_ws(const char *s) {
    while (*s == ' ' || *s == '\t') s++;
    return s;
}

/* Length of s[0..n) without trailing blanks. */
static size_t trim(const char *s, size_t n) {
    while (n && (s[n - 1] == ' ' || s[n - 1] == '\t')) n--;
    return n;
}

/* A "charset=..." parameter must say UTF-8 (JSON is UTF-8, RFC 8259); others pass. */
static int param_ok(const char *p, size_t n) {
    size_t eq = strcspn(p, "=");
    if (eq >= n || trim(p, eq) != 7 || strncasecmp(p, "charset", 7)) return 1;
    const char *v = skip_ws(p + eq + 1);
    size_t vn = trim(v, n - (size_t)(v - p));
    if (vn >= 2 && v[0] == '"' && v[vn - 1] == '"') v++, vn -= 2;
    return (vn == 5 && !strncasecmp(v, "utf-8", 5)) || (vn == 4 && !strncasecmp(v, "utf8", 4));
}

int tc_media_is_json(const char *ct) {
    if (!ct) return 0;
    ct = skip_ws(ct);
    size_t n = strcspn(ct, ";");
    if (trim(ct, n) != 16 || strncasecmp(ct, "application/json", 16)) return 0;
    for (const char *p = ct + n; *p == ';';) {
        p = skip_ws(p + 1);
        size_t pn = strcspn(p, ";");
        if (!param_ok(p, pn)) return 0;
        p += pn;
    }
    return 1;
}

long long tc_content_length(const char *v) {
    if (!v) return -1;
    v = skip_ws(v);
    if (*v < '0' || *v > '9') return -1;
    long long n = 0;
    for (; *v >= '0' && *v <= '9'; v++) n = n > (LLONG_MAX - 9) / 10 ? LLONG_MAX : n * 10 + (*v - '0');
    return *skip_ws(v) ? -1 : n;
}

/* Bytes of the sequence starting with lead byte c, and the range of its second
 * byte (which excludes overlong forms, surrogates and code points > U+10FFFF); 0 if c cannot lead. */
static int seq_len(unsigned c, unsigned *lo, unsigned *hi) {
    *lo = 0x80, *hi = 0xBF;
    if (c >= 0xC2 && c <= 0xDF) return 2;
    if (c == 0xE0) return *lo = 0xA0, 3;
    if (c == 0xED) return *hi = 0x9F, 3;
    if (c >= 0xE1 && c <= 0xEF) return 3;
    if (c == 0xF0) return *lo = 0x90, 4;
    if (c == 0xF4) return *hi = 0x8F, 4;
    if (c >= 0xF1 && c <= 0xF3) return 4;
    return 0;
}

long long tc_utf8_error(const char *s, size_t n) {
    const unsigned char *p = (const unsigned char *)s;
    size_t i = 0;
    while (i < n) {
        uint64_t w;
        if (n - i >= 8 && (memcpy(&w, p + i, 8), !(w & 0x8080808080808080ull))) {
            i += 8; /* eight ASCII bytes at once: bodies are mostly ASCII */
            continue;
        }
        if (p[i] < 0x80) {
            i++;
            continue;
        }
        unsigned lo, hi;
        size_t len = (size_t)seq_len(p[i], &lo, &hi);
        if (!len || n - i < len || p[i + 1] < lo || p[i + 1] > hi) return (long long)i;
        for (size_t k = 2; k < len; k++)
            if ((p[i + k] & 0xC0) != 0x80) return (long long)i;
        i += len;
    }
    return -1;
}
