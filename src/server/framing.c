/* framing.c — request framing that a proxy and libmicrohttpd 0.9.75 could read
 * differently: two lengths, a hidden Transfer-Encoding, HTTP/1.1 without Host. */
#include <stdio.h>
#include <string.h>
#include <strings.h>

#include "server/framing.h"

/* What the request's header fields say about its framing. */
typedef struct {
    int content_lengths, different_lengths;
    const char *first_length;
    int transfer_encodings, hosts;
    const char *transfer_encoding;
    const char *bad_name; /* a field name with blanks: "Transfer-Encoding " */
} fields;

static enum MHD_Result note(void *cls, enum MHD_ValueKind kind, const char *key, const char *value) {
    (void)kind;
    fields *f = cls;
    if (!key || !value) return MHD_YES;
    if (strpbrk(key, " \t")) f->bad_name = f->bad_name ? f->bad_name : key;
    else if (!strcasecmp(key, MHD_HTTP_HEADER_CONTENT_LENGTH)) {
        if (f->content_lengths++ && strcmp(value, f->first_length)) f->different_lengths = 1;
        if (!f->first_length) f->first_length = value;
    } else if (!strcasecmp(key, MHD_HTTP_HEADER_TRANSFER_ENCODING)) {
        f->transfer_encodings++;
        f->transfer_encoding = value;
    } else if (!strcasecmp(key, MHD_HTTP_HEADER_HOST)) f->hosts++;
    return MHD_YES;
}

/* libmicrohttpd reads a body as chunked only for exactly "chunked"; anything
 * else (gzip, "gzip, chunked") would leave the length to guesswork. */
static int chunked_only(const char *te) {
    while (*te == ' ' || *te == '\t') te++;
    size_t n = strlen(te);
    while (n && (te[n - 1] == ' ' || te[n - 1] == '\t')) n--;
    return n == 7 && !strncasecmp(te, "chunked", 7);
}

int tc_framing_error(struct MHD_Connection *c, const char *version, char *detail, size_t n) {
    fields f = {0};
    MHD_get_connection_values(c, MHD_HEADER_KIND, note, &f);
    const char *why = NULL;
    char name[112];
    if (f.bad_name) {
        snprintf(name, sizeof name, "the header name '%.40s' holds a blank (before its colon?)", f.bad_name);
        why = name;
    } else if (f.content_lengths && f.transfer_encodings)
        why = "Content-Length and Transfer-Encoding together: the body's length is ambiguous";
    else if (f.different_lengths) why = "two different Content-Length headers";
    else if (f.transfer_encodings > 1) why = "more than one Transfer-Encoding header";
    else if (f.transfer_encodings && !chunked_only(f.transfer_encoding))
        why = "Transfer-Encoding must be exactly chunked";
    else if (f.hosts > 1) why = "more than one Host header";
    else if (!f.hosts && version && !strcmp(version, MHD_HTTP_VERSION_1_1)) why = "an HTTP/1.1 request without Host";
    if (!why) return 0;
    snprintf(detail, n, "%s (RFC 9112); the connection is closed", why);
    return 1;
}
