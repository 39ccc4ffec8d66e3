/* request_fast.c — the fast path of the request reader for its big numeric arrays: they are
 * scanned straight from the body into doubles, and cJSON parses only the small rest.
 *
 * Why: cJSON builds a ~64-byte node per number and calls strtod on each; for an 8 MB mesh
 * that is most of the request's parse time. Here the top-level members named in
 * fast_keys[] whose value is a uniform array of numbers ("[z, ...]", "[[x, y], ...]",
 * "[[[gx, gy], ...], ...]") are read by tc_strtod_fast (equal to strtod, as cJSON would
 * give) and cJSON parses a skeleton of the body in which each of them is "[]". An error
 * position in the skeleton maps back to the body (tc__rd_fast_origin), so the line and column
 * of any syntax error cJSON reports elsewhere are those of the original text. The doubles
 * become the request's arrays without a copy (tc__rd_fast_take); copying 8 MB and faulting
 * in fresh pages cost as much as the numbers themselves.
 *
 * Invariants that keep every answer (values, errors and their paths) that of the cJSON path:
 * - An array is taken only if it is strictly valid JSON that cJSON reads the same way: JSON's
 *   number grammar, at most 63 characters a number (cJSON's own buffer; it reads longer ones
 *   differently), finite values, only space/tab/CR/LF as whitespace, no empty or null
 *   entries, every entry of the first entry's shape. Anything else is left to cJSON whole.
 * - The top-level walk is strict too and gives up on anything it does not understand; it
 *   also gives up when a top-level key has an escape or when a fast key appears twice,
 *   so a member of the tree is bound to its scanned array by name without ambiguity
 *   (tc__rd_fast_bind: by node, so a nested "points" is never mistaken for one).
 * - A field reader that finds a fast array of a shape it does not accept, or with values it
 *   refuses (a non-integer index), parses the original text of that array with cJSON
 *   (tc__rd_fast_json) and reads it as before: messages and paths cannot differ. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "io/hugemem.h"
#include "io/reader.h"
#include "io/strtod_fast.h"

static _Thread_local int fast_off; /* test hook: 1 = every array through cJSON */

static _Thread_local int last_taken; /* test hook: arrays read fast by the last parse */
static _Thread_local int last_spans; /* test hook: "data" strings read from the body */

void tc_request__fast_arrays(int on) { fast_off = !on; }
int tc_request__fast_taken(void) { return last_taken; }
int tc_request__fast_spans(void) { return last_spans; }

/* The fields whose readers (request_mesh.c) accept a fast array. */
static const char *const fast_keys[] = {"vertices", "triangles", "quads", "values",
                                        "gradients", "normals", "hessians", "points"};
enum { NKEYS = (int)(sizeof fast_keys / sizeof fast_keys[0]), NUM_MAX = 63 };

typedef struct {
    const char *s;
    size_t len, i;
    double *data;
    size_t count, cap;
    int nomem;
} scan;

static void ws(scan *sc) {
    while (sc->i < sc->len) {
        char c = sc->s[sc->i];
        if (c != ' ' && c != '\n' && c != '\r' && c != '\t') return;
        sc->i++;
    }
}

static int at(const scan *sc, char c) { return sc->i < sc->len && sc->s[sc->i] == c; }

/* One number, appended to data: 0, or -1 when it is not one the fast path takes. */
static int number(scan *sc) {
    double d;
    size_t rest = sc->len - sc->i;
    size_t n = tc_strtod_fast(sc->s + sc->i, rest < NUM_MAX + 1 ? rest : NUM_MAX + 1, &d);
    if (n == 0 || n > NUM_MAX || !isfinite(d)) return -1;
    if (n == NUM_MAX + 1 || (n < rest && (sc->s[sc->i + n] == '.' || sc->s[sc->i + n] == 'e' ||
                                          sc->s[sc->i + n] == 'E' || (sc->s[sc->i + n] >= '0' && sc->s[sc->i + n] <= '9'))))
        return -1; /* longer than cJSON's buffer, or "1.5.2": not ours */
    if (sc->count == sc->cap) {
        size_t cap = sc->cap ? 2 * sc->cap : 4096;
        double *p = tc__huge_realloc(sc->data, cap * sizeof *p);
        if (!p) return sc->nomem = 1, -1;
        sc->data = p, sc->cap = cap;
    }
    sc->data[sc->count++] = d;
    sc->i += n;
    return 0;
}

/* "[n, n, ...]" at i (at its '['): the count of numbers, or -1. */
static long numbers(scan *sc) {
    long k = 0;
    sc->i++; /* '[' */
    ws(sc);
    for (;;) {
        if (number(sc)) return -1;
        k++;
        ws(sc);
        if (at(sc, ']')) return sc->i++, k;
        if (!at(sc, ',')) return -1;
        sc->i++;
        ws(sc);
    }
}

/* One entry at i; *d1, *d2 its shape (see tc__fast). -1 when not a uniform numeric entry. */
static int entry(scan *sc, int *d1, int *d2) {
    if (!at(sc, '[')) return number(sc) ? -1 : (*d1 = *d2 = 0, 0);
    size_t open = sc->i++;
    ws(sc);
    if (!at(sc, '[')) {
        sc->i = open;
        long k = numbers(sc);
        if (k < 1 || k > 64) return -1;
        *d1 = (int)k, *d2 = 0;
        return 0;
    }
    long m = -1, k = 0;
    for (;;) {
        if (!at(sc, '[')) return -1;
        long mk = numbers(sc);
        if (mk < 1 || mk > 64 || (m >= 0 && mk != m)) return -1;
        m = mk, k++;
        ws(sc);
        if (at(sc, ']')) break;
        if (!at(sc, ',') || k >= 64) return -1;
        sc->i++;
        ws(sc);
    }
    sc->i++;
    *d1 = (int)k, *d2 = (int)m;
    return 0;
}

/* The array at i (at its '['): 0 and f filled, or -1 (sc->data freed either way on failure).
 * max > 0: -1 as soon as it has more entries (left to the prescan, which reports it). */
static int array(scan *sc, tc__fast *f, int64_t max) {
    f->start = sc->i++;
    sc->data = NULL, sc->count = sc->cap = 0;
    ws(sc);
    size_t n = 0;
    int d1 = 0, d2 = 0;
    for (;;) {
        int e1, e2;
        if (entry(sc, &e1, &e2) || (n && (e1 != d1 || e2 != d2))) goto fail;
        d1 = e1, d2 = e2, n++;
        if (max > 0 && (int64_t)n > max) goto fail;
        ws(sc);
        if (at(sc, ']')) break;
        if (!at(sc, ',')) goto fail;
        sc->i++;
        ws(sc);
    }
    sc->i++;
    f->end = sc->i;
    f->n = n, f->d1 = d1, f->d2 = d2;
    f->data = sc->data;
    f->node = NULL;
    return 0;
fail:
    free(sc->data);
    sc->data = NULL;
    return -1;
}

/* Skips a string at its opening quote; -1 if unterminated. *escaped: it had a backslash or
 * a control byte (a raw NUL would end cJSON's C-string name early), so its name in the tree
 * may differ from its bytes. */
static int string(scan *sc, int *escaped) {
    *escaped = 0;
    for (sc->i++; sc->i < sc->len; sc->i++) {
        unsigned char c = (unsigned char)sc->s[sc->i];
        if (c == '"') return sc->i++, 0;
        if (c < 0x20) *escaped = 1;
        if (c == '\\') *escaped = 1, sc->i++;
    }
    return -1;
}

/* Skips a string at its opening quote when its bytes do not matter (a value skip_value
 * passes over): the same end as string()'s byte loop, the first '"' after an even run of
 * backslashes, found with memchr at memory speed (a typed array's base64 data is most of
 * its body). -1 if unterminated. */
static int skip_string(scan *sc) {
    size_t i = sc->i + 1;
    for (size_t from = i; from < sc->len;) {
        const char *q = memchr(sc->s + from, '"', sc->len - from);
        if (!q) break;
        size_t at = (size_t)(q - sc->s), k = at;
        while (k > i && sc->s[k - 1] == '\\') k--;
        if ((at - k) % 2 == 0) return sc->i = at + 1, 0;
        from = at + 1;
    }
    return -1;
}

/* Skips any value at i the way a JSON parser delimits it (a string, a balanced container with
 * the strings in it, or a scalar up to the next delimiter); -1 when it cannot tell where the
 * value ends. Values it skips are cJSON's to judge. */
static int skip_value(scan *sc) {
    size_t from = sc->i;
    if (at(sc, '"')) return skip_string(sc);
    if (at(sc, '[') || at(sc, '{')) {
        int depth = 0;
        while (sc->i < sc->len) {
            char c = sc->s[sc->i];
            if (c == '"') {
                if (skip_string(sc)) return -1;
                continue;
            }
            sc->i++;
            if (c == '[' || c == '{') depth++;
            else if ((c == ']' || c == '}') && --depth == 0) return 0;
        }
        return -1;
    }
    while (sc->i < sc->len && !strchr(",]}[{\" \t\r\n", sc->s[sc->i]) && sc->s[sc->i]) sc->i++;
    return sc->i > from ? 0 : -1;
}

/* The object value at i (at its '{'), one level deep: each "data" member whose value is a
 * string is recorded in rd->spans, taken when its bytes are plain (no backslash, so cJSON's
 * string is these bytes; no NUL, which would end cJSON's C string early); other values are
 * skipped. Strict like the top-level walk: -1 on anything else (a key with an escape, more
 * than TC__SPAN_MAX strings), and the whole fast path gives up. */
static int object_value(scan *sc, tc__reader *rd) {
    int esc;
    sc->i++;
    ws(sc);
    if (at(sc, '}')) return sc->i++, 0;
    for (;;) {
        if (!at(sc, '"')) return -1;
        size_t k0 = sc->i + 1;
        if (string(sc, &esc) || esc) return -1;
        int is_data = sc->i - 1 - k0 == 4 && !memcmp(sc->s + k0, "data", 4);
        ws(sc);
        if (!at(sc, ':')) return -1;
        sc->i++;
        ws(sc);
        if (is_data && at(sc, '"')) {
            if (rd->nspans == TC__SPAN_MAX) return -1;
            tc__span *sp = &rd->spans[rd->nspans++];
            sp->start = sc->i;
            if (skip_string(sc)) return -1;
            sp->end = sc->i;
            size_t n = sp->end - sp->start - 2;
            const char *t = sc->s + sp->start + 1;
            sp->taken = !memchr(t, '\\', n) && !memchr(t, '\0', n);
            sp->node = NULL;
        } else if (skip_value(sc)) {
            return -1;
        }
        ws(sc);
        if (at(sc, '}')) return sc->i++, 0;
        if (!at(sc, ',')) return -1;
        sc->i++;
        ws(sc);
    }
}

/* The limit tc_request_parse_limited puts on the top-level array `key`; 0: none. */
static int64_t limit_of(const tc__reader *rd, const char *key) {
    for (int k = 0; rd->limits && k < rd->limits->n; k++)
        if (rd->limits->lim[k].max > 0 && !strcmp(rd->limits->lim[k].path, key)) return rd->limits->lim[k].max;
    return 0;
}

static void drop(tc__reader *rd) {
    for (int k = 0; k < rd->nfast; k++) free(rd->fast[k].data);
    rd->nfast = 0;
    rd->nspans = 0;
}

/* The text cut out of the body for the skeleton: [start, end) becomes its first and last
 * byte ("[]" of a fast array, "\"\"" of a taken string). In text order. */
typedef struct {
    size_t start, end;
} cut;

/* The cuts of rd's fast arrays and taken strings, merged in text order; their count. */
static int cuts_of(const tc__reader *rd, cut *out) {
    int n = 0, a = 0, b = 0;
    for (;;) {
        while (b < rd->nspans && !rd->spans[b].taken) b++;
        int use_a = a < rd->nfast && (b == rd->nspans || rd->fast[a].start < rd->spans[b].start);
        if (use_a) out[n++] = (cut){rd->fast[a].start, rd->fast[a].end}, a++;
        else if (b < rd->nspans) out[n++] = (cut){rd->spans[b].start, rd->spans[b].end}, b++;
        else return n;
    }
}

char *tc__rd_fast_scan(tc__reader *rd, const char *json, size_t len, size_t *skel_len) {
    scan sc = {.s = json, .len = len};
    int seen[NKEYS] = {0}, esc;
    rd->nfast = rd->nspans = 0;
    last_taken = last_spans = 0;
    if (fast_off || !json) return NULL;
    ws(&sc);
    if (!at(&sc, '{')) return NULL;
    sc.i++;
    ws(&sc);
    if (at(&sc, '}')) return NULL;
    for (;;) {
        if (!at(&sc, '"')) goto fail;
        size_t k0 = sc.i + 1;
        if (string(&sc, &esc) || esc) goto fail;
        size_t klen = sc.i - 1 - k0;
        ws(&sc);
        if (!at(&sc, ':')) goto fail;
        sc.i++;
        ws(&sc);
        int key = -1;
        for (int k = 0; k < NKEYS; k++)
            if (strlen(fast_keys[k]) == klen && !memcmp(json + k0, fast_keys[k], klen)) key = k;
        if (key >= 0 && seen[key]++) goto fail; /* given twice: cJSON's tree decides, not us */
        size_t at_value = sc.i;
        tc__fast *f = &rd->fast[rd->nfast];
        if (key >= 0 && at(&sc, '[') && !array(&sc, f, limit_of(rd, fast_keys[key]))) {
            f->key = fast_keys[key];
            rd->nfast++;
        } else {
            if (sc.nomem) goto fail;
            sc.i = at_value;
            if (at(&sc, '{') ? object_value(&sc, rd) : skip_value(&sc)) goto fail;
        }
        ws(&sc);
        if (at(&sc, '}')) break;
        if (!at(&sc, ',')) goto fail;
        sc.i++;
        ws(&sc);
    }
    cut cuts[TC__FAST_MAX + TC__SPAN_MAX];
    int ncuts = cuts_of(rd, cuts);
    if (!ncuts) {
        rd->nspans = 0; /* nothing taken: cJSON reads the body, every string included */
        return NULL;
    }
    size_t removed = 0; /* the skeleton: the body with each cut's text replaced by its ends */
    for (int k = 0; k < ncuts; k++) removed += cuts[k].end - cuts[k].start - 2;
    char *skel = malloc(len - removed), *w = skel;
    if (!skel) goto fail;
    size_t from = 0;
    for (int k = 0; k < ncuts; k++) {
        memcpy(w, json + from, cuts[k].start - from);
        w += cuts[k].start - from;
        *w++ = json[cuts[k].start], *w++ = json[cuts[k].end - 1];
        from = cuts[k].end;
    }
    memcpy(w, json + from, len - from);
    *skel_len = len - removed;
    return skel;
fail:
    drop(rd);
    return NULL;
}

int tc__rd_fast_bind(tc__reader *rd, const cJSON *root) {
    last_taken = last_spans = 0;
    if (!root || !tc__json_is(root, cJSON_Object)) return rd->nspans ? -1 : 0;
    for (const cJSON *m = root->child; m; m = m->next)
        for (int k = 0; k < rd->nfast; k++)
            if (m->string && !strcmp(m->string, rd->fast[k].key) && tc__json_is(m, cJSON_Array) && !m->child)
                if (!rd->fast[k].node) rd->fast[k].node = m, last_taken++;
    /* The walk saw, in text order, every "data" string member of every top-level object
     * value; the tree holds them in the same order (cJSON keeps members as written). */
    int k = 0;
    for (const cJSON *m = root->child; m; m = m->next)
        for (const cJSON *c = tc__json_is(m, cJSON_Object) ? m->child : NULL; c; c = c->next)
            if (c->string && !strcmp(c->string, "data") && tc__json_is(c, cJSON_String)) {
                if (k == rd->nspans) return -1;
                rd->spans[k].node = c;
                last_spans += rd->spans[k++].taken;
            }
    return k == rd->nspans ? 0 : -1;
}

const char *tc__rd_fast_data(const tc__reader *rd, const cJSON *v, size_t *len) {
    for (int k = 0; v && k < rd->nspans; k++)
        if (rd->spans[k].node == v && rd->spans[k].taken) {
            *len = rd->spans[k].end - rd->spans[k].start - 2;
            return rd->json + rd->spans[k].start + 1;
        }
    return NULL;
}

size_t tc__rd_fast_origin(const tc__reader *rd, size_t pos) {
    cut cuts[TC__FAST_MAX + TC__SPAN_MAX];
    int n = cuts_of(rd, cuts);
    size_t shift = 0; /* bytes the cuts before pos lost */
    for (int k = 0; k < n; k++) {
        if (pos < cuts[k].start - shift + 2) break; /* before this cut, or on its two bytes */
        shift += cuts[k].end - cuts[k].start - 2;
    }
    return pos + shift;
}

void tc__rd_fast_free(tc__reader *rd) { drop(rd); }

void *tc__rd_fast_take(tc__reader *rd, tc__fast *f) {
    void *p = f->data;
    tc_request *r = rd->r;
    f->data = NULL;
    if (r->nowned_ < TC_REQ_OWNED_MAX && !tc__rd_injected_failure()) {
        r->owned_[r->nowned_++] = p;
        return p;
    }
    free(p);
    rd->nomem = 1;
    return NULL;
}

tc__fast *tc__rd_fast(tc__reader *rd, const cJSON *v) {
    for (int k = 0; v && k < rd->nfast; k++)
        if (rd->fast[k].node == v) return &rd->fast[k];
    return NULL;
}

cJSON *tc__rd_fast_json(tc__reader *rd, const tc__fast *f) {
    cJSON *t = cJSON_ParseWithLength(rd->json + f->start, f->end - f->start);
    if (!t) rd->nomem = 1; /* the text was checked valid: only memory can fail */
    return t;
}

int tc__rd_fast_entries(tc__reader *rd, const tc__fast *f, const tc__jpath *p, size_t max) {
    if (f->n <= max) return 0;
    tc__rd_value_error(rd, p, "too many entries (%zu, at most %zu)", f->n, max);
    return -1;
}
