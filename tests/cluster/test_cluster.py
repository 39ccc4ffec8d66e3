#!/usr/bin/env python3
"""test_cluster.py — tocher as a cluster (issue 16) on real engines: redis-server, 3 tocherd
replicas sharing it (--store redis://) and nginx with deploy/nginx/tocher.conf, all started here
on free loopback ports (deploy/cluster.py) and stopped whatever happens:

    /usr/bin/python3 tests/cluster/test_cluster.py BUILD_DIR

What it establishes, one "ok"/"FAIL" line per check, then "N passed, N failed":
  1. the build has the redis store (else one FAIL says so, and the rest runs with --store memory,
     each mesh POSTed to every replica, so the nginx side is still tested);
  2. meshes POSTed through nginx are served by every replica: all tiles of one mesh by one
     replica (the consistent hash, seen in each replica's /metrics), every replica serving some
     mesh, any replica answering any mesh's tile directly (the shared store); tile bytes through
     nginx equal a single tocherd's; a repeated tile is a cache HIT that reaches no replica, and
     If-None-Match gets a 304;
  3. 300 distinct tile GETs through nginx (so its cache cannot answer them) while one replica
     is killed with SIGKILL and restarted: 0 failed; the restarted replica serves again;
  4. 300 more while a replica drains on SIGTERM: 0 failed, and it exits 0;
  5. through nginx with Redis killed: mesh routes are the API's 503 problem+json with Retry-After
     (never nginx's HTML 502 "no live upstreams", though every replica is then marked failed),
     stateless routes 200; Redis back empty: once nginx retries the replicas (fail_timeout),
     old ids 404 and a re-POST works. (The replicas' own behaviour is tests/endpoint's.)
"""
import http.client
import json
import math
import os
import queue
import re
import shutil
import signal
import sys
import tempfile
import threading
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tests", "pylib"))
sys.path.insert(0, os.path.join(ROOT, "deploy"))
from tochertest import Tocherd, check, finish, say  # noqa: E402
from cluster import Cluster, has_redis_store  # noqa: E402

BUILD = sys.argv[1] if len(sys.argv) > 1 else "build"
if not os.path.isabs(BUILD) and not os.path.isdir(BUILD):
    BUILD = os.path.join(ROOT, BUILD)
BUILD = os.path.abspath(BUILD)
TOCHERD = os.path.join(BUILD, "tocherd")
TMP = tempfile.mkdtemp(prefix="tocher-cluster.")
TILE_ROUTE = 'tocher_http_requests_total{route="/v1/meshes/{id}/tiles/{z}/{x}/{tile}",status="200"}'
JSON_H = {"Content-Type": "application/json"}
CLIENTS = 4


def mesh(k, n=9):
    """An n×n grid of the unit square (2(n-1)² triangles) with data that differs with k: another
    id for every k, so meshes spread over the hash ring."""
    v = [[i / (n - 1), j / (n - 1)] for j in range(n) for i in range(n)]
    t = []
    for j in range(n - 1):
        for i in range(n - 1):
            a = j * n + i
            t += [[a, a + 1, a + n + 1], [a, a + n + 1, a + n]]
    vals = [0.5 + 0.4 * math.sin(3 * x + k) * math.cos(2 * y - 0.3 * k) for x, y in v]
    return json.dumps({"vertices": v, "triangles": t, "values": vals}).encode()


def request(port, method, path, body=None, headers=None, timeout=30):
    c = http.client.HTTPConnection("127.0.0.1", port, timeout=timeout)
    try:
        c.request(method, path, body=body, headers=headers or {})
        r = c.getresponse()
        return r.status, dict((k.lower(), v) for k, v in r.getheaders()), r.read()
    finally:
        c.close()


def tiles_served(port):
    """The replica's count of tile GETs answered 200 (its /metrics)."""
    st, _, body = request(port, "GET", "/metrics")
    m = re.search(re.escape(TILE_ROUTE) + r" (\d+)", body.decode())
    return int(m.group(1)) if st == 200 and m else 0


def load(port, paths, events=(), clients=CLIENTS, pace=0.05):
    """GETs every path through port by `clients` keep-alive clients, each pausing `pace` s between
    requests (so the faults land in the middle of the run); events: (requests done, action) run
    once that many are answered. Returns (failures as strings, bytes by path)."""
    todo, fails, got, done = queue.Queue(), [], {}, [0]
    for p in paths:
        todo.put(p)
    lock = threading.Lock()

    def client():
        c = None
        while True:
            try:
                p = todo.get_nowait()
            except queue.Empty:
                break
            try:
                if c is None:
                    c = http.client.HTTPConnection("127.0.0.1", port, timeout=30)
                c.request("GET", p)
                r = c.getresponse()
                body = r.read()
                with lock:
                    if r.status != 200:
                        fails.append("%s: %d %r" % (p, r.status, body[:120]))
                    got[p] = body
            except (OSError, http.client.HTTPException) as e:
                with lock:
                    fails.append("%s: %r" % (p, e))
                c = None
            with lock:
                done[0] += 1
            time.sleep(pace)
        if c:
            c.close()

    threads = [threading.Thread(target=client) for _ in range(clients)]
    for th in threads:
        th.start()
    pending = sorted(events, key=lambda e: e[0])
    while any(th.is_alive() for th in threads):
        while pending and done[0] >= pending[0][0]:
            pending.pop(0)[1]()
        time.sleep(0.01)
    for th in threads:
        th.join()
    for _, action in pending:  # events past the end still run (and show in the count)
        action()
    return fails, got


def main():
    # A SIGTERM or Ctrl-C still runs the finally below: the cluster's processes, in their own
    # sessions, would otherwise outlive the test.
    for sig in (signal.SIGTERM, signal.SIGINT, signal.SIGHUP):
        signal.signal(sig, lambda *_: sys.exit("test_cluster.py: interrupted"))
    redis = has_redis_store(TOCHERD)
    check("this build has a redis store (tocherd --help lists --store redis://)", redis,
          "this build has no redis store: replicas cannot share meshes; the checks below run with "
          "--store memory, each mesh POSTed to every replica")
    cl = Cluster(BUILD, os.path.join(TMP, "run"), replicas=3, store="redis" if redis else "memory",
                 tocherd_flags=["--threads", "2", "--workers", "2", "--shutdown-grace", "10"])
    single = None
    try:
        cl.start()
        single = Tocherd(TOCHERD, os.path.join(TMP, "single.stderr"), ["--store", "memory"])
        run(cl, single, redis)
    finally:
        if single:
            single.kill()
        cl.stop()
        shutil.rmtree(TMP, ignore_errors=True)
    finish()


def run(cl, single, redis):
    ng, reps = cl.port, cl.replica_ports
    bodies, ids = {}, []

    def post(k):
        """POSTs mesh k through nginx (and, without a shared store, to every replica)."""
        st, _, out = request(ng, "POST", "/v1/meshes", mesh(k), JSON_H)
        if st not in (200, 201):
            raise RuntimeError("POST through nginx: %d %r" % (st, out[:200]))
        if not redis:
            for p in reps:
                request(p, "POST", "/v1/meshes", mesh(k), JSON_H)
        bodies[k] = mesh(k)
        return json.loads(out)["id"]

    # ---- 2. routing by mesh, every replica, shared store, same bytes, the cache ----
    owner, hashed_ok, k = {}, True, 0
    while k < 40 and (k < 3 or len(set(owner.values())) < len(reps)):
        mid = post(k)
        ids.append(mid)
        before = [tiles_served(p) for p in reps]
        for x, y in ((0, 0), (1, 0), (0, 1), (1, 1)):
            st, _, _ = request(ng, "GET", "/v1/meshes/%s/tiles/1/%d/%d.raw?size=16" % (mid, x, y))
            hashed_ok &= st == 200
        grew = [a - b for a, b in zip([tiles_served(p) for p in reps], before)]
        if sorted(grew) != [0] * (len(reps) - 1) + [4]:
            hashed_ok = False
            say("   mesh %d: tiles per replica %s (expected all 4 on one)" % (k, grew))
        else:
            owner[mid] = grew.index(4)
        k += 1
    check("all tiles of a mesh go to one replica (consistent hash on the id), %d meshes" % k, hashed_ok)
    check("every replica serves tiles through nginx (%s)" % sorted(set(owner.values())),
          len(set(owner.values())) == len(reps))
    direct_ok, detail = True, ""
    for mid in ids[:4]:
        path = "/v1/meshes/%s/tiles/2/1/2.raw?size=16" % mid
        _, _, ref = request(ng, "GET", path)
        for p in reps:
            st, _, b = request(p, "GET", path)
            if st != 200 or b != ref:
                direct_ok, detail = False, "replica :%d answered %d for %s" % (p, st, path)
    check("any replica serves any mesh POSTed through nginx (the shared store), same bytes", direct_ok, detail)
    same, detail = True, ""
    for k2, mid in enumerate(ids[:3]):
        st, _, out = request(single.port, "POST", "/v1/meshes", bodies[k2], JSON_H)
        same &= st in (200, 201) and json.loads(out)["id"] == mid
        for path in ("/v1/meshes/%s/tiles/0/0/0.png" % mid, "/v1/meshes/%s/tiles/2/3/1.exr?exposure=2" % mid,
                     "/v1/meshes/%s/tiles/3/5/2.raw?size=64" % mid):
            a, b = request(ng, "GET", path), request(single.port, "GET", path)
            if a[0] != 200 or b[0] != 200 or a[2] != b[2]:
                same, detail = False, "%s: nginx %d (%d bytes), single %d (%d bytes)" % (path, a[0], len(a[2]), b[0], len(b[2]))
    body = bodies[0][:-1] + b',"viewport":{"x0":0,"y0":0,"x1":1,"y1":1,"width":32,"height":32},"format":"png"}'
    a, b = request(ng, "POST", "/v1/render", body, JSON_H), request(single.port, "POST", "/v1/render", body, JSON_H)
    same &= a[0] == 200 and a[2] == b[2]
    check("tile and /v1/render bytes through nginx equal a single tocherd's", same, detail)
    path = "/v1/meshes/%s/tiles/1/1/1.png" % ids[0]
    first = request(ng, "GET", path)
    before = [tiles_served(p) for p in reps]
    again = request(ng, "GET", path)
    after = [tiles_served(p) for p in reps]
    check("a repeated tile is nginx's cache HIT and reaches no replica",
          again[0] == 200 and again[1].get("x-cache-status") == "HIT" and again[2] == first[2] and before == after,
          "%d %s, replicas %s -> %s" % (again[0], again[1].get("x-cache-status"), before, after))
    st, h, _ = request(ng, "GET", path, headers={"If-None-Match": first[1].get("etag", "")})
    check("If-None-Match through nginx: 304", st == 304 and h.get("etag") == first[1].get("etag"), "%d %s" % (st, h))

    # ---- 3. SIGKILL and restart of a replica under load ----
    victim = max(range(len(reps)), key=lambda i: list(owner.values()).count(i))
    paths = ["/v1/meshes/%s/tiles/4/%d/%d.raw?size=16" % (ids[n % len(ids)], (n // len(ids)) % 16, n // (16 * len(ids)))
             for n in range(300)]

    def restart():
        cl.start_replica(victim)
        if not redis:  # its memory store is empty
            for k2 in bodies:
                request(reps[victim], "POST", "/v1/meshes", bodies[k2], JSON_H)

    t0 = time.time()
    fails, _ = load(ng, paths, [(60, lambda: cl.signal_replica(victim, signal.SIGKILL)), (180, restart)])
    check("300 tile GETs through nginx, replica %d killed (SIGKILL) and restarted: 0 failed (%.1f s)"
          % (victim + 1, time.time() - t0), not fails, "%d failed: %s" % (len(fails), fails[:3]))
    # nginx tries a failed server again after fail_timeout (3 s): then it serves its meshes again.
    time.sleep(3.5)
    mine = [m for m, r in owner.items() if r == victim]
    before = tiles_served(reps[victim])
    for n, mid in enumerate(mine[:2]):
        request(ng, "GET", "/v1/meshes/%s/tiles/3/%d/7.raw?size=16" % (mid, n))
    after = tiles_served(reps[victim])
    check("the restarted replica serves its meshes through nginx again (%d tiles)" % (after - before),
          bool(mine) and after - before == len(mine[:2]), "before %d, after %d" % (before, after))

    # ---- 4. graceful SIGTERM (drain) of a replica under load ----
    drained = (victim + 1) % len(reps)
    paths = ["/v1/meshes/%s/tiles/5/%d/%d.raw?size=16" % (ids[n % len(ids)], (n // len(ids)) % 32, n // (32 * len(ids)))
             for n in range(300)]
    t0 = time.time()
    fails, _ = load(ng, paths, [(80, lambda: cl.signal_replica(drained, signal.SIGTERM))])
    p = cl.procs["tocherd-%d" % (drained + 1)]
    try:
        code = p.wait(15)
    except Exception:  # noqa: BLE001 — a replica that does not exit is the failure reported below
        code = None
    check("300 tile GETs through nginx, replica %d drained (SIGTERM): 0 failed (%.1f s)"
          % (drained + 1, time.time() - t0), not fails, "%d failed: %s" % (len(fails), fails[:3]))
    check("the drained replica exits 0", code == 0, "exit %r" % code)

    # ---- 5. Redis down and back, as nginx's clients see it ----
    if not redis:
        check("Redis down behind nginx", False, "not run: this build has no redis store")
        return
    cl.start_replica(drained)
    cl.procs["redis"].kill()
    cl.procs["redis"].wait(5)
    seen, t0 = [], time.time()
    for n in range(8):
        st, h, b = request(ng, "GET", "/v1/meshes/%s/tiles/3/%d/3.raw?size=16" % (ids[n % len(ids)], n))
        seen.append((st, h.get("content-type"), h.get("retry-after")))
    dt = time.time() - t0
    check("Redis down: tile GETs through nginx 503 problem+json with Retry-After (%.1f s for 8)" % dt,
          all(x == (503, "application/problem+json", "1") for x in seen) and dt < 8, seen)
    st = [request(ng, "GET", "/healthz")[0], request(ng, "POST", "/v1/ordinates", mesh(1), JSON_H)[0]]
    check("Redis down: stateless routes through nginx 200", st == [200, 200], st)
    cl.start_redis()
    # Working again without a restart, once the replicas reconnect (their backoff) and nginx
    # tries the replicas it marked failed again (fail_timeout, 3 s): polled, at most 15 s.
    t0 = time.time()
    while True:
        old = request(ng, "GET", "/v1/meshes/%s/tiles/3/7/3.raw?size=16" % ids[0])
        if old[0] != 503 or time.time() - t0 > 15:
            break
        time.sleep(0.25)
    # A POST goes round robin and nginx never retries one, so every replica must have
    # reconnected (each in its own backoff; until then it answers 503 + Retry-After, as
    # documented): wait for each one's /readyz, within the same 15 s.
    ready = all(cl.wait_ready(p, max(0.5, 15 - (time.time() - t0))) for p in reps)
    say("   back after %.1f s (every replica ready: %s)" % (time.time() - t0, ready))
    st, _, out = request(ng, "POST", "/v1/meshes", bodies[0], JSON_H)
    new = request(ng, "GET", "/v1/meshes/%s/tiles/3/7/4.raw?size=16" % ids[0])
    check("Redis back empty: an old id 404, a re-POST 201 and its tiles 200", (old[0], st, new[0]) == (404, 201, 200),
          (old[0], st, out[:100], new[0]))


if __name__ == "__main__":
    main()
