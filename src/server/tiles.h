/* tiles.h — the XYZ tile pyramid of a stored mesh: reading a tile URL
 * ({z}/{x}/{y}.{format} and its query) and the viewport of a tile. */
#ifndef TC_SERVER_TILES_H
#define TC_SERVER_TILES_H

#include <stddef.h>

#include "server/routes.h"
#include "tocher.h"

enum { TC_TILE_MAX_Z = 24, TC_TILE_DEFAULT_SIZE = 256, TC_TILE_MAX_SIZE = 1024 };

typedef struct {
    int z;
    long long x, y; /* 0 .. 2^z - 1; y counts from the top */
    int format;     /* a tc_img_format */
    int size;       /* pixels per side */
    double exposure;
    int overlay, linear;
    int nbackground; /* 0: none; 1: every channel; else one per channel */
    double background[TC_MAX_CHANNELS];
} tc_tile_req;

/* Reads the tile segments ({z}, {x}, "{y}.{format}": params->seg[1..3]) and
 * the query (size, exposure, overlay, linear, background). 0, or 404 (no such
 * tile: z > 24, x or y outside [0, 2^z), an unknown format) or 400 (a bad
 * query value, the parameter named) with detail filled. */
int tc_tile_parse(const tc_path_params *p, const tc_query *q, tc_tile_req *t, char *detail, size_t n);

/* A canonical text of everything but the id that the tile's bytes depend on
 * (for its ETag): equal for URLs that render the same tile. */
void tc_tile_meaning(const tc_tile_req *t, char *out, size_t n);

/* The tile's viewport over a mesh with this bbox (x0, y0, x1, y1): the square of
 * side s = max(x1 - x0, y1 - y0) anchored at (x0, y0), t = s / 2^z, and
 * x in [x0 + x t, x0 + (x + 1) t], y in [y0 + s - (y + 1) t, y0 + s - y t],
 * computed in exactly that order (clients reproduce it bit for bit). */
void tc_tile_viewport(const tc_tile_req *t, const double bbox[4], tc_viewport *vp);

#endif
