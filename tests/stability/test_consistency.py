#!/usr/bin/env python3
"""test_consistency.py — points exactly on vertices and edges give the same answer from every
front door: `tocher eval` and tocherd's POST /v1/evaluate bit for bit (JSON numbers are exact),
and `tocher render` (1, 2, 5 threads) and POST /v1/render (raw float32) bit for bit, each pixel
the evaluate value at its centre rounded once to float; no NaN, no gap. Also: a 1e6-aspect sliver
is reported in the "warnings" of /v1/ordinates, /v1/evaluate and `tocher eval`, and in the
Tocher-Warning headers of /v1/render.

    /usr/bin/python3 tests/stability/test_consistency.py BUILD_DIR

One "ok"/"FAIL" line per check, then "N passed, N failed" (exit 1 on any failure).
"""
import atexit
import http.client
import json
import math
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tests", "pylib"))
from tochertest import SAN_RE, check, finish, first_line  # noqa: E402
BUILD = sys.argv[1] if len(sys.argv) > 1 else "build"
if not os.path.isabs(BUILD) and not os.path.isdir(BUILD):
    BUILD = os.path.join(ROOT, BUILD)
BUILD = os.path.abspath(BUILD)
TOCHER, TOCHERD = os.path.join(BUILD, "tocher"), os.path.join(BUILD, "tocherd")
TMP = tempfile.mkdtemp(prefix="tocher-consistency.")
atexit.register(shutil.rmtree, TMP, True)

# ---- the daemon ---------------------------------------------------------------------------

class Daemon:
    """One tocherd on 127.0.0.1:0 (killed when the script ends)."""

    def __init__(self, *flags):
        env = {k: v for k, v in os.environ.items() if not k.startswith("TOCHER_") or k == "TOCHER_IMAGE_LIB"}
        self.err = open(os.path.join(TMP, "tocherd.stderr"), "wb")
        self.proc = subprocess.Popen([TOCHERD, "--listen", "127.0.0.1:0", *flags], stdin=subprocess.DEVNULL,
                                     stdout=subprocess.PIPE, stderr=self.err, env=env)
        atexit.register(self.stop)
        line = first_line(self.proc, 30)
        m = re.fullmatch(r"tocherd \S+ listening on http://127\.0\.0\.1:(\d+)", line)
        if not m:
            raise RuntimeError("tocherd did not start: %r" % line)
        self.port = int(m.group(1))

    def post(self, path, doc, with_headers=False):
        conn = http.client.HTTPConnection("127.0.0.1", self.port, timeout=300)
        try:
            conn.request("POST", path, body=json.dumps(doc).encode(), headers={"Content-Type": "application/json"})
            r = conn.getresponse()
            body = r.read()
            return (r.status, body, r.msg) if with_headers else (r.status, body)
        finally:
            conn.close()

    def stop(self):
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(10)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        if not self.err.closed:
            self.err.close()

    def sanitizer_report(self):
        self.stop()
        with open(self.err.name, "rb") as fh:
            text = fh.read().decode("utf-8", "replace")
        return SAN_RE.search(text) and text[:400]


def cli(*args):
    r = subprocess.run([TOCHER, *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE, timeout=300)
    err = r.stderr.decode("utf-8", "replace")
    if SAN_RE.search(err):
        check("tocher %s: no sanitizer report" % args[0], False, err[:400])
    return r.returncode, r.stdout, err


# ---- the mesh: an 8 x 8 grid of multiples of 1/8, a C0 row, a C-1 column with a jump ------

N = 8


def f(x, y):
    return math.sin(2 * x + 1) * math.cos(3 * y - 0.5) + 0.5 * x * y + 1


def grad(x, y):
    return [2 * math.cos(2 * x + 1) * math.cos(3 * y - 0.5) + 0.5 * y,
            -3 * math.sin(2 * x + 1) * math.sin(3 * y - 0.5) + 0.5 * x]


def vid(i, j):
    return j * (N + 1) + i


def mesh(quads=False):
    verts = [[i / N, j / N] for j in range(N + 1) for i in range(N + 1)]
    values = [f(x, y) for x, y in verts]
    cells = [(vid(i, j), vid(i + 1, j), vid(i + 1, j + 1), vid(i, j + 1)) for j in range(N) for i in range(N)]
    doc = {"vertices": verts, "values": values, "gradients": [grad(x, y) for x, y in verts],
           "discontinuities": {"c0": [[vid(i, 4) for i in range(N + 1)]], "c-1": [[vid(3, j) for j in range(N + 1)]]}}
    if quads:
        doc["quads"] = [list(c) for c in cells]
        # a jump of 0.5 right of the C-1 column: corner values of the cells whose left side is it
        doc["corner_values"] = [{"quad": j * N + 3, "values": [values[c] + 0.5 * (k in (0, 3))
                                                             for k, c in enumerate(cells[j * N + 3])]}
                                for j in range(N)]
        return doc
    tris = []
    for n, (a, b, c, d) in enumerate(cells):
        tris += [[a, b, c], [a, c, d]] if (n * 7 + n // N) % 3 else [[a, b, d], [b, c, d]]
    doc["triangles"] = tris
    jump = []
    for t, tri in enumerate(tris):  # triangles right of the column x = 3/8 that touch it
        xs = [verts[v][0] for v in tri]
        if min(xs) == 3 / N and max(xs) > 3 / N:
            jump.append({"triangle": t, "values": [values[v] + 0.5 * (verts[v][0] == 3 / N) for v in tri]})
    doc["corner_values"] = jump
    edges = sorted({tuple(sorted((t[k], t[(k + 1) % 3]))) for t in tris for k in range(3)})
    doc["midpoints"] = [{"edge": list(e), "value": f((verts[e[0]][0] + verts[e[1]][0]) / 2,
                                                     (verts[e[0]][1] + verts[e[1]][1]) / 2)}
                        for e in edges if not (verts[e[0]][0] == verts[e[1]][0] == 3 / N)]
    return doc


# Points on every vertex, edge midpoint and quarter point (exact: multiples of 1/32), the corners
# of the domain, and a few outside.
POINTS = [[i / 32, j / 32] for j in range(33) for i in range(33) if i % 4 == 0 or j % 4 == 0 or i == j] + \
         [[-0.25, 0.5], [1.25, 0.5], [0.5, 1.0 + 2 ** -20]]

# Pixel centres at the multiples of 1/32: x0 = -1/64, x1 = x0 + 2, 64 pixels (and y alike from the top).
W = 64
VIEWPORT = {"x0": -1 / 64, "y0": 1 + 1 / 64 - 2, "x1": -1 / 64 + 2, "y1": 1 + 1 / 64, "width": W, "height": W}


def centres():
    v = VIEWPORT
    return [[v["x0"] + (v["x1"] - v["x0"]) * ((i + 0.5) / W), v["y1"] - (v["y1"] - v["y0"]) * ((j + 0.5) / W)]
            for j in range(W) for i in range(W)]


VARIANTS = [("constant", {}), ("linear", {}), ("linear4", {}),
            ("clough-tocher", {"cross_boundary": "normal"}), ("clough-tocher", {"cross_boundary": "salesin"}),
            ("clough-tocher", {"cross_boundary": "affine"}),
            ("clough-tocher", {"cross_boundary": "normal", "wedges": "literal"}),
            ("clough-tocher", {"cross_boundary": "salesin", "wedges": "literal"}),
            ("clough-tocher-c1", {}), ("powell-sabin", {}), ("hermite", {})]


def without_timings(doc):
    return {k: v for k, v in doc.items() if k != "timings"}


def finite_values(doc):
    for v in doc.get("values", []) + [g for p in doc.get("gradients", []) if p for g in p]:
        if v is not None and not math.isfinite(v):
            return False
    return True


def write(name, doc):
    path = os.path.join(TMP, name)
    with open(path, "w") as fh:
        json.dump(doc, fh)
    return path


def run_variant(d, method, opts):
    name = method + "".join("-" + v for v in opts.values())
    req = dict(mesh(method == "hermite"), method=method, **opts)
    # evaluate: CLI and daemon, bit for bit
    ev = dict(req, points=POINTS, with_gradients=True)
    status, body = d.post("/v1/evaluate", ev)
    if status != 200:
        msg = body.decode()[:300]
        return check("%s: evaluate, or a refusal naming the element" % name,
                     "literal" in name and '"path":"' in msg, "status %d: %s" % (status, msg))
    daemon = json.loads(body)
    rc, out, err = cli("eval", write(name + "-eval.json", ev))
    check("%s: tocher eval exits 0" % name, rc == 0, err[:300])
    if rc == 0:
        check("%s: tocher eval == /v1/evaluate bit for bit" % name,
              without_timings(json.loads(out)) == without_timings(daemon), "documents differ")
    inside = [p for p, v in zip(POINTS, daemon["values"]) if 0 <= p[0] <= 1 and 0 <= p[1] <= 1 and v is None]
    check("%s: no NaN or Inf, no gap on vertices and edges" % name, finite_values(daemon) and not inside,
          "%d inside points without a value" % len(inside))
    # render: CLI at 1, 2, 5 threads and the daemon, raw float32, against evaluate at the centres
    rq = dict(req, viewport=VIEWPORT, format="raw")
    path = write(name + "-render.json", rq)
    images = []
    for threads in (1, 2, 5):
        out_path = os.path.join(TMP, "%s-%d.raw" % (name, threads))
        rc, _, err = cli("render", path, "-o", out_path, "--threads", str(threads))
        images.append(open(out_path, "rb").read() if rc == 0 else b"")
    status, body = d.post("/v1/render", rq)
    images.append(body if status == 200 else b"")
    check("%s: render bytes equal (CLI 1, 2, 5 threads, daemon)" % name,
          images[0] and all(im == images[0] for im in images), "sizes %s" % [len(im) for im in images])
    status, body = d.post("/v1/evaluate", dict(req, points=centres()))
    vals = json.loads(body)["values"] if status == 200 else []
    expect = b"".join(struct.pack("<f", 0.0 if v is None else v) for v in vals)
    check("%s: render == (float) evaluate at every pixel centre" % name, images[0] == expect,
          "%d of %d pixels differ" % (sum(a != b for a, b in zip(struct.iter_unpack("<f", images[0]),
                                                                   struct.iter_unpack("<f", expect))), W * W)
          if len(images[0]) == len(expect) else "sizes %d, %d" % (len(images[0]), len(expect)))


# ---- warnings: a 1e6-aspect sliver ---------------------------------------------------------

def sliver_mesh():
    eps = 0.125e-6  # cells 1/8 x eps: aspect 1e6
    ys = [-0.5, 0.0, eps, 0.5]
    verts = [[i / 8, y] for y in ys for i in range(9)]
    tris = []
    for j in range(3):
        for i in range(8):
            a, b, c, d = j * 9 + i, j * 9 + i + 1, (j + 1) * 9 + i + 1, (j + 1) * 9 + i
            tris += [[a, b, c], [a, c, d]]
    return {"vertices": verts, "triangles": tris, "values": [f(x, y) for x, y in verts]}, 1e6


def aspect(doc, t):
    p = [doc["vertices"][v] for v in doc["triangles"][t]]
    e = [(p[(k + 1) % 3][0] - p[k][0], p[(k + 1) % 3][1] - p[k][1]) for k in range(3)]
    longest = max(math.hypot(*v) for v in e)
    return longest * longest / abs(e[0][0] * e[2][1] - e[0][1] * e[2][0])


def names_sliver(doc, warnings):
    for w in warnings or []:
        m = re.fullmatch(r"triangles\[(\d+)\]", w.get("path", ""))
        if not m or "aspect" not in w.get("message", "").lower():
            continue
        ar = aspect(doc, int(m.group(1)))
        nums = [float(x) for x in re.findall(r"\d+(?:\.\d+)?(?:e[+-]?\d+)?", w["message"])]
        if ar > 1e5 and any(0.5 * ar <= x <= 2 * ar for x in nums):
            return True
    return False


def sliver_warnings(d):
    doc, _ = sliver_mesh()
    for path in ("/v1/ordinates", "/v1/evaluate"):
        req = dict(doc, points=[[0.5, 0.0]]) if path == "/v1/evaluate" else doc
        status, body = d.post(path, req)
        w = json.loads(body).get("warnings") if status == 200 else None
        check("sliver 1e6: %s warns at triangles[t] with its aspect ratio" % path, names_sliver(doc, w),
              "status %d, warnings %s" % (status, w))
    view = {"x0": 0, "y0": -0.5, "x1": 1, "y1": 0.5, "width": 16, "height": 16}
    status, body, hdr = d.post("/v1/render", dict(doc, viewport=view, format="raw"), with_headers=True)
    lines = hdr.get_all("Tocher-Warning") or [] if status == 200 else []
    w = [{"path": x.split(": ", 1)[0], "message": x.split(": ", 1)[-1]} for x in lines]
    count = hdr.get("Tocher-Warnings", "0") if status == 200 else "0"
    check("sliver 1e6: /v1/render warns in Tocher-Warning headers at triangles[t] with its aspect ratio",
          names_sliver(doc, w) and int(count) >= len(w) > 0, "status %d, Tocher-Warnings %s, %s" % (status, count, lines))
    rc, out, err = cli("eval", write("sliver.json", dict(doc, points=[[0.5, 0.0]])))
    w = json.loads(out).get("warnings") if rc == 0 else None
    check("sliver 1e6: tocher eval warns at triangles[t] with its aspect ratio", names_sliver(doc, w),
          "exit %d, warnings %s" % (rc, w))


def methods_of_help():
    """The methods `tocher help` lists (the method table)."""
    out = subprocess.run([TOCHER, "help"], stdout=subprocess.PIPE, timeout=60).stdout.decode()
    m = re.search(r"^  method +(.*)$", out, re.M)
    return m.group(1).split(", ") if m else []


def main():
    for exe in (TOCHER, TOCHERD):
        if not os.access(exe, os.X_OK):
            check("%s exists" % exe, False, "build it first (make)")
            finish()
    listed = methods_of_help()
    missing = sorted(set(listed) - {m for m, _ in VARIANTS})
    check("VARIANTS cover every method of the table (%d)" % len(listed), listed and not missing,
          "no variant for: " + ", ".join(missing))
    d = Daemon("--render-threads", "5")
    for method, opts in VARIANTS:
        run_variant(d, method, opts)
    sliver_warnings(d)
    report = d.sanitizer_report()
    check("tocherd: no sanitizer report", not report, report or "")
    finish()


if __name__ == "__main__":
    main()
