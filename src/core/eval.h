/* eval.h — what tests reach inside the point evaluator (eval.c). */
#ifndef TC_CORE_EVAL_H
#define TC_CORE_EVAL_H

#include <stddef.h>
#include <stdint.h>

#include "tocher.h"

/* The mesh size from which tc_eval_points visits batches in Z order (default
 * 32768 triangles), so the sorted path can be checked on small meshes. */
void tc__eval_sort_min_triangles(int32_t nt);

/* tc_eval_points as it was before the batch path: the tree locator and a frame
 * per point. The reference the batch path equals bit for bit (owners, values,
 * gradients). */
void tc__eval_points_ref(const tc_recon *r, const tc_locator *L, size_t n, const double *xy, double *values,
                         double *grads, int32_t *tri);

#endif
