"""Times one tocher thread rendering the 1024² tile of grid64 and scipy's CloughTocher2DInterpolator
evaluating the same pixel centres, in alternating rounds, so that both see the same spells of a
noisy machine: the ratio of issue 17 ("≥ 25× scipy, in the same run") measured side by side.

    /usr/bin/python3 bench/perf/tileratio.py BUILD_DIR [ROUNDS]     -> JSON on stdout

Each round: scipy's best of three calls on all 1024² centres (wall clock), then `bench_scaling grid64.json 1024 1`
(its best wall time over at least 3 renders and 0.5 s, the mesh already built). Reported: the
median of the rounds' ratios, their range, and the best tocher rate over the best scipy rate.
bench/perf/run.sh writes BUILD_DIR/perf (grid64.npz, grid64.json) first.
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


def scipy_rate(ct, tile, reps=3):
    """scipy's best of `reps` calls: each side of a round its best, as bench_scaling takes tocher's."""
    best = 0.0
    for _ in range(reps):
        t0 = time.perf_counter()
        ct(tile)
        best = max(best, len(tile) / (time.perf_counter() - t0))
    return best


def tocher_rate(build, perf):
    out = subprocess.run([os.path.join(build, "bench_scaling"), os.path.join(perf, "grid64.json"),
                          str(TILE), "1"], check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])["runs"][0]["mpixel_s"] * 1e6


def main(argv):
    build = argv[1] if len(argv) > 1 else "build"
    rounds = int(argv[2]) if len(argv) > 2 else 9
    perf = os.path.join(build, "perf")
    data = np.load(os.path.join(perf, "grid64.npz"))
    ct = CloughTocher2DInterpolator(data["points"], data["values"])
    t = (np.arange(TILE) + 0.5) / TILE
    tx, ty = np.meshgrid(t, t)
    tile = np.column_stack([tx.ravel(), ty.ravel()])
    ct(tile[:10000])  # warm-up: the triangulation's transform, the first pages
    sc, tc = [], []
    for _ in range(rounds):
        sc.append(scipy_rate(ct, tile))
        tc.append(tocher_rate(build, perf))
    ratios = sorted(a / b for a, b in zip(tc, sc))
    print(json.dumps({"rounds": rounds, "tile": TILE, "mesh": "grid64",
                      "scipy_pps": sc, "tocher_pps": tc,
                      "ratio_median": statistics.median(ratios), "ratio_min": ratios[0],
                      "ratio_max": ratios[-1], "ratio_best": max(tc) / max(sc)}))


if __name__ == "__main__":
    main(sys.argv)
