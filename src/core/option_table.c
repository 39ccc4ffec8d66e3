/* option_table.c — the table of the reconstruction options (all of tc_options but the
 * method, whose names are the method table's): request names both ways, which methods
 * read each, and tc_degenerate's names (a mesh option's, kept here with the others). */
#include <stddef.h>
#include <string.h>

#include "core/method.h"
#include "core/option_table.h"

/* Request names of each option's values, in enum order, NULL-terminated. */
static const char *const cross_names[] = {
    [TC_CROSS_NORMAL] = "normal", [TC_CROSS_SALESIN] = "salesin", [TC_CROSS_AFFINE] = "affine", NULL};
static const char *const twist_names[] = {[TC_TWIST_ESTIMATE] = "estimate", [TC_TWIST_ZERO] = "zero", NULL};
static const char *const wedges_names[] = {[TC_WEDGES_CORRECTED] = "corrected", [TC_WEDGES_LITERAL] = "literal", NULL};
static const char *const tangents_names[] = {[TC_TANGENTS_AUTO] = "auto", [TC_TANGENTS_GIVEN] = "given",
                                             [TC_TANGENTS_MIDPOINTS] = "midpoints",
                                             [TC_TANGENTS_ESTIMATE] = "estimate", NULL};
static const char *const average_names[] = {[TC_AVERAGE_AREA] = "area", [TC_AVERAGE_NORMALS] = "normals", NULL};
static const char *const range_names[] = {
    [TC_RANGE_LOCAL] = "local", [TC_RANGE_POSITIVE] = "positive", [TC_RANGE_FREE] = "free", NULL};
static const char *const degenerate_names[] = {[TC_DEGENERATE_REFUSE] = "refuse", [TC_DEGENERATE_DROP] = "drop", NULL};

/* The offset of an enum field of tc_options, refused at compile time unless
 * it is an int (the rows read and write enums as int). */
#define FIELD(f) (offsetof(tc_options, f) + 0 * sizeof(char[sizeof(((tc_options *)0)->f) == sizeof(int) ? 1 : -1]))

/* In the order answers echo them and `tocher help` lists them. To add an
 * option: its enum, tc_options field and TC_READS_* bit in tocher.h, then a
 * row here (the code that reads it is the rest). */
static const tc__option options[] = {
    {"cross_boundary", FIELD(cross_boundary), cross_names, TC_READS_CROSS_BOUNDARY, TC__USES_CROSS},
    {"twist", FIELD(twist), twist_names, TC_READS_TWIST, TC__USES_TWIST},
    {"wedges", FIELD(wedges), wedges_names, TC_READS_WEDGES, TC__USES_PLANES},
    {"tangents", FIELD(tangents), tangents_names, TC_READS_TANGENTS, TC__USES_PLANES},
    {"average", FIELD(average), average_names, TC_READS_AVERAGE, TC__USES_PLANES},
    {"range", FIELD(range), range_names, TC_READS_RANGE, TC__USES_PLANES},
};
#define NOPTIONS ((int)(sizeof options / sizeof options[0]))

/* A field added to tc_options without a row here does not compile: the method
 * and one int-sized field per row, then the two that are no options of the
 * result (threads, deadline_ms), nothing between them or after. */
_Static_assert(offsetof(tc_options, threads) == (1 + sizeof options / sizeof options[0]) * sizeof(int) &&
                   offsetof(tc_options, deadline_ms) - offsetof(tc_options, threads) <= sizeof(double) &&
                   sizeof(tc_options) == offsetof(tc_options, deadline_ms) + sizeof(double),
               "every field of tc_options but the method, threads and deadline_ms needs a row in option_table.c");

const tc__option *tc__option_at(int i) { return i >= 0 && i < NOPTIONS ? &options[i] : NULL; }

int tc_option_count(void) { return NOPTIONS; }

const char *tc_option_name(int i) { return i >= 0 && i < NOPTIONS ? options[i].name : NULL; }

unsigned tc_option_bit(int i) { return i >= 0 && i < NOPTIONS ? options[i].bit : 0; }

static int count_of(const char *const *names) {
    int n = 0;
    while (names[n]) n++;
    return n;
}

const char *tc_option_value_name(int i, int v) {
    if (i < 0 || i >= NOPTIONS || v < 0 || v >= count_of(options[i].values)) return NULL;
    return options[i].values[v];
}

int tc_option_get(const tc_options *o, int i) {
    int v = 0;
    if (i >= 0 && i < NOPTIONS) memcpy(&v, (const char *)o + options[i].off, sizeof v);
    return v;
}

void tc_option_set(tc_options *o, int i, int v) {
    if (i >= 0 && i < NOPTIONS) memcpy((char *)o + options[i].off, &v, sizeof v);
}

unsigned tc_method_reads(tc_method m) {
    const tc__method *mt = tc__method_of(m);
    unsigned bits = 0;
    for (int i = 0; mt && i < NOPTIONS; i++)
        if (options[i].read_by & mt->uses) bits |= options[i].bit;
    return bits;
}

/* ---- the per-enum names of tocher.h ---- */

static const char *name_of(const char *const *names, int v) { return v >= 0 && v < count_of(names) ? names[v] : NULL; }

static int parse_name(const char *const *names, const char *s) {
    for (int i = 0; s && names[i]; i++)
        if (strcmp(names[i], s) == 0) return i;
    return -1;
}

/* tc_<kind>_name and tc_<kind>_parse of one enum from its names. */
#define DEFINE_NAMES(kind, type, table)                                 \
    const char *tc_##kind##_name(type v) { return name_of(table, (int)v); } \
    int tc_##kind##_parse(const char *s, type *out) {                   \
        int v = parse_name(table, s);                                   \
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
