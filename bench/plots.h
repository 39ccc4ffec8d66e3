/* plots.h — the per-scene figures built from the results: mean relative error
 * against run time and against samples, and the scanline error profile. */
#ifndef BENCH_PLOTS_H
#define BENCH_PLOTS_H

#include "measure.h"
#include "results.h"

/* Writes <dir>/<scene>-time.svg, -samples.svg, -scanline.svg, -scanline-log.svg
 * and the profile's data <dir>/<scene>-scanline.csv. 0, or -1 if a file failed. */
int bench_plots_write(const bench_results *rs, const bench_reference *ref, const char *dir);

#endif
