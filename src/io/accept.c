/* accept.c — the Accept header of a render request read as RFC 9110 12.5.1 says,
 * against the primary formats of the format table. */
#include <string.h>
#include <strings.h>

#include "image/format.h"
#include "io/accept.h"

// (Line comments here, since the wildcards contain the characters that open a block comment.)
// Each format we can serve gets the q of the most specific media range that matches it
// (exact type or its alias > "image/*" > "*/*"). The answer is the explicitly named format
// with the highest q (> 0; the earliest on ties), unless a wildcard gives some format a
// strictly higher q: then -1, "no preference", and the caller uses its default (png). One
// consequence: "image/png;q=0, image/*" also gives -1. Variants share their primary's MIME
// type (png16, exr-half), so an Accept header never selects them: only the request's
// "format" field does.

typedef struct {
    int level[TC_IMG_NFORMATS]; // 0 unmatched, 1 by "*/*", 2 by "image/*" (or "application/*"), 3 by name
    int q[TC_IMG_NFORMATS];     // thousandths, from the range at that level
    int pos[TC_IMG_NFORMATS];   // where that range was in the header
} acc_state;

typedef struct {
    const char *s;
    size_t n;
} span;

static int is_ows(char c) { return c == ' ' || c == '\t'; }

static span trim(const char *s, size_t n) {
    while (n && is_ows(*s)) s++, n--;
    while (n && is_ows(s[n - 1])) n--;
    return (span){s, n};
}

static int span_is(span a, const char *lit) { return a.n == strlen(lit) && strncasecmp(a.s, lit, a.n) == 0; }

/* Length up to the first `stop` character outside double quotes, at most n: bounded,
 * so that parsing stays linear in the header's length whatever it holds. */
static size_t until_unquoted(const char *s, size_t n, char stop) {
    size_t i = 0;
    for (int quoted = 0; i < n && (quoted || s[i] != stop); i++) {
        if (s[i] == '\\' && quoted && i + 1 < n) i++;
        else if (s[i] == '"') quoted = !quoted;
    }
    return i;
}

/* A qvalue ("0", "0.5", "1.000") in thousandths, or -1 if malformed. */
static int parse_qvalue(span v) {
    if (v.n == 0 || (v.s[0] != '0' && v.s[0] != '1') || v.n > 5) return -1;
    int q = (v.s[0] - '0') * 1000;
    if (v.n == 1) return q;
    if (v.s[1] != '.') return -1;
    for (size_t i = 2, scale = 100; i < v.n; i++, scale /= 10) {
        if (v.s[i] < '0' || v.s[i] > '9') return -1;
        q += (v.s[i] - '0') * (int)scale;
    }
    return q > 1000 ? -1 : q;
}

/* The q parameter among the ";"-separated parameters of one element (1000 when
 * absent, -1 when malformed). */
static int element_q(const char *p, size_t n) {
    while (n) {
        size_t k = until_unquoted(p, n, ';');
        span param = trim(p, k);
        const char *eq = memchr(param.s, '=', param.n);
        if (eq && span_is(trim(param.s, (size_t)(eq - param.s)), "q"))
            return parse_qvalue(trim(eq + 1, param.n - (size_t)(eq + 1 - param.s)));
        p += k < n ? k + 1 : k;
        n -= k < n ? k + 1 : k;
    }
    return 1000;
}

/* How specifically the media range names format f: 3, 2, 1, or 0 (not at all). */
static int match_level(span range, tc_img_format f) {
    const tc_img_traits *t = tc_img_traits_of(f);
    if (span_is(range, "*/*")) return 1;
    size_t major = (size_t)(strchr(t->mime, '/') - t->mime);
    if (range.n == major + 2 && strncasecmp(range.s, t->mime, major) == 0 && range.s[major] == '/' &&
        range.s[major + 1] == '*')
        return 2;
    return span_is(range, t->mime) || (t->mime_alias && span_is(range, t->mime_alias)) ? 3 : 0;
}

/* Records one element of the header ("type/subtype; params"). */
static void accept_element(acc_state *acc, const char *p, size_t n, int pos) {
    size_t k = until_unquoted(p, n, ';');
    span range = trim(p, k);
    int q = element_q(p + k, n - k);
    if (range.n == 0 || q < 0) return; /* malformed: ignored */
    for (int f = 0; f < TC_IMG_NFORMATS; f++) {
        if (tc_img_primary((tc_img_format)f) != f) continue;
        int lv = match_level(range, (tc_img_format)f);
        if (lv > acc->level[f]) acc->level[f] = lv, acc->q[f] = q, acc->pos[f] = pos;
    }
}

static int better(const acc_state *acc, int f, int best) {
    return best < 0 || acc->q[f] > acc->q[best] || (acc->q[f] == acc->q[best] && acc->pos[f] < acc->pos[best]);
}

static int accept_choice(const acc_state *acc) {
    int best = -1, wild_q = 0;
    for (int f = 0; f < TC_IMG_NFORMATS; f++) {
        if (acc->level[f] < 3) {
            if (acc->level[f] && acc->q[f] > wild_q) wild_q = acc->q[f];
        } else if (acc->q[f] > 0 && better(acc, f, best)) {
            best = f;
        }
    }
    return best >= 0 && acc->q[best] >= wild_q ? best : -1;
}

int tc_accept_format(const char *accept) {
    if (!accept) return -1;
    acc_state acc;
    memset(&acc, 0, sizeof acc);
    const char *p = accept;
    size_t left = strlen(accept);
    for (int pos = 0; left; pos++) {
        size_t n = until_unquoted(p, left, ',');
        accept_element(&acc, p, n, pos);
        size_t step = n < left ? n + 1 : n; /* past the comma */
        p += step, left -= step;
    }
    return accept_choice(&acc);
}
