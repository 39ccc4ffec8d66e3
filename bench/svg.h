/* svg.h — a small SVG plotting module: linear or log axes (decade ticks and
 * labels), polylines with dashes and markers, vertical guide lines, a legend. */
#ifndef BENCH_SVG_H
#define BENCH_SVG_H

#include "plan.h"

typedef struct svg_plot svg_plot;

/* A plot with the given title and axis labels; xlog/ylog choose log10 axes. */
svg_plot *svg_plot_new(const char *title, const char *xlabel, const char *ylabel, int xlog, int ylog);
void svg_plot_free(svg_plot *p);

/* Fixes an axis range instead of fitting the data (log axes: both > 0). Data
 * outside is clipped to the plot area. */
void svg_plot_xrange(svg_plot *p, double lo, double hi);
void svg_plot_yrange(svg_plot *p, double lo, double hi);

/* A curve: n points, drawn in order; a point that is not finite, or not > 0 on
 * a log axis, breaks the line. dash: NULL solid, else an SVG dasharray ("6,4").
 * The data is copied. */
void svg_plot_series(svg_plot *p, const char *label, const char *color, const char *dash, bench_marker marker,
                     double width, int n, const double *x, const double *y);
/* A thin vertical guide at x with a short label at the top. */
void svg_plot_vline(svg_plot *p, double x, const char *label);
/* A note under the plot (left-aligned, small). */
void svg_plot_note(svg_plot *p, const char *text);

/* Writes the SVG document; 0, or -1 with a message on stderr. */
int svg_plot_write(const svg_plot *p, const char *path);

#endif
