#!/usr/bin/env python3
"""test_framing_limits.py — the daemon against hostile framing, bodies and slow clients, in a
short form for `make test` (the full-size forms are in tests/torture/):

    /usr/bin/python3 tests/endpoint/test_framing_limits.py BUILD_DIR

  1. framing a proxy could read differently (RFC 9112 §6.3) gets one 400 problem+json and
     the connection closed: Content-Length with Transfer-Encoding (the bytes after the last
     chunk are not run as a second request), two different Content-Length headers, a blank
     before a header's colon, HTTP/1.1 without Host; a bad Content-Length is refused and
     nothing after it runs (libmicrohttpd answers that one itself, see README);
  2. a body over --max-points is refused 413 naming the field without building its JSON tree
     (RSS growth a few times the body, not ~40 times), and a declared Content-Length
     reserves nothing before bytes arrive;
  3. one host's trickling connections do not take the daemon off the air: another address
     gets /healthz at once (per-IP cap), the same host once the header deadline has closed
     them; a trickling body is closed at the body deadline.
Settings go by TOCHER_* variables, which an older build ignores: that is how each check was
seen to fail before the change. Prints "ok"/"FAIL" lines, then "N passed, N failed".
"""
import json
import os
import re
import shutil
import sys
import tempfile
import threading
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tests", "pylib"))
from hostile import JSON_POST, Daemon, Trickler, exchange, healthz_seconds, read_all, status_lines  # noqa: E402
from tochertest import check, finish, say  # noqa: E402

BUILD = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build"))
SAN = os.path.basename(os.path.normpath(BUILD)).endswith("san")
TMP = tempfile.mkdtemp(prefix="tocher-framing.")
MESH = b'{"vertices":[[0,0],[1,0],[0,1]],"triangles":[[0,1,2]],"values":[1,2,3]}'


def problem(out, status):
    """The problem document of a single answer `out` with that status, else None."""
    head, _, body = out.partition(b"\r\n\r\n")
    if not head.startswith(b"HTTP/1.1 %d " % status) or b"application/problem+json" not in head:
        return None
    try:
        doc = json.loads(body)
    except ValueError:
        return None
    return doc if doc.get("status") == status else None


def refused_once(name, d, data):
    """data gets exactly one answer, a 400 problem+json, and the connection is closed."""
    out, closed = exchange(d, data, timeout=5)
    doc = problem(out, 400)
    check("framing: %s -> one 400 problem+json, connection closed" % name,
          doc is not None and "RFC 9112" in doc.get("detail", "") and status_lines(out) == 1 and closed,
          "%r (closed %s)" % (out[:300], closed))


def section_framing(d):
    post = b"POST /v1/ordinates HTTP/1.1\r\n" + JSON_POST
    chunk = b"%x\r\n%s\r\n0\r\n\r\n" % (len(MESH), MESH)
    smuggled = b"GET /healthz HTTP/1.1\r\nHost: t\r\n\r\n"
    refused_once("Content-Length with Transfer-Encoding", d,
                 post + b"Content-Length: %d\r\nTransfer-Encoding: chunked\r\n\r\n" % len(chunk) + chunk + smuggled)
    refused_once("two different Content-Length", d,
                 post + b"Content-Length: %d\r\nContent-Length: 5\r\n\r\n" % len(MESH) + MESH)
    refused_once("'Transfer-Encoding : chunked'", d, post + b"Transfer-Encoding : chunked\r\n\r\n" + chunk)
    refused_once("HTTP/1.1 without Host", d, b"GET /healthz HTTP/1.1\r\n\r\n" + smuggled)
    same = b"POST /v1/ordinates HTTP/1.1\r\nConnection: close\r\n" + JSON_POST + b"Content-Length: %d\r\nContent-Length: %d\r\n\r\n"
    out, _ = exchange(d, same % (len(MESH), len(MESH)) + MESH, timeout=5)
    check("framing: two equal Content-Length headers are one length (200)", out.startswith(b"HTTP/1.1 200"),
          repr(out[:200]))
    out, closed = exchange(d, post + b"Content-Length: abc\r\n\r\n" + smuggled, timeout=5)
    check("framing: a bad Content-Length is refused 400 and nothing after it runs",
          out.startswith(b"HTTP/1.1 400") and closed and b"200 OK" not in out, repr(out[:300]))


def points_body(n):
    return MESH[:-1] + b',"points":[' + b"[0,0]," * (n - 1) + b"[0,0]]}"


def section_limits(d):
    body = points_body(1000000)  # 6 MB; the daemon allows 100 000 points
    rss0 = d.status("VmRSS")
    t0 = time.time()
    out, _ = exchange(d, b"POST /v1/evaluate HTTP/1.1\r\nConnection: close\r\n" + JSON_POST + b"Content-Length: %d\r\n\r\n" % len(body)
                      + body, timeout=60)
    took = time.time() - t0
    grown = (d.status("VmHWM") - rss0) / 1024.0
    doc = problem(out, 413)
    check("limits: 1 000 000 points over --max-points 100000 -> 413 naming points",
          doc is not None and "1000000 points" in doc.get("detail", "") and doc["errors"][0]["path"] == "points",
          repr(out[:300]))
    check("limits: ... refused before any JSON tree: peak RSS growth %.0f MB <= 40 MB (6 MB body), %.2f s"
          % (grown, took), grown <= 40, "the tree of a refused body was built")
    vm0, socks = d.status("VmSize"), []
    head = b"POST /v1/evaluate HTTP/1.1\r\n" + JSON_POST + b"Content-Length: %d\r\n\r\n{" % (60 << 20)
    for _ in range(12):
        s = d.connect()
        s.sendall(head)
        socks.append(s)
    time.sleep(0.5 if not SAN else 1.5)
    grown = (d.status("VmSize") - vm0) / 1024.0
    for s in socks:
        s.close()
    check("limits: 12 connections declaring 60 MiB reserve %.0f MB of virtual memory (<= 128)" % grown,
          grown <= 128, "the declared length was reserved up front")


def section_slow(d):
    slow = Trickler(d, 60, 0.3)
    time.sleep(0.5)
    t = healthz_seconds(d, "127.0.0.2", 2.0)
    check("slow clients: 60 trickling connections from 127.0.0.1; /healthz from 127.0.0.2 within 2 s (%s)"
          % ("%.2f s" % t if t is not None else "none"), t is not None, "the daemon is off the air")
    time.sleep(max(0.0, slow.opened + 2.0 - time.time()))  # header deadline 1.5 s, swept every 0.1 s
    t = healthz_seconds(d, "127.0.0.1", 2.0)
    check("slow clients: past the 1.5 s header deadline, /healthz from 127.0.0.1 within 2 s (%s)"
          % ("%.2f s" % t if t is not None else "none"), t is not None, "the trickling connections still hold it")
    end = time.time() + 3.0  # the trickler notices a close at its next byte; allow a busy machine
    while slow.open_count() and time.time() < end:
        time.sleep(0.1)
    check("slow clients: the trickling connections are closed (%d of 60 still open)" % slow.open_count(),
          slow.open_count() == 0, "they outlive the header deadline")
    slow.close()
    s = d.connect()
    s.sendall(b"POST /v1/ordinates HTTP/1.1\r\n" + JSON_POST + b"Content-Length: 1000\r\n\r\n{")
    stop = threading.Event()

    def trickle():
        while not stop.wait(0.3):
            try:
                s.send(b" ")
            except OSError:
                return
    threading.Thread(target=trickle, daemon=True).start()
    t0 = time.time()
    _, closed = read_all(s, 3.5)
    stop.set()
    s.close()
    check("slow clients: a body trickling past the 1 s body deadline is closed (after %.1f s)" % (time.time() - t0),
          closed, "still open after 3.5 s")
    metrics, _ = exchange(d, b"GET /metrics HTTP/1.1\r\nHost: t\r\nConnection: close\r\n\r\n")
    late = {p: int(n) for p, n in re.findall(rb'tocher_connections_closed_late_total\{part="(\w+)"\} (\d+)', metrics)}
    check("slow clients: /metrics counts the connections closed late (%r)" % late,
          late.get(b"headers", 0) >= 1 and late.get(b"body", 0) >= 1, metrics[-600:])


def main():
    say("# %s against %s%s" % (os.path.basename(__file__), BUILD, " (sanitizers)" if SAN else ""))
    d = Daemon(BUILD, TMP, "limits", threads=2, max_points=100000, max_connections=48, max_connections_per_ip=16,
               header_timeout=1.5, body_timeout=1)
    try:
        for name, fn in (("framing", section_framing), ("limits", section_limits), ("slow clients", section_slow)):
            t0 = time.time()
            try:
                fn(d)
            except Exception as e:  # noqa: BLE001 — a section that dies is a failure, not a crash
                check("section %s ran to its end" % name, False, repr(e))
            say("# %s: %.1f s" % (name, time.time() - t0))
        check("the daemon is alive at the end", d.proc.poll() is None, d.stderr()[-400:])
    finally:
        d.kill()
        shutil.rmtree(TMP, ignore_errors=True)
    finish()


if __name__ == "__main__":
    main()
