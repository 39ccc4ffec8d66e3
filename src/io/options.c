/* options.c — the table of request options: JSON name, where the value lives, what
 * it accepts and which methods read it. Parsing, echo, writing and help walk it. */
#include <pthread.h>
#include <stdio.h>
#include <string.h>

#include "io/jsonout.h"
#include "io/options.h"

static const char *method_names(int v) { return tc_method_name((tc_method)v); }
static const char *degenerate_names(int v) { return tc_degenerate_name((tc_degenerate)v); }

/* The offset of a field, refused at compile time unless it has the size of
 * `type` (the rows read and write enums as int, numbers as double). */
#define SIZED(T, f, type) (offsetof(T, f) + 0 * sizeof(char[sizeof(((T *)0)->f) == sizeof(type) ? 1 : -1]))

/* The rows around the core's options: the method first, the mesh options last. */
static const tc_opt method_row = {"method", TC_OPT_RECON, TC_OPT_ENUM, -1, SIZED(tc_options, method, int),
                                  method_names, 0, 0, 0};
static const tc_opt mesh_rows[] = {
    {"value_tolerance", TC_OPT_MESH, TC_OPT_NUMBER, -1, SIZED(tc_mesh_desc, value_tolerance, double), NULL, 0, 1, 0},
    {"degenerate", TC_OPT_MESH, TC_OPT_ENUM, -1, SIZED(tc_mesh_desc, degenerate, int), degenerate_names, 0, 0, 0},
};
#define NMESH ((int)(sizeof mesh_rows / sizeof mesh_rows[0]))

static tc_opt rows[TC_OPT_MAX];
static int nrows;
static pthread_once_t rows_once = PTHREAD_ONCE_INIT;

/* Invariant once built: rows[0] is the method, rows[1 .. 1 + tc_option_count())
 * the core's options in its order, then the mesh rows; nrows <= TC_OPT_MAX. */
static void build_rows(void) {
    rows[nrows++] = method_row;
    for (int i = 0; i < tc_option_count() && nrows < TC_OPT_MAX - NMESH; i++)
        rows[nrows++] = (tc_opt){tc_option_name(i), TC_OPT_RECON, TC_OPT_ENUM, i, 0, NULL, 0, 0, tc_option_bit(i)};
    for (int i = 0; i < NMESH; i++) rows[nrows++] = mesh_rows[i];
}

int tc_opt_count(void) {
    pthread_once(&rows_once, build_rows);
    return nrows;
}

const tc_opt *tc_opt_at(int i) { return i >= 0 && i < tc_opt_count() ? &rows[i] : NULL; }

int tc_opt_index(const tc_opt *row) { return (int)(row - rows); }

const tc_opt *tc_opt_find(const char *name) {
    for (int i = 0; name && i < tc_opt_count(); i++)
        if (strcmp(rows[i].name, name) == 0) return &rows[i];
    return NULL;
}

int tc_opt_get_enum(const tc_opt *row, const void *obj) {
    if (row->core >= 0) return tc_option_get(obj, row->core);
    int v;
    memcpy(&v, (const char *)obj + row->off, sizeof v);
    return v;
}

double tc_opt_get_number(const tc_opt *row, const void *obj) {
    double v;
    memcpy(&v, (const char *)obj + row->off, sizeof v);
    return v;
}

void tc_opt_set_enum(const tc_opt *row, void *obj, int v) {
    if (row->core >= 0) tc_option_set(obj, row->core, v);
    else memcpy((char *)obj + row->off, &v, sizeof v);
}

void tc_opt_set_number(const tc_opt *row, void *obj, double v) { memcpy((char *)obj + row->off, &v, sizeof v); }

const char *tc_opt_value_name(const tc_opt *row, int v) {
    return row->core >= 0 ? tc_option_value_name(row->core, v) : row->name_of(v);
}

int tc_opt_parse_name(const tc_opt *row, const char *s) {
    for (int v = 0; s && tc_opt_value_name(row, v); v++)
        if (strcmp(tc_opt_value_name(row, v), s) == 0) return v;
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
    if (row->kind == TC_OPT_ENUM) tc_strbuf_json_string(b, tc_opt_value_name(row, tc_opt_get_enum(row, obj)));
    else tc_strbuf_double(b, tc_opt_get_number(row, obj));
}

void tc_opt_accepts(const tc_opt *row, char *buf, size_t cap) {
    size_t n = 0;
    buf[0] = '\0';
    if (row->kind == TC_OPT_NUMBER) {
        snprintf(buf, cap, "a number from %g to %g", row->min, row->max);
        return;
    }
    for (int v = 0; tc_opt_value_name(row, v); v++) {
        int w = snprintf(buf + n, cap - n, "%s%s", v ? ", " : "", tc_opt_value_name(row, v));
        if (w < 0 || (size_t)w >= cap - n) break;
        n += (size_t)w;
    }
}
