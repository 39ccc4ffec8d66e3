#!/usr/bin/env python3
"""test_redis_store.py — tocherd with its mesh store in Redis (issue 16, "The store in Redis"):
real redis-server processes started here on free loopback ports (no persistence), real
daemons from BUILD_DIR:

    /usr/bin/python3 tests/endpoint/test_redis_store.py BUILD_DIR

What it establishes, one "ok"/"FAIL" line per check, then "N passed, N failed":
  1. a mesh POSTed to one replica is in Redis (tocher:mesh:<id>, its TTL --mesh-ttl), and a
     second replica on the same Redis serves its tiles with the same bytes (built from Redis);
  2. every use renews the TTL; a key deleted behind the daemons' backs (what allkeys-lru
     eviction does) or expired answers 404 "POST it again" although the replica's cache still
     holds the build; DELETE on one replica is a 404 on the other; --mesh-ttl 0: no TTL;
  3. Redis killed (SIGKILL): stateless routes 200, every mesh route 503 problem+json with
     Retry-After well within --request-timeout, never a 500; /readyz 503, /healthz 200 with the
     store down; tocher_store_up 0; Redis hung (SIGSTOP): the same within the deadline;
  4. Redis restarted empty: ready again without a restart of the daemons; the old id 404, a
     re-POST 201 and the same tiles; a replica started while Redis was down becomes ready;
  5. --store URLs refused or taken, TOCHER_STORE and TOCHER_MESH_TTL, --help.
Skips (0 checks) only when redis-server is not installed (`make deps` installs it).
"""
import atexit
import http.client
import json
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tests", "pylib"))
from tochertest import SAN_RE, Tocherd, check, finish, say  # noqa: E402

BUILD = sys.argv[1] if len(sys.argv) > 1 else "build"
if not os.path.isabs(BUILD) and not os.path.isdir(BUILD):
    BUILD = os.path.join(ROOT, BUILD)
TOCHERD = os.path.join(os.path.abspath(BUILD), "tocherd")
TMP = tempfile.mkdtemp(prefix="tocher-redis.")
DAEMONS, REDISES = [], []
JSON_H = {"Content-Type": "application/json"}
NOT_FOUND = "mesh not found; POST it again"
DEADLINE = 2.0  # --request-timeout of the daemons that meet a dead Redis
ZSTD_MAGIC = b"\x28\xb5\x2f\xfd"


def _cleanup():
    for d in DAEMONS:
        d.kill()
    for r in REDISES:
        r.kill()
    shutil.rmtree(TMP, ignore_errors=True)


atexit.register(_cleanup)


# ---- Redis: the server, and a minimal RESP client (no Python package needed) -----------

def free_port():
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port


class Redis:
    """redis-server on 127.0.0.1:port without persistence, started and answering."""

    def __init__(self, port):
        self.port = port
        self.proc = subprocess.Popen(["redis-server", "--port", str(port), "--bind", "127.0.0.1", "--save", "",
                                      "--appendonly", "no"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        REDISES.append(self)
        end = time.time() + 10
        while time.time() < end:
            try:
                if self.cmd("PING") == "PONG":
                    return
            except OSError:
                time.sleep(0.05)
        raise RuntimeError("redis-server on port %d did not answer" % port)

    def cmd(self, *args):
        """One command; the reply as str/bytes/int/None/list (an error reply raises)."""
        with socket.create_connection(("127.0.0.1", self.port), timeout=5) as s:
            out = b"*%d\r\n" % len(args)
            for a in args:
                a = a if isinstance(a, bytes) else str(a).encode()
                out += b"$%d\r\n%s\r\n" % (len(a), a)
            s.sendall(out)
            return _read_reply(s.makefile("rb"))

    def kill(self):
        if self.proc.poll() is None:
            self.proc.kill()
        self.proc.wait(10)


def _read_reply(f):
    line = f.readline()
    kind, rest = line[:1], line[1:-2]
    if kind == b"+":
        return rest.decode()
    if kind == b"-":
        raise RuntimeError(rest.decode())
    if kind == b":":
        return int(rest)
    if kind == b"$":
        n = int(rest)
        if n < 0:
            return None
        data = f.read(n + 2)
        return data[:-2]
    if kind == b"*":
        return [_read_reply(f) for _ in range(int(rest))]
    raise RuntimeError("bad RESP line %r" % line)


# ---- HTTP ------------------------------------------------------------------------------

class Resp:
    def __init__(self, status, headers, body, seconds):
        self.status, self.headers, self.body, self.seconds = status, headers, body, seconds

    def h(self, name):
        return self.headers.get(name)

    def json(self):
        return json.loads(self.body)

    def brief(self):
        return "%d %s %.2fs %r" % (self.status, self.h("Content-Type"), self.seconds, self.body[:200])


def request(d, method, path, body=None, headers=None):
    c = http.client.HTTPConnection("127.0.0.1", d.port, timeout=60)
    try:
        t0 = time.time()
        c.request(method, path, body=body, headers=headers or {})
        r = c.getresponse()
        data = r.read()
        return Resp(r.status, r.headers, data, time.time() - t0)
    finally:
        c.close()


def post(d, path, doc):
    return request(d, "POST", path, doc if isinstance(doc, bytes) else json.dumps(doc).encode(), JSON_H)


def is_problem(r, status, detail=None):
    if r.status != status or (r.h("Content-Type") or "") != "application/problem+json":
        return False
    doc = r.json()
    return doc.get("status") == status and (detail is None or detail in doc.get("detail", ""))


def metric(d, name):
    text = request(d, "GET", "/metrics").body.decode()
    m = re.search(r"^%s (\S+)$" % re.escape(name), text, re.M)
    return float(m.group(1)) if m else None


def start(name, redis_port, *flags, env=None, strict=True):
    store = ("--store", "redis://127.0.0.1:%d" % redis_port) if redis_port else ()
    d = Tocherd(TOCHERD, os.path.join(TMP, name + ".stderr"), (*store, *flags), env, strict=strict)
    d.name = name
    DAEMONS.append(d)
    return d


def load(name):
    with open(os.path.join(ROOT, "api", "examples", name)) as f:
        return json.load(f)


def grid_mesh(n, shift=0.0):
    verts, tris, vals = [], [], []
    for j in range(n + 1):
        for i in range(n + 1):
            x, y = 2.0 * i / n, 1.0 * j / n
            verts.append([x, y])
            vals.append(0.2 + 0.5 * x * x - 0.3 * y + 0.1 * x * y + shift)
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            tris += [[a, a + 1, a + n + 2], [a, a + n + 2, a + n + 1]]
    return {"vertices": verts, "triangles": tris, "values": vals}


def wait_until(fn, seconds):
    end = time.time() + seconds
    while time.time() < end:
        if fn():
            return True
        time.sleep(0.05)
    return fn()


TILE = "/v1/meshes/%s/tiles/1/0/1.png?size=32"


# ---- 1. two replicas, one Redis ----------------------------------------------------------

def section_shared(R, A, B):
    mesh = grid_mesh(30)  # 1800 triangles: its canonical form is compressed
    r = post(A, "/v1/meshes", mesh)
    check("POST to replica A: 201", r.status == 201, r.brief())
    mid = r.json()["id"]
    key = "tocher:mesh:" + mid
    value = R.cmd("GET", key)
    check("the mesh is in Redis under tocher:mesh:<id>", isinstance(value, bytes) and len(value) > 0, repr(value)[:80])
    check("... compressed (zstd frame), smaller than the JSON posted",
          value is not None and value.startswith(ZSTD_MAGIC) and len(value) < len(json.dumps(mesh)) / 2,
          "%d bytes" % len(value or b""))
    ttl = R.cmd("TTL", key)
    check("its TTL is --mesh-ttl (1000 s)", 990 < ttl <= 1000, ttl)
    small = post(A, "/v1/meshes", load("square-light.json")).json()["id"]
    sv = R.cmd("GET", "tocher:mesh:" + small)
    check("a small mesh is stored as it is (canonical JSON)", sv is not None and sv.startswith(b"{"), repr(sv)[:80])
    ta = request(A, "GET", TILE % mid)
    misses = metric(B, "tocher_cache_misses_total")
    tb = request(B, "GET", TILE % mid)
    check("replica B serves the tile of a mesh POSTed to A: 200, bytes equal",
          ta.status == 200 and tb.status == 200 and ta.body == tb.body, "%s | %s" % (ta.brief(), tb.brief()))
    check("... B built it from Redis (one miss)", metric(B, "tocher_cache_misses_total") == misses + 1)
    g = request(B, "GET", "/v1/meshes/" + mid)
    check("GET /v1/meshes/{id} on B: its description", g.status == 200 and g.json()["id"] == mid and
          g.json()["triangles"] == 1800, g.brief())
    ref = post(A, "/v1/ordinates", mesh)
    o = request(B, "GET", "/v1/meshes/%s/ordinates" % mid)
    strip = lambda d: {k: v for k, v in d.items() if k != "timings"}  # noqa: E731
    check("ordinates on B equal /v1/ordinates of the mesh", o.status == 200 and
          strip(o.json()) == strip(ref.json()), o.brief())
    r2 = post(B, "/v1/meshes", mesh)
    check("POST of the same mesh to B: 200 (it exists), same id", r2.status == 200 and r2.json()["id"] == mid,
          r2.brief())
    # 8 threads, both replicas, 10 tiles each.
    bad = []

    def tiles(k):
        d = A if k % 2 else B
        for _ in range(10):
            t = request(d, "GET", TILE % mid)
            if t.status != 200 or t.body != ta.body:
                bad.append(t.brief())

    th = [threading.Thread(target=tiles, args=(k,)) for k in range(8)]
    for t in th:
        t.start()
    for t in th:
        t.join()
    check("80 concurrent tiles over both replicas: all 200 and equal", not bad, bad[:2])
    check("tocher_store_up 1, no store errors, no tocher_meshes_stored (Redis counts its keys)",
          metric(A, "tocher_store_up") == 1 and metric(A, "tocher_store_errors_total") == 0 and
          metric(A, "tocher_meshes_stored") is None)
    return mesh, mid, ta.body


# ---- 2. TTL, eviction, expiry, DELETE ----------------------------------------------------

def section_lifetime(R, A, B, mid):
    key = "tocher:mesh:" + mid
    R.cmd("EXPIRE", key, 30)
    t = request(A, "GET", TILE % mid)
    check("a tile GET (a cache hit) renews the TTL", t.status == 200 and R.cmd("TTL", key) > 990, R.cmd("TTL", key))
    R.cmd("EXPIRE", key, 30)
    request(A, "GET", "/v1/meshes/" + mid, headers={"If-None-Match": t.h("ETag")})
    check("a 304 renews it too", R.cmd("TTL", key) > 990, R.cmd("TTL", key))
    # Evicted behind the daemons' backs (allkeys-lru does exactly this).
    mesh = grid_mesh(4, shift=1.0)
    eid = post(A, "/v1/meshes", mesh).json()["id"]
    check("before eviction: A serves it", request(A, "GET", TILE % eid).status == 200)
    R.cmd("DEL", "tocher:mesh:" + eid)
    for d in (A, B):
        r = request(d, "GET", TILE % eid)
        check("evicted from Redis: %s answers 404 %r (its cache notwithstanding)" % (d.name, NOT_FOUND),
              is_problem(r, 404, NOT_FOUND), r.brief())
    r = post(A, "/v1/meshes", mesh)
    check("POST it again: 201, the same id, tiles again", r.status == 201 and r.json()["id"] == eid and
          request(B, "GET", TILE % eid).status == 200, r.brief())
    # DELETE on one replica: gone on the other.
    r = request(A, "DELETE", "/v1/meshes/" + eid)
    rb = request(B, "GET", TILE % eid)
    check("DELETE on A: 204, then B answers 404", r.status == 204 and is_problem(rb, 404, NOT_FOUND), rb.brief())
    # Expiry, and no TTL.
    E = start("ttl1", R.port, "--mesh-ttl", "1")
    xid = post(E, "/v1/meshes", grid_mesh(3, shift=2.0)).json()["id"]
    ok = request(E, "GET", TILE % xid).status == 200
    time.sleep(2.2)
    r = request(E, "GET", TILE % xid)
    check("--mesh-ttl 1: served, then 2 s unused: 404 %r" % NOT_FOUND, ok and is_problem(r, 404, NOT_FOUND),
          r.brief())
    E.stop()
    Z = start("ttl0", R.port, "--mesh-ttl", "0")
    zid = post(Z, "/v1/meshes", grid_mesh(3, shift=3.0)).json()["id"]
    request(Z, "GET", TILE % zid)
    check("--mesh-ttl 0: the key has no TTL (-1)", R.cmd("TTL", "tocher:mesh:" + zid) == -1,
          R.cmd("TTL", "tocher:mesh:" + zid))
    Z.stop()


# ---- 3. Redis down ------------------------------------------------------------------------

def mesh_routes(mid):
    vp = {"x0": 0, "y0": 0, "x1": 1, "y1": 1, "width": 8, "height": 8}
    return [("GET", "/v1/meshes/" + mid, None), ("GET", "/v1/meshes/%s/ordinates" % mid, None),
            ("GET", TILE % mid, None), ("HEAD", TILE % mid, None),
            ("POST", "/v1/meshes/%s/evaluate" % mid, {"points": [[0.5, 0.5]]}),
            ("POST", "/v1/meshes/%s/render" % mid, {"viewport": vp}),
            ("POST", "/v1/meshes", grid_mesh(2, shift=9.0)), ("DELETE", "/v1/meshes/" + mid, None)]


def all_mesh_routes_503(d, mid, why):
    """Every mesh route on d: 503 busy problem+json with Retry-After, within the deadline."""
    worst, bad = 0.0, []
    for method, path, body in mesh_routes(mid):
        data = json.dumps(body).encode() if body is not None else None
        r = request(d, method, path, data, JSON_H if data else None)
        worst = max(worst, r.seconds)
        want = r.status == 503 and r.h("Retry-After") is not None and r.seconds < DEADLINE and \
            (method == "HEAD" or (is_problem(r, 503) and r.json().get("type") == "/problems/busy"))
        if not want:
            bad.append("%s %s: %s" % (method, path[:40], r.brief()))
    check("%s: all %d mesh routes answer 503 busy problem+json with Retry-After (slowest %.2f s, deadline %g s)"
          % (why, len(mesh_routes(mid)), worst, DEADLINE), not bad, bad[:3])


def stateless_ok(d, why):
    sq = load("square-light.json")
    vp = {"x0": 0, "y0": 0, "x1": 1, "y1": 1, "width": 8, "height": 8}
    rs = [post(d, "/v1/ordinates", sq), post(d, "/v1/render", dict(sq, viewport=vp)),
          post(d, "/v1/evaluate", dict(sq, points=[[0.5, 0.5]])), request(d, "GET", "/v1/version"),
          request(d, "GET", "/metrics")]
    check("%s: stateless routes answer 200" % why, all(r.status == 200 for r in rs), [r.brief() for r in rs
                                                                                        if r.status != 200][:2])


def section_down(R, A, B, mid):
    R.kill()
    stateless_ok(A, "Redis killed")
    all_mesh_routes_503(A, mid, "Redis killed")
    all_mesh_routes_503(B, mid, "Redis killed, replica B")
    rz = request(A, "GET", "/readyz")
    check("Redis killed: /readyz 503 problem+json with Retry-After", is_problem(rz, 503) and
          rz.h("Retry-After") is not None, rz.brief())
    hz = request(A, "GET", "/healthz")
    check("Redis killed: /healthz 200, store redis down", hz.status == 200 and
          hz.json().get("store") == {"backend": "redis", "state": "down"}, hz.brief())
    check("Redis killed: tocher_store_up 0, tocher_store_errors_total > 0",
          metric(A, "tocher_store_up") == 0 and metric(A, "tocher_store_errors_total") > 0)
    # 40 tiles from 8 threads while it is down: each a quick 503, none a 500.
    statuses, slow = [], []

    def burst():
        for _ in range(5):
            r = request(A, "GET", TILE % mid)
            statuses.append(r.status)
            if r.seconds >= DEADLINE:
                slow.append(r.seconds)

    th = [threading.Thread(target=burst) for _ in range(8)]
    for t in th:
        t.start()
    for t in th:
        t.join()
    check("Redis down, 40 tiles from 8 threads: all 503, none past the deadline", set(statuses) == {503} and
          not slow, (sorted(set(statuses)), slow[:3]))


def section_hung(mid_mesh):
    """Redis that accepts connections and never answers (SIGSTOP): bounded by the timeouts."""
    H = Redis(free_port())
    D = start("hung", H.port, "--request-timeout", str(DEADLINE))
    mid = post(D, "/v1/meshes", mid_mesh).json()["id"]
    check("before the hang: tile 200", request(D, "GET", TILE % mid).status == 200)
    H.proc.send_signal(signal.SIGSTOP)
    try:
        all_mesh_routes_503(D, mid, "Redis hung (SIGSTOP)")
        stateless_ok(D, "Redis hung")
        check("Redis hung: /healthz 200 at once", request(D, "GET", "/healthz").seconds < 0.5)
    finally:
        H.proc.send_signal(signal.SIGCONT)
    ok = wait_until(lambda: request(D, "GET", TILE % mid).status == 200, 5)
    check("Redis answers again (SIGCONT): the tile is 200 again", ok)
    D.stop()
    H.kill()


# ---- 4. Redis back, empty -----------------------------------------------------------------

def section_back(port, A, B, mesh, mid, tile):
    late = start("late", port, "--request-timeout", str(DEADLINE))  # started while Redis is down
    check("a replica started while Redis is down runs: /readyz 503, /healthz 200 down",
          request(late, "GET", "/readyz").status == 503 and
          request(late, "GET", "/healthz").json()["store"]["state"] == "down")
    R = Redis(port)
    for d in (A, B, late):
        t0 = time.time()
        ok = wait_until(lambda: request(d, "GET", "/readyz").status == 200, 5)
        check("Redis back (empty): %s ready again in %.1f s, no restart" % (d.name, time.time() - t0), ok)
    r = request(A, "GET", TILE % mid)
    check("Redis back empty: the old id answers 404 %r" % NOT_FOUND, is_problem(r, 404, NOT_FOUND), r.brief())
    r = post(A, "/v1/meshes", mesh)
    check("re-POST: 201, the same id", r.status == 201 and r.json()["id"] == mid, r.brief())
    for d in (A, B, late):
        t = request(d, "GET", TILE % mid)
        check("after the re-POST, %s serves the tile, bytes as before" % d.name, t.status == 200 and t.body == tile,
              t.brief())
    hz = request(B, "GET", "/healthz").json()
    check("/healthz says up, tocher_store_reconnects_total >= 1", hz["store"]["state"] == "up" and
          metric(B, "tocher_store_reconnects_total") >= 1, hz)
    check("the daemons logged the store going down and coming back",
          "unreachable" in A.stderr() and "reachable again" in A.stderr(), A.stderr()[-300:])
    return R


# ---- 5. configuration ---------------------------------------------------------------------

def section_config(R):
    for url in ("redis://", "redis://127.0.0.1", "redis://127.0.0.1:0", "redis://127.0.0.1:99999",
                "redis://127.0.0.1:6379/x", "http://127.0.0.1:6379", "redis:/127.0.0.1:6379"):
        d = start("bad", None, "--store", url, strict=False)
        d.proc.wait(10)
        check("--store %s: refused, exit 2, naming --store" % url, not d.started and d.proc.returncode == 2 and
              "--store" in d.stderr(), d.stderr()[-200:])
    d = start("badttl", R.port, "--mesh-ttl", "-1", strict=False)
    d.proc.wait(10)
    check("--mesh-ttl -1: refused", not d.started and d.proc.returncode == 2, d.stderr()[-200:])
    env = start("env", None, env={"TOCHER_STORE": "redis://127.0.0.1:%d/2" % R.port, "TOCHER_MESH_TTL": "500"})
    mid = post(env, "/v1/meshes", grid_mesh(2, shift=4.0)).json()["id"]
    ttl = _in_db(R, 2, "TTL", "tocher:mesh:" + mid)
    check("TOCHER_STORE=redis://…/2, TOCHER_MESH_TTL=500: the key in DB 2 with TTL 500", 490 < ttl <= 500, ttl)
    check("... and not in DB 0", R.cmd("EXISTS", "tocher:mesh:" + mid) == 0)
    env.stop()
    h = start("help", None, "--help", strict=False)
    out = h.line + h.proc.stdout.read().decode()
    h.proc.wait(10)
    check("--help names redis://, --mesh-ttl and TOCHER_MESH_TTL",
          all(w in out for w in ("redis://HOST:PORT", "--mesh-ttl", "TOCHER_MESH_TTL")), out[-300:])


def _in_db(R, db, *args):
    """One command in DB db (SELECT and the command on one connection)."""
    with socket.create_connection(("127.0.0.1", R.port), timeout=5) as s:
        out = b""
        for cmd in (("SELECT", db), args):
            out += b"*%d\r\n" % len(cmd)
            for a in cmd:
                a = str(a).encode()
                out += b"$%d\r\n%s\r\n" % (len(a), a)
        s.sendall(out)
        f = s.makefile("rb")
        _read_reply(f)
        return _read_reply(f)


def main():
    say("# %s against %s" % (os.path.basename(__file__), BUILD))
    if shutil.which("redis-server") is None:
        say("skip: redis-server is not installed (apt-get install redis-server; `make test` runs `make deps`)")
        finish()
    port = free_port()
    R = Redis(port)
    A = start("A", port, "--mesh-ttl", "1000", "--request-timeout", str(DEADLINE), "--workers", "8")
    B = start("B", port, "--mesh-ttl", "1000", "--request-timeout", str(DEADLINE), "--workers", "8")
    hz = request(A, "GET", "/healthz")
    rz = request(A, "GET", "/readyz")
    check("/healthz: 200, store redis up", hz.status == 200 and
          hz.json().get("store") == {"backend": "redis", "state": "up"}, hz.brief())
    check("/readyz: 200, status ready", rz.status == 200 and rz.json().get("status") == "ready", rz.brief())
    mesh, mid, tile = section_shared(R, A, B)
    section_lifetime(R, A, B, mid)
    section_down(R, A, B, mid)
    section_hung(mesh)
    R = section_back(port, A, B, mesh, mid, tile)
    section_config(R)
    for d in (A, B):
        check("%s exits 0 on SIGTERM" % d.name, d.stop() == 0)
    reports = [d.name for d in DAEMONS if SAN_RE.search(d.stderr())]
    check("no sanitizer report", not reports, reports)
    finish()


if __name__ == "__main__":
    main()
