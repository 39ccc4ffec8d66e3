/* hugemem.h — advice that a big buffer (an answer, a request body, a decoded array) be
 * backed by transparent huge pages, so that filling it costs a few faults, not thousands. */
#ifndef TC_IO_HUGEMEM_H
#define TC_IO_HUGEMEM_H

#include <stddef.h>

/* Buffers from this size on get the advice. glibc's malloc gives every block this big its
 * own mapping (32 MiB is the ceiling of its dynamic mmap threshold), so the advice never
 * covers an arena's heap: there 2 MiB pages would be faulted in (zeroed) for small blocks
 * too, and trimmed and faulted again (measured: the build of an 8192-triangle mesh went from
 * 4 to 18 ms in the daemon when 4 MiB answers were advised). */
#define TC_HUGE_MIN ((size_t)32 << 20)

/* Advises the kernel to back [p, p + n) with huge pages when n >= TC_HUGE_MIN (only the
 * 2 MiB-aligned stretches inside can be). Changes no byte and no ownership: p stays the
 * malloc() block it was. Why: on the development VM a first-touch 4 KiB fault costs ~20 µs,
 * so writing a fresh 106 MB answer took 550 ms of faults and 16 ms with huge pages (THP in
 * "madvise" mode, the default of many distributions). A no-op where the advice is unknown. */
void tc__huge_advise(void *p, size_t n);

/* realloc(p, n), then the advice for the new block. */
void *tc__huge_realloc(void *p, size_t n);

/* Test hook: how many blocks got the advice in this thread so far. */
long tc__huge_advised(void);

#endif
