/* sha256.c — SHA-256 as FIPS 180-4 §6.2 gives it (tests/unit/test_sha256.c checks
 * its test vectors), and base64url content ids over it. */
#include <string.h>

#include "io/sha256.h"

static const uint32_t K[64] = {
    0x428a2f98, 0x71374491, 0xb5c0fbcf, 0xe9b5dba5, 0x3956c25b, 0x59f111f1, 0x923f82a4, 0xab1c5ed5,
    0xd807aa98, 0x12835b01, 0x243185be, 0x550c7dc3, 0x72be5d74, 0x80deb1fe, 0x9bdc06a7, 0xc19bf174,
    0xe49b69c1, 0xefbe4786, 0x0fc19dc6, 0x240ca1cc, 0x2de92c6f, 0x4a7484aa, 0x5cb0a9dc, 0x76f988da,
    0x983e5152, 0xa831c66d, 0xb00327c8, 0xbf597fc7, 0xc6e00bf3, 0xd5a79147, 0x06ca6351, 0x14292967,
    0x27b70a85, 0x2e1b2138, 0x4d2c6dfc, 0x53380d13, 0x650a7354, 0x766a0abb, 0x81c2c92e, 0x92722c85,
    0xa2bfe8a1, 0xa81a664b, 0xc24b8b70, 0xc76c51a3, 0xd192e819, 0xd6990624, 0xf40e3585, 0x106aa070,
    0x19a4c116, 0x1e376c08, 0x2748774c, 0x34b0bcb5, 0x391c0cb3, 0x4ed8aa4a, 0x5b9cca4f, 0x682e6ff3,
    0x748f82ee, 0x78a5636f, 0x84c87814, 0x8cc70208, 0x90befffa, 0xa4506ceb, 0xbef9a3f7, 0xc67178f2};

static uint32_t rotr(uint32_t x, unsigned n) { return (x >> n) | (x << (32 - n)); }

/* One 64-byte block into the state (§6.2.2). */
static void block(uint32_t h[8], const unsigned char *p) {
    uint32_t w[64], v[8];
    for (int t = 0; t < 16; t++)
        w[t] = (uint32_t)p[4 * t] << 24 | (uint32_t)p[4 * t + 1] << 16 | (uint32_t)p[4 * t + 2] << 8 | p[4 * t + 3];
    for (int t = 16; t < 64; t++) {
        uint32_t s0 = rotr(w[t - 15], 7) ^ rotr(w[t - 15], 18) ^ (w[t - 15] >> 3);
        uint32_t s1 = rotr(w[t - 2], 17) ^ rotr(w[t - 2], 19) ^ (w[t - 2] >> 10);
        w[t] = w[t - 16] + s0 + w[t - 7] + s1;
    }
    memcpy(v, h, sizeof v);
    for (int t = 0; t < 64; t++) {
        uint32_t S1 = rotr(v[4], 6) ^ rotr(v[4], 11) ^ rotr(v[4], 25);
        uint32_t ch = (v[4] & v[5]) ^ (~v[4] & v[6]);
        uint32_t t1 = v[7] + S1 + ch + K[t] + w[t];
        uint32_t S0 = rotr(v[0], 2) ^ rotr(v[0], 13) ^ rotr(v[0], 22);
        uint32_t maj = (v[0] & v[1]) ^ (v[0] & v[2]) ^ (v[1] & v[2]);
        memmove(v + 1, v, 7 * sizeof *v);
        v[4] += t1;
        v[0] = t1 + S0 + maj;
    }
    for (int i = 0; i < 8; i++) h[i] += v[i];
}

void tc_sha256_init(tc_sha256_ctx *c) {
    static const uint32_t h0[8] = {0x6a09e667, 0xbb67ae85, 0x3c6ef372, 0xa54ff53a,
                                   0x510e527f, 0x9b05688c, 0x1f83d9ab, 0x5be0cd19};
    memcpy(c->h, h0, sizeof h0);
    c->len = 0;
}

void tc_sha256_update(tc_sha256_ctx *c, const void *data, size_t n) {
    const unsigned char *p = data;
    size_t used = (size_t)(c->len % 64);
    c->len += n;
    if (used) { /* fill the partial block first */
        size_t k = 64 - used < n ? 64 - used : n;
        memcpy(c->buf + used, p, k);
        p += k, n -= k;
        if (used + k < 64) return;
        block(c->h, c->buf);
    }
    for (; n >= 64; p += 64, n -= 64) block(c->h, p);
    memcpy(c->buf, p, n);
}

void tc_sha256_final(tc_sha256_ctx *c, unsigned char out[32]) {
    uint64_t bits = c->len * 8;
    size_t used = (size_t)(c->len % 64);
    c->buf[used++] = 0x80; /* §5.1.1: a one bit, zeros, the length in 64 bits big-endian */
    if (used > 56) {
        memset(c->buf + used, 0, 64 - used);
        block(c->h, c->buf);
        used = 0;
    }
    memset(c->buf + used, 0, 56 - used);
    for (int i = 0; i < 8; i++) c->buf[56 + i] = (unsigned char)(bits >> (56 - 8 * i));
    block(c->h, c->buf);
    for (int i = 0; i < 8; i++)
        for (int k = 0; k < 4; k++) out[4 * i + k] = (unsigned char)(c->h[i] >> (24 - 8 * k));
}

void tc_sha256(const void *data, size_t n, unsigned char out[32]) {
    tc_sha256_ctx c;
    tc_sha256_init(&c);
    tc_sha256_update(&c, data, n);
    tc_sha256_final(&c, out);
}

static const char b64url[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789-_";

void tc_content_id(const void *data, size_t n, char out[TC_CONTENT_ID_LEN + 1]) {
    unsigned char d[32];
    tc_sha256(data, n, d);
    /* 18 bytes = 6 groups of 3 bytes = 24 characters, no padding needed. */
    for (int g = 0; g < 6; g++) {
        uint32_t v = (uint32_t)d[3 * g] << 16 | (uint32_t)d[3 * g + 1] << 8 | d[3 * g + 2];
        for (int k = 0; k < 4; k++) out[4 * g + k] = b64url[(v >> (18 - 6 * k)) & 63];
    }
    out[TC_CONTENT_ID_LEN] = '\0';
}

int tc_content_id_valid(const char *s) {
    size_t n = 0;
    for (; s[n]; n++)
        if (n >= TC_CONTENT_ID_LEN || !strchr(b64url, s[n])) return 0;
    return n == TC_CONTENT_ID_LEN;
}
