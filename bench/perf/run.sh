#!/bin/sh
# run.sh — `make bench`: writes the inputs, times scipy, matplotlib and tocher on them in one run,
# then the daemon under wrk (stateless routes, then stored-mesh tiles: stored.py; the Redis store:
# redis.py; a cluster behind nginx: cluster.py), and writes
# docs/performance.md from the figures (bench/perf/report.py).
#
#     bench/perf/run.sh BUILD_DIR          (BENCH_QUICK=1: the three small meshes only)
set -eu
B=${1:-build}
OUT=$B/perf
PY=/usr/bin/python3
Q=""
[ "${BENCH_QUICK:-0}" = 1 ] && Q=--quick
mkdir -p "$OUT"
echo "bench: inputs -> $OUT"
$PY bench/perf/meshes.py "$OUT" $Q
names=$(tail -n +2 "$OUT/meshes.tsv" | cut -f1)
echo "bench: scipy and matplotlib"
$PY bench/perf/peers.py "$OUT" $Q > "$OUT/peers.json"
echo "bench: tocher"
"$B/bench_perf" "$OUT" $names > "$OUT/tocher.json"
echo "bench: tiles per thread (bench_scaling: grid64, 1024² and 4096², 1 and 2 threads)"
"$B/bench_scaling" "$OUT/grid64.json" 1024 1,2 > "$OUT/scaling1024.json"
"$B/bench_scaling" "$OUT/grid64.json" 4096 1,2 > "$OUT/scaling4096.json"
echo "bench: that 1024² tile and scattered points against scipy, in alternating rounds (sidebyside.py)"
$PY bench/perf/sidebyside.py "$B" 9 > "$OUT/sidebyside.json"
echo "bench: number printing (tc_fmt_double, the old cascade, printf %.17g)"
"$B/bench_numfmt" > "$OUT/numfmt.json"
echo "bench: validation against build (bench_validate: grids, polylines, a wheel; n and 4n; 1 and 2 threads)"
"$B/bench_validate" --threads 1,2 --reps 3 $( [ -n "$Q" ] && echo --quick ) > "$OUT/validate.txt"
echo "bench: whole /v1/ordinates requests against scipy (JSON and typed arrays)"
$PY bench/perf/whole.py "$B" $( [ -n "$Q" ] && echo --quick ) > "$OUT/whole.json"
echo "bench: tocherd under wrk"
$PY bench/perf/daemon.py "$B" 10 > "$OUT/daemon.json"
echo "bench: stored meshes (tiles)"
$PY bench/perf/stored.py "$B" > "$OUT/stored.json"
echo "bench: stored meshes in Redis (bytes, cache misses)"
$PY bench/perf/redis.py "$B" > "$OUT/redis.json"
echo "bench: tiles through nginx with 1, 2 and 3 replicas (redis, tocherd, nginx on loopback)"
$PY bench/perf/cluster.py "$B" > "$OUT/cluster.json"
lscpu > "$OUT/lscpu.txt" 2>/dev/null || true
$PY bench/perf/report.py "$OUT" docs/performance.md
echo "bench: wrote docs/performance.md"
