/* template.c — a tiny mustache-like text template for docs/report.md: named
 * values, conditional sections and one loop, so the prose lives in one file. */
#include "template.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void tmpl_init(tmpl_dict *d) { memset(d, 0, sizeof *d); }

void tmpl_free(tmpl_dict *d) {
    for (int i = 0; i < d->n; i++) free(d->e[i].key), free(d->e[i].val);
    free(d->e);
    tmpl_init(d);
}

static tmpl_entry *find(const tmpl_dict *d, const char *key, size_t len) {
    for (int i = 0; i < d->n; i++)
        if (strlen(d->e[i].key) == len && memcmp(d->e[i].key, key, len) == 0) return &d->e[i];
    return NULL;
}

static void put(tmpl_dict *d, const char *key, char *val, int list) {
    if (!val) {
        d->oom = 1;
        return;
    }
    tmpl_entry *e = find(d, key, strlen(key));
    if (!e) {
        if (d->n == d->cap) {
            int cap = d->cap ? 2 * d->cap : 256;
            tmpl_entry *ne = realloc(d->e, (size_t)cap * sizeof *ne);
            if (!ne) {
                free(val);
                d->oom = 1;
                return;
            }
            d->e = ne, d->cap = cap;
        }
        e = &d->e[d->n++];
        e->key = strdup(key);
        e->val = NULL;
        if (!e->key) d->oom = 1;
    }
    free(e->val);
    e->val = val, e->list = list;
}

static char *vformat(const char *fmt, va_list ap) {
    va_list aq;
    va_copy(aq, ap);
    int n = vsnprintf(NULL, 0, fmt, aq);
    va_end(aq);
    char *s = n >= 0 ? malloc((size_t)n + 1) : NULL;
    if (s) vsnprintf(s, (size_t)n + 1, fmt, ap);
    return s;
}

void tmpl_set(tmpl_dict *d, const char *key, const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    put(d, key, vformat(fmt, ap), 0);
    va_end(ap);
}

void tmpl_setp(tmpl_dict *d, const char *prefix, const char *key, const char *fmt, ...) {
    char full[256];
    snprintf(full, sizeof full, "%s.%s", prefix, key);
    va_list ap;
    va_start(ap, fmt);
    put(d, full, vformat(fmt, ap), 0);
    va_end(ap);
}

void tmpl_set_list(tmpl_dict *d, const char *key, const char *items) { put(d, key, strdup(items), 1); }

const char *tmpl_get(const tmpl_dict *d, const char *key) {
    const tmpl_entry *e = find(d, key, strlen(key));
    return e ? e->val : NULL;
}

/* ---- rendering ------------------------------------------------------------------ */

typedef struct {
    const tmpl_dict *d;
    tc_strbuf *out;
    int problems;
    const char *base; /* the whole template: for "at the start of a line" */
} ctx;

static int line_start(const ctx *c, const char *p) { return p == c->base || p[-1] == '\n'; }

/* The entry for a tag name inside the loop item `prefix` (NULL outside loops). */
static const tmpl_entry *lookup(const ctx *c, const char *prefix, const char *name, size_t len) {
    if (prefix) {
        char full[256];
        int n = snprintf(full, sizeof full, "%s.%.*s", prefix, (int)len, name);
        if (n > 0 && (size_t)n < sizeof full) {
            const tmpl_entry *e = find(c->d, full, (size_t)n);
            if (e) return e;
        }
    }
    return find(c->d, name, len);
}

static int truthy(const tmpl_entry *e) { return e && e->val[0] && strcmp(e->val, "0") != 0; }

/* The "{{/name}}" closing the section whose body starts at s, skipping nested
 * sections of the same name; NULL if missing. *after: just past the tag. */
static const char *section_end(const char *s, const char *end, const char *name, size_t len, const char **after) {
    int depth = 0;
    for (const char *p = s; p && p < end; ) {
        p = strstr(p, "{{");
        if (!p || p >= end) return NULL;
        const char *q = strstr(p + 2, "}}");
        if (!q) return NULL;
        char kind = p[2];
        const char *nm = p + 3;
        size_t nl = (size_t)(q - nm);
        if ((kind == '#' || kind == '^') && nl == len && memcmp(nm, name, len) == 0) depth++;
        if (kind == '/' && nl == len && memcmp(nm, name, len) == 0) {
            if (depth == 0) {
                *after = q + 2;
                return p;
            }
            depth--;
        }
        p = q + 2;
    }
    return NULL;
}

static void render(ctx *c, const char *s, const char *end, const char *prefix) {
    while (s < end) {
        const char *p = strstr(s, "{{");
        if (!p || p >= end) {
            tc_strbuf_append(c->out, s, (size_t)(end - s));
            return;
        }
        tc_strbuf_append(c->out, s, (size_t)(p - s));
        const char *q = strstr(p + 2, "}}");
        if (!q || q > end) {
            fprintf(stderr, "report: template: unclosed tag\n");
            c->problems++;
            tc_strbuf_append(c->out, p, (size_t)(end - p));
            return;
        }
        char kind = p[2];
        if (kind == '!') { /* a comment alone on its line takes its line break with it */
            s = q + 2;
            if (line_start(c, p) && *s == '\n') s++;
            continue;
        }
        if (kind == '/') { /* a stray close tag */
            fprintf(stderr, "report: template: unexpected %.*s\n", (int)(q + 2 - p), p);
            c->problems++;
            s = q + 2;
            continue;
        }
        if (kind == '#' || kind == '^') {
            const char *name = p + 3, *after;
            size_t len = (size_t)(q - name);
            const char *close = section_end(q + 2, end, name, len, &after);
            if (!close) {
                fprintf(stderr, "report: template: no {{/%.*s}}\n", (int)len, name);
                c->problems++;
                return;
            }
            const tmpl_entry *e = lookup(c, prefix, name, len);
            /* A section tag alone on its line takes its line break with it. */
            const char *body = q + 2;
            if (line_start(c, p) && *body == '\n') body++;
            const char *next = after;
            if (line_start(c, close) && *next == '\n') next++;
            if (kind == '#' && e && e->list) {
                const char *it = e->val;
                while (*it) {
                    size_t n = strcspn(it, " ");
                    char item[128];
                    snprintf(item, sizeof item, "%.*s", (int)n, it);
                    render(c, body, close, item);
                    it += n;
                    while (*it == ' ') it++;
                }
            } else if ((kind == '#') == truthy(e)) {
                render(c, body, close, prefix);
            }
            s = next;
            continue;
        }
        const char *name = p + 2;
        size_t len = (size_t)(q - name);
        const tmpl_entry *e = lookup(c, prefix, name, len);
        if (e) {
            tc_strbuf_puts(c->out, e->val);
        } else {
            fprintf(stderr, "report: template: unknown key {{%.*s}}%s%s\n", (int)len, name, prefix ? " in " : "",
                    prefix ? prefix : "");
            c->problems++;
            tc_strbuf_printf(c->out, "{{?%.*s}}", (int)len, name);
        }
        s = q + 2;
    }
}

int tmpl_render(const char *tmpl, const tmpl_dict *d, tc_strbuf *out) {
    ctx c = {d, out, 0, tmpl};
    render(&c, tmpl, tmpl + strlen(tmpl), NULL);
    return c.problems;
}
