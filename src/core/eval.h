/* eval.h — what tests reach inside the point evaluator (eval.c). */
#ifndef TC_CORE_EVAL_H
#define TC_CORE_EVAL_H

#include <stdint.h>

/* The mesh size from which tc_eval_points visits batches in Z order (default
 * 32768 triangles), so the sorted path can be checked on small meshes. */
void tc__eval_sort_min_triangles(int32_t nt);

#endif
