/* option_table.h — the options of tc_options but the method, one row each
 * (option_table.c): the request name, the names of its values, its TC_READS_*
 * bit, and which methods read it, by what a method uses (method.h's rows). */
#ifndef TC_CORE_OPTION_TABLE_H
#define TC_CORE_OPTION_TABLE_H

#include <stddef.h>

#include "tocher.h"

/* What a method uses, as its row says (tc__method.uses); an option is read by
 * the methods that use what its row names (tc__option.read_by). */
enum {
    TC__USES_PLANES = 1u << 0, /* the tangent-plane pipeline (pipeline.h): wedges, planes, range */
    TC__USES_CROSS = 1u << 1,  /* the Clough-Tocher split's cross-boundary rule */
    TC__USES_TWIST = 1u << 2   /* bicubic patches' twists */
};

/* Invariants (option_table.c asserts the first at compile time): every
 * field of tc_options but the method has exactly one row; a field is an enum
 * whose 0 is the default and whose values are values[0 ..] up to the NULL. */
typedef struct {
    const char *name;           /* the request member ("cross_boundary") */
    size_t off;                 /* of its field in tc_options */
    const char *const *values;  /* names of its values 0, 1, ..., NULL-terminated */
    unsigned bit;               /* its TC_READS_* bit */
    unsigned read_by;           /* TC__USES_*: read by the methods that use one of these */
} tc__option;

/* The row of option i (0 .. tc_option_count() - 1), or NULL. */
const tc__option *tc__option_at(int i);

#endif
