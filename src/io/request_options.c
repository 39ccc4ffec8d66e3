/* request_options.c — the request's options (the table in io/options.c), at the top
 * level and in each entry of /v1/compare's "methods". */
#include "io/options.h"
#include "io/reader.h"
#include "io/request_fields.h"

/* ---- fields: options (the table in io/options.c) ------------------------------------ */

/* One option's value into its field: o's for a reconstruction option, the
 * request's mesh description for a mesh option. */
static void read_option(tc__reader *rd, const tc_opt *row, const cJSON *v, const tc__jpath *p, tc_options *o) {
    void *obj = tc_opt_object(row, o, &rd->r->desc);
    char accepts[160], num[32];
    tc_opt_accepts(row, accepts, sizeof accepts);
    if (row->kind == TC_OPT_NUMBER) {
        double x;
        if (tc__rd_number(rd, v, p, &x)) return;
        if (!(x >= row->min && x <= row->max))
            tc__rd_value_error(rd, p, "%s must be %s, got %s", row->name, accepts, tc__number_text(x, num, sizeof num));
        else
            tc_opt_set_number(row, obj, x);
        return;
    }
    if (!tc__json_is(v, cJSON_String) || !v->valuestring) {
        tc__rd_shape_error(rd, p, "expected a string (one of: %s), got %s", accepts, tc__json_kind(v));
        return;
    }
    int x = tc_opt_parse_name(row, v->valuestring);
    if (x < 0) tc__rd_value_error(rd, p, "unknown %s '%.40s'; expected one of: %s", row->name, v->valuestring, accepts);
    else tc_opt_set_enum(row, obj, x);
}

/* The options found at the top level (found[j] for row j): the request's own,
 * and the defaults of each entry of "methods". */
void tc__rd_options(tc__reader *rd, const cJSON *const *found) {
    for (int j = 0; j < tc_opt_count(); j++) {
        const tc_opt *row = tc_opt_at(j);
        if (!found[j]) continue;
        tc__jpath p = tc__jpath_key(NULL, row->name);
        read_option(rd, row, found[j], &p, &rd->r->opt);
    }
}

/* One entry of "methods": a method name, or an object of options (the
 * request's own options are the defaults for the fields it leaves out). A
 * mesh option there would mean another mesh: it is ignored with a warning. */
static void read_method(tc__reader *rd, const cJSON *e, const tc__jpath *p, tc_options *o) {
    *o = rd->r->opt;
    if (tc__json_is(e, cJSON_String)) {
        read_option(rd, tc_opt_find("method"), e, p, o);
        return;
    }
    const cJSON *found[TC_OPT_MAX];
    if (tc__rd_sort_members(rd, e, p, NULL, 0, 1, found, "a method name or an object {method, ...}")) return;
    for (int j = 0; j < tc_opt_count(); j++) {
        const tc_opt *row = tc_opt_at(j);
        if (!found[j]) continue;
        tc__jpath pj = tc__jpath_key(p, row->name);
        if (row->target == TC_OPT_MESH)
            tc__rd_warning(rd, &pj,
                           "'%s' applies to the mesh, which every method shares: give it at the top level (ignored "
                           "here)",
                           row->name);
        else
            read_option(rd, row, found[j], &pj, o);
    }
}

void tc__parse_methods(tc__reader *rd, const cJSON *v, const tc__jpath *p) {
    size_t n, i = 0;
    if (tc__rd_array(rd, v, p, "an array of methods", TC_REQ_MAX_METHODS, &n)) return;
    for (const cJSON *e = v->child; e; e = e->next, i++) {
        tc__jpath pi = tc__jpath_index(p, i);
        read_method(rd, e, &pi, &rd->r->methods[i]);
    }
    rd->r->nmethods = (int)n;
}
