/* markdown.h — docs/report.md: the numbers, tables and figure links of one run
 * filled into the prose template bench/report.md.in. */
#ifndef BENCH_MARKDOWN_H
#define BENCH_MARKDOWN_H

#include "results.h"

/* What the report says about the run itself. */
typedef struct {
    char machine[256]; /* /proc/cpuinfo model name */
    int nproc;
    char commit[96];   /* git describe of the tree measured */
    double total_s;    /* the whole run, to the moment report.md is written */
    const char *fig_rel; /* the figure directory relative to report.md ("report") */
    int images_ok;     /* the PNG rows were written */
} bench_run_info;

/* Renders template_path into out_path. 0; 1 if the template had unknown keys
 * (written anyway, with the keys marked); -1 if a file could not be read or written. */
int bench_markdown_write(const bench_results *rs, const bench_run_info *info, const char *template_path,
                         const char *out_path);

#endif
