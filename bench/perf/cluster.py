#!/usr/bin/env python3
"""cluster.py — the cluster side of `make bench` (issue 16): tiles/s through nginx with 1, 2 and 3
tocherd replicas sharing one Redis (deploy/cluster.py, real processes on loopback), wrk's keep-alive
clients GETting 256² PNG tiles of 48 stored 10k-triangle meshes, each URL once so nginx's cache
never answers (its access log is checked). Prints one JSON object, and the figures on stderr.

    /usr/bin/python3 bench/perf/cluster.py BUILD_DIR [SECONDS]
"""
import http.client
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "bench", "perf"))
sys.path.insert(0, os.path.join(ROOT, "deploy"))
from cluster import Cluster, has_redis_store  # noqa: E402

BUILD = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else "build")
SECONDS = int(sys.argv[2]) if len(sys.argv) > 2 else 6
LUA = os.path.join(ROOT, "bench", "perf", "cluster.lua")
MESHES, Z, THREADS, CONNS = 48, 6, 4, 16


def grid(n, k):
    """An n×n vertex grid of the unit square, 2(n-1)² triangles, with the benchmarks' data
    f = sin(3x+1)·cos(2y) + x²/2 shifted by 0.01·k (another id for each k). Pure Python:
    the cluster bench needs no numpy."""
    v = [[i / (n - 1), j / (n - 1)] for j in range(n) for i in range(n)]
    t = []
    for j in range(n - 1):
        for i in range(n - 1):
            a = j * n + i
            t += [[a, a + 1, a + n + 1], [a, a + n + 1, a + n]]
    f = [math.sin(3 * x + 1) * math.cos(2 * y) + x * x / 2 + 0.01 * k for x, y in v]
    return json.dumps({"vertices": v, "triangles": t, "values": f}).encode()


def call(port, method, path, body=None):
    c = http.client.HTTPConnection("127.0.0.1", port, timeout=120)
    c.request(method, path, body=body, headers={"Content-Type": "application/json"} if body else {})
    r = c.getresponse()
    data = r.read()
    c.close()
    if r.status not in (200, 201):
        raise SystemExit("%s %s on :%d: %d %r" % (method, path, port, r.status, data[:200]))
    return data


def one(n, redis, bodies, tmp):
    cl = Cluster(BUILD, os.path.join(tmp, "run%d" % n), replicas=n, store="redis" if redis else "memory")
    try:
        cl.start()
        ids = []
        for b in bodies:  # through nginx; without a shared store, to every replica as well
            ids.append(json.loads(call(cl.port, "POST", "/v1/meshes", b))["id"])
            if not redis:
                for p in cl.replica_ports:
                    call(p, "POST", "/v1/meshes", b)
        for p in cl.replica_ports:  # the image plugin loaded on every replica (tile 0 is not benchmarked)
            call(p, "GET", "/v1/meshes/%s/tiles/0/0/0.png" % ids[0])
        for i in ids:  # every mesh built on the replica its id hashes to
            call(cl.port, "GET", "/v1/meshes/%s/tiles/0/0/0.png" % i)
        log = os.path.join(cl.run, "nginx-access.log")
        start = os.path.getsize(log)
        env = dict(os.environ, TOCHER_MESH_IDS=",".join(ids), TOCHER_TILE_Z=str(Z), TOCHER_TILE_FORMAT="png",
                   TOCHER_WRK_THREADS=str(THREADS))
        out = subprocess.run(["wrk", "-t%d" % THREADS, "-c%d" % CONNS, "-d%ds" % SECONDS, "-s", LUA,
                              "http://127.0.0.1:%d/" % cl.port], env=env, capture_output=True, text=True,
                             timeout=SECONDS + 60).stdout
        m = re.search(r"^WRKJSON (.*)$", out, re.M)
        if not m:
            raise SystemExit("wrk: %s" % out[-400:])
        res = json.loads(m.group(1))
        time.sleep(0.3)  # nginx writes its access log lines as requests end
        with open(log) as f:
            f.seek(start)
            lines = [l for l in f if "/tiles/%d/" % Z in l]
        ups = {}
        for l in lines:
            u = re.search(r" up=(\S+)", l)
            ups[u.group(1) if u else "-"] = ups.get(u.group(1) if u else "-", 0) + 1
        res.update(replicas=n, tiles_per_s=res["requests"] / (res["duration_us"] * 1e-6),
                   cache_hits=sum(1 for l in lines if "cache=HIT" in l), per_upstream=ups)
        return res
    finally:
        cl.stop()


def main():
    redis = has_redis_store(os.path.join(BUILD, "tocherd"))
    # 48 different meshes of 9800 triangles: the hash spreads them over the replicas.
    bodies = [grid(71, k) for k in range(MESHES)]
    load = "%.1f" % os.getloadavg()[0]
    tmp = tempfile.mkdtemp(prefix="tocher-bench-cluster.")
    try:
        runs = [one(n, redis, bodies, tmp) for n in (1, 2, 3)]
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    res = {"date": time.strftime("%Y-%m-%d", time.gmtime()), "cores": os.cpu_count(),
           "store": "redis" if redis else "memory (this build has no redis store)", "meshes": MESHES, "zoom": Z, "loadavg": load,
           "tocherd": subprocess.run([os.path.join(BUILD, "tocherd"), "--version"], capture_output=True,
                                     text=True).stdout.strip(),
           "wrk_threads": THREADS, "connections": CONNS, "seconds": SECONDS, "runs": runs}
    for r in runs:
        print("cluster: %d replica(s) behind nginx: %.0f tiles/s (256² PNG, %d meshes of 10k triangles, %d connections), "
              "p50 %.1f ms, p99 %.1f ms, %d errors, %d cache hits" %
              (r["replicas"], r["tiles_per_s"], MESHES, CONNS, r["p50_us"] / 1e3, r["p99_us"] / 1e3,
               r["errors"] + r["non2xx"], r["cache_hits"]), file=sys.stderr)
    print(json.dumps(res, indent=1))


if __name__ == "__main__":
    main()
