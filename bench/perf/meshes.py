"""Writes the inputs of the performance comparison (bench/perf/): meshes, data and query points
as tocher requests (JSON), NumPy archives for peers.py, and the 1e6 scattered query points.

    /usr/bin/python3 bench/perf/meshes.py OUTDIR [--quick]

Every mesh's triangles come from scipy.spatial.Delaunay, so scipy, matplotlib and tocher all
work on the identical triangulation. Everything is deterministic (fixed seeds):

    OUTDIR/NAME.json          {"vertices", "triangles", "values", "gradients"} (exact gradients)
    OUTDIR/NAME.noderiv.json  the same without "gradients"
    OUTDIR/NAME.npz           points, simplices, values, grads (for peers.py)
    OUTDIR/points.f64         1e6 query points uniform in [0,1)^2, little-endian float64 x,y pairs
    OUTDIR/meshes.tsv         name, vertices, triangles, json_bytes (with a header line)

The 1024x1024 tile (pixel centres x = (i+0.5)/1024, y = (j+0.5)/1024) is not written: both
sides generate it. --quick writes only grid16, grid64 and del1e3 (for the tests).
"""
import argparse
import json
import os
import sys
import time

import numpy as np
from scipy.spatial import Delaunay

GRIDS = [16, 32, 64, 128, 256, 512]
SCATTERED = [1000, 10000, 100000]
QUICK = {"grid16", "grid64", "del1e3"}
NPOINTS = 1_000_000
SEED_POINTS = 20240601  # the query points
SEED_MESH = 19920727    # the scattered meshes, mixed with the point count


def f(x, y):
    """The data, f(x,y) = sin(3x+1) cos(2y) + x^2/2, and its exact gradient."""
    s, c = np.sin(3 * x + 1), np.cos(2 * y)
    value = s * c + 0.5 * x * x
    gx = 3 * np.cos(3 * x + 1) * c + x
    gy = -2 * s * np.sin(2 * y)
    return value, gx, gy


def grid_points(n):
    """(n+1)^2 vertices i/n, j/n on [0,1]^2 (x fastest); i/n is correctly rounded."""
    t = np.arange(n + 1, dtype=np.float64) / n
    x, y = np.meshgrid(t, t)
    return np.column_stack([x.ravel(), y.ravel()])


def scattered_points(npts):
    """npts uniform random points in [0,1)^2 plus the 4 corners, so the hull is the unit square."""
    rng = np.random.default_rng([SEED_MESH, npts])
    corners = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    return np.vstack([rng.random((npts, 2)), corners])


def triangulate(points, expect=None):
    """scipy's Delaunay triangles, checked: every vertex used, no zero-area triangle, and (for
    the grid, where qhull has to split each square of 4 cocircular points) the expected count."""
    tri = Delaunay(points)
    simplices = np.ascontiguousarray(tri.simplices, dtype=np.int64)
    if expect is not None:
        assert len(simplices) == expect, f"{len(simplices)} triangles, expected {expect}"
    assert len(tri.coplanar) == 0, "qhull dropped vertices"
    assert np.unique(simplices).size == len(points), "a vertex is in no triangle"
    p = points[simplices]
    area2 = ((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) -
             (p[:, 1, 1] - p[:, 0, 1]) * (p[:, 2, 0] - p[:, 0, 0]))
    assert np.all(area2 != 0), "zero-area triangle"
    return simplices


def dumps(obj):
    # json.dumps writes floats with float.__repr__: the shortest string that round-trips exactly.
    return json.dumps(obj, separators=(",", ":"), allow_nan=False)


# Grids also written with C0 rows every n/8 and a C-1 column (NAME.flags.json).
FLAGGED = ("grid64", "grid512")


def write_mesh(outdir, name, points, simplices):
    """NAME.json, NAME.noderiv.json and NAME.npz; returns the size of NAME.json in bytes."""
    values, gx, gy = f(points[:, 0], points[:, 1])
    grads = np.column_stack([gx, gy])
    head = ('{"vertices":' + dumps(points.tolist()) +
            ',"triangles":' + dumps(simplices.tolist()) +
            ',"values":' + dumps(values.tolist()))
    with open(os.path.join(outdir, name + ".noderiv.json"), "w") as out:
        out.write(head + "}\n")
    text = head + ',"gradients":' + dumps(grads.tolist()) + "}\n"
    with open(os.path.join(outdir, name + ".json"), "w") as out:
        out.write(text)
    if name in FLAGGED:  # the same mesh with discontinuities: what the wedge machinery costs
        n = int(name[4:])
        rows = [[j * (n + 1) + i for i in range(n + 1)] for j in range(n // 8, n, n // 8)]
        cols = [[j * (n + 1) + n // 2 for j in range(n + 1)]]
        flags = ',"discontinuities":' + dumps({"c0": rows, "c-1": cols})
        with open(os.path.join(outdir, name + ".flags.json"), "w") as out:
            out.write(text[:-2] + flags + "}\n")
    np.savez(os.path.join(outdir, name + ".npz"),
             points=points, simplices=simplices, values=values, grads=grads)
    return len(text.encode())


def main(argv):
    ap = argparse.ArgumentParser(description="Writes the inputs of the performance comparison.")
    ap.add_argument("outdir")
    ap.add_argument("--quick", action="store_true", help="only grid16, grid64 and del1e3")
    args = ap.parse_args(argv[1:])
    outdir, quick = args.outdir, args.quick
    os.makedirs(outdir, exist_ok=True)

    meshes = [(f"grid{n}", lambda n=n: grid_points(n), 2 * n * n) for n in GRIDS]
    meshes += [(f"del1e{len(str(k)) - 1}", lambda k=k: scattered_points(k), None)
               for k in SCATTERED]
    if quick:
        meshes = [m for m in meshes if m[0] in QUICK]

    rows = ["name\tvertices\ttriangles\tjson_bytes"]
    for name, make_points, expect in meshes:
        t0 = time.perf_counter()
        points = make_points()
        simplices = triangulate(points, expect)
        nbytes = write_mesh(outdir, name, points, simplices)
        rows.append(f"{name}\t{len(points)}\t{len(simplices)}\t{nbytes}")
        print(f"{name}: {len(points)} vertices, {len(simplices)} triangles, {nbytes} bytes, "
              f"{time.perf_counter() - t0:.2f} s", file=sys.stderr)

    pts = np.random.default_rng(SEED_POINTS).random((NPOINTS, 2))
    pts.astype("<f8").tofile(os.path.join(outdir, "points.f64"))
    with open(os.path.join(outdir, "meshes.tsv"), "w") as out:
        out.write("\n".join(rows) + "\n")


if __name__ == "__main__":
    main(sys.argv)
