/* util.h — small helpers shared by the measurement's modules: a monotonic clock,
 * medians, progress lines on stderr, files and directories, CSV fields, shell lines. */
#ifndef BENCH_UTIL_H
#define BENCH_UTIL_H

#include <stddef.h>

#include "io/strbuf.h"

/* CLOCK_MONOTONIC in milliseconds. */
double bench_now_ms(void);
/* Median of x[0..n) (sorts x in place); 0 for n = 0. */
double bench_median(double *x, int n);

/* A progress line on stderr, prefixed with the seconds since bench_log_start. */
void bench_log_start(void);
double bench_elapsed_s(void);
void bench_log(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* mkdir -p; 0 or -1 (with errno). */
int bench_mkdirs(const char *path);
/* Writes n bytes to path (replacing it); 0 or -1 with a message on stderr. */
int bench_write_file(const char *path, const void *data, size_t n);

/* A CSV field: quoted (doubling quotes) when it holds a comma, quote or newline. */
void bench_csv_text(tc_strbuf *b, const char *s);

/* Trimmed first line of `cmd`'s output (popen), or `fallback`. */
void bench_command_line(const char *cmd, char *buf, size_t n, const char *fallback);

#endif
