/* options.c — the table of request options: JSON name, where the value lives,
 * what it accepts and which methods read it. Parsing, echo and writing walk it. */
#include <stdio.h>
#include <string.h>

#include "io/jsonout.h"
#include "io/options.h"

/* The core's tc_<kind>_name seen through int, so one row type serves every enum. */
#define NAMES(kind, type) \
    static const char *kind##_names(int v) { return tc_##kind##_name((type)v); }
NAMES(method, tc_method)
NAMES(cross, tc_cross)
NAMES(wedges, tc_wedges)
NAMES(tangents, tc_tangents)
NAMES(twist, tc_twist)
NAMES(average, tc_average)
NAMES(range, tc_range)
NAMES(degenerate, tc_degenerate)

/* The offset of an enum field, refused at compile time unless it is an int
 * (the rows read and write enums as int); of a double field likewise. */
#define SIZED(T, f, type) (offsetof(T, f) + 0 * sizeof(char[sizeof(((T *)0)->f) == sizeof(type) ? 1 : -1]))
#define ENUM_OPT(f, kind, reads) TC_OPT_RECON, SIZED(tc_options, f, int), TC_OPT_ENUM, kind##_names, 0, 0, reads
#define MESH_NUMBER(f, lo, hi) TC_OPT_MESH, SIZED(tc_mesh_desc, f, double), TC_OPT_NUMBER, NULL, lo, hi, 0
#define MESH_ENUM(f, kind) TC_OPT_MESH, SIZED(tc_mesh_desc, f, int), TC_OPT_ENUM, kind##_names, 0, 0, 0

/* In the order the echo and the writer print them; "method" first. */
const tc_opt tc_opts[] = {
    {"method", ENUM_OPT(method, method, 0)},
    {"cross_boundary", ENUM_OPT(cross_boundary, cross, TC_READS_CROSS_BOUNDARY)},
    {"twist", ENUM_OPT(twist, twist, TC_READS_TWIST)},
    {"wedges", ENUM_OPT(wedges, wedges, TC_READS_WEDGES)},
    {"tangents", ENUM_OPT(tangents, tangents, TC_READS_TANGENTS)},
    {"average", ENUM_OPT(average, average, TC_READS_AVERAGE)},
    {"range", ENUM_OPT(range, range, TC_READS_RANGE)},
    {"value_tolerance", MESH_NUMBER(value_tolerance, 0, 1)},
    {"degenerate", MESH_ENUM(degenerate, degenerate)},
};
const int tc_nopts = (int)(sizeof tc_opts / sizeof tc_opts[0]);
_Static_assert(sizeof tc_opts / sizeof tc_opts[0] <= TC_OPT_MAX, "raise TC_OPT_MAX");

const tc_opt *tc_opt_find(const char *name) {
    for (int i = 0; name && i < tc_nopts; i++)
        if (strcmp(tc_opts[i].name, name) == 0) return &tc_opts[i];
    return NULL;
}

int tc_opt_get_enum(const tc_opt *row, const void *obj) {
    int v;
    memcpy(&v, (const char *)obj + row->off, sizeof v);
    return v;
}

double tc_opt_get_number(const tc_opt *row, const void *obj) {
    double v;
    memcpy(&v, (const char *)obj + row->off, sizeof v);
    return v;
}

void tc_opt_set_enum(const tc_opt *row, void *obj, int v) { memcpy((char *)obj + row->off, &v, sizeof v); }
void tc_opt_set_number(const tc_opt *row, void *obj, double v) { memcpy((char *)obj + row->off, &v, sizeof v); }

int tc_opt_parse_name(const tc_opt *row, const char *s) {
    for (int v = 0; s && row->name_of(v); v++)
        if (strcmp(row->name_of(v), s) == 0) return v;
    return -1;
}

int tc_opt_read_by(const tc_opt *row, tc_method m) {
    return row->target == TC_OPT_RECON && (row->reads == 0 || (tc_method_reads(m) & row->reads));
}

void tc_opt_defaults(tc_options *o, tc_mesh_desc *d) {
    tc_options_default(o);
    tc_mesh_desc_init(d);
}

int tc_opt_is_default(const tc_opt *row, const void *obj) {
    tc_options o;
    tc_mesh_desc d;
    tc_opt_defaults(&o, &d);
    const void *def = tc_opt_object(row, &o, &d);
    if (row->kind == TC_OPT_ENUM) return tc_opt_get_enum(row, obj) == tc_opt_get_enum(row, def);
    return tc_opt_get_number(row, obj) == tc_opt_get_number(row, def);
}

void tc_opt_write(tc_strbuf *b, const char *sep, const tc_opt *row, const void *obj) {
    tc_json_key(b, sep, row->name);
    if (row->kind == TC_OPT_ENUM) tc_strbuf_json_string(b, row->name_of(tc_opt_get_enum(row, obj)));
    else tc_strbuf_double(b, tc_opt_get_number(row, obj));
}

void tc_opt_accepts(const tc_opt *row, char *buf, size_t cap) {
    size_t n = 0;
    buf[0] = '\0';
    if (row->kind == TC_OPT_NUMBER) {
        snprintf(buf, cap, "a number from %g to %g", row->min, row->max);
        return;
    }
    for (int v = 0; row->name_of(v); v++) {
        int w = snprintf(buf + n, cap - n, "%s%s", v ? ", " : "", row->name_of(v));
        if (w < 0 || (size_t)w >= cap - n) break;
        n += (size_t)w;
    }
}
