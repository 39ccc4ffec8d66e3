/* options.h — the request's options, one row each (the idiom of src/server/config.c):
 * the reader, the echo in answers, the request writer and `tocher help` walk this table. */
#ifndef TC_IO_OPTIONS_H
#define TC_IO_OPTIONS_H

#include <stddef.h>

#include "io/strbuf.h"
#include "tocher.h"

/* The rows: "method", then every option of the core's table (tc_option_*: a
 * reconstruction option is added there, and appears here by itself), then the
 * mesh options. A mesh option (one that shapes validation) is a tc_mesh_desc
 * field with its default in tc_mesh_desc_init, and a row in options.c. */

typedef enum {
    TC_OPT_ENUM,  /* a name from the core's names (tc_opt_value_name) */
    TC_OPT_NUMBER /* a finite number in [min, max] */
} tc_opt_kind;

typedef enum {
    TC_OPT_RECON, /* a field of tc_options: per reconstruction, also in /v1/compare's "methods" */
    TC_OPT_MESH   /* a field of tc_mesh_desc: one per request, shapes validation */
} tc_opt_target;

typedef struct {
    const char *name;              /* the JSON member */
    tc_opt_target target;
    tc_opt_kind kind;
    int core;                      /* a core option's index (tc_option_*), else -1 */
    size_t off;                    /* else: of the field in tc_options or tc_mesh_desc */
    const char *(*name_of)(int v); /* else, TC_OPT_ENUM: the name of value v (dense from 0), NULL past the last */
    double min, max;               /* TC_OPT_NUMBER: the accepted range */
    unsigned reads;                /* TC_OPT_RECON: the TC_READS_* bit of the methods that read it;
                                    * 0 = every method (the method itself) */
} tc_opt;

/* At most this many rows (request.c and request_options.c size their member lists with it). */
#define TC_OPT_MAX 32

/* The rows in order (the echo and the writer print them so), 0 .. tc_opt_count() - 1. */
int tc_opt_count(void);
const tc_opt *tc_opt_at(int i);
/* The row named `name`, or NULL; a row's index. */
const tc_opt *tc_opt_find(const char *name);
int tc_opt_index(const tc_opt *row);
/* The object a row's field lives in: o for TC_OPT_RECON rows, d for TC_OPT_MESH. */
static inline void *tc_opt_object(const tc_opt *row, tc_options *o, tc_mesh_desc *d) {
    return row->target == TC_OPT_RECON ? (void *)o : (void *)d;
}
/* The field's value: an enum's as int, a number's as double. */
int tc_opt_get_enum(const tc_opt *row, const void *obj);
double tc_opt_get_number(const tc_opt *row, const void *obj);
void tc_opt_set_enum(const tc_opt *row, void *obj, int v);
void tc_opt_set_number(const tc_opt *row, void *obj, double v);
/* The name of value v of an enum row (NULL past the last); the value named s, or -1. */
const char *tc_opt_value_name(const tc_opt *row, int v);
int tc_opt_parse_name(const tc_opt *row, const char *s);
/* 1 if method m reads a TC_OPT_RECON row (the method row: every method). */
int tc_opt_read_by(const tc_opt *row, tc_method m);
/* The defaults of every row: tc_options_default and tc_mesh_desc_init. */
void tc_opt_defaults(tc_options *o, tc_mesh_desc *d);
/* 1 if the field holds its default (tc_opt_defaults). */
int tc_opt_is_default(const tc_opt *row, const void *obj);
/* Appends `sep` (unless b is empty or ends with '{') then "name":value. */
void tc_opt_write(tc_strbuf *b, const char *sep, const tc_opt *row, const void *obj);
/* What the row accepts, for messages and help: "normal, salesin, affine" or
 * "a number from 0 to 1". */
void tc_opt_accepts(const tc_opt *row, char *buf, size_t cap);

#endif
