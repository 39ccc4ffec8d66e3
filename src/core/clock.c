/* clock.c — the one clock: milliseconds of CLOCK_MONOTONIC, which deadlines
 * (tc_render_options.deadline_ms) are stated in and every timing is taken with. */
#include <time.h>

#include "tocher.h"

double tc_now_ms(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}
