#!/bin/sh
# device.sh — the thread-scaling figures of issue 17 on a machine with more cores than the
# development one (the `device` tool lends a 16-core one): tiles and the build at 1..16 threads,
# and scipy on the same tile's pixel centres, one call (three rounds of each). Not part of `make bench` (CI never has
# such a machine); its output is committed under bench/perf/device/ and read by report.py.
#
#     bench/perf/device.sh DIR OUT     DIR holds bench_scaling, libcjson.so.1 (and bench_clockprobe) built here, and
#                                      meshes/ (bench/perf/meshes.py's grid16, grid64, grid512,
#                                      del1e4 .json and grid64.npz), carried so nothing is made there
set -eu
D=$1
OUT=$2
M=$D/meshes
mkdir -p "$OUT"
export LD_LIBRARY_PATH="$D${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
(lscpu; nproc) > "$OUT/lscpu.txt" 2>&1 || true
T="1,2,4,8,12,16"
# the cores' clock with 1..16 of them busy (bench_clockprobe), if carried: a speed-up that falls
# with the clock is the machine's, not the code's
[ -x "$D/bench_clockprobe" ] && "$D/bench_clockprobe" "$T" > "$OUT/clockprobe.txt"
for m in grid16 del1e4; do "$D/bench_scaling" "$M/$m.json" 1024 1; done > "$OUT/tile1024_others.json"
# Rounds in turns, each a fresh process: the lent machine has slow spells of seconds (the same
# binary measured 23 and 43 Mpixel/s minutes apart), which best-of runs inside one process do
# not escape. report.py takes each thread count's best over the rounds.
for r in 1 2 3; do
  "$D/bench_scaling" "$M/grid64.json" 1024 "$T" > "$OUT/tile1024_r$r.json"
  "$D/bench_scaling" "$M/grid64.json" 4096 "$T" > "$OUT/tile4096_r$r.json"
  "$D/bench_scaling" --build "$M/grid512.json" "$T" > "$OUT/build524k_r$r.json"
  # the build without the huge-page advice (bench_scaling built with -DTC__HUGE_MIN=SIZE_MAX), if carried
  [ -x "$D/nothp/bench_scaling" ] && "$D/nothp/bench_scaling" --build "$M/grid512.json" "$T" > "$OUT/build524k_nothp_r$r.json"
done
${PY:-python3} - "$M" > "$OUT/scipy_tile.json" <<'PY'
import json, sys, time
import numpy as np
from scipy.interpolate import CloughTocher2DInterpolator
z = np.load(sys.argv[1] + "/grid64.npz")
ct = CloughTocher2DInterpolator(z["points"], z["values"])  # qhull here gives meshes.py's triangles
c = (np.arange(1024) + 0.5) / 1024
xy = np.stack(np.meshgrid(c, c[::-1]), axis=-1).reshape(-1, 2)  # row by row from the top, as a tile
ct(xy[:1000])
best = min((lambda t0: (ct(xy), time.perf_counter() - t0)[1])(time.perf_counter()) for _ in range(3))
print(json.dumps({"mesh": "grid64", "points": len(xy), "seconds": best, "per_s": len(xy) / best}))
PY
