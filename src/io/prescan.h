/* prescan.h — a pass over a JSON body's bytes, before any tree is built, that counts
 * the elements of the arrays the server limits and stops at the first one over. */
#ifndef TC_IO_PRESCAN_H
#define TC_IO_PRESCAN_H

#include <stddef.h>
#include <stdint.h>

/* An array the scan counts: `path` names it by the object keys that lead to it
 * from the root ("points", "reference.points"); max <= 0 means no limit. */
typedef struct {
    const char *path;
    int64_t max;
} tc_scan_limit;

/* Index of the first limit in lim[0..n) whose array holds more than its max
 * elements, with that array's full element count in *count; -1 if none is over.
 * The bytes need not be valid JSON (the parser reports syntax afterwards); the
 * scan allocates nothing and reads each byte once. A limited array given as a
 * typed array ({"dtype", "shape": [n, ...], "data"}) counts n, its shape's first
 * length, without decoding the data. */
int tc_prescan(const char *json, size_t len, const tc_scan_limit *lim, int n, int64_t *count);

#endif
