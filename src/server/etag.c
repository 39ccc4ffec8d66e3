/* etag.c — strong ETags from content ids, and If-None-Match lists read as
 * RFC 9110 §8.8.3 writes them (W/ prefixes, quoted opaque tags, "*"). */
#include <stdio.h>
#include <string.h>

#include "io/sha256.h"
#include "server/etag.h"

void tc_etag_make(char *out, size_t n, const char *id, const char *meaning) {
    unsigned char d[32];
    tc_sha256(meaning, strlen(meaning), d);
    snprintf(out, n, "\"%s-%02x%02x%02x%02x%02x%02x%02x%02x\"", id, d[0], d[1], d[2], d[3], d[4], d[5], d[6], d[7]);
}

static const char *skip_space(const char *s) {
    while (*s == ' ' || *s == '\t' || *s == ',') s++;
    return s;
}

int tc_etag_none_match(const char *h, const char *etag) {
    if (!h) return 0;
    size_t elen = strlen(etag);
    for (const char *s = skip_space(h); *s; s = skip_space(s)) {
        if (*s == '*') return 1;
        if (!strncmp(s, "W/", 2)) s += 2;
        if (*s != '"') { /* not an entity tag: skip to the next list member */
            s += strcspn(s, ",");
            continue;
        }
        const char *end = strchr(s + 1, '"');
        if (!end) return 0;
        if ((size_t)(end + 1 - s) == elen && !strncmp(s, etag, elen)) return 1;
        s = end + 1;
    }
    return 0;
}
