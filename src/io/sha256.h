/* sha256.h — SHA-256 (FIPS 180-4) and the content ids made from it: what names a
 * stored mesh, the same for the same canonical bytes on every replica. */
#ifndef TC_IO_SHA256_H
#define TC_IO_SHA256_H

#include <stddef.h>
#include <stdint.h>

/* Incremental hashing: init, any number of updates, final. */
typedef struct {
    uint32_t h[8];
    uint64_t len;          /* bytes hashed so far */
    unsigned char buf[64]; /* a partial block; len % 64 bytes of it are used */
} tc_sha256_ctx;

void tc_sha256_init(tc_sha256_ctx *c);
void tc_sha256_update(tc_sha256_ctx *c, const void *data, size_t n);
void tc_sha256_final(tc_sha256_ctx *c, unsigned char out[32]);
void tc_sha256(const void *data, size_t n, unsigned char out[32]);

/* Characters of a content id, without the NUL: base64url (RFC 4648 §5, no
 * padding) of the first 18 bytes (144 bits) of the SHA-256 of the bytes. */
#define TC_CONTENT_ID_LEN 24
void tc_content_id(const void *data, size_t n, char out[TC_CONTENT_ID_LEN + 1]);

/* 1 if s has the shape of a content id (24 characters of [A-Za-z0-9_-]). */
int tc_content_id_valid(const char *s);

#endif
