/* formfactor.c — point-to-polygon form factors and the polygon operations that
 * turn an occluder into the part of a light it hides (projection, hull, clipping). */
#include "scenes/formfactor.h"

#include <math.h>
#include <stdlib.h>

static const double PI = 3.14159265358979323846;

double tc__form_factor(const tc__poly *p, double height, double x, double y) {
    double sum = 0;
    for (int i = 0; i < p->n; i++) {
        const double *a = p->v[i], *b = p->v[(i + 1) % p->n];
        double r0[3] = {a[0] - x, a[1] - y, height}, r1[3] = {b[0] - x, b[1] - y, height};
        double c[3] = {r0[1] * r1[2] - r0[2] * r1[1], r0[2] * r1[0] - r0[0] * r1[2], r0[0] * r1[1] - r0[1] * r1[0]};
        double cn = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        if (cn == 0) continue; /* a repeated vertex: no edge */
        /* atan2 of |cross| and dot is accurate for any angle, small ones included */
        double angle = atan2(cn, r0[0] * r1[0] + r0[1] * r1[1] + r0[2] * r1[2]);
        sum += angle * (c[2] / cn);
    }
    return fabs(sum) / (2 * PI);
}

void tc__project(double x, double y, const double q[3], double height, double out[2]) {
    double k = height / q[2];
    out[0] = x + (q[0] - x) * k;
    out[1] = y + (q[1] - y) * k;
}

static double dist2(const double a[2], const double b[2]) {
    double dx = a[0] - b[0], dy = a[1] - b[1];
    return dx * dx + dy * dy;
}

static double cross_at(const double o[2], const double a[2], const double b[2]) {
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

double tc__orient(const double a[2], const double b[2], const double c[2]) {
    double la = dist2(b, c), lb = dist2(a, c), lc = dist2(a, b);
    /* The three expressions are equal in exact arithmetic (cyclic shifts). */
    if (la >= lb && la >= lc) return cross_at(a, b, c);
    if (lb >= lc) return cross_at(b, c, a);
    return cross_at(c, a, b);
}

static int by_x_then_y(const void *pa, const void *pb) {
    const double *a = pa, *b = pb;
    if (a[0] != b[0]) return a[0] < b[0] ? -1 : 1;
    if (a[1] != b[1]) return a[1] < b[1] ? -1 : 1;
    return 0;
}

/* One chain of the monotone-chain hull over the sorted points (step +1: lower,
 * -1: upper); appends to out, leaving the chain's last point off (it starts the other). */
static void hull_chain(double (*s)[2], int n, int step, tc__poly *out) {
    int start = out->n;
    for (int k = 0; k < n; k++) {
        const double *p = s[step > 0 ? k : n - 1 - k];
        while (out->n - start >= 2 && tc__orient(out->v[out->n - 2], out->v[out->n - 1], p) <= 0) out->n--;
        out->v[out->n][0] = p[0];
        out->v[out->n][1] = p[1];
        out->n++;
    }
    out->n--;
}

void tc__hull(const double (*pts)[2], int n, tc__poly *out) {
    double s[TC__POLY_MAX][2];
    out->n = 0;
    if (n <= 0 || n > TC__POLY_MAX) return;
    for (int i = 0; i < n; i++) s[i][0] = pts[i][0], s[i][1] = pts[i][1];
    qsort(s, (size_t)n, sizeof s[0], by_x_then_y);
    if (n < 3) return;
    hull_chain(s, n, +1, out);
    hull_chain(s, n, -1, out);
    if (out->n < 3) out->n = 0;
}

static void push(tc__poly *p, double x, double y) {
    if (p->n == TC__POLY_MAX) return; /* cannot happen: convex clipping adds one vertex per edge */
    p->v[p->n][0] = x;
    p->v[p->n][1] = y;
    p->n++;
}

/* The subject clipped by the half-plane left of a -> b. */
static void clip_half(const tc__poly *in, const double a[2], const double b[2], tc__poly *out) {
    out->n = 0;
    for (int i = 0; i < in->n; i++) {
        const double *s = in->v[i], *t = in->v[(i + 1) % in->n];
        double ds = tc__orient(a, b, s), dt = tc__orient(a, b, t);
        if (ds >= 0) push(out, s[0], s[1]);
        if ((ds > 0 && dt < 0) || (ds < 0 && dt > 0)) {
            double u = ds / (ds - dt); /* in (0, 1): s and t are near the light */
            push(out, s[0] + u * (t[0] - s[0]), s[1] + u * (t[1] - s[1]));
        }
    }
}

void tc__clip(const tc__poly *subject, const tc__poly *clip, tc__poly *out) {
    tc__poly tmp;
    *out = *subject;
    for (int e = 0; e < clip->n && out->n > 0; e++) {
        clip_half(out, clip->v[e], clip->v[(e + 1) % clip->n], &tmp);
        *out = tmp;
    }
    if (out->n < 3) out->n = 0;
}

int tc__inside(const tc__poly *p, double x, double y) {
    double q[2] = {x, y};
    if (p->n < 3) return 0;
    for (int e = 0; e < p->n; e++)
        if (tc__orient(p->v[e], p->v[(e + 1) % p->n], q) < 0) return 0;
    return 1;
}
