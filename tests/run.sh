#!/bin/sh
# run.sh — runs every test suite against the build in $1 (default: build) and
# prints the combined tally as the last line: "N passed, N failed".
set -u
B=${1:-build}
total_pass=0; total_fail=0
tally() { # $1 = a suite's last output line "N passed, N failed"
  p=$(echo "$1" | sed -n 's/^\([0-9]*\) passed, \([0-9]*\) failed$/\1/p')
  f=$(echo "$1" | sed -n 's/^\([0-9]*\) passed, \([0-9]*\) failed$/\2/p')
  if [ -z "$p" ]; then total_fail=$((total_fail + 1)); return; fi
  total_pass=$((total_pass + p)); total_fail=$((total_fail + f))
}
run_suite() { # $1 = name, rest = command
  name=$1; shift
  echo "== $name"
  out=$("$@" 2>&1); rc=$?
  echo "$out" | sed 's/^/   /'
  last=$(echo "$out" | tail -n 1)
  tally "$last"
  [ $rc -eq 0 ] || echo "   ($name exited with $rc)"
}
run_suite unit "$B/test_unit"
for t in tests/cli/*.sh; do
  [ -e "$t" ] || continue
  run_suite "$(basename "$t")" sh "$t" "$B/tocher"
done
for t in tests/endpoint/*.sh; do
  [ -e "$t" ] || continue
  run_suite "$(basename "$t")" sh "$t" "$B/tocherd"
done
for t in tests/endpoint/*.py; do
  [ -e "$t" ] || continue
  run_suite "$(basename "$t")" /usr/bin/python3 "$t" "$B"
done
# The cluster (issue 16): real redis-server, nginx and tocherd replicas on loopback.
for t in tests/cluster/*.py; do
  [ -e "$t" ] || continue
  run_suite "$(basename "$t")" /usr/bin/python3 "$t" "$B"
done
for t in tests/stability/test_*.py; do
  [ -e "$t" ] || continue
  run_suite "$(basename "$t")" /usr/bin/python3 "$t" "$B"
done
for t in tests/peers/*.py; do
  [ -e "$t" ] || continue
  run_suite "$(basename "$t")" /usr/bin/python3 "$t" "$B/tocher"
done
echo "$total_pass passed, $total_fail failed"
[ "$total_fail" -eq 0 ]
