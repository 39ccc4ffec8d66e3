/* validate.c — the validation (tc_mesh_new) and build (tc_recon_new) of a reconstruction
 * timed apart, on meshes made here in memory, at n and 4n to show both grow linearly.
 *
 *     build/bench_validate [--threads N,M,...] [--reps R] [--quick | --big] [--only grid|flags|wheel]
 *
 * Meshes: gridN (a regular grid, 2N^2 triangles, exact gradients given, as meshes.py's
 * gridN.json), flagsN (the same grid with one C0 and one C-1 polyline snaking through
 * it, each thousands of segments long, crossing each other), wheelK (K triangles around
 * one vertex of valence K, 7 rings of quads around it: many vertices of high valence).
 * For each mesh and thread count: best of R runs of each phase, in ms, and the ratio
 * validate / build. The lines "scaling" give time(4n) / time(n) per phase: ~4 is linear,
 * ~16 quadratic. --quick: n 4x smaller; --big: n 4x larger (524k -> 2.1M triangles). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tocher.h"

typedef struct {
    char name[32];
    int32_t nv, nt;
    double *xy, *val, *grad;
    int32_t *tri;
    int32_t pl_start[2][2];  /* one polyline per set: start = {0, n} */
    int32_t *pl[2];          /* c0, c-1 vertex lists (NULL: none) */
    int32_t pl_n[2];
} bmesh;

static void data_at(const double *p, double *v, double *g) {
    double x = p[0], y = p[1], s = sin(3 * x + 1), c = cos(2 * y);
    *v = s * c + 0.5 * x * x;
    g[0] = 3 * cos(3 * x + 1) * c + x;
    g[1] = -2 * s * sin(2 * y);
}

static void fill_data(bmesh *b) {
    b->val = malloc((size_t)b->nv * sizeof *b->val);
    b->grad = malloc((size_t)b->nv * 2 * sizeof *b->grad);
    for (int32_t v = 0; v < b->nv; v++) data_at(b->xy + 2 * v, b->val + v, b->grad + 2 * v);
}

/* (n+1)^2 vertices i/n, j/n; each square split along its (i,j)-(i+1,j+1) diagonal. */
static void make_grid(bmesh *b, int n) {
    memset(b, 0, sizeof *b);
    snprintf(b->name, sizeof b->name, "grid%d", n);
    b->nv = (n + 1) * (n + 1);
    b->nt = 2 * n * n;
    b->xy = malloc((size_t)b->nv * 2 * sizeof *b->xy);
    b->tri = malloc((size_t)b->nt * 3 * sizeof *b->tri);
    for (int j = 0; j <= n; j++)
        for (int i = 0; i <= n; i++) {
            b->xy[2 * (j * (n + 1) + i)] = (double)i / n;
            b->xy[2 * (j * (n + 1) + i) + 1] = (double)j / n;
        }
    int32_t *t = b->tri;
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            int32_t a = j * (n + 1) + i, bb = a + 1, c = a + n + 2, d = a + n + 1;
            t[0] = a, t[1] = bb, t[2] = c, t[3] = a, t[4] = c, t[5] = d;
            t += 6;
        }
    fill_data(b);
}

/* The C0 polyline runs along the rows 4, 8, .. n-4 between columns 1 and n-1, turning
 * at columns 1 and n-1; the C-1 one along the columns 2, 6, .. between rows 1 and n-1,
 * turning at rows 1 and n-1. They cross at many vertices, never share an edge. */
static int32_t *serpentine(int n, int rows, int32_t *len) {
    int32_t *p = malloc((size_t)(n + 1) * (size_t)(n + 1) * sizeof *p), k = 0;
    int first = rows ? 4 : 2, lo = 1, hi = n - 1;
    for (int r = first, dir = 0; r + 4 <= n - 1 || (r <= n - 2 && r == first); r += 4, dir ^= 1) {
        for (int s = 0; s <= hi - lo; s++) {
            int along = dir ? hi - s : lo + s;
            int i = rows ? along : r, j = rows ? r : along;
            p[k++] = j * (n + 1) + i;
        }
        if (r + 8 > n - 1) break;
        for (int s = 1; s < 4; s++) { /* the turn: 3 more vertices, the 4th starts the next run */
            int end = dir ? lo : hi;
            int i = rows ? end : r + s, j = rows ? r + s : end;
            p[k++] = j * (n + 1) + i;
        }
    }
    *len = k;
    return p;
}

static void make_flags(bmesh *b, int n) {
    make_grid(b, n);
    snprintf(b->name, sizeof b->name, "flags%d", n);
    for (int s = 0; s < 2; s++) {
        b->pl[s] = serpentine(n, s == 0, &b->pl_n[s]);
        b->pl_start[s][0] = 0, b->pl_start[s][1] = b->pl_n[s];
    }
}

/* Vertex 0 at the centre, R rings of k vertices at radii 1..R; k fan triangles at the
 * centre, quads (split in 2) between rings. */
static void make_wheel(bmesh *b, int k) {
    enum { R = 8 };
    memset(b, 0, sizeof *b);
    snprintf(b->name, sizeof b->name, "wheel%d", k);
    b->nv = 1 + R * k;
    b->nt = k + 2 * k * (R - 1);
    b->xy = malloc((size_t)b->nv * 2 * sizeof *b->xy);
    b->tri = malloc((size_t)b->nt * 3 * sizeof *b->tri);
    b->xy[0] = b->xy[1] = 0;
    for (int r = 0; r < R; r++)
        for (int i = 0; i < k; i++) {
            double a = 6.283185307179586 * i / k;
            b->xy[2 * (1 + r * k + i)] = (r + 1) * cos(a) / R;
            b->xy[2 * (1 + r * k + i) + 1] = (r + 1) * sin(a) / R;
        }
    int32_t *t = b->tri;
    for (int i = 0; i < k; i++) t[0] = 0, t[1] = 1 + i, t[2] = 1 + (i + 1) % k, t += 3;
    for (int r = 0; r + 1 < R; r++)
        for (int i = 0; i < k; i++) {
            int32_t a = 1 + r * k + i, bb = 1 + r * k + (i + 1) % k, c = bb + k, d = a + k;
            t[0] = a, t[1] = bb, t[2] = c, t[3] = a, t[4] = c, t[5] = d;
            t += 6;
        }
    fill_data(b);
}

static void free_mesh(bmesh *b) {
    free(b->xy), free(b->val), free(b->grad), free(b->tri), free(b->pl[0]), free(b->pl[1]);
}

static void describe(const bmesh *b, tc_mesh_desc *d) {
    tc_mesh_desc_init(d);
    d->nverts = b->nv, d->xy = b->xy, d->ntris = b->nt, d->tris = b->tri;
    d->nchan = 1, d->values = b->val, d->gradients = b->grad;
    if (b->pl[0]) d->c0 = (tc_polylines){1, b->pl_start[0], b->pl[0]};
    if (b->pl[1]) d->cm1 = (tc_polylines){1, b->pl_start[1], b->pl[1]};
}

typedef struct {
    double validate, build;
} times;

/* Best of reps runs of tc_mesh_new and tc_recon_new with `threads`. */
static times measure(const bmesh *b, int threads, int reps) {
    tc_mesh_desc d;
    describe(b, &d);
    times best = {INFINITY, INFINITY};
    tc_options o;
    tc_options_default(&o);
    o.threads = threads;
    d.threads = threads;
    for (int r = 0; r < reps; r++) {
        tc_diags dg;
        tc_diags_init(&dg);
        tc_mesh *m = NULL;
        tc_recon *rc = NULL;
        double t0 = tc_now_ms();
        if (tc_mesh_new(&d, &m, &dg) != TC_OK) {
            fprintf(stderr, "%s: %s: %s\n", b->name, dg.count ? dg.items[0].path : "",
                    dg.count ? dg.items[0].message : "?");
            exit(1);
        }
        double t1 = tc_now_ms();
        if (tc_recon_new(m, &o, &rc, &dg) != TC_OK) {
            fprintf(stderr, "%s: build failed: %s\n", b->name, dg.count ? dg.items[0].message : "?");
            exit(1);
        }
        double t2 = tc_now_ms();
        if (t1 - t0 < best.validate) best.validate = t1 - t0;
        if (t2 - t1 < best.build) best.build = t2 - t1;
        tc_recon_free(rc);
        tc_mesh_free(m);
        tc_diags_free(&dg);
    }
    return best;
}

int main(int argc, char **argv) {
    int threads[16] = {1}, nthreads = 1, reps = 5, quick = 0;
    const char *only = NULL;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--threads") && i + 1 < argc) {
            nthreads = 0;
            for (char *s = argv[++i]; *s && nthreads < 16;) {
                threads[nthreads++] = (int)strtol(s, &s, 10);
                if (*s == ',') s++;
            }
        } else if (!strcmp(argv[i], "--reps") && i + 1 < argc) {
            reps = atoi(argv[++i]);
        } else if (!strcmp(argv[i], "--only") && i + 1 < argc) {
            only = argv[++i];
        } else if (!strcmp(argv[i], "--quick")) {
            quick = 1;
        } else if (!strcmp(argv[i], "--big")) {
            quick = -1;
        } else {
            fprintf(stderr, "usage: %s [--threads N,M,...] [--reps R] [--quick | --big] [--only grid|flags|wheel]\n", argv[0]);
            return 2;
        }
    }
    /* pairs (n, 4n): grid 256 / 512 (131k / 524k triangles), the flags at the same sizes,
     * wheels of 16k / 64k fan triangles */
    int sizes[3][2] = {{256, 512}, {256, 512}, {16384, 65536}};
    if (quick > 0) sizes[0][0] = sizes[1][0] = 64, sizes[0][1] = sizes[1][1] = 128, sizes[2][0] = 1024,
                   sizes[2][1] = 4096;
    if (quick < 0) sizes[0][0] = sizes[1][0] = 512, sizes[0][1] = sizes[1][1] = 1024, sizes[2][0] = 65536,
                   sizes[2][1] = 262144;
    printf("%-12s %9s %8s %12s %10s %10s\n", "mesh", "triangles", "threads", "validate_ms", "build_ms",
           "val/build");
    static const char *const kinds[3] = {"grid", "flags", "wheel"};
    for (int kind = 0; kind < 3; kind++) {
        if (only && strcmp(only, kinds[kind])) continue;
        times at[2][16];
        for (int s = 0; s < 2; s++) {
            bmesh b;
            int n = sizes[kind][s];
            if (kind == 0) make_grid(&b, n);
            else if (kind == 1) make_flags(&b, n);
            else make_wheel(&b, n);
            for (int ti = 0; ti < nthreads; ti++) {
                at[s][ti] = measure(&b, threads[ti], reps);
                printf("%-12s %9d %8d %12.2f %10.2f %10.2f", b.name, (int)b.nt, threads[ti], at[s][ti].validate,
                       at[s][ti].build, at[s][ti].validate / at[s][ti].build);
                if (kind == 1) printf("   (polylines: %d + %d segments)", (int)b.pl_n[0] - 1, (int)b.pl_n[1] - 1);
                if (ti > 0)
                    printf("   speed-up %.2f", (at[s][0].validate + at[s][0].build) /
                                                   (at[s][ti].validate + at[s][ti].build));
                printf("\n");
            }
            free_mesh(&b);
        }
        for (int ti = 0; ti < nthreads; ti++)
            printf("scaling %-4s threads %d: validate x%.2f, build x%.2f for x4 the size\n",
                   kinds[kind], threads[ti],
                   at[1][ti].validate / at[0][ti].validate, at[1][ti].build / at[0][ti].build);
    }
    return 0;
}
