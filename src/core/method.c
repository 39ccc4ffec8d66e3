/* method.c — the table of reconstruction methods: per method its name, its
 * coefficients, its build and evaluator, the flags it keeps and the options it reads. */
#include <string.h>

#include "core/ct.h"
#include "core/hermite.h"
#include "core/linear.h"
#include "core/method.h"
#include "core/option_table.h"
#include "core/powell_sabin.h"

/* What each method is built with (option_table.h), so the options it reads: the
 * tangent-plane pipeline reads tangents, wedges (and through them the averaging:
 * "literal" averages unit normals), average and range; the cubic split reads
 * cross_boundary; bicubic patches twist. */
#define PLANES TC__USES_PLANES
#define CROSS TC__USES_CROSS
#define TWIST TC__USES_TWIST

/* To add a method: its enumerator in tocher.h, a row here, its code (labels, build,
 * evaluator) in a module of its own. The rest follows from the row; what does not is
 * checked: api/openapi.yaml's method enum (the endpoint tests), a variant in the
 * stability suite (stab.c and test_consistency.py refuse a method without one) and
 * its promises there (stab_props.c's switch, which does not compile without it). */

/* What the overlay shows follows from `honour` and `smooth` (tc__method_edge):
 *  - the cubics, powell-sabin and hermite are C1 where they are not cut
 *    (hermite only across parallelogram edges: drawn as C1, see design-notes);
 *  - clough-tocher-c1 cuts nothing but the boundary; powell-sabin cuts C-1
 *    edges and smooths C0 ones (a C1 quadratic cannot keep a kink);
 *  - linear and linear4 are C0 everywhere and jump across C-1 edges where the
 *    corner values do; constant is discontinuous across every edge. */
static const tc__method methods[] = {
    [TC_METHOD_CLOUGH_TOCHER] = {"clough-tocher", TC_CT_ORDINATES, tc__ct_labels, tc__ct_build, tc__ct_eval,
                                 TC_HONOR_ALL, TC_C1, PLANES | CROSS, 0, TC_CT_ORDINATES},
    [TC_METHOD_CLOUGH_TOCHER_C1] = {"clough-tocher-c1", TC_CT_ORDINATES, tc__ct_labels, tc__ct_build, tc__ct_eval,
                                    TC_HONOR_NONE, TC_C1, PLANES | CROSS, 0, TC_CT_ORDINATES},
    [TC_METHOD_LINEAR] = {"linear", 3, tc__linear_labels, tc__linear_build, tc__linear_eval, TC_HONOR_ALL, TC_C0, 0,
                          0, 0},
    [TC_METHOD_LINEAR4] = {"linear4", 6, tc__linear4_labels, tc__linear4_build, tc__linear4_eval, TC_HONOR_ALL, TC_C0,
                           0, 0, 0},
    [TC_METHOD_CONSTANT] = {"constant", 1, tc__constant_labels, tc__constant_build, tc__constant_eval, TC_HONOR_ALL,
                            TC_CM1, 0, 0, 0},
    [TC_METHOD_POWELL_SABIN] = {"powell-sabin", TC_PS_COEFS, tc__ps_labels, tc__ps_build, tc__ps_eval, TC_HONOR_CM1,
                                TC_C1, PLANES, 0, TC_PS_ORDINATES},
    [TC_METHOD_HERMITE] = {"hermite", TC_HERMITE_COEFS, tc__hermite_labels, tc__hermite_build, tc__hermite_eval,
                           TC_HONOR_ALL, TC_C1, PLANES | TWIST, 1, TC_HERMITE_GEOM},
};
#define NMETHODS ((int)(sizeof methods / sizeof methods[0]))
/* A method added to tc_method without its row here does not compile. */
_Static_assert(NMETHODS == TC_METHOD_COUNT, "every tc_method needs a row in methods[]");

const tc__method *tc__method_of(tc_method m) {
    return (int)m >= 0 && (int)m < NMETHODS && methods[m].name ? &methods[m] : NULL;
}

int tc_method_count(void) { return NMETHODS; }

const char *tc_method_name(tc_method m) {
    const tc__method *mt = tc__method_of(m);
    return mt ? mt->name : NULL;
}

int tc_method_parse(const char *s, tc_method *out) {
    for (int i = 0; s && i < NMETHODS; i++)
        if (methods[i].name && strcmp(methods[i].name, s) == 0) {
            *out = (tc_method)i;
            return 0;
        }
    return -1;
}

int tc_method_quads_only(tc_method m) {
    const tc__method *mt = tc__method_of(m);
    return mt ? mt->quads_only : 0;
}
