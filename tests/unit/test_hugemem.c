/* test_hugemem.c — the huge-page advice for big io buffers (io/hugemem.h): an answer buffer
 * that grows past TC_HUGE_MIN gets it (the kernel marks its mapping "hg"), a small one does
 * not, and the advice changes no byte. */
#include <malloc.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "core/alloc.h"
#include "image/image.h"
#include "io/hugemem.h"
#include "io/strbuf.h"

/* 1 if the mapping holding p is marked for huge pages (VmFlags "hg" in /proc/self/smaps),
 * 0 if not, -1 if that cannot be read here. */
static int marked_huge(const void *p) {
    FILE *f = fopen("/proc/self/smaps", "r");
    if (!f) return -1;
    char line[512];
    int inside = 0, found = -1;
    uintptr_t a = (uintptr_t)p;
    while (fgets(line, sizeof line, f)) {
        unsigned long lo, hi;
        if (sscanf(line, "%lx-%lx ", &lo, &hi) == 2) { /* a mapping's first line; its fields follow */
            inside = a >= lo && a < hi;
            continue;
        }
        if (inside && !strncmp(line, "VmFlags:", 8)) {
            found = strstr(line, " hg") != NULL;
            break;
        }
    }
    fclose(f);
    return found;
}

TEST(hugemem_big_answer_buffer_is_advised) {
    tc_strbuf b;
    tc_strbuf_init(&b);
    long a0 = tc__huge_advised();
    for (int i = 0; i < 1000; i++) tc_strbuf_putc(&b, (char)('a' + i % 26));
    CHECK_MSG(tc__huge_advised() == a0, "a 1000-byte buffer got the advice");
    size_t big = TC_HUGE_MIN + 12345;
    CHECK(tc_strbuf_reserve(&b, big) == 0);
    CHECK_MSG(tc__huge_advised() > a0, "a %zu-byte buffer did not get the advice", b.cap);
    for (int i = 0; i < 1000; i++) CHECK(b.buf[i] == (char)('a' + i % 26)); /* the content moved intact */
    memset(b.buf + b.len, 'x', big);
    b.len += big;
    b.buf[b.len] = '\0';
    int m = marked_huge(b.buf + b.len / 2);
#ifdef __linux__
    CHECK_MSG(m != 0, "the buffer's mapping is not marked for huge pages");
#endif
    (void)m;
    tc_strbuf_free(&b);
}

/* Empties the process's spares (a daemon's answers leave some): each taken, then freed. */
static void no_spare(void) {
    tc__spare_drop(TC__SPARE_ANSWERS);
}

TEST(hugemem_advice_only_from_its_threshold) {
    no_spare(); /* a block made from the spare is not advised again */
    long a0 = tc__huge_advised();
    char *p = tc__huge_realloc(NULL, TC_HUGE_MIN - 1);
    CHECK(p && tc__huge_advised() == a0);
    p = tc__huge_realloc(p, TC_HUGE_MIN);
    CHECK(p && tc__huge_advised() == a0 + 1);
    tc__huge_advise(NULL, TC_HUGE_MIN); /* a failed allocation: nothing to advise */
    CHECK(tc__huge_advised() == a0 + 1);
    free(p);
}

/* The spares (tc__huge_free, tc__huge_keep, tc__huge_take): a big block freed serves the next
 * fresh big block (tc__huge_realloc, with the small block's bytes it grows from), the smallest
 * that holds it; a small block and an answer under TC_HUGE_MIN are freed; one too small for what
 * is asked goes; and a spare is usable memory after its pages were given as lazily free. */
TEST(hugemem_spares_serve_the_next_big_blocks) {
    no_spare();
    CHECK(tc__huge_spare() == 0);
    tc__huge_free(NULL);
    tc__huge_free(malloc(1000));
    CHECK_MSG(tc__huge_spare() == 0, "a 1000-byte block became a spare");
    size_t n = TC_HUGE_MIN + 4096, part = TC__SPARE_MIN + 100;
    char *p = tc__huge_realloc(NULL, n), *q0 = malloc(part);
    CHECK(p && q0);
    if (!p || !q0) return;
    memset(p, 'p', n);
    size_t pn = malloc_usable_size(p);
    tc__huge_free(q0); /* under TC_HUGE_MIN: freed, glibc reuses such blocks */
    CHECK_MSG(tc__huge_spare() == 0, "a %zu-byte answer became a spare", part);
    q0 = malloc(part);
    CHECK(q0 != NULL);
    if (!q0) return;
    tc__huge_free(p);
    tc__huge_keep(q0); /* a part buffer: kept from TC__SPARE_MIN */
    size_t both = tc__huge_spare();
    CHECK_MSG(both >= n + part, "spares %zu bytes after freeing %zu and %zu", both, n, part);
    CHECK_MSG(tc__huge_take(1000) == NULL && tc__huge_spare() == both, "a 1000-byte block was a spare");
    CHECK_MSG(tc__huge_take(part) == q0, "the smallest spare that holds it was not taken"); /* best fit */
    tc__huge_keep(q0);
    char *small = malloc(64);
    CHECK(small != NULL);
    if (!small) return;
    memcpy(small, "the answer's first bytes", 25);
    char *q = tc__huge_realloc(small, n - 100); /* a buffer growing past the threshold */
    CHECK_MSG(q == p, "the block made was not the spare");
    CHECK(q && !strcmp(q, "the answer's first bytes"));
    CHECK(tc__huge_spare() == both - pn);
    if (!q) return;
    memset(q, 'q', n - 100); /* every page writable after MADV_FREE */
    CHECK(q[0] == 'q' && q[n / 2] == 'q' && q[n - 101] == 'q');
    tc__huge_free(q);
    CHECK(tc__huge_spare() == both);
    char *r = tc__huge_take(n + (8 << 20)); /* more than any spare holds: none, and the largest goes */
    CHECK(r == NULL && tc__huge_spare() == both - pn);
    /* The bounds of a pool (its bytes, its blocks, the smallest going first): test_spare.c. */
    no_spare();
}

/* The core's big arrays (core/alloc.h, from TC__HUGE_MIN bytes): whole huge pages, advised
 * for huge pages before their first write (a build's page faults cost as much as its work
 * on 4 KiB pages); calloc's still zeroed. Smaller ones are plain malloc blocks. */
TEST(hugemem_core_big_arrays_are_advised) {
    tc__spare_drop(TC__SPARE_ARRAYS); /* an earlier test's array kept as a spare would be the one made */
    size_t n = TC__HUGE_MIN / sizeof(double) + 1000;
    double *a = tc__malloc(n, sizeof *a), *z = tc__calloc(n, sizeof *z);
    CHECK(a && z);
    if (!a || !z) return;
    CHECK_MSG((uintptr_t)a % ((size_t)2 << 20) == 0, "a %zu-byte array is not on a 2 MiB boundary", n * sizeof *a);
    size_t nonzero = 0;
    for (size_t i = 0; i < n; i++)
        if (z[i] != 0) nonzero++;
    CHECK(nonzero == 0);
    for (size_t i = 0; i < n; i++) a[i] = (double)i;
    CHECK(a[n - 1] == (double)(n - 1));
#ifdef __linux__
    CHECK_MSG(marked_huge(a + n / 2) != 0, "the big array's mapping is not marked for huge pages");
    CHECK_MSG(marked_huge(z + n / 2) != 0, "the big zeroed array's mapping is not marked for huge pages");
#endif
    free(a), free(z);
    CHECK(tc__malloc((size_t)-1 / 2, 4) == NULL && tc__calloc((size_t)-1 / 2, 4) == NULL); /* n * size overflows */
}

/* A raw image's answer (the whole file, written band by band) is made from a spare when one
 * holds it: a 4096² tile is 64 MiB, which fresh pages made 4x as slow to write as to render;
 * and its bytes are still every sample's little-endian float32. */
TEST(hugemem_raw_image_written_into_a_spare) {
    enum { W = 4096, H = 4096, BAND = 64 };
    no_spare();
    size_t bytes = (size_t)W * H * 4;
    char *spare = tc__huge_realloc(NULL, bytes + 4096);
    float *band = malloc((size_t)W * BAND * sizeof *band);
    CHECK(spare && band);
    if (!spare || !band) return free(spare), free(band);
    uintptr_t spare_at = (uintptr_t)spare; /* compared as a number: p is not used once freed */
    tc__huge_free(spare);
    CHECK(tc__huge_spare() >= bytes + 4096);
    tc_img header = {W, H, 1, NULL, NULL, 0, 0};
    tc_img_writer *w;
    char err[256];
    CHECK(tc_img_writer_open(&header, TC_IMG_RAW, &w, err, sizeof err) == 0);
    for (int r = 0; r < H; r += BAND) {
        for (size_t i = 0; i < (size_t)W * BAND; i++) band[i] = (float)((size_t)r * W + i) * 0.25f - 1e6f;
        CHECK(tc_img_writer_rows(w, band, NULL, BAND, err, sizeof err) == 0);
    }
    unsigned char *out;
    size_t len, cap;
    CHECK(tc_img_writer_finish(w, &out, &len, &cap, err, sizeof err) == 0);
    tc_img_writer_free(w);
    CHECK_MSG((uintptr_t)out == spare_at, "the raw answer was not made from the spare");
    CHECK(len == bytes && tc__huge_spare() == 0);
    int same = 1;
    for (size_t i = 0; out && i < (size_t)W * H; i += 4097) {
        float v = (float)i * 0.25f - 1e6f;
        uint32_t u;
        memcpy(&u, &v, sizeof u);
        same &= out[4 * i] == (u & 0xff) && out[4 * i + 3] == u >> 24;
    }
    CHECK(same);
    tc__huge_free(out);
    free(band);
    no_spare();
}
