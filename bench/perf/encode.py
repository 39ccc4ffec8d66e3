#!/usr/bin/env python3
# encode.py — the /v1/ordinates answer's encode phase (Server-Timing "encode") on a 131k-triangle
# mesh (grid256 of meshes.py: f and its gradients), the figure issue 17's number printing moves.
#
#     bench/perf/encode.py BUILD [BUILD...]    (each BUILD's tocherd; one JSON object out)
#
# Each figure is the minimum over RUNS requests to one daemon (the machines are noisy).
import http.client
import json
import os
import re
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from meshes import dumps, f, grid_points  # noqa: E402

N = 256          # 2 * 256^2 = 131072 triangles
RUNS = 7


def grid_triangles(n):
    """Two triangles per square of the (n+1)^2 grid, counter-clockwise."""
    t = []
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            t += [[a, a + 1, a + n + 2], [a, a + n + 2, a + n + 1]]
    return t


def body():
    p = grid_points(N)
    v, gx, gy = f(p[:, 0], p[:, 1])
    return ('{"vertices":' + dumps(p.tolist()) + ',"triangles":' + dumps(grid_triangles(N)) +
            ',"values":' + dumps(v.tolist()) + ',"gradients":' +
            dumps(np.column_stack([gx, gy]).tolist()) + "}").encode()


def phases(header):
    return {m.group(1): float(m.group(2)) for m in re.finditer(r"(\w+);dur=([0-9.]+)", header)}


def measure(build, req):
    proc = subprocess.Popen([os.path.join(build, "tocherd"), "--listen", "127.0.0.1:0"],
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
    try:
        m = re.search(r"127\.0\.0\.1:(\d+)", proc.stdout.readline().decode())
        if not m:
            raise SystemExit("tocherd did not start")
        best, size = None, 0
        for _ in range(RUNS):
            c = http.client.HTTPConnection("127.0.0.1", int(m.group(1)), timeout=120)
            c.request("POST", "/v1/ordinates", body=req, headers={"Content-Type": "application/json"})
            r = c.getresponse()
            data = r.read()
            c.close()
            if r.status != 200:
                raise SystemExit("status %d: %s" % (r.status, data[:200]))
            ph = phases(r.getheader("Server-Timing", ""))
            size = len(data)
            if best is None or ph.get("encode", 1e9) < best.get("encode", 1e9):
                best = ph
        return {"build": build, "triangles": 2 * N * N, "answer_bytes": size, "best_ms": best}
    finally:
        proc.terminate()
        proc.wait()


if __name__ == "__main__":
    req = body()
    print(json.dumps([measure(b, req) for b in sys.argv[1:] or ["build"]], indent=1))
