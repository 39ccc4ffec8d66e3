/* viewer.c — GET /viewer: the browser viewer (src/server/viewer.html), embedded in the
 * daemon at build time so that the page needs nothing but the daemon's own API. */
#include <string.h>

#include "server/viewer.h"

/* .incbin keeps the page a plain HTML file in the tree (editable, diffable) with no
 * generator step; the assembler reads it relative to the directory make runs in (the
 * repository root; the Makefile names it as the object's prerequisite). A NUL ends it. */
__asm__(".section .rodata\n"
        ".global tc_viewer_html\n"
        ".type tc_viewer_html, @object\n"
        "tc_viewer_html:\n"
        ".incbin \"src/server/viewer.html\"\n"
        ".byte 0\n"
        ".size tc_viewer_html, . - tc_viewer_html\n"
        ".previous\n");
extern const char tc_viewer_html[];

void tc_viewer(const tc_route_input *in, tc_reply *out) {
    (void)in;
    out->status = 200;
    out->content_type = "text/html; charset=utf-8";
    /* The page talks to this daemon's API: a copy cached past an upgrade could speak an older
     * one, so browsers revalidate (it is a few kB, answered from memory). */
    out->cache_control = "no-cache";
    tc_strbuf_puts(&out->body, tc_viewer_html);
}
