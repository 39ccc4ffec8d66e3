/* prescan.c — counts the limited arrays of a JSON body in its bytes, so that a body
 * over a limit is refused before cJSON spends ~40 bytes of tree per byte of input. */
#include <stdlib.h>
#include <string.h>

#include "io/prescan.h"

enum { MAX_TRACKED = 8, KEY_MAX = 48 };

/* One open container: its kind, the key that leads into it, and what it expects next. */
typedef struct {
    char array;            /* '[' or '{' */
    char want;             /* array: a value may start; object: a key may start */
    int limit;             /* array: index into the limits, -1 when not limited */
    int shape_of;          /* array: the "shape" of a typed array given for limit shape_of
                            * ({"dtype", "shape": [n, ...], "data"}): its first length is
                            * that array's element count; -1 otherwise */
    int64_t count;         /* array: elements begun so far */
    char named;            /* every step from the root is an object key */
    char path[KEY_MAX];    /* those keys, joined by '.' */
    char key[KEY_MAX];     /* object: the last key read */
} level;

typedef struct {
    const char *s;
    size_t len, i;
    const tc_scan_limit *lim;
    int n;
    int depth; /* open containers; only the first MAX_TRACKED are tracked */
    int64_t shape_count; /* a typed array's count over its limit (step returns 2) */
    level lv[MAX_TRACKED];
} scanner;

static level *top(scanner *sc) {
    return sc->depth >= 1 && sc->depth <= MAX_TRACKED ? &sc->lv[sc->depth - 1] : NULL;
}

/* The index just past the string whose content starts at i (after its opening quote): past
 * its closing quote, the first '"' not escaped by an odd run of backslashes, or len + 1 if it
 * is unterminated (as the byte loop of skip_string ends). memchr finds the quotes at memory
 * speed: a typed array's base64 data is most of a body's bytes and has no escapes. */
static size_t string_end(const char *s, size_t len, size_t i) {
    for (size_t from = i; from < len;) {
        const char *q = memchr(s + from, '"', len - from);
        if (!q) break;
        size_t at = (size_t)(q - s), k = at;
        while (k > i && s[k - 1] == '\\') k--;
        if ((at - k) % 2 == 0) return at + 1;
        from = at + 1;
    }
    return len + 1;
}

/* Skips a string starting at its opening quote; copies up to cap-1 bytes of it. */
static void skip_string(scanner *sc, char *out, size_t cap) {
    if (!out) {
        sc->i = string_end(sc->s, sc->len, sc->i + 1);
        return;
    }
    size_t k = 0;
    for (sc->i++; sc->i < sc->len; sc->i++) {
        char c = sc->s[sc->i];
        if (c == '"') break;
        if (c == '\\') sc->i++;
        else if (out && k + 1 < cap) out[k++] = c;
    }
    sc->i++;
    if (out) out[k] = '\0';
}

static int find_limit(const scanner *sc, const char *path) {
    for (int k = 0; k < sc->n; k++)
        if (sc->lim[k].max > 0 && !strcmp(sc->lim[k].path, path)) return k;
    return -1;
}

/* A container opened inside `up` is named by a path only when every step from
 * the root is an object key: up is the root, or a named object. */
static void name_child(const level *up, int root, level *l) {
    l->named = 1;
    l->path[0] = '\0';
    if (root) return;
    l->named = up && up->named && up->array == '{';
    if (!l->named) return;
    size_t n = strlen(up->path), k = strlen(up->key);
    if (n + 1 + k >= KEY_MAX) return (void)(l->named = 0);
    if (n) memcpy(l->path, up->path, n), l->path[n++] = '.';
    memcpy(l->path + n, up->key, k + 1);
}

static void open_container(scanner *sc, char kind) {
    level *up = top(sc);
    int root = sc->depth == 0;
    sc->depth++;
    level *l = top(sc);
    if (!l) return;
    l->array = kind;
    l->want = 1;
    l->count = 0;
    l->key[0] = '\0';
    name_child(up, root, l);
    l->limit = kind == '[' && l->named ? find_limit(sc, l->path) : -1;
    /* "points": {"shape": [ ... opens: up is the typed array's object, named by the limited path. */
    l->shape_of = kind == '[' && !root && up && up->array == '{' && up->named && !strcmp(up->key, "shape")
                      ? find_limit(sc, up->path)
                      : -1;
}

/* The number starting at byte i (the first length of a typed array's shape), or -1. */
static int64_t number_at(const scanner *sc, size_t i) {
    char buf[32];
    size_t k = 0;
    for (; i < sc->len && k + 1 < sizeof buf; i++) {
        char c = sc->s[i];
        if (!c || !strchr("0123456789.eE+-", c)) break;
        buf[k++] = c;
    }
    buf[k] = '\0';
    double d = k ? strtod(buf, NULL) : -1;
    return d >= 0 && d < 9.2e18 ? (int64_t)d : d >= 9.2e18 ? INT64_MAX : -1;
}

/* A value begins in the current container: count it if that is a limited array.
 * Returns 1 when the count passes the limit. */
static int value_begins(scanner *sc) {
    level *l = top(sc);
    if (!l || l->array != '[' || !l->want) return 0;
    l->want = 0;
    l->count++;
    return l->limit >= 0 && l->count > sc->lim[l->limit].max;
}

/* Skips the container opening at byte i, nested ones and strings included: nothing
 * inside an array's element is named by keys from the root, so nothing there is limited. */
static void skip_container(scanner *sc) {
    int depth = 0;
    while (sc->i < sc->len) {
        char c = sc->s[sc->i];
        if (c == '"') {
            skip_string(sc, NULL, 0);
            continue;
        }
        sc->i++;
        if (c == '[' || c == '{') depth++;
        else if ((c == ']' || c == '}') && --depth == 0) return;
    }
}

/* Counts the rest of the array at the current depth (no limit applies any more). */
static int64_t finish_count(scanner *sc) {
    level *l = top(sc);
    while (sc->i < sc->len) {
        char c = sc->s[sc->i];
        if (c == ']' || c == '}') break;
        if (c == ',' || c == ' ' || c == '\t' || c == '\n' || c == '\r') {
            l->want |= c == ',';
            sc->i++;
            continue;
        }
        if (l->want) l->want = 0, l->count++;
        if (c == '"') skip_string(sc, NULL, 0);
        else if (c == '[' || c == '{') skip_container(sc);
        else sc->i++;
    }
    return l->count;
}

/* One structural step at byte i. Returns 1 when a limited array passed its limit. */
static int step(scanner *sc) {
    char c = sc->s[sc->i];
    level *l = top(sc);
    if (c == '"') {
        int is_key = l && l->array == '{' && l->want;
        if (!is_key) return value_begins(sc) ? 1 : (skip_string(sc, NULL, 0), 0);
        skip_string(sc, l->key, KEY_MAX);
        l->want = 0;
        return 0;
    }
    sc->i++;
    switch (c) {
    case ' ': case '\t': case '\n': case '\r': case ':': return 0;
    case ',': if (l) l->want = 1; return 0;
    case ']': case '}': if (sc->depth > 0) sc->depth--; return 0;
    case '[': case '{':
        sc->i--; /* leave the byte: finish_count or skip_container reads it */
        if (value_begins(sc)) return 1;
        if (l && l->array == '[') return skip_container(sc), 0; /* an element: [x,y], {...} */
        sc->i++;
        open_container(sc, c);
        return 0;
    default: {
        if (l && l->shape_of >= 0 && l->want && l->count == 0) { /* a typed array's length */
            int64_t n = number_at(sc, sc->i - 1);
            value_begins(sc);
            if (n > sc->lim[l->shape_of].max) return sc->shape_count = n, 2;
            return 0;
        }
        int over = value_begins(sc);
        if (over) sc->i--;
        return over;
    }
    }
}

int tc_prescan(const char *json, size_t len, const tc_scan_limit *lim, int n, int64_t *count) {
    scanner sc = {.s = json, .len = len, .lim = lim, .n = n};
    while (json && sc.i < len) {
        int over = step(&sc);
        if (!over) continue;
        level *l = top(&sc);
        if (over == 2) { /* a typed array: its shape says the count, no data is decoded */
            *count = sc.shape_count;
            return l->shape_of;
        }
        l->want = 1, l->count--; /* the element that passed the limit is counted again */
        *count = finish_count(&sc);
        return l->limit;
    }
    return -1;
}
