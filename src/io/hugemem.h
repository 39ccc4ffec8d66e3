/* hugemem.h — big buffers (an answer, a request body, a decoded array): backed by transparent
 * huge pages, so that filling one costs a few faults, not thousands; and the one spare block
 * that a sent answer leaves for the next, so that its pages need not be faulted in again. */
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

/* realloc(p, n), then the advice for the new block. A fresh big block (n >= TC_HUGE_MIN, p
 * NULL or smaller than that) is the spare (tc__huge_free) when there is one of at least n bytes:
 * p's bytes are copied into it and p freed, as realloc would. */
void *tc__huge_realloc(void *p, size_t n);

/* free(p); except that a big block (TC_HUGE_MIN .. TC_HUGE_SPARE_MAX usable bytes) becomes the
 * process's one spare, and the spare it replaces is freed. Why: glibc gives every block from
 * 32 MiB its own mapping and unmaps it on free, so each big answer was written into fresh
 * pages, which the kernel zeroes as they fault in: measured on the 2-core VM, the JSON
 * ordinates of 131k triangles (49 MB) took 78-158 ms to print into fresh pages and 43-45 ms
 * into the last answer's. The spare's pages are given to the kernel as lazily free
 * (MADV_FREE): under memory pressure it takes them back (and the next write faults them in
 * again, zeroed), otherwise they are reused as they are. So an idle daemon holds at most one
 * spare, reclaimable, outside the render budget (--max-memory). */
void tc__huge_free(void *p);

/* The largest spare kept: a bigger answer's faults are small beside its own work. */
#define TC_HUGE_SPARE_MAX ((size_t)256 << 20)

/* Test hook: the spare's usable size, 0 when there is none. */
size_t tc__huge_spare(void);

/* Test hook: how many blocks got the advice in this thread so far. */
long tc__huge_advised(void);

#endif
