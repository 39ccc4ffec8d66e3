/* test_hugemem.c — the huge-page advice for big io buffers (io/hugemem.h): an answer buffer
 * that grows past TC_HUGE_MIN gets it (the kernel marks its mapping "hg"), a small one does
 * not, and the advice changes no byte. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
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

TEST(hugemem_advice_only_from_its_threshold) {
    long a0 = tc__huge_advised();
    char *p = tc__huge_realloc(NULL, TC_HUGE_MIN - 1);
    CHECK(p && tc__huge_advised() == a0);
    p = tc__huge_realloc(p, TC_HUGE_MIN);
    CHECK(p && tc__huge_advised() == a0 + 1);
    tc__huge_advise(NULL, TC_HUGE_MIN); /* a failed allocation: nothing to advise */
    CHECK(tc__huge_advised() == a0 + 1);
    free(p);
}
