/* base64.c — RFC 4648 base64, standard alphabet with padding, strict on input: the
 * typed arrays' "data" (io/typed.c) and the "encoding": "base64" answers (io/response.c). */
#include <pthread.h>
#include <stdint.h>
#include <string.h>

#include "io/base64.h"

static const char alphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

size_t tc_base64_encoded_len(size_t n) {
    size_t groups = n / 3 + (n % 3 != 0);
    return groups > SIZE_MAX / 4 ? SIZE_MAX : 4 * groups;
}

/* The two characters of each 12-bit group, built once: one lookup per 12 bits instead of
 * per 6 halves the table work of the encoder (the typed answers' hot loop). */
static char pairs[4096][2];
static pthread_once_t pairs_once = PTHREAD_ONCE_INIT;

static void make_pairs(void) {
    for (int v = 0; v < 4096; v++) pairs[v][0] = alphabet[v >> 6], pairs[v][1] = alphabet[v & 63];
}

void tc_base64_encode(const void *in, size_t n, char *out) {
    const unsigned char *p = in;
    size_t i = 0;
    pthread_once(&pairs_once, make_pairs);
    for (; i + 3 <= n; i += 3, out += 4) {
        uint32_t w = (uint32_t)p[i] << 16 | (uint32_t)p[i + 1] << 8 | p[i + 2];
        memcpy(out, pairs[w >> 12], 2);
        memcpy(out + 2, pairs[w & 4095], 2);
    }
    if (i == n) return;
    uint32_t w = (uint32_t)p[i] << 16 | (i + 1 < n ? (uint32_t)p[i + 1] << 8 : 0);
    out[0] = alphabet[w >> 18], out[1] = alphabet[w >> 12 & 63];
    out[2] = i + 1 < n ? alphabet[w >> 6 & 63] : '=';
    out[3] = '=';
}

void tc_base64_append(tc_strbuf *b, const void *in, size_t n) {
    size_t k = tc_base64_encoded_len(n);
    if (k == SIZE_MAX || tc_strbuf_reserve(b, k)) {
        b->oom = 1;
        return;
    }
    tc_base64_encode(in, n, b->buf + b->len);
    b->len += k;
    b->buf[b->len] = '\0';
}

/* The 6-bit value of each byte, -1 outside the alphabet (a table: decoding is a hot loop). */
static const signed char sextets[256] = {
    -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1,
    -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1,
    -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, 62, -1, -1, -1, 63,
    52, 53, 54, 55, 56, 57, 58, 59, 60, 61, -1, -1, -1, -1, -1, -1,
    -1,  0,  1,  2,  3,  4,  5,  6,  7,  8,  9, 10, 11, 12, 13, 14,
    15, 16, 17, 18, 19, 20, 21, 22, 23, 24, 25, -1, -1, -1, -1, -1,
    -1, 26, 27, 28, 29, 30, 31, 32, 33, 34, 35, 36, 37, 38, 39, 40,
    41, 42, 43, 44, 45, 46, 47, 48, 49, 50, 51, -1, -1, -1, -1, -1,
    -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1,
    -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1,
    -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1,
    -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1,
    -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1,
    -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1,
    -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1,
    -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1,
};

static int sextet(unsigned char c) { return sextets[c]; }

/* '=' characters at the end (0, 1 or 2 in valid text). */
static size_t padding(const char *s, size_t len) {
    if (len < 4 || s[len - 1] != '=') return 0;
    return s[len - 2] == '=' ? 2 : 1;
}

size_t tc_base64_decoded_len(const char *s, size_t len) {
    if (len % 4) return 0;
    return len / 4 * 3 - padding(s, len);
}

static int fail(size_t at, const char *reason, size_t *bad, const char **why) {
    *bad = at;
    *why = reason;
    return -1;
}

/* Each character of s[from..len - pad) is in the alphabet (the pad last ones are '='). */
static int check_chars(const char *s, size_t from, size_t len, size_t pad, size_t *bad, const char **why) {
    for (size_t i = from; i < len - pad; i++)
        if (sextet((unsigned char)s[i]) < 0)
            return fail(i, s[i] == '=' ? "'=' before the end" : "a character outside the base64 alphabet", bad,
                        why);
    return 0;
}

/* Decodes the full groups s[0..4 * groups) into o, one pass: the OR of the sextets is
 * negative iff some character is outside the alphabet (-1 in the table). 0 or -1. */
static int decode_groups(const char *s, size_t groups, unsigned char *o) {
    int any = 0;
    for (size_t g = 0; g < groups; g++, s += 4, o += 3) {
        int a = sextet((unsigned char)s[0]), b = sextet((unsigned char)s[1]);
        int c = sextet((unsigned char)s[2]), d = sextet((unsigned char)s[3]);
        any |= a | b | c | d;
        uint32_t w = (uint32_t)a << 18 | (uint32_t)b << 12 | (uint32_t)c << 6 | (uint32_t)d;
        o[0] = (unsigned char)(w >> 16), o[1] = (unsigned char)(w >> 8), o[2] = (unsigned char)w;
    }
    return any < 0 ? -1 : 0;
}

int tc_base64_decode(const char *s, size_t len, void *out, size_t *bad, const char **why) {
    unsigned char *o = out;
    if (len % 4) return fail(len, "length not a multiple of 4 (padding missing?)", bad, why);
    if (len == 0) return 0;
    size_t pad = padding(s, len), full = (len - (pad ? 4 : 0)) / 4, i = 4 * full;
    if (decode_groups(s, full, o)) { /* out holds garbage; this second pass finds where */
        check_chars(s, 0, len, pad, bad, why);
        return -1;
    }
    if (!pad) return 0;
    if (check_chars(s, i, len, pad, bad, why)) return -1; /* the last group, before its '=' */
    o += 3 * full;
    uint32_t w = (uint32_t)sextet((unsigned char)s[i]) << 18 | (uint32_t)sextet((unsigned char)s[i + 1]) << 12;
    if (pad == 1) w |= (uint32_t)sextet((unsigned char)s[i + 2]) << 6;
    if (w & (pad == 1 ? 0xFFu : 0xFFFFu)) /* bits the padding drops must be zero */
        return fail(i + 3 - pad, "non-zero bits before the padding (not canonical base64)", bad, why);
    o[0] = (unsigned char)(w >> 16);
    if (pad == 1) o[1] = (unsigned char)(w >> 8);
    return 0;
}
