/* log.c — the daemon's stderr log. Lines are formatted in a buffer and written
 * with one write(2), so lines of concurrent requests never interleave. */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "server/log.h"

enum { LINE_MAX_BYTES = 1024, PATH_SHOWN = 200 };

/* Copies s into out (size n), %XX-escaping bytes that are not printable
 * ASCII, spaces included, and cutting it with "..." beyond PATH_SHOWN. */
static void escape(const char *s, char *out, size_t n) {
    static const char hex[] = "0123456789ABCDEF";
    size_t k = 0;
    for (; *s && k + 4 < n; s++) {
        unsigned char c = (unsigned char)*s;
        if (k >= PATH_SHOWN) {
            memcpy(out + k, "...", 3), k += 3;
            break;
        }
        if (c > 0x20 && c < 0x7f && c != '%') out[k++] = (char)c;
        else out[k++] = '%', out[k++] = hex[c >> 4], out[k++] = hex[c & 15];
    }
    out[k] = '\0';
}

static void emit(const char *line, int len) {
    if (len <= 0) return;
    if (len >= LINE_MAX_BYTES) len = LINE_MAX_BYTES - 1;
    ssize_t w = write(STDERR_FILENO, line, (size_t)len);
    (void)w; /* nowhere to report a failed log write */
}

void tc_log_request(const char *method, const char *path, int status, size_t bytes, double ms, const char *note) {
    char m[40], p[PATH_SHOWN + 8], code[16], line[LINE_MAX_BYTES];
    escape(method ? method : "-", m, sizeof m);
    escape(path ? path : "-", p, sizeof p);
    if (status > 0) snprintf(code, sizeof code, "%d", status);
    else strcpy(code, "-");
    int n = snprintf(line, sizeof line - 1, "%s %s %s %zu %.2fms%s%s%s\n", m, p, code, bytes, ms, note ? " (" : "",
                     note ? note : "", note ? ")" : "");
    if (n >= (int)sizeof line - 1) line[sizeof line - 2] = '\n', n = sizeof line - 1;
    emit(line, n);
}

void tc_log_notice(const char *fmt, ...) {
    char line[LINE_MAX_BYTES];
    int n = snprintf(line, sizeof line, "tocherd: ");
    va_list ap;
    va_start(ap, fmt);
    int m = vsnprintf(line + n, sizeof line - (size_t)n - 1, fmt, ap);
    va_end(ap);
    if (m < 0) return;
    n += m < (int)(sizeof line - (size_t)n - 1) ? m : (int)(sizeof line - (size_t)n - 2);
    line[n++] = '\n';
    emit(line, n);
}
