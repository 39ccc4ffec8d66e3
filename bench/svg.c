/* svg.c — a small SVG plotting module: linear or log axes (decade ticks and
 * labels), polylines with dashes and markers, vertical guide lines, a legend. */
#include "svg.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/strbuf.h"
#include "util.h"

/* Layout in SVG units (pixels). */
#define W_TOTAL 920.0
#define H_TOTAL 540.0
#define LEFT 84.0
#define RIGHT 300.0 /* legend column */
#define TOP 44.0
#define BOTTOM 62.0
#define MAX_SERIES 32
#define PI 3.14159265358979323846
#define MAX_VLINES 32

typedef struct {
    char label[96], color[16], dash[16];
    bench_marker marker;
    double width;
    int n;
    double *x, *y;
} series;

typedef struct {
    double x;
    char label[32];
} vline;

typedef struct {
    int log;
    int fixed;
    double lo, hi; /* data units */
} axis;

struct svg_plot {
    char title[160], xlabel[96], ylabel[96], note[400];
    axis ax, ay;
    series s[MAX_SERIES];
    int ns;
    vline v[MAX_VLINES];
    int nv;
};

static void copy(char *dst, size_t n, const char *src) { snprintf(dst, n, "%s", src ? src : ""); }

svg_plot *svg_plot_new(const char *title, const char *xlabel, const char *ylabel, int xlog, int ylog) {
    svg_plot *p = calloc(1, sizeof *p);
    if (!p) return NULL;
    copy(p->title, sizeof p->title, title);
    copy(p->xlabel, sizeof p->xlabel, xlabel);
    copy(p->ylabel, sizeof p->ylabel, ylabel);
    p->ax.log = xlog, p->ay.log = ylog;
    return p;
}

void svg_plot_free(svg_plot *p) {
    if (!p) return;
    for (int i = 0; i < p->ns; i++) free(p->s[i].x), free(p->s[i].y);
    free(p);
}

void svg_plot_xrange(svg_plot *p, double lo, double hi) { p->ax.fixed = 1, p->ax.lo = lo, p->ax.hi = hi; }
void svg_plot_yrange(svg_plot *p, double lo, double hi) { p->ay.fixed = 1, p->ay.lo = lo, p->ay.hi = hi; }

void svg_plot_series(svg_plot *p, const char *label, const char *color, const char *dash, bench_marker marker,
                     double width, int n, const double *x, const double *y) {
    if (p->ns == MAX_SERIES || n < 0) return;
    series *s = &p->s[p->ns];
    s->x = malloc((size_t)(n ? n : 1) * sizeof *s->x);
    s->y = malloc((size_t)(n ? n : 1) * sizeof *s->y);
    if (!s->x || !s->y) {
        free(s->x), free(s->y);
        return;
    }
    memcpy(s->x, x, (size_t)n * sizeof *x);
    memcpy(s->y, y, (size_t)n * sizeof *y);
    copy(s->label, sizeof s->label, label);
    copy(s->color, sizeof s->color, color);
    copy(s->dash, sizeof s->dash, dash);
    s->marker = marker, s->width = width > 0 ? width : 1.6, s->n = n;
    p->ns++;
}

void svg_plot_vline(svg_plot *p, double x, const char *label) {
    if (p->nv == MAX_VLINES) return;
    p->v[p->nv].x = x;
    copy(p->v[p->nv].label, sizeof p->v[p->nv].label, label);
    p->nv++;
}

void svg_plot_note(svg_plot *p, const char *text) { copy(p->note, sizeof p->note, text); }

/* ---- axes -------------------------------------------------------------------- */

static int usable(const axis *a, double v) { return isfinite(v) && (!a->log || v > 0); }

/* Fits an unfixed axis to the data: log axes to whole decades, linear ones to
 * "nice" multiples with a little room. */
static void fit(axis *a, const svg_plot *p, int which) {
    if (a->fixed) return;
    double lo = INFINITY, hi = -INFINITY;
    for (int i = 0; i < p->ns; i++)
        for (int k = 0; k < p->s[i].n; k++) {
            double v = which ? p->s[i].y[k] : p->s[i].x[k];
            if (!usable(a, v)) continue;
            lo = fmin(lo, v), hi = fmax(hi, v);
        }
    if (!(lo <= hi)) lo = a->log ? 1 : 0, hi = a->log ? 10 : 1;
    if (a->log) {
        a->lo = pow(10, floor(log10(lo) + 1e-9));
        a->hi = pow(10, ceil(log10(hi) - 1e-9));
        if (a->hi <= a->lo) a->hi = a->lo * 10;
    } else {
        if (hi == lo) hi = lo + 1;
        double pad = 0.04 * (hi - lo);
        a->lo = lo >= 0 && lo - pad < 0 ? 0 : lo - pad;
        a->hi = hi + pad;
    }
}

/* Position in [0, 1] along the axis. */
static double frac(const axis *a, double v) {
    if (a->log) return (log10(v) - log10(a->lo)) / (log10(a->hi) - log10(a->lo));
    return (v - a->lo) / (a->hi - a->lo);
}

static double px(const axis *a, double v) { return LEFT + frac(a, v) * (W_TOTAL - LEFT - RIGHT); }
static double py(const axis *a, double v) { return H_TOTAL - BOTTOM - frac(a, v) * (H_TOTAL - TOP - BOTTOM); }

static void escape(tc_strbuf *b, const char *s) {
    for (; *s; s++) {
        if (*s == '&') tc_strbuf_puts(b, "&amp;");
        else if (*s == '<') tc_strbuf_puts(b, "&lt;");
        else if (*s == '>') tc_strbuf_puts(b, "&gt;");
        else tc_strbuf_putc(b, *s);
    }
}

/* "10^k" with a superscript exponent. */
static void decade_label(tc_strbuf *b, int k) {
    if (k == 0) tc_strbuf_puts(b, "1");
    else if (k == 1) tc_strbuf_puts(b, "10");
    else tc_strbuf_printf(b, "10<tspan dy=\"-6\" font-size=\"10\">%d</tspan>", k);
}

/* A linear tick step of 1, 2 or 5 times a power of ten giving about 6 ticks. */
static double nice_step(double span) {
    double raw = span / 6, mag = pow(10, floor(log10(raw)));
    double f = raw / mag;
    return (f < 1.5 ? 1 : f < 3.5 ? 2 : f < 7.5 ? 5 : 10) * mag;
}

static void linear_label(tc_strbuf *b, double v, double step) {
    if (fabs(v) < step * 1e-9) v = 0;
    int digits = step >= 1 ? 0 : (int)ceil(-log10(step) - 1e-9);
    if (fabs(v) != 0 && (fabs(v) < 1e-3 || fabs(v) >= 1e5)) tc_strbuf_printf(b, "%.2g", v);
    else tc_strbuf_printf(b, "%.*f", digits, v);
}

/* Ticks, grid lines and tick labels of one axis (which: 0 x, 1 y). */
static void draw_axis(tc_strbuf *b, const axis *a, int which) {
    double x0 = LEFT, x1 = W_TOTAL - RIGHT, y0 = H_TOTAL - BOTTOM, y1 = TOP;
    if (a->log) {
        int k0 = (int)floor(log10(a->lo) + 1e-9), k1 = (int)ceil(log10(a->hi) - 1e-9);
        int every = k1 - k0 > 10 ? 2 : 1;
        for (int k = k0; k <= k1; k++) {
            for (int m = 1; m <= 9; m++) {
                double v = m * pow(10, k);
                if (v < a->lo * (1 - 1e-9) || v > a->hi * (1 + 1e-9)) continue;
                double len = m == 1 ? 6 : 3;
                if (which == 0) {
                    double x = px(a, v);
                    if (m == 1) tc_strbuf_printf(b, "<line x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" class=\"grid\"/>\n", x, y0, x, y1);
                    tc_strbuf_printf(b, "<line x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" class=\"tick\"/>\n", x, y0, x, y0 - len);
                    if (m == 1 && (k - k0) % every == 0) {
                        tc_strbuf_printf(b, "<text x=\"%.2f\" y=\"%.2f\" text-anchor=\"middle\">", x, y0 + 20);
                        decade_label(b, k);
                        tc_strbuf_puts(b, "</text>\n");
                    }
                } else {
                    double y = py(a, v);
                    if (m == 1) tc_strbuf_printf(b, "<line x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" class=\"grid\"/>\n", x0, y, x1, y);
                    tc_strbuf_printf(b, "<line x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" class=\"tick\"/>\n", x0, y, x0 + len, y);
                    if (m == 1 && (k - k0) % every == 0) {
                        tc_strbuf_printf(b, "<text x=\"%.2f\" y=\"%.2f\" text-anchor=\"end\">", x0 - 8, y + 4);
                        decade_label(b, k);
                        tc_strbuf_puts(b, "</text>\n");
                    }
                }
            }
        }
        return;
    }
    double step = nice_step(a->hi - a->lo);
    for (double v = ceil(a->lo / step - 1e-9) * step; v <= a->hi + step * 1e-9; v += step) {
        if (which == 0) {
            double x = px(a, v);
            tc_strbuf_printf(b, "<line x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" class=\"grid\"/>\n", x, y0, x, y1);
            tc_strbuf_printf(b, "<text x=\"%.2f\" y=\"%.2f\" text-anchor=\"middle\">", x, y0 + 20);
        } else {
            double y = py(a, v);
            tc_strbuf_printf(b, "<line x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" class=\"grid\"/>\n", x0, y, x1, y);
            tc_strbuf_printf(b, "<text x=\"%.2f\" y=\"%.2f\" text-anchor=\"end\">", x0 - 8, y + 4);
        }
        linear_label(b, v, step);
        tc_strbuf_puts(b, "</text>\n");
    }
}

/* A marker centred at (x, y). */
static void draw_marker(tc_strbuf *b, bench_marker m, double x, double y, const char *color) {
    const double r = 3.6;
    switch (m) {
    case MK_NONE: break;
    case MK_CIRCLE: tc_strbuf_printf(b, "<circle cx=\"%.2f\" cy=\"%.2f\" r=\"%.1f\" fill=\"%s\"/>", x, y, r, color); break;
    case MK_SQUARE:
        tc_strbuf_printf(b, "<rect x=\"%.2f\" y=\"%.2f\" width=\"%.1f\" height=\"%.1f\" fill=\"%s\"/>", x - r * 0.85,
                         y - r * 0.85, 1.7 * r, 1.7 * r, color);
        break;
    case MK_TRIANGLE:
    case MK_DOWN: {
        double s = m == MK_TRIANGLE ? 1 : -1;
        tc_strbuf_printf(b, "<path d=\"M%.2f %.2fL%.2f %.2fL%.2f %.2fZ\" fill=\"%s\"/>", x, y - s * r * 1.15,
                         x + r, y + s * r * 0.75, x - r, y + s * r * 0.75, color);
        break;
    }
    case MK_DIAMOND:
        tc_strbuf_printf(b, "<path d=\"M%.2f %.2fL%.2f %.2fL%.2f %.2fL%.2f %.2fZ\" fill=\"%s\"/>", x, y - r * 1.2,
                         x + r, y, x, y + r * 1.2, x - r, y, color);
        break;
    case MK_PLUS:
        tc_strbuf_printf(b, "<path d=\"M%.2f %.2fH%.2fM%.2f %.2fV%.2f\" stroke=\"%s\" stroke-width=\"2\"/>", x - r * 1.2,
                         y, x + r * 1.2, x, y - r * 1.2, y + r * 1.2, color);
        break;
    case MK_CROSS:
        tc_strbuf_printf(b, "<path d=\"M%.2f %.2fL%.2f %.2fM%.2f %.2fL%.2f %.2f\" stroke=\"%s\" stroke-width=\"2\"/>",
                         x - r, y - r, x + r, y + r, x - r, y + r, x + r, y - r, color);
        break;
    case MK_STAR: {
        tc_strbuf_puts(b, "<path d=\"");
        for (int k = 0; k < 10; k++) {
            double ang = -PI / 2 + k * PI / 5, rr = k % 2 ? r * 0.55 : r * 1.45;
            tc_strbuf_printf(b, "%c%.2f %.2f", k ? 'L' : 'M', x + rr * cos(ang), y + rr * sin(ang));
        }
        tc_strbuf_printf(b, "Z\" fill=\"%s\"/>", color);
        break;
    }
    }
}

static void draw_series(tc_strbuf *b, const svg_plot *p, const series *s) {
    tc_strbuf_printf(b, "<g fill=\"none\" stroke=\"%s\" stroke-width=\"%.2f\" stroke-linejoin=\"round\"%s%s%s>\n",
                     s->color, s->width, s->dash[0] ? " stroke-dasharray=\"" : "", s->dash,
                     s->dash[0] ? "\"" : "");
    int open = 0;
    for (int k = 0; k < s->n; k++) {
        int ok = usable(&p->ax, s->x[k]) && usable(&p->ay, s->y[k]);
        if (!ok) {
            if (open) tc_strbuf_puts(b, "\"/>\n");
            open = 0;
            continue;
        }
        tc_strbuf_printf(b, "%s%.2f,%.2f", open ? " " : "<polyline points=\"", px(&p->ax, s->x[k]),
                         py(&p->ay, s->y[k]));
        open = 1;
    }
    if (open) tc_strbuf_puts(b, "\"/>\n");
    tc_strbuf_puts(b, "</g>\n");
    if (s->marker == MK_NONE) return;
    tc_strbuf_puts(b, "<g stroke=\"none\">");
    for (int k = 0; k < s->n; k++)
        if (usable(&p->ax, s->x[k]) && usable(&p->ay, s->y[k]))
            draw_marker(b, s->marker, px(&p->ax, s->x[k]), py(&p->ay, s->y[k]), s->color);
    tc_strbuf_puts(b, "</g>\n");
}

static void draw_legend(tc_strbuf *b, const svg_plot *p) {
    double x = W_TOTAL - RIGHT + 18, y = TOP + 8;
    for (int i = 0; i < p->ns; i++, y += 19) {
        const series *s = &p->s[i];
        tc_strbuf_printf(b, "<line x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" stroke=\"%s\" stroke-width=\"%.2f\"%s%s%s/>",
                         x, y, x + 34, y, s->color, s->width, s->dash[0] ? " stroke-dasharray=\"" : "", s->dash,
                         s->dash[0] ? "\"" : "");
        draw_marker(b, s->marker, x + 17, y, s->color);
        tc_strbuf_printf(b, "<text x=\"%.2f\" y=\"%.2f\">", x + 42, y + 4);
        escape(b, s->label);
        tc_strbuf_puts(b, "</text>\n");
    }
}

int svg_plot_write(const svg_plot *p, const char *path) {
    svg_plot q = *p; /* the fitted axes; the series stay p's */
    fit(&q.ax, p, 0);
    fit(&q.ay, p, 1);
    double x0 = LEFT, x1 = W_TOTAL - RIGHT, y0 = H_TOTAL - BOTTOM, y1 = TOP;
    tc_strbuf b;
    tc_strbuf_init(&b);
    tc_strbuf_printf(&b,
                     "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
                     "<!-- A figure of docs/report.md, generated by build/report (bench/plots.c, bench/svg.c). -->\n"
                     "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" viewBox=\"0 0 %.0f %.0f\" "
                     "font-family=\"DejaVu Sans, Helvetica, Arial, sans-serif\" font-size=\"12\">\n"
                     "<style>.grid{stroke:#e3e3e3;stroke-width:1}.tick{stroke:#333;stroke-width:1}"
                     ".guide{stroke:#888;stroke-width:1;stroke-dasharray:3,3}</style>\n"
                     "<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n",
                     W_TOTAL, H_TOTAL, W_TOTAL, H_TOTAL);
    tc_strbuf_printf(&b, "<defs><clipPath id=\"area\"><rect x=\"%.2f\" y=\"%.2f\" width=\"%.2f\" height=\"%.2f\"/></clipPath></defs>\n",
                     x0, y1, x1 - x0, y0 - y1);
    draw_axis(&b, &q.ax, 0);
    draw_axis(&b, &q.ay, 1);
    tc_strbuf_puts(&b, "<g clip-path=\"url(#area)\">\n");
    for (int i = 0; i < p->nv; i++) {
        if (!usable(&q.ax, p->v[i].x) || frac(&q.ax, p->v[i].x) < 0 || frac(&q.ax, p->v[i].x) > 1) continue;
        double x = px(&q.ax, p->v[i].x);
        tc_strbuf_printf(&b, "<line x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" class=\"guide\"/>\n", x, y0, x, y1);
    }
    for (int i = 0; i < p->ns; i++) draw_series(&b, &q, &p->s[i]);
    tc_strbuf_puts(&b, "</g>\n");
    for (int i = 0; i < p->nv; i++) {
        if (!usable(&q.ax, p->v[i].x) || frac(&q.ax, p->v[i].x) < 0 || frac(&q.ax, p->v[i].x) > 1) continue;
        tc_strbuf_printf(&b, "<text x=\"%.2f\" y=\"%.2f\" text-anchor=\"middle\" font-size=\"10\" fill=\"#555\">",
                         px(&q.ax, p->v[i].x), y1 - 4);
        escape(&b, p->v[i].label);
        tc_strbuf_puts(&b, "</text>\n");
    }
    tc_strbuf_printf(&b, "<rect x=\"%.2f\" y=\"%.2f\" width=\"%.2f\" height=\"%.2f\" fill=\"none\" stroke=\"#333\"/>\n",
                     x0, y1, x1 - x0, y0 - y1);
    tc_strbuf_printf(&b, "<text x=\"%.2f\" y=\"%.2f\" text-anchor=\"middle\" font-size=\"15\" font-weight=\"bold\">",
                     (x0 + x1) / 2, 22.0);
    escape(&b, p->title);
    tc_strbuf_printf(&b, "</text>\n<text x=\"%.2f\" y=\"%.2f\" text-anchor=\"middle\" font-size=\"13\">", (x0 + x1) / 2,
                     y0 + 42);
    escape(&b, p->xlabel);
    tc_strbuf_printf(&b, "</text>\n<text transform=\"translate(%.2f %.2f) rotate(-90)\" text-anchor=\"middle\" font-size=\"13\">",
                     20.0, (y0 + y1) / 2);
    escape(&b, p->ylabel);
    tc_strbuf_puts(&b, "</text>\n");
    if (p->note[0]) {
        tc_strbuf_printf(&b, "<text x=\"%.2f\" y=\"%.2f\" font-size=\"10\" fill=\"#555\">", 8.0, H_TOTAL - 6);
        escape(&b, p->note);
        tc_strbuf_puts(&b, "</text>\n");
    }
    draw_legend(&b, p);
    tc_strbuf_puts(&b, "</svg>\n");
    int st = b.oom ? -1 : bench_write_file(path, b.buf, b.len);
    tc_strbuf_free(&b);
    return st;
}
