/* log.h — the daemon's stderr log: one line per request (method, path, status,
 * response bytes, milliseconds) and free-form notices. */
#ifndef TC_SERVER_LOG_H
#define TC_SERVER_LOG_H

#include <stddef.h>

/* `POST /v1/ordinates 200 1834 1.27ms`; status 0 prints as "-". note (may be
 * NULL) is appended in parentheses. The path is escaped, so a client cannot
 * forge log lines. Thread-safe: each line is one write(2). */
void tc_log_request(const char *method, const char *path, int status, size_t bytes, double ms, const char *note);

/* "tocherd: " + the message + newline, as one write(2). */
void tc_log_notice(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

#endif
