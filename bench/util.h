/* util.h — small helpers shared by the report's modules: a monotonic clock,
 * medians, progress lines on stderr, files and directories, number formatting. */
#ifndef BENCH_UTIL_H
#define BENCH_UTIL_H

#include <stddef.h>

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
/* Reads a whole text file (NUL-terminated, free() it), or NULL with a message on stderr. */
char *bench_read_file(const char *path);

/* Numbers for tables and prose: g3 = 3 significant digits ("0.000123",
 * "1.23e-07" below 1e-4), ms = milliseconds with 3 significant digits,
 * ratio = "12×"-style factor with 2 significant digits (3 below 10). */
void bench_fmt_g3(char *buf, size_t n, double x);
void bench_fmt_ms(char *buf, size_t n, double ms);
void bench_fmt_ratio(char *buf, size_t n, double r);

/* Trimmed first line of `cmd`'s output (popen), or `fallback`. */
void bench_command_line(const char *cmd, char *buf, size_t n, const char *fallback);

#endif
