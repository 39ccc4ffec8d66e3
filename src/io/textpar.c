/* textpar.c — tc__text_parallel and tc__base64_append_parallel: part 0 prints into the
 * answer itself, the other parts into buffers of their own, copied after it in order. */
#include "io/textpar.h"

#include <string.h>

#include "core/alloc.h"
#include "core/parallel.h"
#include "io/base64.h"
#include "io/hugemem.h"

typedef struct {
    tc__text_fn fn;
    void *ctx;
    size_t per_item;
    tc_strbuf *out;                      /* part 0's text goes here, after what it holds */
    tc_strbuf part[TC_PARALLEL_MAX];     /* parts 1.. print here */
    size_t at[TC_PARALLEL_MAX];          /* where part p's text starts in out */
} text_job;

static void print_part(void *c, int32_t lo, int32_t hi, int part) {
    text_job *j = c;
    tc_strbuf *b = part ? &j->part[part] : j->out;
    size_t items = (size_t)(hi - lo);
    if (j->per_item > 0 && items <= (SIZE_MAX - 1) / j->per_item) {
        size_t bound = items * j->per_item;
        /* A part's own buffer: from 4 MiB on a spare (io/hugemem.h: the last answer's part
         * buffers, their pages still there), else from the core's allocator, which asks for
         * huge pages (a part of a big answer is some 10 MB; in fresh 4 KiB pages its first
         * writes cost more page faults than printing). */
        if (part && !b->cap) {
            char *p = tc__huge_take(bound + 1);
            if (!p) p = tc__malloc(bound + 1, 1);
            if (p) tc_strbuf_adopt(b, p, 0, bound + 1);
        }
        tc_strbuf_reserve(b, bound); /* part 0 too: out's caller may have reserved less */
    }
    j->fn(b, j->ctx, lo, hi);
}

/* Part p + 1's text to its place: the copies run in parallel, faulting in the answer's
 * pages on several threads. */
static void copy_part(void *c, int32_t lo, int32_t hi, int unused) {
    text_job *j = c;
    (void)unused;
    for (int32_t p = lo + 1; p <= hi; p++) memcpy(j->out->buf + j->at[p], j->part[p].buf, j->part[p].len);
}

void tc__text_parallel(tc_strbuf *b, int32_t n, int threads, int32_t min_part, size_t per_item,
                       tc__text_fn fn, void *ctx) {
    /* One part per thread, not the few per thread a build's loops take: every part but the
     * first goes through a buffer of its own, fresh memory that the kernel zeroes and that
     * is copied once more (measured on 131k triangles, 2 threads: 8 parts 109 ms, 2 parts
     * 54, one thread 94). */
    int parts = tc__parallel_thread_parts(threads, n, min_part);
    if (parts <= 1 || b->oom) {
        fn(b, ctx, 0, n);
        return;
    }
    text_job j = {.fn = fn, .ctx = ctx, .per_item = per_item, .out = b};
    for (int p = 1; p < parts; p++) tc_strbuf_init(&j.part[p]);
    tc__parallel_for_threads(threads, n, min_part, print_part, &j);
    size_t total = 0;
    int oom = b->oom;
    for (int p = 1; p < parts; p++) oom |= j.part[p].oom, total += j.part[p].len;
    if (!oom && tc_strbuf_reserve(b, total) == 0) {
        j.at[1] = b->len;
        for (int p = 2; p < parts; p++) j.at[p] = j.at[p - 1] + j.part[p - 1].len;
        tc__parallel_for(threads, parts - 1, 1, copy_part, &j);
        b->len += total;
        b->buf[b->len] = '\0';
    } else {
        b->oom = 1;
    }
    for (int p = 1; p < parts; p++) tc__huge_keep(j.part[p].buf); /* a spare for the next answer's */
}

/* Bytes per index of the base64 loop: whole 3-byte groups, so every block but the
 * last encodes to text that joins its neighbours' without padding. */
enum { B64_BLOCK = 3 << 14 };

typedef struct {
    const unsigned char *in;
    size_t bytes;
    char *out;
} b64_job;

static void b64_part(void *c, int32_t lo, int32_t hi, int unused) {
    const b64_job *j = c;
    size_t from = (size_t)lo * B64_BLOCK, to = (size_t)hi * B64_BLOCK;
    (void)unused;
    if (to > j->bytes) to = j->bytes;
    tc_base64_encode(j->in + from, to - from, j->out + from / 3 * 4);
}

void tc__base64_append_parallel(tc_strbuf *b, const void *in, size_t bytes, int threads) {
    size_t blocks = bytes / B64_BLOCK + (bytes % B64_BLOCK != 0);
    size_t k = tc_base64_encoded_len(bytes);
    if (threads <= 1 || blocks < 2 || blocks > INT32_MAX) {
        tc_base64_append(b, in, bytes);
        return;
    }
    if (k == SIZE_MAX || tc_strbuf_reserve(b, k)) {
        b->oom = 1;
        return;
    }
    b64_job j = {in, bytes, b->buf + b->len};
    tc__parallel_for(threads, (int32_t)blocks, 8, b64_part, &j);
    b->len += k;
    b->buf[b->len] = '\0';
}
