/* base64.h — RFC 4648 base64 (standard alphabet, '=' padding) for typed arrays:
 * the request's "data" strings in, "encoding": "base64" answers out. */
#ifndef TC_IO_BASE64_H
#define TC_IO_BASE64_H

#include <stddef.h>

#include "io/strbuf.h"

/* Characters of the encoding of n bytes: 4 * ceil(n / 3) (SIZE_MAX if that overflows). */
size_t tc_base64_encoded_len(size_t n);
/* Writes tc_base64_encoded_len(n) characters (no NUL) of in[0..n) to out. */
void tc_base64_encode(const void *in, size_t n, char *out);
/* Appends the encoding of in[0..n) to b (sets b->oom on failure). */
void tc_base64_append(tc_strbuf *b, const void *in, size_t n);

/* Bytes that s[0..len) decodes to when it is well formed: 3 * len / 4 less the
 * padding; 0 when len is not a multiple of 4 (tc_base64_decode then refuses it). */
size_t tc_base64_decoded_len(const char *s, size_t len);
/* Strict decoding: len a multiple of 4, only A-Z a-z 0-9 + / (no whitespace, no
 * line breaks, no URL-safe - _), '=' only as the last one or two characters of
 * the text, and the unused bits before the padding zero (so each byte string
 * has exactly one accepted text). Writes tc_base64_decoded_len bytes to out.
 * Returns 0, or -1 with *bad the offset of the first offending character (len
 * for a wrong length) and *why a short reason. */
int tc_base64_decode(const char *s, size_t len, void *out, size_t *bad, const char **why);

#endif
