"""Times tocher's peers, scipy's CloughTocher2DInterpolator and matplotlib's Cubic/Linear
TriInterpolator, on the inputs bench/perf/meshes.py wrote, and prints the figures as JSON.

    /usr/bin/python3 bench/perf/peers.py OUTDIR [--quick] > OUTDIR/peers.json

For each mesh (OUTDIR/NAME.npz) it prints {"versions": {...}, "meshes": {NAME: {...}}} with
build times in seconds (*_s), evaluation rates in points per second (*_pps) on the 1e6
scattered points (OUTDIR/points.f64) and on the 1024x1024 tile of pixel centres, the number of
points a rate was measured on (*_scattered_n; scipy's walk from the last point found costs
O(sqrt(triangles)) per random point, so big meshes take a prefix), array sizes (*_bytes: the
interpolators' main numpy arrays, not matplotlib's C++ trapezoid map) and the peak RSS.
A figure that would take too long is null, with the reason under "skipped". It also writes
OUTDIR/NAME.scipy_vals.f64, scipy's values (exact gradients) at the first 1000 scattered points,
which the C side compares with its own.

Each figure is the minimum of 3 runs when a run takes under 1 s, else one run (time.perf_counter).

What the scipy build figures include (scipy 1.10, interpnd.pyx):
  CloughTocher2DInterpolator.__init__ is NDInterpolatorBase.__init__ (shape checks, contiguous
  float64 copies of points and values), then qhull.Delaunay(points) unless a Delaunay is given,
  then self.grad = estimate_gradients_2d_global(tri, values) (Nielson/Renka global curvature
  minimisation, Gauss-Seidel; it also computes the triangulation's lazy vertex_neighbor_vertices).
  - ct_build_points_s: all of it, from the raw points.
  - ct_build_tri_s:    all but the Delaunay, given a Delaunay whose lazy caches are still empty.
  - ct_build_grad_s:   "gradients given": NDInterpolatorBase.__init__ on the Delaunay, then .grad
                       set to the exact gradients; no Delaunay, no gradient estimate. scipy has no
                       public way to do this; bypassing __init__ this way gives an object equal to
                       a normally built one whose .grad is overwritten (checked to 1e-12).
  None of them includes the barycentric transforms (Delaunay.transform, lazy, paid by the first
  evaluation): that is ct_transform_s, and it is forced before the evaluation figures are taken.
matplotlib: the TrapezoidMapTriFinder (built by the interpolators' constructors unless the
Triangulation already has one) is mpl_trifinder_s; mpl_cubic_build_s and mpl_linear_build_s are
the constructors given a Triangulation that already has its trifinder.
"""
import argparse
import copy
import gc
import json
import os
import platform
import resource
import sys
import time

import numpy as np
import scipy
import matplotlib
from scipy.spatial import Delaunay
from scipy.interpolate import CloughTocher2DInterpolator
from scipy.interpolate.interpnd import NDInterpolatorBase
from matplotlib.tri import CubicTriInterpolator, LinearTriInterpolator, Triangulation

MESHES = ["grid16", "grid32", "grid64", "grid128", "grid256", "grid512",
          "del1e3", "del1e4", "del1e5"]
QUICK = ["grid16", "grid64", "del1e3"]
TILE = 1024
NCHECK = 1000           # scattered points whose scipy values go to NAME.scipy_vals.f64
PILOT = 10_000          # points of a first, untimed run that predicts a full one
CT_PREFIX_TRI = 100_000  # scipy: above this many triangles, scattered points on a prefix ...
CT_PREFIX = 100_000      # ... of this many
CT_MAX_S = 20.0          # scipy: a prefix too when one call on all points would take longer
MPL_PREFIX_TRI = 150_000  # matplotlib: likewise, above this many triangles ...
MPL_PREFIX = 100_000      # ... a prefix of this many
MPL_MAX_S = 40.0          # matplotlib: skip a figure whose run would take longer


def log(*args):
    print(*args, file=sys.stderr, flush=True)


def best_time(fn, setup=None):
    """Minimum of 3 runs of fn(setup()) if one takes under 1 s, else the one run; the setup is
    not timed. Returns (seconds, fn's result of the last run)."""
    best = None
    for _ in range(3):
        arg = setup() if setup else None
        t0 = time.perf_counter()
        result = fn(arg) if setup else fn()
        t = time.perf_counter() - t0
        best = t if best is None else min(best, t)
        if best >= 1.0:
            break
    return best, result


def nbytes(*arrays):
    return int(sum(a.nbytes for a in arrays if isinstance(a, np.ndarray)))


def pristine(tri):
    """A shallow copy of a Delaunay with its lazily computed arrays (transform, vertex
    neighbours, ...) not yet computed, as qhull.Delaunay returns it, sharing the big arrays."""
    t = copy.copy(tri)
    for attr in ("_transform", "_vertex_to_simplex", "_vertex_neighbor_vertices"):
        assert hasattr(t, attr), f"scipy's Delaunay has no {attr}: not the 1.10 layout"
        setattr(t, attr, None)
    return t


def ct_given_gradients(tri, values, grads):
    """A CloughTocher2DInterpolator on tri with the given gradients: CloughTocher2DInterpolator's
    __init__ without its Delaunay (tri is given) and without estimate_gradients_2d_global."""
    obj = CloughTocher2DInterpolator.__new__(CloughTocher2DInterpolator)
    NDInterpolatorBase.__init__(obj, tri, values, ndim=2, fill_value=np.nan, rescale=False)
    # The shape estimate_gradients_2d_global returns: (npoints, nvalues, 2).
    obj.grad = np.ascontiguousarray(grads, dtype=np.double).reshape(len(grads), 1, 2)
    return obj


def rate(evaluate, npoints, n_cap, max_s, shrink):
    """Points per second of one call evaluate(n) on the first n points. A pilot call on PILOT
    points (untimed; it also warms up) predicts the time for n = min(npoints, n_cap); over
    max_s, n shrinks to fit max_s if `shrink`, else the figure is skipped.
    Returns (pps or None, n, reason it was skipped or None)."""
    n = min(npoints, n_cap or npoints)
    t0 = time.perf_counter()
    evaluate(PILOT)
    predicted = (time.perf_counter() - t0) * n / PILOT
    if predicted > max_s:
        if not shrink:
            return None, n, f"predicted {predicted:.3g} s for {n} points, over {max_s:.3g} s"
        n = max(PILOT, int(n * max_s / predicted) // PILOT * PILOT)
    t, _ = best_time(lambda: evaluate(n))
    return n / t, n, None


def bench_scipy(name, outdir, points, simplices, values, grads, scattered, tile, fig):
    tri0 = Delaunay(points)
    # The triangles meshes.py wrote are these; otherwise tocher would not see the same mesh.
    assert np.array_equal(tri0.simplices, simplices), f"{name}: qhull's triangles differ"
    ntri = len(simplices)

    fig["ct_build_points_s"], _ = best_time(lambda: CloughTocher2DInterpolator(points, values))
    fig["ct_build_tri_s"], ct = best_time(lambda t: CloughTocher2DInterpolator(t, values),
                                          lambda: pristine(tri0))
    fig["ct_build_grad_s"], given = best_time(lambda t: ct_given_gradients(t, values, grads),
                                              lambda: pristine(tri0))
    fig["ct_transform_s"], _ = best_time(lambda t: t.transform, lambda: pristine(tri0))
    for interp in (ct, given):
        _ = interp.tri.transform  # paid here, not by the evaluations below
    log(f"  scipy build: points {fig['ct_build_points_s']:.4f} s, "
        f"tri {fig['ct_build_tri_s']:.4f} s, grads given {fig['ct_build_grad_s']:.2e} s, "
        f"transform {fig['ct_transform_s']:.4f} s")

    # The bypass is faithful: a normally built interpolator with .grad overwritten agrees.
    ref = CloughTocher2DInterpolator(pristine(tri0), values)
    ref.grad = grads.reshape(ref.grad.shape).copy()
    check = scattered[:NCHECK]
    vals = given(check)
    diff = np.max(np.abs(vals - ref(check)))
    assert diff <= 1e-12, f"{name}: gradients-given interpolator differs by {diff}"
    log(f"  scipy gradients given: {diff:.3g} from the normal one with .grad overwritten")
    vals.astype("<f8").tofile(os.path.join(outdir, name + ".scipy_vals.f64"))

    cap = CT_PREFIX if ntri > CT_PREFIX_TRI else None
    # (Row slices of a C-contiguous (N, 2) array are contiguous: scipy copies nothing.)
    fig["ct_eval_scattered_pps"], fig["ct_eval_scattered_n"], _ = rate(
        lambda n: ct(scattered[:n]), len(scattered), cap, CT_MAX_S, shrink=True)
    fig["ct_eval_tile_pps"], n, _ = rate(lambda n: ct(tile[:n]), len(tile), None, CT_MAX_S,
                                         shrink=True)
    if n < len(tile):
        fig["ct_eval_tile_n"] = n
    fig["ct_tile_checksum"] = float(np.sum(given(tile)))
    log(f"  scipy eval: scattered {fig['ct_eval_scattered_pps']:.3g} pts/s "
        f"(n={fig['ct_eval_scattered_n']}), tile {fig['ct_eval_tile_pps']:.3g} pts/s")

    tri = ct.tri
    fig["ct_bytes"] = nbytes(ct.grad, ct.values, tri.simplices, tri.neighbors, tri.points)
    # What evaluation also reads: the barycentric transforms and qhull's lifted hyperplanes.
    fig["ct_eval_extra_bytes"] = nbytes(tri.transform, tri.equations)
    return vals


def bench_mpl(points, simplices, values, grads, scattered, tile, fig, skipped, ct_vals):
    x, y = points[:, 0].copy(), points[:, 1].copy()
    ntri = len(simplices)

    fig["mpl_triangulation_s"], triang = best_time(lambda: Triangulation(x, y, simplices))
    fig["mpl_trifinder_s"], _ = best_time(lambda t: t.get_trifinder(),
                                          lambda: Triangulation(x, y, simplices))
    triang.get_trifinder()  # shared by both interpolators below, as their constructors would
    # values.copy(): CubicTriInterpolator renumbers its z in place through np.asarray.
    fig["mpl_cubic_build_s"], cubic = best_time(lambda: CubicTriInterpolator(
        triang, values.copy(), kind="user", dz=(grads[:, 0].copy(), grads[:, 1].copy())))
    fig["mpl_linear_build_s"], linear = best_time(
        lambda: LinearTriInterpolator(triang, values.copy()))
    log(f"  mpl build: trifinder {fig['mpl_trifinder_s']:.4f} s, "
        f"cubic {fig['mpl_cubic_build_s']:.4f} s, linear {fig['mpl_linear_build_s']:.4f} s")

    # Sanity, not a figure of merit: both are C1 cubics on the same data, different schemes.
    fig["mpl_cubic_vs_ct_maxdiff"] = float(np.max(np.abs(
        cubic(scattered[:NCHECK, 0], scattered[:NCHECK, 1]) - ct_vals)))

    # matplotlib takes x and y apart; contiguous copies made here, not in the timed calls.
    sx, sy = np.ascontiguousarray(scattered[:, 0]), np.ascontiguousarray(scattered[:, 1])
    tx, ty = np.ascontiguousarray(tile[:, 0]), np.ascontiguousarray(tile[:, 1])
    cap = MPL_PREFIX if ntri > MPL_PREFIX_TRI else None
    for kind, interp in (("cubic", cubic), ("linear", linear)):
        for where, (px, py), n_cap in (("tile", (tx, ty), None), ("scattered", (sx, sy), cap)):
            key = f"mpl_{kind}_{where}_pps"
            fig[key], n, reason = rate(lambda n, f=interp, px=px, py=py: f(px[:n], py[:n]),
                                       len(px), n_cap, MPL_MAX_S, shrink=False)
            if where == "scattered":
                fig[f"mpl_{kind}_scattered_n"] = n
            if reason:
                skipped[key] = reason
        tile_pps, scattered_pps = fig[f"mpl_{kind}_tile_pps"], fig[f"mpl_{kind}_scattered_pps"]
        log(f"  mpl {kind} eval: tile {tile_pps or 0:.3g} pts/s, scattered {scattered_pps or 0:.3g}"
            f" pts/s (n={fig[f'mpl_{kind}_scattered_n']}; 0 = skipped)")

    # The cubic's own arrays (_dof, _pts, _tris_pts, _triangles, _eccs, _z, ...) and the
    # Triangulation's; the C++ triangulation and trapezoid map are not visible from Python.
    fig["mpl_cubic_bytes"] = nbytes(x, y, triang.triangles,
                                    *[v for v in vars(cubic).values() if isinstance(v, np.ndarray)])


def main(argv):
    ap = argparse.ArgumentParser(description="Times scipy and matplotlib on the bench meshes.")
    ap.add_argument("outdir")
    ap.add_argument("--quick", action="store_true", help="only grid16, grid64 and del1e3")
    args = ap.parse_args(argv[1:])

    t_start = time.perf_counter()
    scattered = np.fromfile(os.path.join(args.outdir, "points.f64"), dtype="<f8").reshape(-1, 2)
    t = (np.arange(TILE) + 0.5) / TILE
    tx, ty = np.meshgrid(t, t)  # row j, column i: (x_i, y_j)
    tile = np.column_stack([tx.ravel(), ty.ravel()])

    out = {"versions": {"python": platform.python_version(), "numpy": np.__version__,
                        "scipy": scipy.__version__, "matplotlib": matplotlib.__version__},
           "meshes": {}}
    for name in QUICK if args.quick else MESHES:
        t0 = time.perf_counter()
        data = np.load(os.path.join(args.outdir, name + ".npz"))
        points, simplices = data["points"], data["simplices"]
        values, grads = data["values"], data["grads"]
        log(f"{name}: {len(points)} vertices, {len(simplices)} triangles")
        fig = {"vertices": len(points), "triangles": len(simplices)}
        skipped = {}
        ct_vals = bench_scipy(name, args.outdir, points, simplices, values, grads,
                              scattered, tile, fig)
        gc.collect()
        bench_mpl(points, simplices, values, grads, scattered, tile, fig, skipped, ct_vals)
        gc.collect()
        if skipped:
            fig["skipped"] = skipped
        fig["peak_rss_kb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        fig["wall_s"] = time.perf_counter() - t0
        out["meshes"][name] = fig
        log(f"  {fig['wall_s']:.1f} s, peak RSS {fig['peak_rss_kb'] // 1024} MB")
    log(f"total {time.perf_counter() - t_start:.1f} s")
    json.dump(out, sys.stdout, indent=1)
    print()


if __name__ == "__main__":
    main(sys.argv)
