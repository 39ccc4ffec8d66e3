"""sidebyside.py — issue 17's ratios against scipy's CloughTocher2DInterpolator, each measured in
alternating rounds so that both sides see the same spells of a noisy machine ("in the same run").

    /usr/bin/python3 bench/perf/sidebyside.py BUILD_DIR [ROUNDS]     -> JSON on stdout

Each round, each side its best of three (wall clock):
  tile       scipy on the 1024² pixel centres of grid64's unit square, then
             `bench_scaling grid64.json 1024 1` (its best render over at least 3 and 0.5 s);
  scattered  scipy on bench/perf/meshes.py's random points (grid16: all 1e6; grid256: the first
             1e5, as peers.py does above 1e5 triangles: scipy walks from the last point found,
             slow on a large mesh), then `bench_points --batch` (tc_eval_points on all 1e6).
Reported per comparison: the median of the rounds' ratios, their range, and the best tocher rate
over the best scipy rate. bench/perf/run.sh writes BUILD_DIR/perf (the meshes, points.f64) first.
"""
import json
import os
import statistics
import subprocess
import sys
import time

import numpy as np
from scipy.interpolate import CloughTocher2DInterpolator

TILE = 1024
SCATTERED = {"grid16": None, "grid256": 100_000}  # mesh: scipy's prefix of the points (None: all)


def best_rate(fn, n, reps=3):
    best = 0.0
    for _ in range(reps):
        t0 = time.perf_counter()
        fn()
        best = max(best, n / (time.perf_counter() - t0))
    return best


def run_json(cmd):
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip() if cmd[0].endswith("bench_points") else out.strip().splitlines()[-1])


def interpolator(perf, name):
    data = np.load(os.path.join(perf, name + ".npz"))
    return CloughTocher2DInterpolator(data["points"], data["values"])


def summary(sc, tc):
    ratios = sorted(a / b for a, b in zip(tc, sc))
    return {"scipy_pps": sc, "tocher_pps": tc, "ratio_median": statistics.median(ratios),
            "ratio_min": ratios[0], "ratio_max": ratios[-1], "ratio_best": max(tc) / max(sc)}


def main(argv):
    build = argv[1] if len(argv) > 1 else "build"
    rounds = int(argv[2]) if len(argv) > 2 else 9
    perf = os.path.join(build, "perf")
    t = (np.arange(TILE) + 0.5) / TILE
    tx, ty = np.meshgrid(t, t)
    tile = np.column_stack([tx.ravel(), ty.ravel()])
    pts = np.fromfile(os.path.join(perf, "points.f64"), dtype="<f8").reshape(-1, 2)
    cts = {name: interpolator(perf, name) for name in ["grid64", *SCATTERED]}
    for ct in cts.values():
        ct(pts[:10000])  # warm-up: the triangulation's transform, the first pages
    scipy_bench = {name: (lambda ct=cts[name], q=pts[:cap or len(pts)]: ct(q), cap or len(pts))
                   for name, cap in SCATTERED.items()}
    tile_s, tile_t = [], []
    scat_s = {name: [] for name in SCATTERED}
    scat_t = {name: [] for name in SCATTERED}
    for _ in range(rounds):
        tile_s.append(best_rate(lambda: cts["grid64"](tile), len(tile)))
        tile_t.append(run_json([os.path.join(build, "bench_scaling"), os.path.join(perf, "grid64.json"),
                                str(TILE), "1"])["runs"][0]["mpixel_s"] * 1e6)
        for name, (fn, n) in scipy_bench.items():
            scat_s[name].append(best_rate(fn, n))
        got = run_json([os.path.join(build, "bench_points"), "--batch", perf, *SCATTERED])
        for name in SCATTERED:
            scat_t[name].append(got["points"] / got["meshes"][name]["points_s"])
    out = {"rounds": rounds, "tile": dict(summary(tile_s, tile_t), size=TILE, mesh="grid64"),
           "scattered": {name: dict(summary(scat_s[name], scat_t[name]), scipy_points=n)
                         for name, (_, n) in scipy_bench.items()}}
    print(json.dumps(out))


if __name__ == "__main__":
    main(sys.argv)
