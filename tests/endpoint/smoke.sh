#!/bin/sh
# smoke.sh — starts tocherd ($1, default build/tocherd) on a free loopback port,
# calls each endpoint once, checks statuses and content types, then SIGTERM -> exit 0.
set -u
D=${1:-build/tocherd}
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
EX=$ROOT/api/examples
T=$(mktemp -d "${TMPDIR:-/tmp}/tocherd-smoke.XXXXXX") || exit 1
pid=
cleanup() {
  [ -n "$pid" ] && kill -KILL "$pid" 2>/dev/null
  rm -rf "$T"
}
trap cleanup EXIT
trap 'exit 1' HUP INT TERM
pass=0
fail=0
ok() { pass=$((pass + 1)); echo "ok   $1"; }
bad() { fail=$((fail + 1)); echo "FAIL $1: $2"; }

# A small --max-body so that the 413 needs no big upload; the examples fit under it.
"$D" --listen 127.0.0.1:0 --max-body 4096 --threads 2 >"$T/stdout" 2>"$T/stderr" &
pid=$!
i=0
while [ ! -s "$T/stdout" ] && [ $i -lt 100 ] && kill -0 "$pid" 2>/dev/null; do sleep 0.1; i=$((i + 1)); done
line=$(head -n 1 "$T/stdout")
port=$(echo "$line" | sed -n 's|^tocherd [^ ]* listening on http://127\.0\.0\.1:\([0-9][0-9]*\)$|\1|p')
if [ -z "$port" ]; then
  bad "startup line" "got '$line'; stderr: $(head -c 300 "$T/stderr")"
  echo "$pass passed, $fail failed"
  exit 1
fi
ok "startup line ($line)"
URL=http://127.0.0.1:$port

# call NAME WANT_STATUS WANT_TYPE_PREFIX CURL_ARGS...: response in $T/body, headers in $T/head
call() {
  name=$1 want=$2 type=$3
  shift 3
  got=$(curl -s -o "$T/body" -D "$T/head" -w '%{http_code} %{content_type}' "$@")
  code=${got%% *} ctype=${got#* }
  case "$code" in
  "$want") ;;
  *) bad "$name" "status $code, expected $want; body: $(head -c 300 "$T/body")"; return 1 ;;
  esac
  case "$ctype" in
  "$type"*) ;;
  *) bad "$name" "content type '$ctype', expected $type"; return 1 ;;
  esac
  if ! grep -qi '^Server-Timing: parse;dur=' "$T/head"; then bad "$name" "no Server-Timing header"; return 1; fi
  ok "$name"
}
body_has() { # NAME STRING: the last body contains STRING
  if grep -qF -- "$2" "$T/body"; then ok "$1"; else bad "$1" "body lacks '$2': $(head -c 300 "$T/body")"; fi
}
JSON='Content-Type: application/json'

call "GET /healthz" 200 application/json "$URL/healthz" && body_has "healthz says ok" '"status":"ok"'
call "GET /v1/version" 200 application/json "$URL/v1/version" && body_has "version has api v1" '"api":"v1"'
call "POST /v1/ordinates" 200 application/json -H "$JSON" --data-binary "@$EX/square-light.json" "$URL/v1/ordinates" &&
  body_has "ordinates has timings" '"timings":{"parse":'
{ printf '{"points": [[0.5, 0.5], [0.25, 0.3], [2, 2]],'; tail -c +2 "$EX/square-light.json"; } >"$T/eval.json"
call "POST /v1/evaluate" 200 application/json -H "$JSON; charset=utf-8" --data-binary "@$T/eval.json" "$URL/v1/evaluate" &&
  body_has "evaluate has values" '"values":'
call "GET /metrics" 200 text/plain "$URL/metrics" &&
  body_has "metrics count ordinates" 'tocher_http_requests_total{route="/v1/ordinates",status="200"} 1'
call "404 unknown path" 404 application/problem+json "$URL/v1/nothing-here" && body_has "404 type" '/problems/not-found'
call "405 wrong method" 405 application/problem+json -X DELETE "$URL/v1/ordinates" &&
  if grep -qi '^Allow: POST' "$T/head"; then ok "405 has Allow"; else bad "405 has Allow" "$(cat "$T/head")"; fi
call "415 not JSON" 415 application/problem+json -H 'Content-Type: text/plain' --data-binary "@$EX/square-light.json" \
  "$URL/v1/ordinates"
head -c 10000 /dev/zero | tr '\0' ' ' >"$T/big.json"
call "413 over --max-body" 413 application/problem+json -H "$JSON" --data-binary "@$T/big.json" "$URL/v1/ordinates" &&
  body_has "413 type" '/problems/too-large'

kill -TERM "$pid"
i=0
while kill -0 "$pid" 2>/dev/null && [ $i -lt 300 ]; do sleep 0.1; i=$((i + 1)); done
if kill -0 "$pid" 2>/dev/null; then
  bad "SIGTERM" "still running after 30 s"
else
  wait "$pid"
  rc=$?
  pid=
  if [ $rc -eq 0 ]; then ok "SIGTERM -> exit 0"; else bad "SIGTERM" "exit status $rc"; fi
fi
if grep -qE 'AddressSanitizer|LeakSanitizer|runtime error:|UndefinedBehaviorSanitizer' "$T/stderr"; then
  bad "sanitizers" "$(grep -m 5 -E 'Sanitizer|runtime error' "$T/stderr")"
else
  ok "no sanitizer reports"
fi
if grep -q '^POST /v1/ordinates 200 [0-9]* [0-9.]*ms$' "$T/stderr"; then ok "request log line"; else
  bad "request log line" "$(head -c 400 "$T/stderr")"
fi
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
