/* quads.c — quad meshes: each quad checked (indices, distinct corners, strict
 * convexity, repeats) and split along its diagonal a-c into two triangles. */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "core/alloc.h"
#include "core/geom.h"
#include "core/mesh_build.h"

void tc__elem_path(const struct tc_mesh *m, int32_t t, char *buf, size_t n) {
    if (m->nq) snprintf(buf, n, "quads[%d]", (int)(t / 2));
    else snprintf(buf, n, "triangles[%d]", (int)tc__given(m, t));
}

const char *tc__elem_word(const struct tc_mesh *m) { return m->nq ? "quad" : "triangle"; }

/* An error at "quads[q]". The path is formatted here, on failure only: the
 * checks run for every quad of a large mesh. */
static int quad_error(tc_diags *dg, int32_t q, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static int quad_error(tc_diags *dg, int32_t q, const char *fmt, ...) {
    char path[48], msg[sizeof dg->items->message];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    snprintf(path, sizeof path, "quads[%d]", (int)q);
    return tc_diags_add(dg, TC_SEV_ERROR, path, "%s", msg);
}

static int check_indices(const tc_mesh_desc *d, int32_t q, tc_diags *dg) {
    const int32_t *v = d->quads + 4 * (size_t)q;
    char path[48];
    for (int k = 0; k < 4; k++)
        if (v[k] < 0 || v[k] >= d->nverts) {
            snprintf(path, sizeof path, "quads[%d][%d]", (int)q, k);
            return tc_diags_add(dg, TC_SEV_ERROR, path, "vertex index %d out of range (%d vertices)", (int)v[k],
                                (int)d->nverts);
        }
    for (int i = 0; i < 4; i++)
        for (int j = i + 1; j < 4; j++)
            if (v[i] == v[j])
                return quad_error(dg, q, "degenerate quad: a vertex appears twice in [%d, %d, %d, %d]", (int)v[0],
                                    (int)v[1], (int)v[2], (int)v[3]);
    return TC_OK;
}

/* Strict convexity: the turn at every corner is non-zero relative to the two
 * edges that meet there (the zero-area test of a triangle on those edges), and
 * all four turn the same way. Four same-signed turns, each under 180 degrees,
 * add up to exactly one full turn, so the quad is also simple. Both split
 * triangles must pass the triangle test too (it is relative to other edges),
 * so the triangle machinery downstream never meets a degenerate one. */
static int check_shape(const tc_mesh_desc *d, int32_t q, tc_diags *dg) {
    const int32_t *v = d->quads + 4 * (size_t)q;
    const double *p[4];
    int npos = 0, sign[4];
    for (int k = 0; k < 4; k++) p[k] = d->xy + 2 * (size_t)v[k];
    for (int k = 0; k < 4; k++) {
        const double *prev = p[(k + 3) % 4], *next = p[(k + 1) % 4];
        double ein[2], eout[2];
        tc__sub(ein, p[k], prev);
        tc__sub(eout, next, p[k]);
        if (!tc__nonzero_area(p[k], next, prev))
            return quad_error(dg, q,
                                "degenerate quad: its edges at vertex %d (corner %d) are collinear or coincide", (int)v[k],
                                k);
        sign[k] = tc__cross(ein, eout) > 0;
        npos += sign[k];
    }
    if (npos == 2)
        return quad_error(dg, q,
                            "non-convex quad: its sides cross; give the corners [%d, %d, %d, %d] in order around it",
                            (int)v[0], (int)v[1], (int)v[2], (int)v[3]);
    for (int k = 0; k < 4 && npos != 0 && npos != 4; k++)
        if (sign[k] != (npos > 2))
            return quad_error(dg, q,
                                "non-convex quad: it turns the other way at vertex %d (corner %d)", (int)v[k], k);
    if (!tc__nonzero_area(p[0], p[1], p[2]) || !tc__nonzero_area(p[0], p[2], p[3]))
        return quad_error(dg, q,
                            "degenerate quad: a triangle of its split along the diagonal [%d, %d] has zero area",
                            (int)v[0], (int)v[2]);
    return TC_OK;
}

/* Quads with the same four vertices, whatever their order: sorted 4-tuples
 * with their index, sorted, then compared neighbour to neighbour. */
typedef struct {
    int32_t key[4];
    int32_t q;
} quad_key;

static int by_key(const void *pa, const void *pb) {
    const quad_key *a = pa, *b = pb;
    for (int k = 0; k < 4; k++)
        if (a->key[k] != b->key[k]) return a->key[k] < b->key[k] ? -1 : 1;
    return a->q < b->q ? -1 : a->q > b->q;
}

static void sort4(int32_t k[4]) {
    for (int i = 1; i < 4; i++)
        for (int j = i; j > 0 && k[j - 1] > k[j]; j--) {
            int32_t x = k[j];
            k[j] = k[j - 1], k[j - 1] = x;
        }
}

static int check_repeats(const tc_mesh_desc *d, tc_diags *dg) {
    quad_key *keys = tc__malloc((size_t)d->nquads, sizeof *keys);
    if (!keys) return TC_ENOMEM;
    for (int32_t q = 0; q < d->nquads; q++) {
        memcpy(keys[q].key, d->quads + 4 * (size_t)q, sizeof keys[q].key);
        sort4(keys[q].key);
        keys[q].q = q;
    }
    qsort(keys, (size_t)d->nquads, sizeof *keys, by_key);
    int rc = TC_OK;
    for (int32_t i = 1, first = 0; i < d->nquads; i++) {
        if (memcmp(keys[i].key, keys[i - 1].key, sizeof keys[i].key) != 0) {
            first = i;
            continue;
        }
        char path[48];
        snprintf(path, sizeof path, "quads[%d]", (int)keys[i].q);
        rc = tc_diags_add(dg, TC_SEV_ERROR, path, "repeats quads[%d] (same four vertices)", (int)keys[first].q);
    }
    tc__free(keys);
    return rc;
}

int tc__quads_split(struct tc_mesh *m, const tc_mesh_desc *d, tc_diags *dg) {
    int rc = TC_OK;
    for (int32_t q = 0; q < d->nquads; q++)
        if (check_indices(d, q, dg) != TC_OK || check_shape(d, q, dg) != TC_OK) rc = TC_EINVAL;
    if (rc == TC_OK) rc = check_repeats(d, dg);
    if (rc != TC_OK) return rc;
    m->quad = tc__malloc((size_t)m->nq * 4, sizeof *m->quad);
    m->tri = tc__malloc((size_t)m->nt * 3, sizeof *m->tri);
    if (!m->quad || !m->tri) return TC_ENOMEM;
    memcpy(m->quad, d->quads, (size_t)m->nq * 4 * sizeof *m->quad);
    for (int32_t q = 0; q < m->nq; q++) {
        const int32_t *v = m->quad + 4 * (size_t)q;
        int32_t *t = m->tri + 6 * (size_t)q;
        t[0] = v[0], t[1] = v[1], t[2] = v[2]; /* 2q   = (a, b, c) */
        t[3] = v[0], t[4] = v[2], t[5] = v[3]; /* 2q+1 = (a, c, d) */
    }
    return TC_OK;
}
