/* hugemem.h — big buffers (an answer, a request body, a decoded array): backed by transparent
 * huge pages, so that filling one costs a few faults, not thousands; and the spare blocks that a
 * sent answer leaves for the next, so that their pages need not be faulted in again. */
#ifndef TC_IO_HUGEMEM_H
#define TC_IO_HUGEMEM_H

#include <stddef.h>

#include "core/spare.h"

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
 * NULL or smaller than that) is a spare (tc__huge_take) when one holds n bytes: p's bytes are
 * copied into it and p freed, as realloc would. The answers' buffers come from here: a growing
 * text (strbuf.c) and a raw image written whole (image/codec.c). */
void *tc__huge_realloc(void *p, size_t n);

/* free(p); except that a big block (TC_HUGE_MIN .. TC__SPARE_MAX usable bytes) is kept as a
 * spare (core/spare.h, which the core's big arrays share). Why answers: glibc gives every block
 * from 32 MiB its own mapping and unmaps it on free (smaller ones it reuses: their threshold
 * moves up to 32 MiB as such blocks are freed, so they are left to it), and so each big answer
 * was written into fresh pages that the kernel faults in and zeroes again. Measured on the 2-core
 * VM, the JSON ordinates of 131k triangles (49 MB, two threads): encoding 90-170 ms into fresh
 * buffers, 44-51 ms into the last answer's. A spare's pages are lazily free (MADV_FREE), so an
 * idle daemon holds at most TC__SPARE_MAX, reclaimable, outside the render budget
 * (--max-memory). */
void tc__huge_free(void *p);

/* The same from TC__SPARE_MIN: for buffers only tc__huge_take reuses, which glibc would not
 * (the part buffers of a parallel text, textpar.c: 2 MiB aligned blocks of their own, or a heap
 * that it trims, 4 KiB faults each time). */
void tc__huge_keep(void *p);

/* The smallest spare answer buffer of n to 2n bytes, taken (uninitialized, like malloc's); NULL
 * if n < TC__SPARE_MIN or none fits, and then the largest spare smaller than n is freed: it
 * would only sit beside the block the caller makes instead. Free the result with tc__huge_free
 * (or free). */
void *tc__huge_take(size_t n);

/* Test hook: the bytes the spares hold. */
size_t tc__huge_spare(void);

/* Test hook: how many blocks got the advice in this thread so far. */
long tc__huge_advised(void);

#endif
