"""Scattered-point evaluation, tocher against scipy in one run (issue 17 §3): points per second of
tc_eval_points (build/bench_points) and of scipy's CloughTocher2DInterpolator on the same meshes
and the same 1e6 uniform random points, one thread each.

    /usr/bin/python3 bench/perf/points.py BUILD_DIR [OUTDIR] [--meshes grid16,grid256,del1e5]
                                          [--rounds 3]

Writes the meshes (bench/perf/meshes.py's, byte for byte) into OUTDIR (default BUILD_DIR/points)
unless they are there, then for each mesh alternates scipy and tocher `--rounds` times and keeps
each one's best, so both see the same machine state. Times are CPU time of the measuring thread
(time.thread_time, CLOCK_THREAD_CPUTIME_ID), which a busy shared machine disturbs least; tocher's
2-thread figure is wall time. scipy walks from the last simplex found, so on meshes above 1e5
triangles it gets the first 1e5 points (as in peers.py); tocher always gets all 1e6.
Prints JSON: per mesh scipy_pps, tocher_pps (values), tocher_grad_pps, tocher_2t_pps, the old
path's (ref_pps), the ratios and bench_points' own figures.
"""
import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import meshes as M  # noqa: E402

from scipy.interpolate import CloughTocher2DInterpolator  # noqa: E402
from scipy.interpolate.interpnd import NDInterpolatorBase  # noqa: E402
from scipy.spatial import Delaunay  # noqa: E402

PREFIX_TRI = 100_000
PREFIX = 100_000


def log(*a):
    print(*a, file=sys.stderr, flush=True)


def write_inputs(outdir, names):
    os.makedirs(outdir, exist_ok=True)
    for name in names:
        if os.path.exists(os.path.join(outdir, name + ".npz")):
            continue
        if name.startswith("grid"):
            n = int(name[4:])
            pts = M.grid_points(n)
            simp = M.triangulate(pts, 2 * n * n)
        else:
            pts = M.scattered_points(10 ** int(name[5:]))
            simp = M.triangulate(pts)
        M.write_mesh(outdir, name, pts, simp)
    path = os.path.join(outdir, "points.f64")
    if not os.path.exists(path):
        pts = np.random.default_rng(M.SEED_POINTS).random((M.NPOINTS, 2))
        pts.astype("<f8").tofile(path)


def scipy_interp(npz):
    d = np.load(npz)
    tri = Delaunay(d["points"])
    obj = CloughTocher2DInterpolator.__new__(CloughTocher2DInterpolator)
    NDInterpolatorBase.__init__(obj, tri, d["values"], ndim=2, fill_value=np.nan, rescale=False)
    obj.grad = np.ascontiguousarray(d["grads"], dtype=np.double).reshape(len(d["grads"]), 1, 2)
    _ = obj.tri.transform  # lazily computed: paid here, not in the timed calls
    return obj, len(d["simplices"])


def scipy_best(interp, pts):
    t0 = time.thread_time()
    interp(pts)
    return time.thread_time() - t0


def main(argv):
    ap = argparse.ArgumentParser()
    ap.add_argument("build")
    ap.add_argument("outdir", nargs="?")
    ap.add_argument("--meshes", default="grid16,grid256,del1e5")
    ap.add_argument("--rounds", type=int, default=3)
    a = ap.parse_args(argv[1:])
    outdir = a.outdir or os.path.join(a.build, "points")
    names = a.meshes.split(",")
    write_inputs(outdir, names)
    scattered = np.fromfile(os.path.join(outdir, "points.f64"), dtype="<f8").reshape(-1, 2)
    out = {"points": len(scattered), "meshes": {}}
    for name in names:
        interp, ntri = scipy_interp(os.path.join(outdir, name + ".npz"))
        n_sp = PREFIX if ntri > PREFIX_TRI else len(scattered)
        pts = scattered[:n_sp]
        interp(pts[:1000])  # warm up
        s_best, t_best = None, None
        for r in range(a.rounds):
            s = scipy_best(interp, pts)
            s_best = s if s_best is None else min(s_best, s)
            res = subprocess.run([os.path.join(a.build, "bench_points"), outdir, name],
                                 check=True, capture_output=True, text=True)
            fig = json.loads(res.stdout)["meshes"][name]
            if t_best is None:
                t_best = fig
            else:
                t_best = {k: (min(v, fig[k]) if k.endswith("_s") else v and fig[k]) for k, v in t_best.items()}
            log(f"{name} round {r}: scipy {n_sp / s:.4g} pts/s, tocher {len(scattered) / fig['points_s']:.4g} pts/s")
        n = len(scattered)
        row = {"triangles": ntri, "scipy_points": n_sp, "scipy_pps": n_sp / s_best,
               "tocher_pps": n / t_best["points_s"], "tocher_grad_pps": n / t_best["points_grad_s"],
               "tocher_2t_pps": n / t_best["points_2t_s"], "ref_pps": n / t_best["ref_s"],
               "ref_grad_pps": n / t_best["ref_grad_s"]}
        row["tocher_over_scipy"] = row["tocher_pps"] / row["scipy_pps"]
        row["ref_over_scipy"] = row["ref_pps"] / row["scipy_pps"]
        row["bench_points"] = t_best
        out["meshes"][name] = row
        log(f"{name}: tocher {row['tocher_pps']:.4g} pts/s ({row['tocher_over_scipy']:.3g}x scipy), "
            f"old path {row['ref_pps']:.4g} ({row['ref_over_scipy']:.3g}x), scipy {row['scipy_pps']:.4g}")
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main(sys.argv)
