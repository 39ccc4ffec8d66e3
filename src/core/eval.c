/* eval.c — evaluating a reconstruction: one triangle's piece at a point, or
 * many points located through a tc_locator (outside points: 0 and tri -1), in batches. */
#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/assert.h"
#include "core/ct.h"
#include "core/ct_points.h"
#include "core/eval.h"
#include "core/geom.h"
#include "core/locate.h"
#include "core/minmax.h"
#include "core/recon.h"

void tc_eval_triangle(const tc_recon *r, int32_t t, double x, double y, double *value, double *grad) {
    TC_ASSERT(r && t >= 0 && t < r->m->nt && value);
    tc__eval_point at;
    int nc = r->m->nc;
    tc__at(r->m, t, x, y, &at);
    const double *coef = r->coef + (size_t)t * (size_t)nc * (size_t)r->ncoef;
    for (int ch = 0; ch < nc; ch++) {
        r->eval(coef + (size_t)ch * (size_t)r->ncoef, &at, &value[ch], grad ? grad + 2 * ch : NULL);
        value[ch] = tc__floored(r, ch, value[ch]);
    }
}

/* Point i, at (x, y). */
static void eval_one(const tc_recon *r, const tc_locator *L, size_t i, double x, double y, double *values,
                     double *grads, int32_t *tri) {
    int nc = r->m->nc;
    double *v = values + i * (size_t)nc, *g = grads ? grads + 2 * i * (size_t)nc : NULL;
    int32_t t = tc__locate_tree(L, x, y);
    if (tri) tri[i] = t;
    if (t >= 0) {
        tc_eval_triangle(r, t, x, y, v, g);
    } else {
        memset(v, 0, (size_t)nc * sizeof *v);
        if (g) memset(g, 0, 2 * (size_t)nc * sizeof *g);
    }
}

/* Below this many points, or on meshes whose locator fits in cache, the
 * visiting order is not worth a sort (measured: on 512 triangles the sort
 * costs more than it saves; on 524k it makes evaluation 3.7x faster). */
#define SORT_MIN_POINTS 1024
static int32_t sort_min_triangles = 32768;

void tc__eval_sort_min_triangles(int32_t nt) {
    sort_min_triangles = nt;
}

/* A point in the visiting order: its Z-order key above its index, and its coordinates
 * carried along so the evaluation reads them in order. */
typedef struct {
    uint64_t key;
    double x, y;
} visit;

/* Spreads the low 16 bits of x to the even bits of the result. */
static uint32_t spread16(uint32_t x) {
    x &= 0xffff;
    x = (x | x << 8) & 0x00ff00ffu;
    x = (x | x << 4) & 0x0f0f0f0fu;
    x = (x | x << 2) & 0x33333333u;
    return (x | x << 1) & 0x55555555u;
}

/* The points in Z (Morton) order of their position, 16 bits per axis over
 * their bounding box: neighbours in the order are neighbours in the plane, so
 * the locator's tree and the coefficients stay in cache. Two stable 16-bit
 * radix passes over (key << 32 | index). NULL when out of memory. */
static visit *z_order(size_t n, const double *xy) {
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (size_t i = 0; i < n; i++)
        for (size_t k = 0; k < 2; k++)
            if (isfinite(xy[2 * i + k])) lo[k] = tc__fmin(lo[k], xy[2 * i + k]), hi[k] = tc__fmax(hi[k], xy[2 * i + k]);
    visit *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b);
    uint32_t *count = calloc(65536, sizeof *count);
    if (!a || !b || !count) {
        tc__free(a), tc__free(b), tc__free(count);
        return NULL;
    }
    double s[2];
    for (int k = 0; k < 2; k++) s[k] = hi[k] > lo[k] ? 65535 / (hi[k] - lo[k]) : 0;
    for (size_t i = 0; i < n; i++) {
        uint32_t q[2];
        for (size_t k = 0; k < 2; k++) {
            double u = (xy[2 * i + k] - lo[k]) * s[k];
            q[k] = u >= 0 && u <= 65535 ? (uint32_t)u : 0; /* NaN, Inf: anywhere */
        }
        a[i] = (visit){(uint64_t)(spread16(q[0]) | spread16(q[1]) << 1) << 32 | i, xy[2 * i], xy[2 * i + 1]};
    }
    for (int pass = 0; pass < 2; pass++) {
        int shift = 32 + 16 * pass;
        memset(count, 0, 65536 * sizeof *count);
        for (size_t i = 0; i < n; i++) count[a[i].key >> shift & 0xffff]++;
        uint32_t sum = 0;
        for (int d = 0; d < 65536; d++) {
            uint32_t c = count[d];
            count[d] = sum, sum += c;
        }
        for (size_t i = 0; i < n; i++) b[count[a[i].key >> shift & 0xffff]++] = a[i];
        visit *t = a;
        a = b, b = t;
    }
    tc__free(b), tc__free(count);
    return a;
}

/* The path this file had before the batch below: each point located by the
 * tree alone (tc__locate_tree) and evaluated with its own frame. Kept as the
 * reference the batch path must equal bit for bit (tests, bench/perf/points.c). */
void tc__eval_points_ref(const tc_recon *r, const tc_locator *L, size_t n, const double *xy, double *values,
                         double *grads, int32_t *tri) {
    TC_ASSERT(r && L && (n == 0 || (xy && values)));
    int sort = n >= SORT_MIN_POINTS && n <= UINT32_MAX && r->m->nt >= sort_min_triangles;
    visit *order = sort ? z_order(n, xy) : NULL;
    for (size_t i = 0; i < n; i++) {
        if (!order) {
            eval_one(r, L, i, xy[2 * i], xy[2 * i + 1], values, grads, tri);
            continue;
        }
        eval_one(r, L, (size_t)(order[i].key & 0xffffffffu), order[i].x, order[i].y, values, grads, tri);
    }
    tc__free(order);
}

/* ==== The batch path ==========================================================
 * Points go through in chunks: the chunk's points are located together
 * (tc__locate_many: the locator's grid), then evaluated. A triangle's frame
 * (tc__frame: seven divisions) is made once per run of points in the same
 * triangle, or once per call for every triangle when the batch has at least
 * as many points as the mesh has triangles. Every value is still tc__frame +
 * tc__frame_at + the method's piece at that point, the operations of
 * tc_eval_triangle, so the bits are the same whatever the order, the chunking
 * or the number of threads. */

#define CHUNK 256

/* The frames of one thread's share of a call: a table over every triangle,
 * made up front, when the share has at least as many points as the mesh has
 * triangles (and the mesh is not large); else one frame per run of consecutive points in the same
 * triangle, in a buffer per chunk. */
typedef struct {
    tc__eval_frame *table; /* [nt] or NULL */
    tc__eval_frame *buf;   /* [CHUNK] when there is no table */
} frames;

/* A table pays for itself from about one point per triangle; past this many
 * triangles its first touch (page faults) and cache misses cost more than
 * a frame per run of points in Z order. */
#define TABLE_MAX_TRIANGLES 32768

static int frames_init(frames *fr, const struct tc_mesh *m, size_t npoints) {
    memset(fr, 0, sizeof *fr);
    if (npoints >= (size_t)m->nt && m->nt <= TABLE_MAX_TRIANGLES) {
        fr->table = tc__malloc((size_t)m->nt, sizeof *fr->table);
        if (fr->table) {
            for (int32_t t = 0; t < m->nt; t++) tc__frame(m, t, &fr->table[t]);
            return 0;
        }
    }
    fr->buf = tc__malloc(CHUNK, sizeof *fr->buf);
    return fr->buf ? 0 : -1;
}

static void frames_free(frames *fr) {
    tc__free(fr->table), tc__free(fr->buf);
}

/* fp[j] = the frame of own[j] for each owned point j of a chunk. */
static void chunk_frames(frames *fr, const struct tc_mesh *m, size_t k, const int32_t *own,
                         const tc__eval_frame **fp) {
    const tc__eval_frame *prev = NULL;
    int32_t prev_t = -1;
    for (size_t j = 0; j < k; j++) {
        int32_t t = own[j];
        if (t < 0) continue;
        if (fr->table) {
            fp[j] = &fr->table[t];
            continue;
        }
        if (t != prev_t) tc__frame(m, t, &fr->buf[j]), prev = &fr->buf[j], prev_t = t;
        fp[j] = prev;
    }
}

/* Point i (its results' index) at (x, y), owned by t (>= 0) with frame f: any method. */
static void eval_owned(const tc_recon *r, const tc__eval_frame *f, int32_t t, size_t i, double x, double y,
                       double *values, double *grads) {
    int nc = r->m->nc;
    double *v = values + i * (size_t)nc, *g = grads ? grads + 2 * i * (size_t)nc : NULL;
    tc__eval_point at;
    tc__frame_at(f, x, y, &at);
    const double *coef = r->coef + (size_t)t * (size_t)nc * (size_t)r->ncoef;
    for (int ch = 0; ch < nc; ch++) {
        r->eval(coef + (size_t)ch * (size_t)r->ncoef, &at, &v[ch], g ? g + 2 * ch : NULL);
        v[ch] = tc__floored(r, ch, v[ch]);
    }
}

/* One thread's share: the points order[lo, hi) of the visiting order (NULL:
 * the points lo .. hi - 1 as given). */
typedef struct {
    const tc_recon *r;
    const tc_locator *L;
    const double *xy;
    const visit *order;
    size_t lo, hi;
    double *values, *grads;
    int32_t *tri;
} share;

/* The owned points of a chunk with the Clough-Tocher piece, four at a time
 * (the last group repeats its last point: the same results written twice). */
static void eval_ct_chunk(const share *sh, size_t k, const size_t *idx, const double *pxy, const int32_t *own,
                          const tc__eval_frame *const *fp) {
    const tc_recon *r = sh->r;
    int nc = r->m->nc;
    tc__ct_lane lane[4];
    int n = 0;
    enum { AHEAD = 8 }; /* points between asking for a triangle's data and using it */
    size_t per = (size_t)nc * TC_CT_ORDINATES * sizeof(double);
    for (size_t j = 0; j < k; j++) {
        if (j + AHEAD < k && own[j + AHEAD] >= 0) {
            const char *cf = (const char *)(r->coef + (size_t)own[j + AHEAD] * (size_t)nc * TC_CT_ORDINATES);
            const char *fa = (const char *)fp[j + AHEAD];
            for (size_t b = 0; b < per; b += 64) __builtin_prefetch(cf + b);
            for (size_t b = 0; b < sizeof **fp; b += 64) __builtin_prefetch(fa + b);
        }
        if (own[j] < 0) continue;
        size_t i = idx[j];
        lane[n++] = (tc__ct_lane){fp[j], r->coef + (size_t)own[j] * (size_t)nc * TC_CT_ORDINATES, pxy[2 * j],
                                  pxy[2 * j + 1], sh->values + i * (size_t)nc,
                                  sh->grads ? sh->grads + 2 * i * (size_t)nc : NULL};
        if (n == 4) tc__ct_points4(lane, nc, r->floor0), n = 0;
    }
    if (n == 0) return;
    for (int l = n; l < 4; l++) lane[l] = lane[n - 1];
    tc__ct_points4(lane, nc, r->floor0);
}

static void eval_share(const share *sh) {
    const tc_recon *r = sh->r;
    int nc = r->m->nc, ct = tc__recon_is_ct(r);
    frames fr;
    int no_frames = frames_init(&fr, r->m, sh->hi - sh->lo);
    double pxy[2 * CHUNK];
    size_t idx[CHUNK];
    int32_t own[CHUNK];
    const tc__eval_frame *fp[CHUNK];
    for (size_t c = sh->lo; c < sh->hi; c += CHUNK) {
        size_t k = sh->hi - c < CHUNK ? sh->hi - c : CHUNK;
        const double *cxy = sh->xy + 2 * c; /* the chunk's points, and their indices */
        for (size_t j = 0; j < k; j++) idx[j] = c + j;
        if (sh->order) {
            for (size_t j = 0; j < k; j++) {
                const visit *p = &sh->order[c + j];
                idx[j] = (size_t)(p->key & 0xffffffffu), pxy[2 * j] = p->x, pxy[2 * j + 1] = p->y;
            }
            cxy = pxy;
        }
        tc__locate_many(sh->L, k, cxy, own);
        for (size_t j = 0; j < k; j++) {
            size_t i = idx[j];
            if (sh->tri) sh->tri[i] = own[j];
            if (own[j] >= 0) continue;
            memset(sh->values + i * (size_t)nc, 0, (size_t)nc * sizeof *sh->values);
            if (sh->grads) memset(sh->grads + 2 * i * (size_t)nc, 0, 2 * (size_t)nc * sizeof *sh->grads);
        }
        if (no_frames) { /* out of memory for even a chunk's frames: each point its own */
            for (size_t j = 0; j < k; j++)
                if (own[j] >= 0) tc_eval_triangle(r, own[j], cxy[2 * j], cxy[2 * j + 1], sh->values + idx[j] * (size_t)nc,
                                                  sh->grads ? sh->grads + 2 * idx[j] * (size_t)nc : NULL);
            continue;
        }
        chunk_frames(&fr, r->m, k, own, fp);
        if (ct) {
            eval_ct_chunk(sh, k, idx, cxy, own, fp);
            continue;
        }
        for (size_t j = 0; j < k; j++)
            if (own[j] >= 0) eval_owned(r, fp[j], own[j], idx[j], cxy[2 * j], cxy[2 * j + 1], sh->values, sh->grads);
    }
    frames_free(&fr);
}

static void *share_main(void *arg) {
    eval_share(arg);
    return NULL;
}

/* Below this many points per thread a thread costs more than it saves. */
#define POINTS_PER_THREAD 4096
#define MAX_THREADS 64

void tc_eval_points_mt(const tc_recon *r, const tc_locator *L, size_t n, const double *xy, double *values,
                       double *grads, int32_t *tri, int threads) {
    TC_ASSERT(r && L && (n == 0 || (xy && values)));
    tc__locator_note(L, n);
    int sort = n >= SORT_MIN_POINTS && n <= UINT32_MAX && r->m->nt >= sort_min_triangles;
    visit *order = sort ? z_order(n, xy) : NULL;
    size_t most = n / POINTS_PER_THREAD;
    int nth = threads < 1 ? 1 : threads > MAX_THREADS ? MAX_THREADS : threads;
    if ((size_t)nth > most) nth = most > 1 ? (int)most : 1;
    share sh[MAX_THREADS];
    pthread_t tid[MAX_THREADS];
    int started = 0;
    for (int k = 0; k < nth; k++) /* contiguous parts of the visiting order */
        sh[k] = (share){r, L, xy, order, n * (size_t)k / (size_t)nth, n * (size_t)(k + 1) / (size_t)nth,
                        values, grads, tri};
    for (int k = 1; k < nth; k++, started++)
        if (pthread_create(&tid[k], NULL, share_main, &sh[k]) != 0) break;
    eval_share(&sh[0]);
    for (int k = 1; k <= started; k++) pthread_join(tid[k], NULL);
    for (int k = started + 1; k < nth; k++) eval_share(&sh[k]); /* threads that did not start */
    tc__free(order);
}

void tc_eval_points(const tc_recon *r, const tc_locator *L, size_t n, const double *xy, double *values,
                    double *grads, int32_t *tri) {
    tc_eval_points_mt(r, L, n, xy, values, grads, tri, 1);
}
