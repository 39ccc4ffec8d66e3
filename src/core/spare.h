/* spare.h — big blocks kept after use, for the next big allocation of any layer: the core's
 * arrays of a build, an answer's buffers (io/hugemem.c). Their pages are not faulted in again. */
#ifndef TC_CORE_SPARE_H
#define TC_CORE_SPARE_H

#include <stddef.h>

/* Two pools, so that neither evicts the other's blocks: the core's arrays (a build of 524k
 * triangles alone has more than a pool holds) and the io layer's answers. Each pool holds at
 * most TC__SPARE_MAX bytes in at most TC__SPARES blocks. */
enum { TC__SPARE_ARRAYS, TC__SPARE_ANSWERS, TC__SPARE_POOLS };
#define TC__SPARE_MAX ((size_t)256 << 20)
#define TC__SPARES 32

/* The least block worth keeping: glibc reuses smaller freed blocks from its heap (their
 * mmap threshold rises to 32 MiB as such blocks are freed), whose pages stay; 4 MiB blocks
 * already went to fresh mappings in a daemon's requests, and faulted in again each time. */
#define TC__SPARE_MIN ((size_t)4 << 20)

/* The smallest spare of n to 2n bytes, taken (uninitialized, like malloc's; free it with
 * tc__spare_keep or free), or NULL. Not a bigger one: a spare is usually the same array or
 * answer of the last request, and serves best the block of its own size. With drop_smaller,
 * when none is taken, the largest spare smaller than n is freed: for a buffer that grows (an
 * answer), which would only sit beside the block the caller makes instead. */
void *tc__spare_take(int pool, size_t n, int drop_smaller);

/* free(p); except that a block whose usable size is in [from, TC__SPARE_MAX] is kept as a
 * spare, the smallest going first when the spares would exceed TC__SPARE_MAX or TC__SPARES.
 * Why: glibc gives every block from its mmap threshold (at most 32 MiB) its own mapping and
 * unmaps it on free, so each request's big arrays were fresh pages the kernel faulted in and
 * zeroed again. A spare's pages are given to the kernel as lazily free (MADV_FREE): under
 * memory pressure it takes them back (the next write faults them in again, zeroed), otherwise
 * they are reused as they are. */
void tc__spare_keep(int pool, void *p, size_t from);

/* The bytes the spares hold (tests, and a process that wants them back: tc__spare_drop). */
size_t tc__spare_bytes(int pool);

/* Frees every spare of the pool. */
void tc__spare_drop(int pool);

#endif
