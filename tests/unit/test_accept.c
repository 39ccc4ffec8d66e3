/* test_accept.c — content negotiation (src/io/accept.c): the format an Accept header
 * asks for, by the rules of RFC 9110 12.5.1, over the primary formats of the table. */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "image/format.h"
#include "io/accept.h"

TEST(accept_header) {
    static const struct {
        const char *accept;
        int want;
    } cases[] = {
        {NULL, -1},
        {"", -1},
        {"image/png", TC_IMG_PNG},
        {"image/x-exr", TC_IMG_EXR},
        {"image/exr", TC_IMG_EXR},
        {"IMAGE/TIFF", TC_IMG_TIFF},
        {"application/octet-stream", TC_IMG_RAW},
        {"*/*", -1},
        {"image/*", -1},
        {"text/html, application/json", -1},
        {"image/avif,image/webp,image/apng,image/svg+xml,image/*,*/*;q=0.8", -1},
        {"image/png;q=0.5, image/x-exr;q=0.8", TC_IMG_EXR},
        {"image/tiff;q=0.5, */*;q=0.1", TC_IMG_TIFF},
        {"image/tiff;q=0.5, */*", -1},   /* the wildcard prefers anything else */
        {"image/tiff, */*", TC_IMG_TIFF}, /* a tie goes to the named type */
        {"image/png, image/tiff", TC_IMG_PNG},
        {"image/tiff, image/png", TC_IMG_TIFF},
        {"image/x-exr;q=0, image/tiff;q=0.1", TC_IMG_TIFF},
        {"image/x-exr;q=0", -1},
        {"image/x-exr;level=1;q=0.9, image/png;q=0.8", TC_IMG_EXR},
        {"image/png; x=\"a,b;q=1\"; q=0.2, image/tiff;q=0.3", TC_IMG_TIFF},
        {"image/tiff;q=2, image/png;q=0.1", TC_IMG_PNG}, /* malformed q: ignored */
        {"image/tiff;q=0.5x, image/png;q=0.1", TC_IMG_PNG},
        {"  image/tiff ;q=0.7 ,image/png;q=0.6", TC_IMG_TIFF},
        {"image/png;q=0.001, application/octet-stream;q=0.002", TC_IMG_RAW},
        {"application/*;q=0.9, image/png;q=0.5", -1},
        {",,image/tiff,,", TC_IMG_TIFF},
    };
    /* A long header (parsing must stay linear): many ranges, then the one we serve. */
    size_t n = 200000;
    char *big = malloc(n + 32);
    if (big) {
        for (size_t i = 0; i < n; i += 2) big[i] = 'x', big[i + 1] = ',';
        strcpy(big + n, "image/tiff;q=0.4");
        CHECK(tc_accept_format(big) == TC_IMG_TIFF);
        free(big);
    }
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        int got = tc_accept_format(cases[i].accept);
        CHECK_MSG(got == cases[i].want, "Accept '%s': %d, want %d", cases[i].accept ? cases[i].accept : "(null)",
                  got, cases[i].want);
    }
}

/* Every primary format is chosen by its own media type (and its alias); a
 * variant never is: its type names its primary. */
TEST(accept_every_primary_format) {
    for (int f = 0; f < TC_IMG_NFORMATS; f++) {
        const tc_img_traits *t = tc_img_traits_of((tc_img_format)f);
        int want = tc_img_primary((tc_img_format)f);
        CHECK_MSG(t && tc_accept_format(t->mime) == want, "%s: Accept '%s' gives %d, want %d", t ? t->name : "?",
                  t ? t->mime : "", t ? tc_accept_format(t->mime) : -2, want);
        if (t && t->mime_alias) CHECK(tc_accept_format(t->mime_alias) == want);
    }
}
