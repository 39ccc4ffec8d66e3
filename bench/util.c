/* util.c — small helpers shared by the measurement's modules: a monotonic clock,
 * medians, progress lines on stderr, files and directories, CSV fields, shell lines. */
#include "util.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

double bench_now_ms(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

static int by_double(const void *pa, const void *pb) {
    double a = *(const double *)pa, b = *(const double *)pb;
    return a < b ? -1 : a > b;
}

double bench_median(double *x, int n) {
    if (n <= 0) return 0;
    qsort(x, (size_t)n, sizeof *x, by_double);
    return n % 2 ? x[n / 2] : 0.5 * (x[n / 2 - 1] + x[n / 2]);
}

static double log_t0;

void bench_log_start(void) { log_t0 = bench_now_ms(); }

double bench_elapsed_s(void) { return (bench_now_ms() - log_t0) / 1e3; }

void bench_log(const char *fmt, ...) {
    va_list ap;
    fprintf(stderr, "[%6.1fs] ", bench_elapsed_s());
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
}

int bench_mkdirs(const char *path) {
    char tmp[1024];
    size_t n = strlen(path);
    if (n == 0 || n >= sizeof tmp) return -1;
    memcpy(tmp, path, n + 1);
    for (size_t i = 1; i <= n; i++) {
        if (tmp[i] != '/' && tmp[i] != '\0') continue;
        char c = tmp[i];
        tmp[i] = '\0';
        if (mkdir(tmp, 0777) != 0 && errno != EEXIST) return -1;
        tmp[i] = c;
    }
    return 0;
}

int bench_write_file(const char *path, const void *data, size_t n) {
    FILE *f = fopen(path, "wb");
    if (!f) {
        fprintf(stderr, "report: cannot write %s: %s\n", path, strerror(errno));
        return -1;
    }
    size_t w = fwrite(data, 1, n, f);
    int bad = fclose(f) != 0 || w != n;
    if (bad) fprintf(stderr, "report: error writing %s\n", path);
    return bad ? -1 : 0;
}

void bench_csv_text(tc_strbuf *b, const char *s) {
    if (!strpbrk(s, ",\"\n")) {
        tc_strbuf_puts(b, s);
        return;
    }
    tc_strbuf_putc(b, '"');
    for (; *s; s++) {
        if (*s == '"') tc_strbuf_putc(b, '"');
        tc_strbuf_putc(b, *s == '\n' ? ' ' : *s);
    }
    tc_strbuf_putc(b, '"');
}

void bench_command_line(const char *cmd, char *buf, size_t n, const char *fallback) {
    snprintf(buf, n, "%s", fallback);
    FILE *p = popen(cmd, "r");
    if (!p) return;
    char line[512];
    if (fgets(line, sizeof line, p)) {
        size_t k = strcspn(line, "\r\n");
        line[k] = '\0';
        while (k > 0 && (line[k - 1] == ' ' || line[k - 1] == '\t')) line[--k] = '\0';
        char *s = line;
        while (*s == ' ' || *s == '\t') s++;
        if (*s) snprintf(buf, n, "%s", s);
    }
    pclose(p);
}
