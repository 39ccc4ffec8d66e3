#!/bin/sh
# run.sh — runs every test suite against the build in $1 (default: build) and
# prints the combined tally as the last line: "N passed, N failed". Before it, a digest of
# each suite that failed (its exit status, its failure and sanitizer lines, its last lines):
# CI shows only the end of the output, and that end must say what went wrong.
set -u
B=${1:-build}
total_pass=0; total_fail=0
digest=$(mktemp); trap 'rm -f "$digest"' EXIT
tally() { # $1 = a suite's last output line "N passed, N failed"; 0 when it says none failed
  p=$(echo "$1" | sed -n 's/^\([0-9]*\) passed, \([0-9]*\) failed$/\1/p')
  f=$(echo "$1" | sed -n 's/^\([0-9]*\) passed, \([0-9]*\) failed$/\2/p')
  if [ -z "$p" ]; then total_fail=$((total_fail + 1)); return 1; fi
  total_pass=$((total_pass + p)); total_fail=$((total_fail + f))
  [ "$f" -eq 0 ]
}
run_suite() { # $1 = name, rest = command
  name=$1; shift
  echo "== $name"
  out=$("$@" 2>&1); rc=$?
  echo "$out" | sed 's/^/   /'
  last=$(echo "$out" | tail -n 1)
  if tally "$last" && [ $rc -eq 0 ]; then return; fi
  [ $rc -eq 0 ] || echo "   ($name exited with $rc)"
  { echo "!! $name: exit status $rc, last line: $last"
    echo "$out" | grep -E 'FAIL|Assertion|assert|Traceback|Error:' | head -n 6 | cut -c1-300 | sed 's/^/!!   /'
    echo "$out" | grep -E -A6 'ERROR: .*Sanitizer|runtime error' | head -n 10 | cut -c1-300 | sed 's/^/!!   /'
    echo "$out" | tail -n 4 | cut -c1-300 | sed 's/^/!!   | /'; } >>"$digest"
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
if [ -s "$digest" ]; then echo "== what failed"; cat "$digest"; fi
echo "$total_pass passed, $total_fail failed"
[ "$total_fail" -eq 0 ]
