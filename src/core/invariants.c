/* invariants.c — checkers for what mesh.h and wedge.h state of a built mesh and
 * wedge set: the builders TC_ASSERT them with TC_DEBUG (make check); tests call them. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/alloc.h"
#include "core/geom.h"
#include "core/mesh.h"
#include "core/wedge.h"

/* Writes the broken invariant to why[n] (if any) and returns 1. */
__attribute__((format(printf, 3, 4))) static int broken(char *why, size_t n, const char *fmt, ...) {
    if (why && n) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(why, n, fmt, ap);
        va_end(ap);
    }
    return 1;
}

static int all_finite(const double *x, size_t n) {
    for (size_t i = 0; x && i < n; i++)
        if (!isfinite(x[i])) return 0;
    return 1;
}

static int is_flag(int f) { return f == TC_C1 || f == TC_C0 || f == TC_CM1; }

/* ---- the mesh (mesh.h) ---- */

/* Sizes, the given <-> kept maps and the split quads. */
static int check_elements(const struct tc_mesh *m, char *why, size_t n) {
    if (m->nv < 1 || m->nt < 1 || m->nc < 1 || m->nc > TC_MAX_CHANNELS)
        return broken(why, n, "sizes: nv %d, nt %d, nc %d", (int)m->nv, (int)m->nt, m->nc);
    if (m->ngiven < m->nt) return broken(why, n, "ngiven %d < nt %d", (int)m->ngiven, (int)m->nt);
    if ((m->ngiven == m->nt) != (m->given == NULL) || (m->given == NULL) != (m->kept == NULL))
        return broken(why, n, "given/kept must be NULL exactly when ngiven == nt");
    int32_t nkept = 0;
    for (int32_t i = 0; m->kept && i < m->ngiven; i++) {
        int32_t t = m->kept[i];
        if (t < -1 || t >= m->nt || (t >= 0 && m->given[t] != i))
            return broken(why, n, "kept[%d] = %d is not the triangle whose given index it is", (int)i, (int)t);
        nkept += t >= 0;
    }
    for (int32_t t = 0; m->given && t < m->nt; t++)
        if (m->given[t] < 0 || m->given[t] >= m->ngiven || (t > 0 && m->given[t] <= m->given[t - 1]))
            return broken(why, n, "given[%d] = %d out of range or out of order", (int)t, (int)m->given[t]);
    if (m->kept && nkept != m->nt) return broken(why, n, "kept[] names %d triangles, nt is %d", (int)nkept, (int)m->nt);
    if (m->nq < 0 || (m->nq > 0 && (m->nt != 2 * m->nq || m->ngiven != m->nt || !m->quad)))
        return broken(why, n, "quads: nq %d, nt %d, ngiven %d", (int)m->nq, (int)m->nt, (int)m->ngiven);
    for (int32_t q = 0; q < m->nq; q++) {
        const int32_t *v = m->quad + 4 * (size_t)q, *t0 = m->tri + 6 * (size_t)q, *t1 = t0 + 3;
        if (t0[0] != v[0] || t0[1] != v[1] || t0[2] != v[2] || t1[0] != v[0] || t1[1] != v[2] || t1[2] != v[3])
            return broken(why, n, "quad %d is not split as (a, b, c), (a, c, d)", (int)q);
    }
    return 0;
}

/* Vertex indices, distinct vertices, non-zero area, orientation. */
static int check_triangles(const struct tc_mesh *m, char *why, size_t n) {
    for (int32_t t = 0; t < m->nt; t++) {
        const int32_t *v = m->tri + 3 * (size_t)t;
        for (int k = 0; k < 3; k++)
            if (v[k] < 0 || v[k] >= m->nv) return broken(why, n, "triangle %d: vertex %d out of range", (int)t, (int)v[k]);
        if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2])
            return broken(why, n, "triangle %d repeats a vertex", (int)t);
        const double *p0 = tc__vxy(m, v[0]), *p1 = tc__vxy(m, v[1]), *p2 = tc__vxy(m, v[2]);
        if (!tc__nonzero_area(p0, p1, p2)) return broken(why, n, "triangle %d has zero area", (int)t);
        double e1[2], e2[2];
        tc__sub(e1, p1, p0);
        tc__sub(e2, p2, p0);
        if (m->orient[t] != (tc__cross(e1, e2) > 0 ? 1 : -1))
            return broken(why, n, "triangle %d: orient %d is not its orientation", (int)t, (int)m->orient[t]);
    }
    return 0;
}

/* The vertex -> corner lists: a CSR of every corner once, at its own vertex,
 * in increasing order; max_valence the longest list. */
static int check_vertex_corners(const struct tc_mesh *m, char *why, size_t n) {
    int32_t maxval = 0;
    if (m->vstart[0] != 0 || m->vstart[m->nv] != 3 * m->nt)
        return broken(why, n, "vstart spans %d..%d, not the %d corners", (int)m->vstart[0], (int)m->vstart[m->nv],
                      (int)(3 * m->nt));
    for (int32_t v = 0; v < m->nv; v++) {
        if (m->vstart[v + 1] < m->vstart[v]) return broken(why, n, "vstart decreases at vertex %d", (int)v);
        if (m->vstart[v + 1] - m->vstart[v] > maxval) maxval = m->vstart[v + 1] - m->vstart[v];
        for (int32_t i = m->vstart[v]; i < m->vstart[v + 1]; i++) {
            int32_t c = m->vcorner[i];
            if (c < 0 || c >= 3 * m->nt || m->tri[c] != v || (i > m->vstart[v] && c <= m->vcorner[i - 1]))
                return broken(why, n, "vcorner[%d] = %d is not the next corner of vertex %d", (int)i, (int)c, (int)v);
        }
    }
    if (m->max_valence != maxval)
        return broken(why, n, "max_valence is %d, the longest corner list %d", (int)m->max_valence, (int)maxval);
    return 0;
}

/* nbr/nbr_k mutual, on the same two vertices, with another third vertex; flags
 * known, TC_CM1 on the boundary, equal on both sides, quad diagonals interior
 * C1; nflagged the interior edges flagged; corner values equal across C0/C1. */
static int check_edges(const struct tc_mesh *m, char *why, size_t n) {
    int32_t nflagged = 0;
    for (int32_t e = 0; e < 3 * m->nt; e++) {
        int32_t t = e / 3, k = e % 3, u = m->nbr[e];
        int f = m->flag[e];
        if (!is_flag(f)) return broken(why, n, "edge %d: flag %d is no tc_continuity", (int)e, f);
        if (tc__is_diagonal(m, e) && (u < 0 || f != TC_C1))
            return broken(why, n, "edge %d: a quad's diagonal must be interior and C1", (int)e);
        if (u < 0) {
            if (u != -1 || f != TC_CM1) return broken(why, n, "boundary edge %d: nbr %d, flag %d", (int)e, (int)u, f);
            continue;
        }
        int j = m->nbr_k[e];
        if (u >= m->nt || u == t || j < 0 || j > 2)
            return broken(why, n, "edge %d: neighbour (%d, %d) out of range", (int)e, (int)u, j);
        int32_t back = 3 * u + j;
        if (m->nbr[back] != t || m->nbr_k[back] != k)
            return broken(why, n, "neighbours not mutual: edge (%d, %d) -> (%d, %d) -> (%d, %d)", (int)t, (int)k, (int)u,
                          j, (int)m->nbr[back], (int)m->nbr_k[back]);
        int32_t a = m->tri[e], b = m->tri[3 * t + (k + 1) % 3], a2 = m->tri[back], b2 = m->tri[3 * u + (j + 1) % 3];
        if (!((a == a2 && b == b2) || (a == b2 && b == a2)))
            return broken(why, n, "edge (%d, %d) [%d, %d] and its neighbour (%d, %d) [%d, %d] differ", (int)t, (int)k,
                          (int)a, (int)b, (int)u, j, (int)a2, (int)b2);
        if (m->tri[3 * t + (k + 2) % 3] == m->tri[3 * u + (j + 2) % 3])
            return broken(why, n, "triangles %d and %d repeat each other", (int)t, (int)u);
        /* Opposite sides of the edge as their orientations have them (topology.c side_of_third):
         * running it the same way, opposite orientations; the other way round, the same. */
        if ((m->orient[t] == m->orient[u]) == (a == a2))
            return broken(why, n, "triangles %d and %d lie on one side of their shared edge [%d, %d] as their "
                          "orientations have them", (int)t, (int)u, (int)a, (int)b);
        if (m->flag[back] != f)
            return broken(why, n, "flags not symmetric: edge (%d, %d) %d, (%d, %d) %d", (int)t, (int)k, f, (int)u, j,
                          (int)m->flag[back]);
        if (back > e && f != TC_C1) nflagged++;
        if (f == TC_CM1) continue;
        for (int end = 0; end < 2; end++) {
            int32_t v = end ? b : a, ca = 3 * t + tc__corner_of(m, t, v), cb = 3 * u + tc__corner_of(m, u, v);
            size_t nc = (size_t)m->nc, za = (size_t)ca * nc, zb = (size_t)cb * nc;
            for (size_t ch = 0; ch < nc; ch++)
                if (m->cz[za + ch] != m->cz[zb + ch])
                    return broken(why, n, "corner values differ across the %s edge (%d, %d) at vertex %d",
                                  f == TC_C0 ? "C0" : "C1", (int)t, (int)k, (int)v);
        }
    }
    if (nflagged != m->nflagged)
        return broken(why, n, "nflagged %d, but %d interior edges are flagged", (int)m->nflagged, (int)nflagged);
    return 0;
}

/* Every edge has at most two triangles, and exactly the edges with two are
 * linked: per vertex a, cnt[b] counts its triangles with edge [a, b]. */
static int check_manifold(const struct tc_mesh *m, int32_t *cnt, char *why, size_t n) {
    for (int32_t a = 0; a < m->nv; a++) {
        int bad = 0;
        for (int pass = 0; pass < 3; pass++)
            for (int32_t i = m->vstart[a]; i < m->vstart[a + 1]; i++) {
                int32_t c = m->vcorner[i], t = c / 3, k = c % 3;
                int32_t ends[2] = {m->tri[3 * t + (k + 1) % 3], m->tri[3 * t + (k + 2) % 3]};
                int32_t edges[2] = {c, 3 * t + (k + 2) % 3}; /* edge k joins a to ends[0], edge k+2 ends[1] to a */
                for (int s = 0; s < 2; s++) {
                    int32_t b = ends[s];
                    if (pass == 0) cnt[b]++;
                    else if (pass == 2) cnt[b] = 0;
                    else if (!bad && (cnt[b] > 2 || (cnt[b] == 2) != (m->nbr[edges[s]] >= 0)))
                        bad = broken(why, n, "edge [%d, %d] has %d triangles, nbr %d", (int)a, (int)b, (int)cnt[b],
                                     (int)m->nbr[edges[s]]);
                }
            }
        if (bad) return 1; /* after pass 2: cnt[] is all 0 again */
    }
    return 0;
}

/* The channel range tc_mesh_new kept: that of the corner values (a scan here). */
static int check_kept_range(const struct tc_mesh *m, char *why, size_t n) {
    if (!m->cz_range_kept) return broken(why, n, "the channel range of the corner values was not kept");
    for (int ch = 0; ch < m->nc; ch++) {
        double lo = INFINITY, hi = -INFINITY, big = 0;
        for (size_t c = 0; c < 3 * (size_t)m->nt; c++) {
            double z = m->cz[tc__ix((long)c, m->nc, ch)];
            lo = z < lo ? z : lo, hi = z > hi ? z : hi, big = fabs(z) > big ? fabs(z) : big;
        }
        if (lo != m->cz_lo[ch] || hi != m->cz_hi[ch] || big != m->cz_big[ch])
            return broken(why, n, "the kept range of channel %d is [%g, %g] (|.| %g), the values' [%g, %g] (|.| %g)",
                          ch, m->cz_lo[ch], m->cz_hi[ch], m->cz_big[ch], lo, hi, big);
    }
    return 0;
}

int tc__mesh_check(const struct tc_mesh *m, char *why, size_t n) {
    if (why && n) why[0] = '\0';
    if (!m) return broken(why, n, "no mesh");
    if (!m->xy || !m->tri || !m->orient || !m->cz || !m->nbr || !m->nbr_k || !m->flag || !m->vstart || !m->vcorner)
        return broken(why, n, "an array of the mesh is NULL");
    if (check_elements(m, why, n) || check_triangles(m, why, n) || check_vertex_corners(m, why, n) ||
        check_edges(m, why, n))
        return 1;
    size_t nc = 3 * (size_t)m->nt * (size_t)m->nc;
    if (!all_finite(m->xy, 2 * (size_t)m->nv) || !all_finite(m->cz, nc) || !all_finite(m->given_grad, 2 * nc) ||
        !all_finite(m->mid, nc) || !all_finite(m->hess, 3 * (size_t)m->nv * (size_t)m->nc))
        return broken(why, n, "a number of the mesh is not finite");
    int32_t *cnt = tc__calloc((size_t)m->nv, sizeof *cnt);
    int rc = cnt ? check_manifold(m, cnt, why, n) : 0; /* out of memory: that part unchecked */
    tc__free(cnt);
    return rc ? rc : check_kept_range(m, why, n);
}

/* ---- the wedges (wedge.h) ---- */

/* The edge of triangle t at its corner c (vertex v) crossed turning clockwise
 * (cw = 1) or counter-clockwise around v. */
static int32_t exit_edge(const struct tc_mesh *m, int32_t c, int cw) {
    int32_t t = c / 3, k = c % 3;
    int leaves_v = (m->orient[t] > 0) == (cw != 0); /* edge k goes from v to the next corner */
    return leaves_v ? c : 3 * t + (k + 2) % 3;
}

static int delimits(const struct tc_mesh *m, const tc__wedge_set *ws, int32_t v, int32_t e) {
    return ws->vclass[v] != TC_C1 && tc__eff_flag(m, ws->honor_flags, e) != TC_C1;
}

/* Wedge i: its corners at its vertex, one fan in counter-clockwise order
 * across edges that do not delimit it; a full turn at C1 vertices only, holding
 * all the vertex's corners; else sides on delimiters at the fan's ends. */
static int check_fan(const struct tc_mesh *m, const tc__wedge_set *ws, int32_t i, char *why, size_t n) {
    const tc__wedge *w = &ws->w[i];
    int32_t v = w->v, first = ws->corners[w->first], last = ws->corners[w->first + w->count - 1];
    int full = w->side_edge[0] < 0;
    if ((w->side_edge[1] < 0) != full) return broken(why, n, "wedge %d has one side", (int)i);
    if ((ws->vclass[v] == TC_C1) != full)
        return broken(why, n, "wedge %d: a full turn exactly at C1 vertices (vertex %d is %d)", (int)i, (int)v,
                      (int)ws->vclass[v]);
    if (full && w->count != m->vstart[v + 1] - m->vstart[v])
        return broken(why, n, "wedge %d: a full turn without all the corners of vertex %d", (int)i, (int)v);
    for (int32_t j = 0; j < w->count; j++) {
        int32_t c = ws->corners[w->first + j];
        if (j + 1 == w->count && !full) break;
        int32_t next = j + 1 < w->count ? ws->corners[w->first + j + 1] : first, e = exit_edge(m, c, 0);
        if (m->nbr[e] != next / 3 || delimits(m, ws, v, e))
            return broken(why, n, "wedge %d: corners %d and %d are not counter-clockwise neighbours across an edge that "
                          "does not delimit it", (int)i, (int)c, (int)next);
    }
    if (full) return 0;
    int32_t side[2] = {exit_edge(m, first, 1), exit_edge(m, last, 0)};
    for (int s = 0; s < 2; s++) {
        if (w->side_edge[s] != side[s] || !delimits(m, ws, v, side[s]))
            return broken(why, n, "wedge %d: side %c is edge %d, not the delimiter %d ending its fan", (int)i, "AB"[s],
                          (int)w->side_edge[s], (int)side[s]);
        int c0 = tc__eff_flag(m, ws->honor_flags, side[s]) == TC_C0;
        if (w->side_kind[s] != (c0 ? TC_C0 : TC_CM1))
            return broken(why, n, "wedge %d: side %c of kind %d on an edge of flag %d", (int)i, "AB"[s],
                          (int)w->side_kind[s], tc__eff_flag(m, ws->honor_flags, side[s]));
    }
    return 0;
}

/* Sides: across another wedge of the vertex exactly on C0 sides, whose own
 * side there is across back. */
static int check_across(const tc__wedge_set *ws, int32_t i, char *why, size_t n) {
    const tc__wedge *w = &ws->w[i];
    for (int s = 0; s < 2; s++) {
        int32_t o = w->across[s];
        if ((o >= 0) != (w->side_kind[s] == TC_C0 && w->side_edge[s] >= 0) || o < -1 || o >= ws->nw || o == i)
            return broken(why, n, "wedge %d: side %c of kind %d is across wedge %d", (int)i, "AB"[s],
                          (int)w->side_kind[s], (int)o);
        if (o >= 0 && (ws->w[o].v != w->v || (ws->w[o].across[0] != i && ws->w[o].across[1] != i)))
            return broken(why, n, "wedge %d: wedge %d across its side %c is not across back", (int)i, (int)o, "AB"[s]);
    }
    return 0;
}

int tc__wedges_check(const struct tc_mesh *m, const tc__wedge_set *ws, char *why, size_t n) {
    if (why && n) why[0] = '\0';
    int32_t ncorner = 3 * m->nt, at = 0, ncoupled = 0;
    if (!ws->w || !ws->corners || !ws->of_corner || !ws->vclass) return broken(why, n, "an array of the set is NULL");
    if (ws->nw < 0 || ws->nw > ncorner) return broken(why, n, "%d wedges for %d corners", (int)ws->nw, (int)ncorner);
    if (ws->honor_flags != TC_HONOR_NONE && ws->honor_flags != TC_HONOR_ALL && ws->honor_flags != TC_HONOR_CM1)
        return broken(why, n, "honor_flags %d", ws->honor_flags);
    for (int32_t v = 0; v < m->nv; v++)
        if (!is_flag(ws->vclass[v])) return broken(why, n, "vertex %d: class %d", (int)v, (int)ws->vclass[v]);
    for (int32_t i = 0; i < ws->nw; i++) { /* wedges tile corners[] in order; each corner's wedge is of_corner */
        const tc__wedge *w = &ws->w[i];
        if (w->first != at || w->count < 1 || w->count > ncorner - at || w->v < 0 || w->v >= m->nv)
            return broken(why, n, "wedge %d: corners [%d, +%d) at vertex %d do not follow the previous wedge's (%d)",
                          (int)i, (int)w->first, (int)w->count, (int)w->v, (int)at);
        for (int32_t j = w->first; j < w->first + w->count; j++) {
            int32_t c = ws->corners[j];
            if (c < 0 || c >= ncorner || ws->of_corner[c] != i || m->tri[c] != w->v)
                return broken(why, n, "wedge %d holds corner %d, of vertex %d, whose of_corner is %d", (int)i, (int)c,
                              c >= 0 && c < ncorner ? (int)m->tri[c] : -1,
                              c >= 0 && c < ncorner ? (int)ws->of_corner[c] : -1);
        }
        at += w->count;
    }
    if (at != ncorner) return broken(why, n, "the wedges hold %d of the %d corners", (int)at, (int)ncorner);
    /* No corner listed twice: with ncorner positions, every corner once. */
    uint8_t *seen = tc__calloc((size_t)ncorner, sizeof *seen);
    for (int32_t j = 0; seen && j < ncorner; j++) {
        if (seen[ws->corners[j]]++) {
            int32_t c = ws->corners[j];
            tc__free(seen);
            return broken(why, n, "corner %d is in two wedges' lists", (int)c);
        }
    }
    tc__free(seen);
    for (int32_t i = 0; i < ws->nw; i++) {
        if (check_fan(m, ws, i, why, n) || check_across(ws, i, why, n)) return 1;
        ncoupled += ws->w[i].across[0] >= 0 || ws->w[i].across[1] >= 0;
    }
    if (ncoupled != ws->ncoupled)
        return broken(why, n, "ncoupled %d, but %d wedges have a C0 side", (int)ws->ncoupled, (int)ncoupled);
    return 0;
}
