/* deadline.h — the one test of a build's deadline (tc_options.deadline_ms, on the
 * clock of tc_now_ms): the stages of tc_recon_new and its longest loops ask it. */
#ifndef TC_CORE_DEADLINE_H
#define TC_CORE_DEADLINE_H

#include "tocher.h"

/* Past deadline_ms (0: none). One clock read, so a loop asks it every few hundred items. */
static inline int tc__past(double deadline_ms) { return deadline_ms > 0 && tc_now_ms() > deadline_ms; }

#endif
