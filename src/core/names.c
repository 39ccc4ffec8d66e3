/* names.c — the request-format names of the options, both ways (the methods'
 * are in their table, method.c). One table per enum so a name and its value cannot drift apart. */
#include <string.h>

#include "tocher.h"

static const char *const cross_names[] = {
    [TC_CROSS_NORMAL] = "normal", [TC_CROSS_SALESIN] = "salesin", [TC_CROSS_AFFINE] = "affine"};
static const char *const wedges_names[] = {
    [TC_WEDGES_CORRECTED] = "corrected", [TC_WEDGES_LITERAL] = "literal"};
static const char *const twist_names[] = {[TC_TWIST_ESTIMATE] = "estimate", [TC_TWIST_ZERO] = "zero"};
static const char *const average_names[] = {[TC_AVERAGE_AREA] = "area", [TC_AVERAGE_NORMALS] = "normals"};
static const char *const tangents_names[] = {
    [TC_TANGENTS_AUTO] = "auto", [TC_TANGENTS_GIVEN] = "given",
    [TC_TANGENTS_MIDPOINTS] = "midpoints", [TC_TANGENTS_ESTIMATE] = "estimate"};

#define COUNT(a) ((int)(sizeof(a) / sizeof((a)[0])))

static const char *name_of(const char *const *names, int n, int v) {
    return v >= 0 && v < n ? names[v] : NULL;
}

static int parse_name(const char *const *names, int n, const char *s) {
    for (int i = 0; s && i < n; i++)
        if (names[i] && strcmp(names[i], s) == 0) return i;
    return -1;
}

const char *tc_cross_name(tc_cross c) { return name_of(cross_names, COUNT(cross_names), (int)c); }
const char *tc_wedges_name(tc_wedges w) { return name_of(wedges_names, COUNT(wedges_names), (int)w); }
const char *tc_tangents_name(tc_tangents t) { return name_of(tangents_names, COUNT(tangents_names), (int)t); }
const char *tc_twist_name(tc_twist t) { return name_of(twist_names, COUNT(twist_names), (int)t); }
const char *tc_average_name(tc_average a) { return name_of(average_names, COUNT(average_names), (int)a); }

#define DEFINE_PARSE(fn, type, table)                                   \
    int fn(const char *s, type *out) {                                  \
        int v = parse_name(table, COUNT(table), s);                     \
        if (v < 0) return -1;                                           \
        *out = (type)v;                                                 \
        return 0;                                                       \
    }
DEFINE_PARSE(tc_cross_parse, tc_cross, cross_names)
DEFINE_PARSE(tc_wedges_parse, tc_wedges, wedges_names)
DEFINE_PARSE(tc_tangents_parse, tc_tangents, tangents_names)
DEFINE_PARSE(tc_twist_parse, tc_twist, twist_names)
DEFINE_PARSE(tc_average_parse, tc_average, average_names)

void tc_options_default(tc_options *o) {
    o->method = TC_METHOD_CLOUGH_TOCHER;
    o->cross_boundary = TC_CROSS_NORMAL;
    o->wedges = TC_WEDGES_CORRECTED;
    o->tangents = TC_TANGENTS_AUTO;
    o->twist = TC_TWIST_ESTIMATE;
    o->average = TC_AVERAGE_AREA;
}
