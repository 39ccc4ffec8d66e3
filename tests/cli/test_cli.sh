#!/bin/sh
# test_cli.sh — black-box tests of the tocher command-line tool ($1, default build/tocher):
# arguments, exit codes, stdin/-o handling, and that its output is the API's JSON.
set -u
CLI=${1:-build/tocher}
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
EX=$ROOT/api/examples
PY=/usr/bin/python3
T=$(mktemp -d "${TMPDIR:-/tmp}/tocher-cli.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT
trap 'exit 1' HUP INT TERM
pass=0
fail=0

ok() { pass=$((pass + 1)); echo "ok   $1"; }
bad() { fail=$((fail + 1)); echo "FAIL $1: $2"; }

# run CMD...: stdout -> $T/out, stderr -> $T/err, exit status -> $rc
run() { "$@" >"$T/out" 2>"$T/err"; rc=$?; }

# expect NAME WANT_RC [STDERR_SUBSTRING]: checks the last run
expect() {
  if [ "$rc" -ne "$2" ]; then
    bad "$1" "exit $rc, expected $2; stderr: $(head -c 300 "$T/err")"
  elif [ $# -ge 3 ] && ! grep -qF -- "$3" "$T/err"; then
    bad "$1" "stderr does not contain '$3': $(head -c 300 "$T/err")"
  else
    ok "$1"
  fi
}

# check NAME DETAIL CMD...: passes when CMD succeeds
check() {
  name=$1 detail=$2
  shift 2
  if "$@"; then ok "$name"; else bad "$name" "$detail"; fi
}
empty() { [ ! -s "$1" ]; }

is_json() { "$PY" -c 'import json,sys; json.load(sys.stdin)' <"$1" 2>/dev/null; }

# same NAME FILE1 FILE2: identical bytes, non-empty
same() {
  if [ ! -s "$2" ]; then bad "$1" "$2 is empty"
  elif cmp -s "$2" "$3"; then ok "$1"
  else bad "$1" "$2 and $3 differ"; fi
}

if [ ! -x "$CLI" ]; then
  echo "FAIL: $CLI is not an executable"
  echo "0 passed, 1 failed"
  exit 1
fi

# ---- help and version ----------------------------------------------------------------
for a in help --help -h ""; do
  if [ -n "$a" ]; then run "$CLI" "$a"; else run "$CLI"; fi
  if [ "$rc" -eq 0 ] && grep -q '^usage: tocher' "$T/out" && [ ! -s "$T/err" ]; then ok "help '$a'"
  else bad "help '$a'" "exit $rc, or no usage on stdout"; fi
done
for a in version --version; do
  run "$CLI" "$a"
  if [ "$rc" -eq 0 ] && grep -Eq '^tocher [0-9]+\.[0-9]+\.[0-9]+' "$T/out"; then ok "$a"
  else bad "$a" "exit $rc, stdout: $(head -c 100 "$T/out")"; fi
done

# ---- usage errors: exit 2, usage on stderr, nothing on stdout -------------------------
usage_case() { # NAME ARGS...
  name=$1; shift
  run "$CLI" "$@"
  if [ "$rc" -eq 2 ] && grep -q '^usage: tocher' "$T/err" && [ ! -s "$T/out" ]; then ok "$name"
  else bad "$name" "exit $rc, expected 2 with usage on stderr and empty stdout"; fi
}
usage_case "unknown command" frobnicate "$EX/square-light.json"
usage_case "ordinates without a file" ordinates
usage_case "eval without a file" eval
usage_case "ordinates with two files" ordinates "$EX/square-light.json" "$EX/points.json"
usage_case "eval with three files" eval "$EX/shadow-edges.json" "$EX/points.json" "$EX/points.json"
usage_case "unknown option" ordinates --frob "$EX/square-light.json"
usage_case "-o without a name" ordinates "$EX/square-light.json" -o

# ---- file errors: exit 4, naming the file ---------------------------------------------
run "$CLI" ordinates "$T/no-such-file.json"
expect "nonexistent mesh file" 4 "no-such-file.json"
run "$CLI" eval "$EX/shadow-edges.json" "$T/no-such-points.json"
expect "nonexistent points file" 4 "no-such-points.json"
run "$CLI" ordinates "$EX/square-light.json" -o "$T/no-such-dir/out.json"
expect "unwritable -o" 4 "no-such-dir/out.json"
mkdir "$T/adir"
run "$CLI" ordinates "$T/adir"
expect "directory as mesh file" 4 "adir"
if [ -w /dev/full ]; then
  run "$CLI" ordinates "$EX/square-light.json" -o /dev/full
  expect "-o on a full device" 4 "/dev/full"
  "$CLI" ordinates "$EX/square-light.json" >/dev/full 2>"$T/err"; rc=$?
  expect "stdout on a full device" 4 "stdout"
fi
: >"$T/empty.json"
run "$CLI" ordinates "$T/empty.json"
expect "empty mesh file: exit 3" 3 "empty request"

# ---- invalid input: exit 3, the JSON path on stderr, nothing on stdout ----------------
printf '%s\n' '{"vertices": [[0,0],[1,0],[2,0],[0,1]], "triangles": [[0,1,3],[0,1,2]], "values": [1,2,3,4]}' \
  >"$T/zero-area.json"
run "$CLI" ordinates "$T/zero-area.json"
expect "invalid mesh: exit 3 naming triangles[1]" 3 "triangles[1]"
check "invalid mesh: empty stdout" "stdout not empty" empty "$T/out"
run "$CLI" eval "$T/zero-area.json" "$EX/points.json"
expect "invalid mesh (eval): exit 3 naming triangles[1]" 3 "triangles[1]"
printf '%s\n' '{"vertices": [[0,0],[1,0],[0,1]], "triangles": [[0,1,2]], "values": [1,"two",3]}' >"$T/shape.json"
run "$CLI" ordinates "$T/shape.json"
expect "malformed value: exit 3 naming values[1]" 3 "values[1]"
# Findings about the points file name the points file, not the mesh file.
printf '%s\n' '{"points": [[0.5]], "colour": 1}' >"$T/bad-points.json"
run "$CLI" eval "$EX/square-light.json" "$T/bad-points.json"
expect "bad points file: exit 3 naming that file" 3 "bad-points.json: error: points[0]"
check "bad points file: the mesh file is not blamed" "stderr blames the mesh file" \
  sh -c '! grep -q "square-light.json" "$1"' sh "$T/err"
printf '%s' '{"vertices": [[0,0],' >"$T/truncated.json"
run "$CLI" ordinates "$T/truncated.json"
expect "truncated JSON: exit 3" 3 "not valid JSON"
run "$CLI" eval "$EX/square-light.json"
expect "eval without points: exit 3 naming points" 3 "points"
printf '%s\n' '{"points": [[0.5]]}' >"$T/badpoints.json"
run "$CLI" eval "$EX/square-light.json" "$T/badpoints.json"
expect "bad points document: exit 3 naming points[0]" 3 "points[0]"

# ---- ordinates: file, stdin and -o give the same bytes, valid JSON --------------------
run "$CLI" ordinates "$EX/square-light.json"
cp "$T/out" "$T/ord-file.json"
expect "ordinates from a file" 0
check "ordinates output is JSON" "does not parse" is_json "$T/ord-file.json"
check "ordinates output has ordinates" "member missing" grep -q '"ordinates":\[' "$T/ord-file.json"
"$CLI" ordinates - <"$EX/square-light.json" >"$T/ord-stdin.json" 2>"$T/err"; rc=$?
expect "ordinates from stdin" 0
same "ordinates: stdin = file" "$T/ord-file.json" "$T/ord-stdin.json"
run "$CLI" ordinates "$EX/square-light.json" -o "$T/ord-o.json"
expect "ordinates -o" 0
check "ordinates -o: empty stdout" "stdout not empty" empty "$T/out"
same "ordinates -o = stdout" "$T/ord-file.json" "$T/ord-o.json"
run "$CLI" ordinates -o "$T/ord-o2.json" - <"$EX/square-light.json"
expect "ordinates -o before stdin" 0
same "ordinates -o before - = stdout" "$T/ord-file.json" "$T/ord-o2.json"
run "$CLI" ordinates "$EX/square-light.json"
same "ordinates: deterministic" "$T/ord-file.json" "$T/out"
run "$CLI" ordinates "$EX/shadow-edges.json"
expect "ordinates shadow-edges" 0
check "ordinates shadow-edges output is JSON" "does not parse" is_json "$T/out"

# ---- eval: MESH POINTS equals one document with the same points ----------------------
run "$CLI" eval "$EX/shadow-edges.json" "$EX/points.json"
cp "$T/out" "$T/eval-two.json"
expect "eval MESH POINTS" 0
check "eval output is JSON" "does not parse" is_json "$T/eval-two.json"
"$PY" - "$EX/shadow-edges.json" "$EX/points.json" "$T/combined.json" <<'EOF'
import json, sys
mesh = json.load(open(sys.argv[1]))
mesh.update(json.load(open(sys.argv[2])))
json.dump(mesh, open(sys.argv[3], "w"))
EOF
run "$CLI" eval "$T/combined.json"
expect "eval of one document" 0
same "eval: MESH POINTS = one document" "$T/eval-two.json" "$T/out"
"$CLI" eval "$EX/shadow-edges.json" - <"$EX/points.json" >"$T/eval-stdin.json" 2>"$T/err"; rc=$?
expect "eval points from stdin" 0
same "eval: points from stdin = file" "$T/eval-two.json" "$T/eval-stdin.json"
run "$CLI" eval "$EX/shadow-edges.json" "$EX/points.json" -o "$T/eval-o.json"
expect "eval -o" 0
same "eval -o = stdout" "$T/eval-two.json" "$T/eval-o.json"
# The example points: 5 values, with gradients, the last point outside.
if "$PY" - "$T/eval-two.json" 2>/dev/null <<'EOF'
import json, sys
r = json.load(open(sys.argv[1]))
v, g = r["values"], r["gradients"]
assert len(v) == 5 and len(g) == 5, r
assert all(isinstance(x, float) for x in v[:4]) and v[4] is None, v
assert all(len(x) == 2 for x in g[:4]) and g[4] is None, g
assert r["outside"] == [4] and r["warnings"] == [], r
EOF
then ok "eval output content"; else bad "eval output content" "unexpected values/gradients/outside"; fi

# ---- warnings: exit 0, on stderr and in the JSON --------------------------------------
printf '%s\n' '{"vertices": [[0,0],[1,0],[0,1]], "triangles": [[0,1,2]], "values": [1,2,3], "colour": 1}' \
  >"$T/warn.json"
run "$CLI" ordinates "$T/warn.json"
expect "unknown field: exit 0, warning on stderr" 0 "colour"
if "$PY" -c 'import json,sys; w = json.load(sys.stdin)["warnings"]; assert w[0]["path"] == "colour", w' \
  <"$T/out" 2>/dev/null; then ok "unknown field: warning in the JSON"
else bad "unknown field: warning in the JSON" "$(head -c 300 "$T/out")"; fi

# ---- scene --quads: a quad mesh for hermite; adaptive meshes cannot be quads ---------
run "$CLI" scene penumbra --quads --density 2 -o "$T/quads.json"
expect "scene --quads: exit 0" 0
if "$PY" -c 'import json,sys; r = json.load(sys.stdin)
assert "quads" in r and "triangles" not in r and r["method"] == "hermite", list(r)
assert all(len(q) == 4 for q in r["quads"])' <"$T/quads.json" 2>/dev/null; then ok "scene --quads: quads, method hermite"
else bad "scene --quads: quads, method hermite" "$(head -c 300 "$T/quads.json")"; fi
run "$CLI" ordinates "$T/quads.json"
expect "ordinates of a scene's quad mesh: exit 0" 0
if "$PY" -c 'import json,sys; r = json.load(sys.stdin); assert r["method"] == "hermite" and len(r["labels"]) == 22, r["labels"]' \
  <"$T/out" 2>/dev/null; then ok "hermite ordinates: 22 labels"
else bad "hermite ordinates: 22 labels" "$(head -c 300 "$T/out")"; fi
run "$CLI" scene penumbra --quads --mesh adaptive
expect "scene --quads --mesh adaptive: exit 3" 3 "hanging vertices"

# ---- scene --mesh dm: fans as discontinuity meshers make them; no C0, printed values, a patch
run "$CLI" scene stiff --mesh dm --window 0.305,0.355,0.335,0.385 --rotate 35 --density 2 --no-c0 --digits 6 \
  --no-midpoints -o "$T/dm.json"
expect "scene --mesh dm --no-c0 --digits 6 --window --rotate: exit 0" 0
if "$PY" -c 'import json,sys; r = json.load(sys.stdin); d = r.get("discontinuities", {})
assert not d.get("c0") and "midpoints" not in r and len(r["triangles"]) > 10, list(r)
assert all(float("%.5e" % v) == v for v in r["values"]), "not 6 digits"
x = [p[0] for p in r["vertices"]]; y = [p[1] for p in r["vertices"]]
assert min(x) == 0.305 and max(x) == 0.335 and min(y) == 0.355 and max(y) == 0.385, "not the window"' \
  <"$T/dm.json" 2>/dev/null; then ok "scene --mesh dm: no C0 flags, 6-digit values, the window"
else bad "scene --mesh dm: no C0 flags, 6-digit values, the window" "$(head -c 300 "$T/dm.json")"; fi
run "$CLI" ordinates "$T/dm.json"
expect "ordinates of a dm patch: exit 0" 0
run "$CLI" scene penumbra --mesh dm --rotate 30
expect "scene --mesh dm --rotate: exit 0" 0
if "$PY" -c 'import json,sys; r = json.load(sys.stdin); assert r["discontinuities"]["c0"], list(r)' \
  <"$T/out" 2>/dev/null; then ok "scene --mesh dm: C0 flags by default"
else bad "scene --mesh dm: C0 flags by default" "$(head -c 300 "$T/out")"; fi
run "$CLI" scene penumbra --mesh disc --rotate 30
expect "scene --rotate on a disc mesh: exit 3" 3 "only dm meshes can be rotated"
run "$CLI" scene penumbra --mesh dm --window 1,0,0,1
expect "scene --window with x0 > x1: exit 2" 2 "--window"

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
