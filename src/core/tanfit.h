/* tanfit.h — the estimated tangent plane of a wedge: a weighted least-squares
 * fit to the samples around it, never across a delimiter (tanfit.c). */
#ifndef TC_CORE_TANFIT_H
#define TC_CORE_TANFIT_H

#include "core/wedge.h"

/* Per-mesh work space of the fits (marks by generation, so nothing is cleared
 * between wedges). */
typedef struct {
    int32_t *tmark, *vmark; /* [nt], [nv]: the generation that last visited */
    int32_t *vsample;       /* [nv]: a vertex's row in the current fit */
    int32_t gen;
} tc__fit_space;

int tc__fit_space_init(const struct tc_mesh *m, tc__fit_space *fs);
void tc__fit_space_free(tc__fit_space *fs);

/* g[nc][2]: the estimated plane of wedge w from the corner values cz. */
void tc__fit_wedge(const struct tc_mesh *m, const tc__wedge_set *ws, const tc__wedge *w, const double *cz,
                   tc__fit_space *fs, double *g);

#endif
