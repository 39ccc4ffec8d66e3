/* test_base64.c — the base64 codec (io/base64.h): RFC 4648 §10 vectors both ways, every
 * length mod 3 round-tripped, and each refusal (alphabet, padding, length, bits) with its offset. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "io/base64.h"

static const struct {
    const char *raw, *enc;
} rfc[] = {{"", ""},         {"f", "Zg=="},         {"fo", "Zm8="},        {"foo", "Zm9v"},
           {"foob", "Zm9vYg=="}, {"fooba", "Zm9vYmE="}, {"foobar", "Zm9vYmFy"}};

TEST(base64_rfc4648_vectors) {
    for (size_t i = 0; i < sizeof rfc / sizeof rfc[0]; i++) {
        size_t n = strlen(rfc[i].raw), k = strlen(rfc[i].enc);
        char enc[16] = {0};
        unsigned char dec[16] = {0};
        CHECK(tc_base64_encoded_len(n) == k);
        tc_base64_encode(rfc[i].raw, n, enc);
        CHECK_MSG(!memcmp(enc, rfc[i].enc, k), "encode(\"%s\") = %.*s", rfc[i].raw, (int)k, enc);
        size_t bad = 99;
        const char *why = NULL;
        CHECK(tc_base64_decoded_len(rfc[i].enc, k) == n);
        CHECK_MSG(tc_base64_decode(rfc[i].enc, k, dec, &bad, &why) == 0, "decode(%s): %s", rfc[i].enc, why);
        CHECK(!memcmp(dec, rfc[i].raw, n));
        tc_strbuf b;
        tc_strbuf_init(&b);
        tc_strbuf_puts(&b, "x");
        tc_base64_append(&b, rfc[i].raw, n);
        CHECK(b.len == k + 1 && !memcmp(b.buf + 1, rfc[i].enc, k) && b.buf[b.len] == '\0');
        tc_strbuf_free(&b);
    }
}

/* Every byte value in every position, lengths 0 .. 300 (each length mod 3). */
TEST(base64_round_trip_every_length) {
    unsigned char raw[300], dec[300];
    char enc[400];
    srand((unsigned)tc_test_seed());
    for (size_t n = 0; n <= sizeof raw; n++) {
        for (size_t i = 0; i < n; i++) raw[i] = (unsigned char)(n < 256 ? (i + n) & 0xFF : rand() & 0xFF);
        size_t k = tc_base64_encoded_len(n), bad;
        const char *why;
        tc_base64_encode(raw, n, enc);
        CHECK(k % 4 == 0 && tc_base64_decoded_len(enc, k) == n);
        int rc = tc_base64_decode(enc, k, dec, &bad, &why);
        CHECK_MSG(rc == 0 && !memcmp(raw, dec, n), "length %zu", n);
        for (size_t i = 0; i < k; i++)
            CHECK(strchr("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/=", enc[i]) != NULL);
    }
}

/* decode(s) must fail at offset `at` with a reason containing `why_part`. */
static void refused_at(const char *file, int line, const char *s, size_t at, const char *why_part) {
    unsigned char out[64];
    size_t bad = 12345;
    const char *why = NULL;
    int rc = tc_base64_decode(s, strlen(s), out, &bad, &why);
    if (rc != -1) tc_test_fail(file, line, "\"%s\" accepted", s);
    else if (bad != at || !why || !strstr(why, why_part))
        tc_test_fail(file, line, "\"%s\": offset %zu (%s), expected %zu (%s)", s, bad, why ? why : "?", at, why_part);
}
#define REFUSED(s, at, why) refused_at(__FILE__, __LINE__, s, at, why)

TEST(base64_refusals) {
    REFUSED("Zm9", 3, "multiple of 4");          /* padding missing */
    REFUSED("Zg", 2, "multiple of 4");
    REFUSED("Zm9vY", 5, "multiple of 4");
    REFUSED("Zm 9", 2, "outside the base64 alphabet"); /* no whitespace */
    REFUSED("Zm9v\nYmFy", 9, "multiple of 4"); /* a line break makes the length wrong */
    REFUSED("Zm9v\nYmE", 4, "outside the base64 alphabet");
    REFUSED("Zm-v", 2, "outside");               /* URL-safe alphabet refused */
    REFUSED("Zm_v", 2, "outside");
    REFUSED("Z===", 1, "'=' before the end");    /* three '=' */
    REFUSED("Zg==Zm9v", 2, "'=' before the end"); /* padding in the middle */
    REFUSED("=Zm9", 0, "'=' before the end");
    REFUSED("Zh==", 1, "non-zero bits");         /* 'h' leaves bits the padding drops */
    REFUSED("Zm9=", 2, "non-zero bits");
    REFUSED("Zm\x80v", 2, "outside");
    unsigned char out[4];
    size_t bad;
    const char *why;
    CHECK(tc_base64_decode("Zm8=", 4, out, &bad, &why) == 0 && out[0] == 'f' && out[1] == 'o');
    CHECK(tc_base64_decoded_len("Zm9", 3) == 0);
}

/* A character outside the alphabet in the first place of the last, padded group: refused
 * with its offset, like anywhere else. The check of that group's characters must start at the
 * group's first one: its bits are not among those the padding drops, so the canonical-bits
 * test would not notice it ("*QA=" would decode to a garbage byte, "*Q==" would be refused
 * for the wrong reason). */
TEST(base64_refuses_bad_first_char_of_padded_group) {
    REFUSED("*QA=", 0, "outside the base64 alphabet");
    REFUSED("*Q==", 0, "outside the base64 alphabet");
    REFUSED("Zm9v*QA=", 4, "outside the base64 alphabet");
    REFUSED("Zm9v\x80g==", 4, "outside the base64 alphabet");
    REFUSED("Zm9v=g==", 4, "'=' before the end");
}

/* Each bit that the padding drops, alone: "ZB==" .. "ZI==" set one of the four low bits of the
 * second character (bits 12 to 15 of the group), "ZmB=" and "ZmC=" one of the two low bits of
 * the third (bits 6 and 7). Every one must be refused as non-canonical, at the character that
 * carries it, or two texts would decode to the same bytes. */
TEST(base64_refuses_every_dropped_bit) {
    static const char two[4][5] = {"ZB==", "ZC==", "ZE==", "ZI=="}, one[2][5] = {"ZmB=", "ZmC="};
    for (int k = 0; k < 4; k++) REFUSED(two[k], 1, "non-zero bits");
    for (int k = 0; k < 2; k++) REFUSED(one[k], 2, "non-zero bits");
    REFUSED("Zm9vZmC=", 6, "non-zero bits");
    REFUSED("Zm9vZI==", 5, "non-zero bits");
}
