/* diag.c — the bounded list of findings (errors and warnings) about an input.
 * Keeps the first TC_DIAGS_KEEP entries and counts every one, so a huge bad
 * input cannot make the report itself huge. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tocher.h"

void tc_diags_init(tc_diags *d) { memset(d, 0, sizeof *d); }

void tc_diags_free(tc_diags *d) {
    if (!d) return;
    free(d->items);
    tc_diags_init(d);
}

void tc_diags_clear(tc_diags *d) {
    d->count = d->errors = d->warnings = 0;
}

int tc_diags_add(tc_diags *d, tc_severity sev, const char *path, const char *fmt, ...) {
    int status = sev == TC_SEV_ERROR ? TC_EINVAL : TC_OK;
    if (!d) return status;
    if (sev == TC_SEV_ERROR) d->errors++;
    else d->warnings++;
    if (d->count >= TC_DIAGS_KEEP) return status;
    if (!d->items) {
        /* Allocated at the first finding: a clean input costs nothing. If this
         * fails the finding is still counted, only its text is lost. */
        d->items = malloc(TC_DIAGS_KEEP * sizeof *d->items);
        if (!d->items) return status;
    }
    tc_diag *e = &d->items[d->count++];
    e->severity = sev;
    snprintf(e->path, sizeof e->path, "%s", path ? path : "");
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(e->message, sizeof e->message, fmt, ap);
    va_end(ap);
    return status;
}
