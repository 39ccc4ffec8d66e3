"""loadkit.py — the daemon-under-load scenarios shared by tests/endpoint/test_daemon_load.py
(short forms, in `make test`) and tests/torture/ (full size): head-of-line blocking behind
long renders, the worker queue's 503, request deadlines, and SIGTERM with requests in the
sockets. Each scenario starts its own tocherd on 127.0.0.1:0 and reports through tochertest."""
import atexit
import http.client
import json
import math
import os
import re
import shutil
import signal
import socket
import subprocess
import tempfile
import threading
import time

from tochertest import SAN_RE, Tocherd, check, say

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
JSON_H = {"Content-Type": "application/json"}
SMALL = {"vertices": [[0, 0], [1, 0], [1, 1], [0, 1]], "triangles": [[0, 1, 2], [0, 2, 3]], "values": [0, 1, 2, 3]}
TMP = tempfile.mkdtemp(prefix="tocher-load.")
DAEMONS = []


def build_dir(argv):
    b = argv[1] if len(argv) > 1 else "build"
    if not os.path.isabs(b) and not os.path.isdir(b):
        b = os.path.join(ROOT, b)
    return os.path.abspath(b)


def is_san(build):
    return os.path.basename(os.path.normpath(build)).endswith("san")


class Daemon(Tocherd):
    """One tocherd with the given flags, stderr in TMP; killed at exit. started: whether it came up."""

    def __init__(self, build, name, *flags):
        super().__init__(os.path.join(build, "tocherd"), os.path.join(TMP, name + ".stderr"), flags, strict=False)
        DAEMONS.append(self)

    def stop(self, timeout=60):
        return super().stop(timeout)


def _kill_all():
    for d in DAEMONS:
        if d.proc.poll() is None:
            d.proc.kill()
            d.proc.wait()
    shutil.rmtree(TMP, ignore_errors=True)


atexit.register(_kill_all)


def started(d, name):
    return check("%s: daemon starts" % name, d.started, d.stderr()[-300:])


def grid(n):
    """An n x n grid of the unit square, two triangles per cell, smooth values."""
    vs = [[i / n, j / n] for j in range(n + 1) for i in range(n + 1)]
    ts = []
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            ts += [[a, a + 1, a + n + 2], [a, a + n + 2, a + n + 1]]
    return {"vertices": vs, "triangles": ts, "values": [math.sin(3 * x) * math.cos(2 * y) for x, y in vs]}


def shadow():
    with open(os.path.join(ROOT, "api", "examples", "shadow-edges.json")) as f:
        return json.load(f)


def post(port, path, body, timeout=300, conn=None):
    """(status, headers, body bytes, seconds) on a new connection, or on conn (kept open)."""
    c = conn or http.client.HTTPConnection("127.0.0.1", port, timeout=timeout)
    data = body if isinstance(body, bytes) else json.dumps(body).encode()
    t0 = time.time()
    try:
        c.request("POST", path, data, JSON_H)
        r = c.getresponse()
        b = r.read()
        return r.status, r.headers, b, time.time() - t0
    finally:
        if conn is None:
            c.close()


LONG_RENDERS = ("--max-pixels", "0", "--max-samples", "0")


def render_body(width, height=None):
    """A PNG render of the shadow scene, width x height (square by default): PNG, not raw,
    because its encoding (zlib, one thread) costs more per pixel than the cubic, so a few
    seconds of work fit in a tile well under 8192 on a side on most machines (raw at 8192 took
    under 1 s on one, PNG at 8192 0.67 s on another: calibrate_render then goes taller)."""
    vp = {"x0": -0.1, "y0": -0.1, "x1": 1.1, "y1": 1.1, "width": width, "height": height or width}
    return json.dumps(dict(shadow(), viewport=vp, format="png")).encode()


def server_seconds(headers):
    """The daemon's own time for a request (Server-Timing total), or None."""
    m = re.search(r"total;dur=([0-9.]+)", (headers or {}).get("Server-Timing", "") or "")
    return float(m.group(1)) / 1e3 if m else None


# The largest render calibrate_render asks for: 8192 wide, up to four times as tall (the
# viewport allows 2^20 a side; the daemon renders it in bands of ~8 MiB and holds the PNG).
CAL_WIDTH, CAL_PIXELS = 8192, 8192 * 32768


def calibrate_render(port, seconds, worker=False):
    """A render body (render_body) whose request takes about `seconds` (at most CAL_PIXELS: the
    daemon must run with LONG_RENDERS, the pixel and sample limits lifted; a 4096^2 PNG of
    this mesh takes under a second), and the seconds it took. The time is the client's whole
    request (rendering, encoding and the transfer), or with worker=True the daemon's own
    (Server-Timing total: what holds a worker; the transfer of a big raw answer comes after,
    and can be most of the client's time). Small renders are dominated by per-triangle costs,
    so one measurement does not extrapolate: the pixel count is refined until a render takes
    0.7 to 1.5 times `seconds`, or reaches CAL_PIXELS; square up to CAL_WIDTH, then taller."""
    pixels, took = 600 * 600, seconds
    for _ in range(6):
        width = min(CAL_WIDTH, math.isqrt(pixels))
        body = render_body(width, pixels // width)
        st, h, _, t = post(port, "/v1/render", body)
        took = (server_seconds(h) or t) if worker else t
        if st != 200 or 0.7 * seconds <= took <= 1.5 * seconds:
            break
        new = int(min(CAL_PIXELS, max(64 * 64, pixels * seconds / max(took, 1e-3))))
        if new == pixels:
            break
        pixels = new
    return body, took


# ---- head-of-line blocking -------------------------------------------------------------

def hol(build, name, renders, conns, render_s, limit_s, threads=2, conn_timeout=2):
    """`renders` long renders (about render_s each) on their own connections while `conns`
    pre-opened keep-alive connections send small /v1/ordinates in a loop: the slowest
    small answer must take at most limit_s, and none may go unanswered."""
    d = Daemon(build, name, "--threads", str(threads), "--render-threads", "1", *LONG_RENDERS,
               "--connection-timeout", str(conn_timeout))
    if not started(d, name):
        return
    body, _ = calibrate_render(d.port, render_s)
    small = json.dumps(SMALL).encode()
    kas = [http.client.HTTPConnection("127.0.0.1", d.port, timeout=60) for _ in range(conns)]
    idle = []
    for c in kas:  # bound to the I/O threads, round robin, before the renders start
        idle.append(post(d.port, "/v1/ordinates", small, conn=c)[3])
    res = {"render": [], "small": [], "lost": []}
    lock = threading.Lock()
    running = threading.Event()

    def render():
        try:
            st, _, _, t = post(d.port, "/v1/render", body)
        except Exception as e:  # noqa: BLE001
            st, t = repr(e), 0
        with lock:
            res["render"].append((st, t))

    def small_loop(c):
        while running.is_set():
            t0 = time.time()
            try:
                st, _, _, t = post(d.port, "/v1/ordinates", small, conn=c)
                with lock:
                    res["small"].append((st, t))
            except Exception as e:  # noqa: BLE001
                with lock:  # a request lost counts as waiting until it was
                    res["lost"].append(repr(e))
                    res["small"].append((None, time.time() - t0))
                c.close()
            time.sleep(0.05)

    rs = [threading.Thread(target=render) for _ in range(renders)]
    running.set()
    ss = [threading.Thread(target=small_loop, args=(c,)) for c in kas]
    for t in rs + ss:
        t.start()
    for t in rs:
        t.join()
    running.clear()
    for t in ss:
        t.join()
    for c in kas:
        c.close()
    slow = max((t for _, t in res["small"]), default=float("inf"))
    bad = [s for s, _ in res["small"] if s not in (200, None)]
    r_ok = all(s == 200 for s, _ in res["render"])
    r_min = min((t for _, t in res["render"]), default=0)
    say("     %s: %d renders of %.2f-%.2f s; %d small requests on %d keep-alive connections: slowest %.3f s "
        "(idle %.3f s), %d not 200, %d closed unanswered" % (
            name, renders, r_min, max((t for _, t in res["render"]), default=0), len(res["small"]), conns, slow,
            max(idle), len(bad), len(res["lost"])))
    check("%s: every render answered 200 and took >= %.1f s (else this proves nothing)" % (name, 0.5 * render_s),
          r_ok and r_min >= 0.5 * render_s, repr(res["render"]))
    check("%s: slowest small request on a pre-opened keep-alive connection during the renders <= %.2f s" % (
        name, limit_s), slow <= limit_s, "%.3f s" % slow)
    check("%s: every small request answered 200, none closed unanswered" % name, not bad and not res["lost"],
          "not 200: %s; lost: %s" % (bad[:5], res["lost"][:5]))
    rc = d.stop()
    check("%s: exits 0, no sanitizer report" % name, rc == 0 and not SAN_RE.search(d.stderr()), d.stderr()[-400:])


# ---- the worker queue ------------------------------------------------------------------

def worker_gauges(port):
    """[(name, value)] of /metrics' tocher_workers_busy and tocher_worker_queue_length, sorted."""
    c = http.client.HTTPConnection("127.0.0.1", port, timeout=30)
    c.request("GET", "/metrics")
    text = c.getresponse().read().decode()
    c.close()
    return sorted(re.findall(r"^(tocher_workers_busy|tocher_worker_queue_length) (\d+)$", text, re.M))


def wait_gauges(port, busy, queued, timeout):
    """Polls /metrics until `busy` workers are busy and `queued` requests wait; the last gauges."""
    want = [("tocher_worker_queue_length", str(queued)), ("tocher_workers_busy", str(busy))]
    end = time.time() + timeout
    while True:
        got = worker_gauges(port)
        if got == want or time.time() > end:
            return got
        time.sleep(0.005)


def queue_full(build, name, render_s):
    """--workers 1 --max-queue 1: one render runs, one waits, a third gets 503 with
    Retry-After at once; the two accepted ones are answered 200. Each request is sent once
    /metrics shows the one before it running or waiting: how long a render holds the worker
    is the machine's (a fast one renders even the largest side in a fraction of a second)."""
    d = Daemon(build, name, "--workers", "1", "--max-queue", "1", "--render-threads", "1", *LONG_RENDERS)
    if not started(d, name):
        return
    body, busy_s = calibrate_render(d.port, render_s, worker=True)  # how long a render holds the worker
    say("     %s: a render holds the worker %.2f s" % (name, busy_s))
    out = {}

    def go(k):
        try:
            out[k] = post(d.port, "/v1/render", body)
        except Exception as e:  # noqa: BLE001
            out[k] = (repr(e), {}, b"", 0)

    a = threading.Thread(target=go, args=("a",))
    a.start()
    wait_gauges(d.port, 1, 0, 10 * render_s)
    b = threading.Thread(target=go, args=("b",))
    b.start()
    seen = wait_gauges(d.port, 1, 1, 10 * render_s)
    go("c")
    st, h, body_c, t = out["c"]
    ok = st == 503 and h.get("Retry-After") and b"/problems/" in body_c and t < 0.5 * render_s
    check("%s: a request beyond the queue gets 503 + Retry-After at once (%.3f s)" % (name, t), bool(ok),
          "%r %r %r" % (st, dict(h) if h else {}, body_c[:200]))
    check("%s: /metrics meanwhile: one worker busy, one request waiting" % name,
          seen == [("tocher_worker_queue_length", "1"), ("tocher_workers_busy", "1")], repr(seen))
    a.join()
    b.join()
    check("%s: the running and the queued render both answer 200" % name,
          out["a"][0] == 200 and out["b"][0] == 200, "%r %r" % (out["a"][0], out["b"][0]))
    log = d.stderr()
    check("%s: the 503 is in the log" % name, "POST /v1/render 503" in log, log[-300:])
    rc = d.stop()
    check("%s: exits 0, no sanitizer report" % name, rc == 0 and not SAN_RE.search(d.stderr()), d.stderr()[-400:])


# ---- deadlines ---------------------------------------------------------------------------

def deadlines(build, name, n, npoints):
    """/v1/ordinates, /v1/compare on an n x n grid, /v1/evaluate of npoints points with
    gradients on 16 channels: with --request-timeout at 15 % of what each takes without
    one (the body arrives well within it), the 503 says the time limit passed and comes
    well before the whole computation would have ended."""
    g = grid(n)
    g16 = grid(10)
    g16["values"] = [[v * k for k in range(1, 17)] for v in g16["values"]]
    pts = [[(i * 0.618034) % 1, (i * 0.414214) % 1] for i in range(npoints)]
    bodies = {"/v1/ordinates": g, "/v1/evaluate": dict(g16, points=pts, with_gradients=True),
              "/v1/compare": dict(g, reference={"points": [[0.3, 0.4]] * 100, "values": [0.0] * 100})}
    free = Daemon(build, name + "-free", "--request-timeout", "0")
    if not started(free, name):
        return
    for path, body in bodies.items():
        data = json.dumps(body).encode()
        st, _, _, full = post(free.port, path, data)
        limit = "%.3f" % (0.15 * full)
        tight = Daemon(build, name + "-tight", "--request-timeout", limit)
        if not started(tight, name):
            continue
        st2, _, b, t = post(tight.port, path, data)
        try:
            detail = json.loads(b).get("detail", "")
        except ValueError:
            detail = repr(b[:100])
        ok = st == 200 and st2 == 503 and "time limit" in detail and t < 0.8 * full
        check("%s: %s past --request-timeout %s: 503 in %.3f s (all of it: %.3f s): %s" % (
            name, path, limit, t, full, detail), ok, "status %s then %s" % (st, st2))
        rc = tight.stop()
        check("%s: exits 0, no sanitizer report" % name, rc == 0 and not SAN_RE.search(tight.stderr()),
              tight.stderr()[-400:])
    rc = free.stop()
    check("%s: exits 0, no sanitizer report" % name, rc == 0 and not SAN_RE.search(free.stderr()),
          free.stderr()[-400:])


# ---- SIGTERM -----------------------------------------------------------------------------

def _one(port, data, keep):
    """One request: 'refused' (not sent), 'ok' (an answer: 200, or 503 with Retry-After),
    or what went wrong after the whole request was sent. keep: a socket to reuse."""
    s = keep.get("s")
    how = "on a kept connection" if s else "on a new connection"
    if s is None:
        try:
            s = socket.create_connection(("127.0.0.1", port), timeout=30)
        except OSError:
            return "refused"
    req = (b"POST /v1/ordinates HTTP/1.1\r\nHost: t\r\nContent-Type: application/json\r\n"
           b"Content-Length: %d\r\n\r\n" % len(data)) + data
    try:
        s.sendall(req)
    except OSError:
        keep.pop("s", None)
        s.close()
        return "refused"  # not all of it sent
    try:
        r = http.client.HTTPResponse(s, method="POST")
        r.begin()
        r.read()
        st, retry, close = r.status, r.getheader("Retry-After"), r.will_close
    except (ConnectionResetError, BrokenPipeError) as e:
        keep.pop("s", None)
        s.close()
        return "reset %s (%s)" % (how, e.__class__.__name__)
    except Exception as e:  # noqa: BLE001
        keep.pop("s", None)
        s.close()
        return "no answer %s (%s)" % (how, e.__class__.__name__)
    if close:
        keep.pop("s", None)
        s.close()
    else:
        keep["s"] = s
    if st == 200 or (st == 503 and retry):
        return "ok"
    return "status %d%s" % (st, "" if retry else " without Retry-After")


def sigterm(build, name, rounds, clients, render_s):
    """Each round: a daemon, `clients` threads sending small requests (half on keep-alive
    connections, half a new connection each) and two long renders; SIGTERM mid-way. Every
    request sent whole must get an answer (200, or 503 with Retry-After), never a reset or
    a close without a status line; the daemon exits 0."""
    data = json.dumps(SMALL).encode()
    sent = 0
    bad = []
    exits = []
    body = None  # calibrated on the first daemon that starts
    for k in range(rounds):
        d = Daemon(build, "%s-%d" % (name, k), "--render-threads", "1", *LONG_RENDERS)
        if not d.started:
            bad.append("daemon %d did not start" % k)
            continue
        if body is None:
            body, _ = calibrate_render(d.port, render_s)
        stop = threading.Event()
        lock = threading.Lock()
        counts = {"sent": 0}

        def client(i):
            keep = {"s": None} if i % 2 == 0 else None
            while not stop.is_set():
                once = keep if keep is not None else {}
                out = _one(d.port, data, once)
                if keep is None and once.get("s"):
                    once["s"].close()
                if out == "refused":
                    if d.proc.poll() is not None:
                        break
                    time.sleep(0.01)
                    continue
                with lock:
                    counts["sent"] += 1
                    if out != "ok":
                        bad.append(out)
            if keep and keep.get("s"):
                keep["s"].close()

        def render():
            try:
                st, _, _, _ = post(d.port, "/v1/render", body)
                if st not in (200, 503):
                    with lock:
                        bad.append("render %s" % st)
            except OSError:
                pass

        th = [threading.Thread(target=client, args=(i,)) for i in range(clients)]
        th += [threading.Thread(target=render) for _ in range(2)]
        for t in th:
            t.start()
        time.sleep(0.3 + 0.4 * render_s)
        d.proc.send_signal(signal.SIGTERM)
        try:
            rc = d.proc.wait(60)
        except subprocess.TimeoutExpired:
            rc = None
        stop.set()
        for t in th:
            t.join(60)
        exits.append(rc == 0 and not SAN_RE.search(d.stderr()))
        sent += counts["sent"]
    say("     %s: %d rounds, %d requests sent whole, %d without an answer: %s" % (
        name, rounds, sent, len(bad), sorted(set(bad))[:5]))
    check("%s: every request sent whole before or during SIGTERM gets an answer (%d of %d did not)" % (
        name, len(bad), sent), not bad and sent > 0, "; ".join(sorted(set(bad))[:5]))
    check("%s: the daemon exits 0 each time, no sanitizer report" % name, all(exits) and exits, repr(exits))
