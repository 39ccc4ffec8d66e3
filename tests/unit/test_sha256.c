/* test_sha256.c — SHA-256 against the FIPS 180-4 examples (and the long
 * one-million-'a' message), fed whole and in uneven pieces; content ids' shape. */
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "io/sha256.h"

static void hex(const unsigned char d[32], char out[65]) {
    for (int i = 0; i < 32; i++) sprintf(out + 2 * i, "%02x", d[i]);
}

TEST(sha256_fips_vectors) {
    static const struct {
        const char *msg, *digest;
    } v[] = {
        {"abc", "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"},
        {"", "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855"},
        {"abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq",
         "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1"},
        {"abcdefghbcdefghicdefghijdefghijkefghijklfghijklmghijklmnhijklmnoijklmnopjklmnopqklmnopqrlmnopqrsmnopqrstnopqrstu",
         "cf5b16a778af8380036ce59e7b0492370b249b11e8f07a51afac45037afee9d1"},
    };
    for (size_t i = 0; i < sizeof v / sizeof v[0]; i++) {
        unsigned char d[32];
        char h[65];
        tc_sha256(v[i].msg, strlen(v[i].msg), d);
        hex(d, h);
        CHECK_MSG(!strcmp(h, v[i].digest), "sha256(\"%s\") = %s, expected %s", v[i].msg, h, v[i].digest);
        /* The same fed one byte, then 3, then the rest: block boundaries inside updates. */
        tc_sha256_ctx c;
        tc_sha256_init(&c);
        size_t n = strlen(v[i].msg), a = n > 0 ? 1 : 0, b = n > 4 ? 3 : 0;
        tc_sha256_update(&c, v[i].msg, a);
        tc_sha256_update(&c, v[i].msg + a, b);
        tc_sha256_update(&c, v[i].msg + a + b, n - a - b);
        tc_sha256_final(&c, d);
        hex(d, h);
        CHECK_MSG(!strcmp(h, v[i].digest), "pieces of \"%s\": %s", v[i].msg, h);
    }
}

TEST(sha256_million_a) {
    static char block[1000];
    memset(block, 'a', sizeof block);
    tc_sha256_ctx c;
    tc_sha256_init(&c);
    for (int i = 0; i < 1000; i++) tc_sha256_update(&c, block, sizeof block);
    unsigned char d[32];
    char h[65];
    tc_sha256_final(&c, d);
    hex(d, h);
    CHECK(!strcmp(h, "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0"));
}

TEST(content_id_shape) {
    char id[TC_CONTENT_ID_LEN + 1], other[TC_CONTENT_ID_LEN + 1];
    tc_content_id("abc", 3, id);
    /* base64url of ba7816bf8f01cfea414140de5dae2223b003 */
    CHECK_MSG(!strcmp(id, "ungWv48Bz-pBQUDeXa4iI7AD"), "id %s", id);
    CHECK(tc_content_id_valid(id));
    tc_content_id("abd", 3, other);
    CHECK(strcmp(id, other) != 0);
    CHECK(!tc_content_id_valid(""));
    CHECK(!tc_content_id_valid("ungWv48Bz-pBQUDeXa4iI7A"));   /* 23 */
    CHECK(!tc_content_id_valid("ungWv48Bz-pBQUDeXa4iI7ADx")); /* 25 */
    CHECK(!tc_content_id_valid("ungWv48Bz+pBQUDeXa4iI7AD"));  /* '+' is not base64url */
    CHECK(!tc_content_id_valid("../../../../../etc/passwd"));
}
