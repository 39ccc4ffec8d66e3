/* runinfo.h — run.json: what the presentation script (bench/report.py) needs beyond
 * the CSVs: the machine and tree, the run's constants, the methods, scenes and surfaces. */
#ifndef BENCH_RUNINFO_H
#define BENCH_RUNINFO_H

#include "scenes/scene.h"

typedef struct {
    char machine[256]; /* /proc/cpuinfo model name */
    int nproc;
    char commit[96];   /* short hash of the tree measured, "-dirty" if its sources differ */
    double total_s;    /* the whole measurement */
    int images_ok;     /* every PNG row was written */
} bench_run_info;

/* Fills machine, nproc and commit; images_ok = 1. */
void bench_run_info_init(bench_run_info *info);

/* Writes path. scene_on[TC_SCENE_COUNT]: the scenes measured. 0, or -1. */
int bench_run_info_write(const bench_run_info *info, const int *scene_on, const char *path);

#endif
