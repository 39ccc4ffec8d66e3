/* test_textpar.c — text printed in parts on threads (io/textpar.c) is the serial text
 * byte for byte: the generic joiner, the parallel base64, and the ordinates answer. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "io/base64.h"
#include "io/response.h"
#include "io/textpar.h"
#include "meshgen.h"
#include "props.h"

/* Item i as its number and a separator before all but the first: texts of
 * different lengths, so a part's place in the answer depends on the parts before. */
static void print_items(tc_strbuf *b, void *ctx, int32_t lo, int32_t hi) {
    (void)ctx;
    for (int32_t i = lo; i < hi; i++) {
        if (i) tc_strbuf_putc(b, ',');
        tc_strbuf_int(b, (long long)i * i);
    }
}

TEST(textpar_joins_parts_in_order) {
    static const int32_t counts[] = {0, 1, 2, 7, 100, 10007};
    static const int threads[] = {2, 3, 8, 64};
    for (size_t c = 0; c < sizeof counts / sizeof *counts; c++) {
        tc_strbuf want;
        tc_strbuf_init(&want);
        tc_strbuf_puts(&want, "prefix:");
        print_items(&want, NULL, 0, counts[c]);
        for (size_t t = 0; t < sizeof threads / sizeof *threads; t++) {
            for (int32_t min_part = 1; min_part <= 4096; min_part *= 8) {
                tc_strbuf got;
                tc_strbuf_init(&got);
                tc_strbuf_puts(&got, "prefix:");
                tc__text_parallel(&got, counts[c], threads[t], min_part, 12, print_items, NULL);
                CHECK_MSG(!got.oom && got.len == want.len && !memcmp(got.buf, want.buf, want.len + 1),
                          "%d items, %d threads, parts >= %d: %zu bytes, serial %zu", counts[c], threads[t],
                          min_part, got.len, want.len);
                tc_strbuf_free(&got);
            }
        }
        tc_strbuf_free(&want);
    }
}

/* per_item may under-estimate: a part grows its buffer as any strbuf does. */
TEST(textpar_bound_is_only_a_hint) {
    tc_strbuf want, got;
    tc_strbuf_init(&want), tc_strbuf_init(&got);
    print_items(&want, NULL, 0, 5000);
    tc__text_parallel(&got, 5000, 4, 16, 1, print_items, NULL);
    CHECK(!got.oom && got.len == want.len && !memcmp(got.buf, want.buf, want.len + 1));
    tc_strbuf_free(&want), tc_strbuf_free(&got);
}

TEST(textpar_base64_equals_serial) {
    enum { BLOCK = 3 << 14 }; /* textpar.c's block: sizes around its multiples */
    static const size_t sizes[] = {0, 1, 2, 3, 4, BLOCK - 1, BLOCK, BLOCK + 1, 2 * BLOCK - 1, 2 * BLOCK,
                                   2 * BLOCK + 1, 2 * BLOCK + 2, 9 * BLOCK + 5, 33 * BLOCK + 1};
    static const int threads[] = {1, 2, 3, 8};
    size_t most = 33 * BLOCK + 1;
    unsigned char *in = malloc(most);
    for (size_t i = 0; i < most; i++) in[i] = (unsigned char)(i * 2654435761u >> 13);
    for (size_t s = 0; s < sizeof sizes / sizeof *sizes; s++) {
        tc_strbuf want;
        tc_strbuf_init(&want);
        tc_strbuf_putc(&want, '"');
        tc_base64_append(&want, in, sizes[s]);
        for (size_t t = 0; t < sizeof threads / sizeof *threads; t++) {
            tc_strbuf got;
            tc_strbuf_init(&got);
            tc_strbuf_putc(&got, '"');
            tc__base64_append_parallel(&got, in, sizes[s], threads[t]);
            CHECK_MSG(!got.oom && got.len == want.len && !memcmp(got.buf, want.buf, want.len + 1),
                      "%zu bytes on %d threads: %zu characters, serial %zu", sizes[s], threads[t], got.len, want.len);
            tc_strbuf_free(&got);
        }
        tc_strbuf_free(&want);
    }
    free(in);
}

static void wave(const void *ctx, double x, double y, int ch, double *val, double grad[2]) {
    (void)ctx;
    *val = (ch + 1) * (x * x - 0.3 * y) + 0.1;
    if (grad) grad[0] = (ch + 1) * 2 * x, grad[1] = -0.3 * (ch + 1);
}

/* The ordinates answer, JSON and base64, of a mesh big enough to be split (9800
 * triangles and dropped ones among them: "null" rows and the staged typed path)
 * on 1, 2, 3 and 8 threads. */
TEST(textpar_ordinates_answer_same_on_threads) {
    trng rng;
    trng_seed(&rng, 17);
    tmesh g;
    tmesh_grid(&g, 70, 70, 0.2, -1, &rng);
    tmesh_sample(&g, 2, wave, NULL, 1, 0, 0);
    tc_mesh_desc d;
    tmesh_desc(&g, &d);
    /* every 1000th triangle repeated with a vertex twice: dropped */
    int32_t nt = (int32_t)d.ntris, extra = nt / 1000;
    int32_t *tris = malloc(3 * (size_t)(nt + extra) * sizeof *tris);
    for (int32_t i = 0, k = 0; i < nt; i++) {
        memcpy(tris + 3 * k++, d.tris + 3 * i, 3 * sizeof *tris);
        if (i % 1000 == 999) tris[3 * k] = tris[3 * k + 1] = d.tris[3 * i], tris[3 * k + 2] = d.tris[3 * i + 2], k++;
    }
    d.tris = tris, d.ntris = nt + extra, d.degenerate = TC_DEGENERATE_DROP;
    tc_diags dg;
    tc_diags_init(&dg);
    tc_mesh *m = NULL;
    CHECK(tc_mesh_new(&d, &m, &dg) == TC_OK);
    char *want[2] = {NULL, NULL};
    static const int threads[] = {1, 2, 3, 8};
    for (size_t t = 0; m && t < sizeof threads / sizeof *threads; t++) {
        tc_options o;
        tc_options_default(&o);
        o.threads = threads[t];
        tc_recon *r = NULL;
        CHECK(tc_recon_new(m, &o, &r, &dg) == TC_OK);
        for (int base64 = 0; r && base64 < 2; base64++) {
            tc_strbuf b;
            tc_strbuf_init(&b);
            tc_strbuf_putc(&b, '{');
            tc_json_ordinates_enc(&b, r, base64);
            char *text = tc_strbuf_detach(&b, NULL);
            CHECK(text != NULL);
            if (!want[base64]) {
                want[base64] = text;
                CHECK(base64 || strstr(text, "null") != NULL);
                continue;
            }
            CHECK_MSG(text && !strcmp(text, want[base64]), "%s ordinates on %d threads differ from 1 thread's",
                      base64 ? "base64" : "JSON", threads[t]);
            free(text);
        }
        tc_recon_free(r);
    }
    free(want[0]), free(want[1]);
    tc_mesh_free(m);
    tc_diags_free(&dg);
    free(tris);
    tmesh_free(&g);
}
