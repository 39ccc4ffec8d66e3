#!/usr/bin/env python3
"""whole.py — a whole `/v1/ordinates` request as a client sees it, against scipy's
CloughTocher2DInterpolator built from the same points with the gradients given, in one run.
Prints one JSON object.

    /usr/bin/python3 bench/perf/whole.py [BUILD_DIR ...] [--repeat N] [--quick] [--only NAME.FORM]

(e.g. a baseline beside this tree: `git worktree add /tmp/base main && make -C /tmp/base
build/tocherd`, then `whole.py /tmp/base/build build`; about 4 minutes on 2 shared cores.)

Each BUILD_DIR (default: build) has its build/tocherd started on a free loopback port; with
several (e.g. a baseline build and this one) they are timed in turns in the same run, so their
figures compare side by side. The meshes are bench/perf/meshes.py's grids, made in memory:
grid64 (8192 triangles), grid256 (131 072) and grid512 (524 288), with exact gradients.

The client: one keep-alive http.client connection per daemon, the body prepared beforehand
(bytes), timed from sending the request to having read the whole answer (not decoding it).
Figures are the best of N rounds (--repeat, default 5; at most 3 for grid512), each round scipy
once and then every case on every daemon once, so that a slow spell hits both sides; the phase breakdown
(Server-Timing: parse, validate, build, encode, total in ms) is that of the best run, and
"transport_ms" is the client's wall clock less the daemon's total (sending the body, the
answer's bytes through the socket, HTTP framing).

scipy (peers.py's definitions, its best of the same rounds):
  - scipy_points_s: Delaunay(points) then peers.ct_given_gradients — the interpolator built
    from the points with the gradients given (no gradient estimate). The ratios use this.
  - scipy_tri_s:    peers.ct_given_gradients on an already built Delaunay (ct_build_grad_s
    in peers.py), for reference: it is nearly only numpy copies.
The cases: "json" (plain JSON numbers in and out) and "typed" (typed arrays in, "encoding":
"base64" out). Each answer is checked once (an untimed first request that also warms the
daemon up): status 200, the ordinates' shape [T, 1, 19] and, typed, the data's length.
Warm-up matters on small meshes: the daemon's workers each have a malloc arena, and the first
few answers a worker writes fault their pages in (use --repeat 5 or more for 8192 triangles).
"""
import argparse
import base64
import copy
import gc
import http.client
import json
import os
import re
import subprocess
import sys
import time

import numpy as np
from scipy.spatial import Delaunay

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import meshes  # noqa: E402  (bench/perf/meshes.py: the grids and their data)
import peers  # noqa: E402   (bench/perf/peers.py: ct_given_gradients, pristine)

ROOT = os.path.dirname(os.path.dirname(HERE))
CASES = [("grid64", "json"), ("grid64", "typed"), ("grid256", "json"), ("grid256", "typed"),
         ("grid512", "typed")]
TARGETS = {("grid256", "json"): 3.0, ("grid512", "typed"): 6.0}


def log(*args):
    print(*args, file=sys.stderr, flush=True)


def mesh(name):
    n = int(name[4:])
    points = meshes.grid_points(n)
    simplices = meshes.triangulate(points, 2 * n * n)
    values, gx, gy = meshes.f(points[:, 0], points[:, 1])
    return points, simplices, values, np.column_stack([gx, gy])


def typed(a, dtype):
    a = np.ascontiguousarray(a, dtype=np.dtype(dtype).newbyteorder("<"))
    return {"dtype": dtype, "shape": list(a.shape), "data": base64.b64encode(a.tobytes()).decode()}


def body(points, simplices, values, grads, form):
    if form == "json":  # meshes.py's own text: float.__repr__, shortest round trip
        return ('{"vertices":' + meshes.dumps(points.tolist()) + ',"triangles":' +
                meshes.dumps(simplices.tolist()) + ',"values":' + meshes.dumps(values.tolist()) +
                ',"gradients":' + meshes.dumps(grads.tolist()) + "}\n").encode()
    return json.dumps({"vertices": typed(points, "float64"), "triangles": typed(simplices, "int32"),
                       "values": typed(values, "float64"), "gradients": typed(grads, "float64"),
                       "encoding": "base64"}, separators=(",", ":")).encode()


class Daemon:
    def __init__(self, build):
        self.build = build
        self.proc = subprocess.Popen([os.path.join(build, "tocherd"), "--listen", "127.0.0.1:0",
                                      "--connection-timeout", "600"],
                                     stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
        line = self.proc.stdout.readline().decode()
        m = re.search(r"127\.0\.0\.1:(\d+)", line)
        if not m:
            self.proc.kill()
            raise SystemExit("%s/tocherd did not start: %r" % (build, line))
        self.port = int(m.group(1))
        self.conn = http.client.HTTPConnection("127.0.0.1", self.port, timeout=300)

    def post(self, path, data):
        """(seconds from send to the whole answer read, status, answer bytes, Server-Timing)."""
        t0 = time.perf_counter()
        self.conn.request("POST", path, body=data, headers={"Content-Type": "application/json"})
        r = self.conn.getresponse()
        answer = r.read()
        t = time.perf_counter() - t0
        return t, r.status, answer, r.getheader("Server-Timing") or ""

    def close(self):
        self.conn.close()
        self.proc.terminate()
        self.proc.wait(timeout=30)


def phases(header):
    return {k: float(v) for k, v in re.findall(r"(\w+);dur=([0-9.]+)", header)}


def check(status, answer, form, ntri):
    assert status == 200, answer[:300]
    doc = json.loads(answer)
    ords = doc["ordinates"]
    shape = ords["shape"] if form == "typed" else [len(ords), len(ords[0]), len(ords[0][0])]
    assert shape[0] == ntri and shape[1] == 1, shape
    if form == "typed":
        assert len(base64.b64decode(ords["data"])) == 8 * shape[0] * shape[1] * shape[2]
    return shape


def scipy_round(points, values, grads, tri0):
    """One timing of each scipy figure: (from points, given a Delaunay), in seconds."""
    gc.collect()
    t0 = time.perf_counter()
    peers.ct_given_gradients(Delaunay(points), values, grads)
    tp = time.perf_counter() - t0
    tri = peers.pristine(tri0)
    gc.collect()
    t0 = time.perf_counter()
    peers.ct_given_gradients(tri, values, grads)
    return tp, time.perf_counter() - t0


def timed_rounds(name, points, simplices, values, grads, forms, daemons, repeat):
    """The bodies of each form, then `repeat` rounds of: scipy once, each form on each daemon
    once. In turns, so that a slow spell of the machine hits scipy and tocher alike. Returns
    (best scipy from points, best scipy given a Delaunay, {form: ([best (t, timing)] per daemon,
    body bytes, answer bytes, shape)})."""
    tri0 = Delaunay(points)
    assert np.array_equal(tri0.simplices, simplices)
    res = {}
    for form in forms:
        data = body(points, simplices, values, grads, form)
        res[form] = [data, [None] * len(daemons), 0, None]
        for d in daemons:  # one untimed run each: warms up, checks the answer
            _, status, answer, _ = d.post("/v1/ordinates", data)
            res[form][2:] = [len(answer), check(status, answer, form, len(simplices))]
            del answer
    sp = st = None
    for _ in range(repeat):
        tp, tt = scipy_round(points, values, grads, tri0)
        sp, st = tp if sp is None else min(sp, tp), tt if st is None else min(st, tt)
        for form in forms:
            data, best = res[form][0], res[form][1]
            for k, d in enumerate(daemons):
                gc.collect()
                t, status, answer, timing = d.post("/v1/ordinates", data)
                assert status == 200
                del answer
                if best[k] is None or t < best[k][0]:
                    best[k] = (t, timing)
    log(f"{name}: scipy from points {sp * 1e3:.1f} ms, given a Delaunay {st * 1e3:.2f} ms")
    return sp, st, {f: (r[1], len(r[0]), r[2], r[3]) for f, r in res.items()}


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("builds", nargs="*", default=["build"])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--quick", action="store_true", help="grid64 only (a smoke test)")
    ap.add_argument("--only", action="append", help="a case NAME.FORM (e.g. grid512.typed); repeatable")
    args = ap.parse_args(argv[1:])
    builds = [os.path.abspath(b) for b in args.builds]
    cases = [c for c in CASES if (not args.quick or c[0] == "grid64") and
             (not args.only or "%s.%s" % c in args.only)]
    out = {"builds": builds, "repeat": args.repeat, "cases": {}}
    daemons = [Daemon(b) for b in builds]
    try:
        for name in dict.fromkeys(c[0] for c in cases):
            points, simplices, values, grads = mesh(name)
            ntri = len(simplices)
            repeat = args.repeat if ntri < 500_000 else max(1, min(args.repeat, 3))
            forms = [f for n, f in cases if n == name]
            sp, st, timed = timed_rounds(name, points, simplices, values, grads, forms, daemons, repeat)
            for form in forms:
                best, body_bytes, answer_bytes, shape = timed[form]
                res = {"triangles": ntri, "body_bytes": body_bytes, "scipy_points_ms": sp * 1e3,
                       "scipy_tri_ms": st * 1e3, "tocher": {}, "answer_bytes": answer_bytes, "shape": shape}
                for k, b in enumerate(builds):
                    t, timing = best[k]
                    ph = phases(timing)
                    row = {"wall_ms": t * 1e3, "phases_ms": ph,
                           "transport_ms": t * 1e3 - ph.get("total", 0.0),
                           "vs_scipy_points": sp / t, "vs_scipy_tri": st / t}
                    if (name, form) in TARGETS:
                        row["target"] = TARGETS[(name, form)]
                        row["meets_target"] = sp / t >= TARGETS[(name, form)]
                    res["tocher"][b] = row
                    log(f"{name} {form} {b}: {t * 1e3:.1f} ms, {sp / t:.2f}x scipy; {timing}")
                out["cases"][f"{name}.{form}"] = res
    finally:
        for d in daemons:
            d.close()
    json.dump(out, sys.stdout, indent=1)
    print()


if __name__ == "__main__":
    main(sys.argv)
