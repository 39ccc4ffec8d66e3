/* template.h — a tiny mustache-like text template for docs/report.md: named
 * values, conditional sections and one loop, so the prose lives in one file. */
#ifndef BENCH_TEMPLATE_H
#define BENCH_TEMPLATE_H

#include "io/strbuf.h"

/* Syntax ("{{" opens a tag, the next "}}" closes it, so a comment cannot contain "}}"):
 *   {{key}}              the value of key
 *   {{#key}}...{{/key}}  the body if key is "true" (set, not "" and not "0");
 *                        if key is a list: the body once per item, with
 *                        {{k}} inside looking up "<item>.k" before "k"
 *   {{^key}}...{{/key}}  the body if key is not true
 *   {{! comment }}       nothing
 * A {{key}} that is not set renders as "{{?key}}" and is counted, so a typo
 * shows in the output instead of vanishing. */

typedef struct {
    char *key, *val;
    int list; /* val: items separated by single spaces */
} tmpl_entry;

typedef struct {
    tmpl_entry *e;
    int n, cap;
    int oom;
} tmpl_dict;

void tmpl_init(tmpl_dict *d);
void tmpl_free(tmpl_dict *d);
/* Sets key (printf-style value), replacing an earlier value. */
void tmpl_set(tmpl_dict *d, const char *key, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
/* Sets "<prefix>.<key>". */
void tmpl_setp(tmpl_dict *d, const char *prefix, const char *key, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
/* Marks key as a list of space-separated items. */
void tmpl_set_list(tmpl_dict *d, const char *key, const char *items);
const char *tmpl_get(const tmpl_dict *d, const char *key);

/* Renders tmpl into out; returns the number of unknown keys and unbalanced
 * sections (reported on stderr), 0 when all is well. */
int tmpl_render(const char *tmpl, const tmpl_dict *d, tc_strbuf *out);

#endif
