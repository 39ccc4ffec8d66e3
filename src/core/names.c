/* names.c — the request-format names of the options (and of tc_degenerate), both ways
 * (the methods' are in their table, method.c). One table per enum so a name and its value cannot drift apart. */
#include <string.h>

#include "tocher.h"

static const char *const cross_names[] = {
    [TC_CROSS_NORMAL] = "normal", [TC_CROSS_SALESIN] = "salesin", [TC_CROSS_AFFINE] = "affine"};
static const char *const wedges_names[] = {
    [TC_WEDGES_CORRECTED] = "corrected", [TC_WEDGES_LITERAL] = "literal"};
static const char *const twist_names[] = {[TC_TWIST_ESTIMATE] = "estimate", [TC_TWIST_ZERO] = "zero"};
static const char *const average_names[] = {[TC_AVERAGE_AREA] = "area", [TC_AVERAGE_NORMALS] = "normals"};
static const char *const range_names[] = {
    [TC_RANGE_LOCAL] = "local", [TC_RANGE_POSITIVE] = "positive", [TC_RANGE_FREE] = "free"};
static const char *const degenerate_names[] = {[TC_DEGENERATE_REFUSE] = "refuse", [TC_DEGENERATE_DROP] = "drop"};
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

/* tc_<kind>_name and tc_<kind>_parse of one enum from its table. */
#define DEFINE_NAMES(kind, type, table)                                 \
    const char *tc_##kind##_name(type v) { return name_of(table, COUNT(table), (int)v); } \
    int tc_##kind##_parse(const char *s, type *out) {                   \
        int v = parse_name(table, COUNT(table), s);                     \
        if (v < 0) return -1;                                           \
        *out = (type)v;                                                 \
        return 0;                                                       \
    }
DEFINE_NAMES(cross, tc_cross, cross_names)
DEFINE_NAMES(wedges, tc_wedges, wedges_names)
DEFINE_NAMES(tangents, tc_tangents, tangents_names)
DEFINE_NAMES(twist, tc_twist, twist_names)
DEFINE_NAMES(average, tc_average, average_names)
DEFINE_NAMES(range, tc_range, range_names)
DEFINE_NAMES(degenerate, tc_degenerate, degenerate_names)

/* Every default is its enum's 0 (the invariant in tocher.h), so an option
 * added to tc_options needs nothing here. */
void tc_options_default(tc_options *o) { *o = (tc_options){TC_METHOD_CLOUGH_TOCHER}; }
