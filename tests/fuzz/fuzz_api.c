/* fuzz_api.c — libFuzzer target over the JSON API's request -> response functions
 * (src/io/api.h), built by `make fuzz` into build/fuzz/fuzz_api with ASan and UBSan. */
/* Input: the first byte picks the endpoint, the rest is the request body:
 *   b % 4 == 0  tc_api_ordinates
 *   b % 4 == 1  tc_api_evaluate (with b & 4: the body splits at its first NUL into the
 *               mesh and a second "points" document, as `tocher eval MESH POINTS` sends)
 *   b % 4 == 2  tc_api_render_as, raw unless the request names a format
 *   b % 4 == 3  tc_api_compare
 * Besides the sanitizers, what is checked on every input: the status is one the API
 * documents, a JSON answer and every problem document parse back as JSON (so an
 * escaping or number-printing slip is a crash, not a silently broken client), and a
 * 200 raw tile has the byte count its viewport asks for. */
#include <cjson/cJSON.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image/format.h"
#include "io/api.h"

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerInitialize(int *argc, char ***argv) {
    (void)argc, (void)argv;
    /* A request naming png/exr/tiff would load OpenImageIO, which is neither built with
     * the sanitizers nor needed: pointing the plugin search at nothing makes those
     * requests a 500 "image library unavailable", which is a documented answer. */
    setenv("TOCHER_IMAGE_LIB", "/nonexistent/libtocher_image.so", 1);
    return 0;
}

static void fail(const char *what, int endpoint, int status, const tc_strbuf *out) {
    fprintf(stderr, "fuzz_api: endpoint %d, status %d: %s\n%.2000s\n", endpoint, status, what,
            out->buf ? out->buf : "(empty)");
    abort();
}

static void must_parse(const tc_strbuf *out, int endpoint, int status) {
    cJSON *j = cJSON_ParseWithLength(out->buf ? out->buf : "", out->len);
    if (!j) fail("the answer does not parse as JSON", endpoint, status, out);
    cJSON_Delete(j);
}

/* The raw tile's expected size: width * height * channels * 4, read back from the
 * request (only when it parses; a request that does not cannot have got a 200). */
static void check_raw(const char *body, size_t len, const tc_strbuf *out, int status) {
    cJSON *j = cJSON_ParseWithLength(body, len);
    if (!j) return;
    const cJSON *vp = cJSON_GetObjectItemCaseSensitive(j, "viewport");
    const cJSON *fmt = cJSON_GetObjectItemCaseSensitive(j, "format");
    const cJSON *vals = cJSON_GetObjectItemCaseSensitive(j, "values");
    const cJSON *v0 = cJSON_IsArray(vals) ? cJSON_GetArrayItem(vals, 0) : NULL;
    const cJSON *w = cJSON_GetObjectItemCaseSensitive(vp, "width"), *h = cJSON_GetObjectItemCaseSensitive(vp, "height");
    int raw = !fmt || (cJSON_IsString(fmt) && strcmp(fmt->valuestring, "raw") == 0);
    if (raw && cJSON_IsNumber(w) && cJSON_IsNumber(h) && v0) {
        double ch = cJSON_IsArray(v0) ? cJSON_GetArraySize(v0) : 1;
        double want = w->valuedouble * h->valuedouble * ch * 4;
        if ((double)out->len != want) fail("raw tile of the wrong size", 2, status, out);
    }
    cJSON_Delete(j);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    if (size < 1) return 0;
    int sel = data[0];
    const char *body = (const char *)data + 1;
    size_t len = size - 1;
    /* Small caps keep each input in the milliseconds; raw tiles of at most 64 x 64. */
    tc_api_limits lim = {.max_vertices = 512, .max_triangles = 1024, .max_points = 512, .max_pixels = 4096,
                         .render_threads = 1, .deadline_ms = 0};
    lim.deadline_ms = tc_now_ms() + 2000;
    tc_strbuf out;
    tc_strbuf_init(&out);
    tc_api_result res;
    tc_api_result_init(&res);
    int endpoint = sel % 4, status;
    switch (endpoint) {
    case 0: status = tc_api_ordinates(body, len, &lim, &out, &res); break;
    case 1: {
        const char *nul = (sel & 4) ? memchr(body, '\0', len) : NULL;
        if (nul)
            status = tc_api_evaluate(body, (size_t)(nul - body), nul + 1, len - (size_t)(nul - body) - 1, &lim,
                                     &out, &res);
        else
            status = tc_api_evaluate(body, len, NULL, 0, &lim, &out, &res);
        break;
    }
    case 2: status = tc_api_render_as(body, len, TC_IMG_RAW, &lim, &out, &res); break;
    default: status = tc_api_compare(body, len, &lim, &out, &res); break;
    }
    if (status != res.status) fail("returned status differs from res.status", endpoint, status, &out);
    switch (status) {
    case 200:
        if (endpoint != 2)
            must_parse(&out, endpoint, status);
        else
            check_raw(body, len, &out, status);
        break;
    case 400: case 413: case 422: case 500: case 503: {
        /* The problem document the daemon would send must parse, and say why. */
        if (res.diags.errors == 0 && status != 500) fail("an error without a diagnostic", endpoint, status, &out);
        tc_strbuf_free(&out);
        tc_api_problem(&out, &res);
        must_parse(&out, endpoint, status);
        break;
    }
    default: fail("a status the API does not document", endpoint, status, &out);
    }
    tc_api_result_free(&res);
    tc_strbuf_free(&out);
    return 0;
}
