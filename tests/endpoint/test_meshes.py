#!/usr/bin/env python3
"""test_meshes.py — the stored-mesh resources of tocherd (issue 15), against real daemons
started from BUILD_DIR over loopback:

    /usr/bin/python3 tests/endpoint/test_meshes.py BUILD_DIR

What it establishes, one "ok"/"FAIL" line per check, then "N passed, N failed":
  1. POST /v1/meshes: 201 + Location + the description, 200 when it exists; the id is a
     content address: other whitespace, key order, number spelling or spelled-out defaults
     give the same id, any change of data or options another;
  2. GET /v1/meshes/{id}, /ordinates, POST /evaluate and /render answer as the stateless
     routes do for the same mesh (ordinates and evaluate equal, render bytes equal, Accept
     included);
  3. tiles: bytes equal /v1/render of the tile's viewport (computed here the way the
     server does) for several z/x/y, every format and the query parameters; 304 on
     If-None-Match (lists, W/, *), ETag, Cache-Control, HEAD;
  4. every error: unknown or malformed ids, tiles outside the pyramid, bad query values,
     bodies that bring the wrong parts, wrong methods (405 with Allow);
  5. DELETE: 204, then 404 everywhere (an old ETag included);
  6. a daemon with a tiny --cache-memory evicts and rebuilds from the store, answering the
     same bytes; concurrent uses of an evicted mesh build it once (/metrics);
  7. concurrent POST / tile / render / DELETE: every answer is right or a 404, none fails;
  8. --store / --cache-memory and their TOCHER_* variables, and --help naming them.
"""
import atexit
import http.client
import json
import os
import re
import shutil
import sys
import tempfile
import threading

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tests", "pylib"))
from tochertest import Tocherd, check, finish, say  # noqa: E402

BUILD = sys.argv[1] if len(sys.argv) > 1 else "build"
if not os.path.isabs(BUILD) and not os.path.isdir(BUILD):
    BUILD = os.path.join(ROOT, BUILD)
TOCHERD = os.path.join(os.path.abspath(BUILD), "tocherd")
TMP = tempfile.mkdtemp(prefix="tocher-meshes.")
DAEMONS = []
JSON_H = {"Content-Type": "application/json"}
FORMATS = ("png", "png16", "exr", "exr-half", "tiff", "raw")
ID_RE = re.compile(r"[A-Za-z0-9_-]{16,64}")
NOT_FOUND = "mesh not found; POST it again"
IMMUTABLE = "public, max-age=31536000, immutable"


def start(name, *flags):
    d = Tocherd(TOCHERD, os.path.join(TMP, name + ".stderr"), flags)
    DAEMONS.append(d)
    return d


def _cleanup():
    for d in DAEMONS:
        d.kill()
    shutil.rmtree(TMP, ignore_errors=True)


atexit.register(_cleanup)


class Resp:
    def __init__(self, status, headers, body):
        self.status, self.headers, self.body = status, headers, body

    def h(self, name):
        return self.headers.get(name)

    def json(self):
        return json.loads(self.body)

    def brief(self):
        return "%d %s %r" % (self.status, self.h("Content-Type"), self.body[:240])


def request(d, method, path, body=None, headers=None, conn=None):
    c = conn or http.client.HTTPConnection("127.0.0.1", d.port, timeout=120)
    try:
        c.request(method, path, body=body, headers=headers or {})
        r = c.getresponse()
        return Resp(r.status, r.headers, r.read())
    finally:
        if conn is None:
            c.close()


def post(d, path, doc, headers=None, conn=None):
    body = doc if isinstance(doc, bytes) else json.dumps(doc).encode()
    return request(d, "POST", path, body, dict(JSON_H, **(headers or {})), conn)


def no_timings(doc):
    doc = dict(doc)
    doc.pop("timings", None)
    return doc


def is_problem(r, status, detail=None, path=None):
    if r.status != status or (r.h("Content-Type") or "") != "application/problem+json":
        return False
    doc = r.json()
    return doc.get("status") == status and (detail is None or detail in doc.get("detail", "")) and \
        (path is None or doc.get("path") == path)


def load(name):
    with open(os.path.join(ROOT, "api", "examples", name)) as f:
        return json.load(f)


def grid_mesh(n, channels=1, shift=0.0):
    """An n x n grid of squares on [0, 2] x [0, 1] (wider than high: the tile square is not
    the bbox), split into triangles, smooth data; shift changes the values."""
    verts, tris, vals = [], [], []
    for j in range(n + 1):
        for i in range(n + 1):
            x, y = 2.0 * i / n, 1.0 * j / n
            verts.append([x, y])
            v = [0.2 + 0.5 * x * x - 0.3 * y + 0.1 * x * y + shift + 0.1 * c for c in range(channels)]
            vals.append(v[0] if channels == 1 else v)
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            tris += [[a, a + 1, a + n + 2], [a, a + n + 2, a + n + 1]]
    return {"vertices": verts, "triangles": tris, "values": vals}


def tile_viewport(bbox, z, x, y, size):
    """The server's arithmetic, in the same order: s = max(w, h), t = s / 2^z."""
    x0, y0, x1, y1 = bbox
    s = max(x1 - x0, y1 - y0)
    t = s / float(1 << z)
    return {"x0": x0 + x * t, "y0": y0 + s - (y + 1) * t, "x1": x0 + (x + 1) * t, "y1": y0 + s - y * t,
            "width": size, "height": size}


def metric(d, name):
    text = request(d, "GET", "/metrics").body.decode()
    m = re.search(r"^%s (\S+)$" % re.escape(name), text, re.M)
    return float(m.group(1)) if m else None


# ---- 1. POST and ids --------------------------------------------------------------------

def section_post(D):
    mesh = load("square-light.json")
    r = post(D, "/v1/meshes", mesh)
    check("POST /v1/meshes: 201", r.status == 201, r.brief())
    doc = r.json()
    mid = doc.get("id", "")
    check("id is 16-64 characters of [A-Za-z0-9_-]", ID_RE.fullmatch(mid) is not None, mid)
    check("Location: /v1/meshes/{id}", r.h("Location") == "/v1/meshes/" + mid, r.h("Location"))
    check("description: counts, bbox, method, warnings, timings",
          doc.get("vertices") == len(mesh["vertices"]) and doc.get("triangles") == len(mesh["triangles"]) and
          doc.get("channels") == 1 and doc.get("bbox") == [0, 0, 1, 1] and doc.get("method") == "clough-tocher" and
          isinstance(doc.get("warnings"), list) and "timings" in doc, doc)
    r2 = post(D, "/v1/meshes", mesh)
    check("POST of an existing mesh: 200, same id and Location",
          r2.status == 200 and r2.json()["id"] == mid and r2.h("Location") == r.h("Location"), r2.brief())
    # The same mesh spelled otherwise.
    text = json.dumps(mesh, indent=3, sort_keys=True).replace("0.5", "5e-1")
    check("the respelling really differs", text.encode() != json.dumps(mesh).encode() and "5e-1" in text)
    r3 = post(D, "/v1/meshes", text.encode())
    check("other whitespace, key order, 5e-1 for 0.5: same id", r3.status == 200 and r3.json()["id"] == mid,
          r3.brief())
    spelled = dict(mesh, method="clough-tocher", cross_boundary="normal", wedges="corrected")
    r4 = post(D, "/v1/meshes", spelled)
    check("defaults spelled out: same id", r4.status == 200 and r4.json()["id"] == mid, r4.brief())
    changed = json.loads(json.dumps(mesh))
    changed["values"][4] += 1e-12
    r5 = post(D, "/v1/meshes", changed)
    check("a value changed by 1e-12: another id", r5.status == 201 and r5.json()["id"] != mid, r5.brief())
    r6 = post(D, "/v1/meshes", dict(mesh, cross_boundary="affine"))
    check("an option changed: another id", r6.status == 201 and r6.json()["id"] not in (mid, r5.json()["id"]),
          r6.brief())
    r7 = post(D, "/v1/meshes", dict(mesh, method="linear"))
    check("another method: another id, its method in the description",
          r7.status == 201 and r7.json()["id"] != mid and r7.json()["method"] == "linear", r7.brief())
    return mesh, mid, doc


# ---- 2. the stateless answers ------------------------------------------------------------

def section_same_answers(D, mesh, mid, desc):
    base = "/v1/meshes/" + mid
    g = request(D, "GET", base)
    check("GET /v1/meshes/{id}: 200 JSON, the POST's description without timings",
          g.status == 200 and g.h("Content-Type") == "application/json" and g.json() == no_timings(desc), g.brief())
    check("GET: strong ETag and immutable Cache-Control",
          (g.h("ETag") or "").startswith('"' + mid + "-") and g.h("Cache-Control") == IMMUTABLE,
          "%s %s" % (g.h("ETag"), g.h("Cache-Control")))
    o1 = request(D, "GET", base + "/ordinates")
    o2 = post(D, "/v1/ordinates", mesh)
    check("/ordinates: identical to /v1/ordinates", o1.status == 200 and o2.status == 200 and
          no_timings(o1.json()) == no_timings(o2.json()), o1.brief())
    check("/ordinates: ETag, Cache-Control", o1.h("ETag") not in (None, g.h("ETag")) and
          o1.h("Cache-Control") == IMMUTABLE, o1.h("ETag"))
    pts = {"points": [[0.1, 0.2], [0.5, 0.5], [0.9, 0.05], [3, 3]], "with_gradients": True}
    e1 = post(D, base + "/evaluate", pts)
    e2 = post(D, "/v1/evaluate", dict(mesh, **pts))
    check("/evaluate: identical to /v1/evaluate", e1.status == 200 and
          no_timings(e1.json()) == no_timings(e2.json()), "%s | %s" % (e1.brief(), e2.brief()))
    vp = {"x0": -0.1, "y0": 0.05, "x1": 0.93, "y1": 1.01, "width": 37, "height": 29}
    for fmt in FORMATS:
        look = {"viewport": vp, "format": fmt, "exposure": 0.75, "overlay": True, "background": 0.125,
                "linear": fmt == "png"}
        r1 = post(D, base + "/render", look)
        r2 = post(D, "/v1/render", dict(mesh, **look))
        check("/render %s: bytes identical to /v1/render" % fmt, r1.status == 200 and r2.status == 200 and
              r1.body == r2.body and r1.h("Content-Type") == r2.h("Content-Type"),
              "%s | %s" % (r1.brief(), r2.brief()))
    acc = {"Accept": "image/x-exr"}
    r1 = post(D, base + "/render", {"viewport": vp}, acc)
    r2 = post(D, "/v1/render", dict(mesh, viewport=vp), acc)
    check("/render by Accept: the same EXR as /v1/render, Vary: Accept", r1.status == 200 and r1.body == r2.body
          and r1.h("Content-Type") == "image/x-exr" and r1.h("Vary") == "Accept" and r2.h("Vary") == "Accept",
          r1.brief())


# ---- 3. tiles -----------------------------------------------------------------------------

def section_tiles(D):
    mesh = grid_mesh(6)
    r = post(D, "/v1/meshes", mesh)
    mid, bbox = r.json()["id"], r.json()["bbox"]
    check("the grid mesh's bbox is [0, 0, 2, 1]", bbox == [0, 0, 2, 1], bbox)
    base = "/v1/meshes/%s/tiles" % mid
    cases = [(0, 0, 0), (1, 0, 0), (1, 1, 1), (2, 3, 0), (3, 2, 5), (4, 9, 12), (5, 31, 31)]
    for i, (z, x, y) in enumerate(cases):
        for fmt in FORMATS if i < 3 else ("png", FORMATS[i % len(FORMATS)]):
            t = request(D, "GET", "%s/%d/%d/%d.%s?size=48" % (base, z, x, y, fmt))
            ref = post(D, "/v1/render", dict(mesh, viewport=tile_viewport(bbox, z, x, y, 48), format=fmt))
            check("tile %d/%d/%d.%s == /v1/render of its viewport" % (z, x, y, fmt),
                  t.status == 200 and ref.status == 200 and t.body == ref.body and
                  t.h("Content-Type") == ref.h("Content-Type"), "%s | %s" % (t.brief(), ref.brief()))
    q = "size=40&exposure=1.5&overlay=true&linear=1&background=0.3"
    t = request(D, "GET", "%s/2/1/2.png?%s" % (base, q))
    ref = post(D, "/v1/render", dict(mesh, viewport=tile_viewport(bbox, 2, 1, 2, 40), format="png", exposure=1.5,
                                     overlay=True, linear=True, background=0.3))
    check("tile with size, exposure, overlay, linear, background == /v1/render", t.status == 200 and
          t.body == ref.body, t.brief())
    d = request(D, "GET", "%s/0/0/0.png" % base)
    ref = post(D, "/v1/render", dict(mesh, viewport=tile_viewport(bbox, 0, 0, 0, 256), format="png"))
    check("default size 256", d.status == 200 and d.body == ref.body, d.brief())
    # Caching.
    etag = t.h("ETag")
    check("tile: strong ETag of the id, immutable Cache-Control", (etag or "").startswith('"' + mid + "-") and
          t.h("Cache-Control") == IMMUTABLE, "%s %s" % (etag, t.h("Cache-Control")))
    same = request(D, "GET", "%s/2/1/2.png?background=0.30&linear=true&overlay=1&exposure=15e-1&size=40" % base)
    check("the same tile spelled otherwise: the same ETag and bytes", same.h("ETag") == etag and
          same.body == t.body, same.h("ETag"))
    others = {request(D, "GET", "%s/2/1/2.png?%s" % (base, q.replace(a, b))).h("ETag")
              for a, b in [("1.5", "1.25"), ("size=40", "size=41"), ("overlay=true", "overlay=false"),
                           ("linear=1", "linear=0"), ("0.3", "0.4")]}
    others |= {request(D, "GET", "%s/%s?%s" % (base, p, q)).h("ETag") for p in ("2/1/1.png", "2/2/2.png",
                                                                                 "1/1/2.png", "2/1/2.tiff")}
    check("any other parameter or tile: another ETag", len(others) == 9 and etag not in others, others)
    for inm in (etag, 'W/"zzz", ' + etag, "W/" + etag, '"other", ' + etag + ', "x"', "*"):
        n = request(D, "GET", "%s/2/1/2.png?%s" % (base, q), headers={"If-None-Match": inm})
        check("If-None-Match %s: 304, no body, ETag kept" % inm, n.status == 304 and n.body == b"" and
              n.h("ETag") == etag and n.h("Cache-Control") == IMMUTABLE, n.brief())
    n = request(D, "GET", "%s/2/1/2.png?%s" % (base, q), headers={"If-None-Match": '"%s-0", W/"x"' % mid})
    check("If-None-Match without our tag: 200 and the tile", n.status == 200 and n.body == t.body, n.brief())
    g = request(D, "GET", "/v1/meshes/" + mid)
    n = request(D, "GET", "/v1/meshes/" + mid, headers={"If-None-Match": g.h("ETag")})
    check("GET /v1/meshes/{id} with its ETag: 304", n.status == 304 and n.body == b"", n.brief())
    o = request(D, "GET", "/v1/meshes/%s/ordinates" % mid)
    n = request(D, "GET", "/v1/meshes/%s/ordinates" % mid, headers={"If-None-Match": o.h("ETag")})
    check("/ordinates with its ETag: 304", n.status == 304 and n.body == b"", n.brief())
    h = request(D, "HEAD", "%s/2/1/2.png?%s" % (base, q))
    check("HEAD of a tile: 200, no body, the ETag", h.status == 200 and h.body == b"" and h.h("ETag") == etag,
          h.brief())
    # A 3-channel mesh: background per channel.
    rgb = grid_mesh(3, channels=3)
    mid3 = post(D, "/v1/meshes", rgb).json()["id"]
    t = request(D, "GET", "/v1/meshes/%s/tiles/1/0/0.exr?size=16&background=0.1,0.2,0.3" % mid3)
    ref = post(D, "/v1/render", dict(rgb, viewport=tile_viewport([0, 0, 2, 1], 1, 0, 0, 16), format="exr",
                                     background=[0.1, 0.2, 0.3]))
    check("3 channels, background per channel: tile == render", t.status == 200 and t.body == ref.body, t.brief())
    bad = request(D, "GET", "/v1/meshes/%s/tiles/1/0/0.exr?background=0.1,0.2" % mid3)
    check("background of 2 values for 3 channels: 400 naming background", is_problem(bad, 400, "background"),
          bad.brief())
    return mesh, mid


# ---- 4. errors ----------------------------------------------------------------------------

def section_errors(D, mesh, mid):
    ghost = "A" * 24
    for method, path, body in [("GET", "/v1/meshes/" + ghost, None), ("DELETE", "/v1/meshes/" + ghost, None),
                               ("GET", "/v1/meshes/%s/ordinates" % ghost, None),
                               ("POST", "/v1/meshes/%s/evaluate" % ghost, b'{"points":[[0,0]]}'),
                               ("POST", "/v1/meshes/%s/render" % ghost, b'{"viewport":{}}'),
                               ("GET", "/v1/meshes/%s/tiles/0/0/0.png" % ghost, None),
                               ("GET", "/v1/meshes/not-an-id/tiles/0/0/0.png", None),
                               ("GET", "/v1/meshes/" + "x" * 64, None)]:
        r = request(D, method, path, body, JSON_H if body else None)
        check("%s %s: 404 %r" % (method, path[:50], NOT_FOUND), is_problem(r, 404, NOT_FOUND), r.brief())
    base = "/v1/meshes/%s/tiles" % mid
    for path in ("25/0/0.png", "1/2/0.png", "1/0/2.png", "3/8/0.png", "0/0/0.jpg", "0/0/0", "a/0/0.png",
                 "0/-1/0.png", "0/0/0.png/more", "0/0.png"):
        r = request(D, "GET", "%s/%s" % (base, path))
        check("tile %s: 404" % path, r.status == 404 and r.h("ETag") is None, r.brief())
    check("z = 24 exists", request(D, "GET", "%s/24/16777215/0.png?size=2" % base).status == 200)
    for q, name in [("size=0", "size"), ("size=1025", "size"), ("size=abc", "size"), ("size=", "size"),
                    ("exposure=x", "exposure"), ("exposure=100", "exposure"), ("exposure=nan", "exposure"),
                    ("overlay=yes", "overlay"), ("linear=2", "linear"), ("background=a", "background"),
                    ("background=", "background"), ("colour=red", "colour")]:
        r = request(D, "GET", "%s/0/0/0.png?%s" % (base, q))
        check("?%s: 400 naming %s" % (q, name), is_problem(r, 400, name) and r.h("ETag") is None, r.brief())
    m = "/v1/meshes/" + mid
    for extra, field in [({"points": [[0, 0]]}, "points"), ({"viewport": {"x0": 0, "y0": 0, "x1": 1, "y1": 1,
                                                                         "width": 2, "height": 2}}, "viewport"),
                         ({"format": "png"}, "format")]:
        r = post(D, "/v1/meshes", dict(mesh, **extra))
        check("POST /v1/meshes with %s: 400 naming it" % field, is_problem(r, 400, path=field), r.brief())
    r = post(D, "/v1/meshes", dict(mesh, values=[1, 2]))
    check("POST /v1/meshes of an invalid mesh: 422", is_problem(r, 422), r.brief())
    r = post(D, "/v1/meshes", b"{not json")
    check("POST /v1/meshes of bad JSON: 400", is_problem(r, 400), r.brief())
    r = post(D, m + "/render", dict(mesh, viewport={"x0": 0, "y0": 0, "x1": 1, "y1": 1, "width": 2, "height": 2}))
    check("/render with a mesh in the body: 400 naming vertices", is_problem(r, 400, path="vertices"), r.brief())
    r = post(D, m + "/render", {"format": "png"})
    check("/render without viewport: 400", is_problem(r, 400, "viewport"), r.brief())
    r = post(D, m + "/evaluate", {"with_gradients": True})
    check("/evaluate without points: 400", is_problem(r, 400, "points"), r.brief())
    r = post(D, m + "/evaluate", dict(mesh, points=[[0, 0]]))
    check("/evaluate with a mesh in the body: 400", is_problem(r, 400, path="vertices"), r.brief())
    for method, path, allow in [("PUT", m, "GET, HEAD, DELETE"), ("GET", "/v1/meshes", "POST"),
                                ("POST", base + "/0/0/0.png", "GET, HEAD"), ("DELETE", m + "/ordinates", "GET, HEAD"),
                                ("GET", m + "/render", "POST")]:
        r = request(D, method, path)
        check("%s %s: 405, Allow: %s" % (method, path[-30:], allow), r.status == 405 and r.h("Allow") == allow,
              r.brief())


# ---- 5. DELETE ----------------------------------------------------------------------------

def section_delete(D):
    mesh = grid_mesh(2, shift=0.5)
    mid = post(D, "/v1/meshes", mesh).json()["id"]
    tile = request(D, "GET", "/v1/meshes/%s/tiles/0/0/0.png?size=8" % mid)
    stored = metric(D, "tocher_meshes_stored")
    r = request(D, "DELETE", "/v1/meshes/" + mid)
    check("DELETE: 204, no body", r.status == 204 and r.body == b"", r.brief())
    check("tocher_meshes_stored drops by one", metric(D, "tocher_meshes_stored") == stored - 1)
    for method, path in [("GET", ""), ("DELETE", ""), ("GET", "/ordinates"), ("GET", "/tiles/0/0/0.png?size=8")]:
        r = request(D, method, "/v1/meshes/" + mid + path)
        check("after DELETE, %s %s: 404" % (method, path or "/v1/meshes/{id}"), is_problem(r, 404, NOT_FOUND),
              r.brief())
    r = request(D, "GET", "/v1/meshes/%s/tiles/0/0/0.png?size=8" % mid, headers={"If-None-Match": tile.h("ETag")})
    check("after DELETE, an old ETag gets 404, not 304", r.status == 404, r.brief())
    r = post(D, "/v1/meshes", mesh)
    t2 = request(D, "GET", "/v1/meshes/%s/tiles/0/0/0.png?size=8" % mid)
    check("POST it again: 201, the same id, the same tile", r.status == 201 and r.json()["id"] == mid and
          t2.body == tile.body, r.brief())


# ---- 6. eviction, rebuild, build once -----------------------------------------------------

def section_eviction():
    T = start("tiny", "--cache-memory", "1", "--tile-cache-memory", "0")  # every tile GET uses the mesh
    a, b = grid_mesh(5), grid_mesh(5, shift=1.0)
    ia = post(T, "/v1/meshes", a).json()["id"]
    ib = post(T, "/v1/meshes", b).json()["id"]
    check("tiny cache: nothing stays cached", metric(T, "tocher_cache_bytes") == 0)
    ev0, miss0 = metric(T, "tocher_cache_evictions_total"), metric(T, "tocher_cache_misses_total")
    check("tiny cache: the POSTs' builds were evicted", ev0 >= 2, ev0)
    for mid, mesh in ((ia, a), (ib, b), (ia, a)):
        t = request(T, "GET", "/v1/meshes/%s/tiles/1/0/1.tiff?size=24" % mid)
        ref = post(T, "/v1/render", dict(mesh, viewport=tile_viewport([0, 0, 2, 1], 1, 0, 1, 24), format="tiff"))
        check("evicted mesh rebuilt from the store: same bytes as /v1/render", t.status == 200 and
              t.body == ref.body, t.brief())
    check("each use missed and rebuilt", metric(T, "tocher_cache_misses_total") == miss0 + 3)
    check("tocher_mesh_build_seconds counted POSTs and rebuilds", metric(T, "tocher_mesh_build_seconds_count") == 5)
    o = request(T, "GET", "/v1/meshes/%s/ordinates" % ia)
    check("ordinates of an evicted mesh", o.status == 200 and
          no_timings(o.json()) == no_timings(post(T, "/v1/ordinates", a).json()))
    T.stop()
    # A cache that fits one of two meshes: measure their sizes, then use the evicted one from 8 threads.
    big, small = grid_mesh(12), grid_mesh(12, shift=2.0)
    M = start("measure")
    post(M, "/v1/meshes", big)
    size = metric(M, "tocher_cache_bytes")
    M.stop()
    C = start("one", "--cache-memory", str(int(size * 1.5)), "--workers", "8")
    ib = post(C, "/v1/meshes", big).json()["id"]
    post(C, "/v1/meshes", small)
    check("the second mesh evicted the first", metric(C, "tocher_cache_evictions_total") == 1)
    miss0, hit0 = metric(C, "tocher_cache_misses_total"), metric(C, "tocher_cache_hits_total")
    out = [None] * 8
    start_line = threading.Barrier(8)

    def use(k):
        start_line.wait()
        out[k] = request(C, "GET", "/v1/meshes/%s/tiles/0/0/0.raw?size=64" % ib)

    th = [threading.Thread(target=use, args=(k,)) for k in range(8)]
    for t in th:
        t.start()
    for t in th:
        t.join()
    check("8 concurrent tiles of an evicted mesh: all 200, equal",
          all(r.status == 200 and r.body == out[0].body for r in out), [r.status for r in out])
    check("... built once (one miss, seven hits)", metric(C, "tocher_cache_misses_total") == miss0 + 1 and
          metric(C, "tocher_cache_hits_total") == hit0 + 7,
          (metric(C, "tocher_cache_misses_total"), metric(C, "tocher_cache_hits_total")))
    C.stop()


# ---- 7. concurrency -----------------------------------------------------------------------

def section_concurrency(D):
    mesh = grid_mesh(8, shift=3.0)
    r = post(D, "/v1/meshes", mesh)
    mid = r.json()["id"]
    vp = tile_viewport(r.json()["bbox"], 2, 1, 1, 32)
    want = post(D, "/v1/render", dict(mesh, viewport=vp, format="png")).body
    bad = []

    def tiles(k):
        c = http.client.HTTPConnection("127.0.0.1", D.port, timeout=60)
        for i in range(30):
            if i % 2:
                t = request(D, "GET", "/v1/meshes/%s/tiles/2/1/1.png?size=32" % mid, conn=c)
            else:
                t = post(D, "/v1/meshes/%s/render" % mid, {"viewport": vp, "format": "png"}, conn=c)
            if not (t.status == 200 and t.body == want) and not is_problem(t, 404, NOT_FOUND):
                bad.append(t.brief())
        c.close()

    def churn(k):
        for i in range(15):
            if k == 0:
                r = request(D, "DELETE", "/v1/meshes/" + mid)
                ok = r.status in (204, 404)
            else:
                r = post(D, "/v1/meshes", mesh)
                ok = r.status in (200, 201) and r.json()["id"] == mid
            if not ok:
                bad.append(r.brief())

    th = [threading.Thread(target=tiles, args=(k,)) for k in range(6)]
    th += [threading.Thread(target=churn, args=(k,)) for k in range(2)]
    for t in th:
        t.start()
    for t in th:
        t.join()
    check("concurrent POST/tile/render/DELETE: every answer right or 404", not bad, bad[:3])
    post(D, "/v1/meshes", mesh)
    t = request(D, "GET", "/v1/meshes/%s/tiles/2/1/1.png?size=32" % mid)
    check("after the churn: the tile is right", t.status == 200 and t.body == want, t.brief())
    check("daemon alive", D.alive())


# ---- 7b. the encoded-tile cache ----------------------------------------------------------

def section_tile_cache(D):
    """A tile GET again is answered from the encoded-tile cache (same bytes, no render); eight
    clients asking at once for one tile not yet rendered render it once; a tile with a warning
    is not kept; a deleted mesh's cached tiles answer 404 (the store is asked first)."""
    mesh = grid_mesh(6, shift=5.0)
    mid = post(D, "/v1/meshes", mesh).json()["id"]
    url = "/v1/meshes/%s/tiles/1/1/0.png?size=64" % mid
    h0, m0 = metric(D, "tocher_tile_cache_hits_total"), metric(D, "tocher_tile_cache_misses_total")
    first = request(D, "GET", url)
    again = request(D, "GET", url)
    h1, m1 = metric(D, "tocher_tile_cache_hits_total"), metric(D, "tocher_tile_cache_misses_total")
    check("tile cache: the second GET is a hit with the same bytes and headers (misses +%g, hits +%g)" %
          (m1 - m0, h1 - h0), first.status == 200 and again.body == first.body and m1 - m0 == 1 and h1 - h0 == 1
          and again.h("ETag") == first.h("ETag") and again.h("Content-Type") == "image/png", again.brief())
    url2 = "/v1/meshes/%s/tiles/2/3/1.exr?size=128" % mid
    got = []

    def one():
        got.append(request(D, "GET", url2))
    th = [threading.Thread(target=one) for _ in range(8)]
    for t in th:
        t.start()
    for t in th:
        t.join()
    m2 = metric(D, "tocher_tile_cache_misses_total")
    check("tile cache: 8 clients at once for a new tile: rendered once (misses +%g), 8 equal answers" % (m2 - m1),
          m2 - m1 == 1 and len({g.body for g in got}) == 1 and all(g.status == 200 for g in got),
          [g.brief() for g in got][:2])
    hot = dict(grid_mesh(3, shift=7.0), values=[1e6 * (1 + i) for i in range(16)])
    hid = post(D, "/v1/meshes", hot).json()["id"]
    url3 = "/v1/meshes/%s/tiles/0/0/0.exr-half?size=8" % hid
    a, b = request(D, "GET", url3), request(D, "GET", url3)
    check("tile cache: a tile with a warning is not kept: each GET renders it and says so",
          a.status == b.status == 200 and a.h("Tocher-Warning") and b.h("Tocher-Warning") and a.body == b.body,
          a.brief())
    request(D, "DELETE", "/v1/meshes/" + mid)
    r = request(D, "GET", url)
    check("tile cache: after DELETE the cached tile answers 404", is_problem(r, 404, NOT_FOUND), r.brief())


# ---- 8. configuration ------------------------------------------------------------------

def section_config():
    bad = Tocherd(TOCHERD, os.path.join(TMP, "badstore.stderr"), ("--store", "redis"), strict=False)
    DAEMONS.append(bad)
    bad.proc.wait(10)
    check("--store redis (not a redis:// URL): refused naming --store, exit 2",
          not bad.started and bad.proc.returncode == 2 and "--store" in bad.stderr(), bad.stderr()[-300:])
    env = Tocherd(TOCHERD, os.path.join(TMP, "envstore.stderr"), (), {"TOCHER_STORE": "memory",
                                                                        "TOCHER_CACHE_MEMORY": "0"})
    DAEMONS.append(env)
    r = post(env, "/v1/meshes", grid_mesh(2))
    check("TOCHER_STORE=memory, TOCHER_CACHE_MEMORY=0: stores, caches nothing", r.status == 201 and
          metric(env, "tocher_cache_bytes") == 0 and metric(env, "tocher_meshes_stored") == 1, r.brief())
    t = request(env, "GET", "/v1/meshes/%s/tiles/0/0/0.raw?size=4" % r.json()["id"])
    check("... and serves tiles, rebuilding each time", t.status == 200 and len(t.body) == 4 * 4 * 4 and
          metric(env, "tocher_cache_misses_total") == 2, t.brief())
    env.stop()
    h = Tocherd(TOCHERD, os.path.join(TMP, "help.stderr"), ("--help",), strict=False)
    DAEMONS.append(h)
    out = h.line + h.proc.stdout.read().decode()
    h.proc.wait(10)
    check("--help lists --store and --cache-memory with their variables",
          all(w in out for w in ("--store", "TOCHER_STORE", "--cache-memory", "TOCHER_CACHE_MEMORY")), out[-400:])


def main():
    say("# %s against %s" % (os.path.basename(__file__), BUILD))
    D = start("main", "--workers", "8")
    mesh, mid, desc = section_post(D)
    section_same_answers(D, mesh, mid, desc)
    gmesh, gid = section_tiles(D)
    section_errors(D, gmesh, gid)
    section_delete(D)
    section_concurrency(D)
    section_tile_cache(D)
    section_eviction()
    section_config()
    check("metrics: hits, misses, evictions, bytes, stored, build histogram", all(
        metric(D, n) is not None for n in ("tocher_cache_hits_total", "tocher_cache_misses_total",
                                           "tocher_cache_evictions_total", "tocher_cache_bytes",
                                           "tocher_meshes_stored", "tocher_mesh_build_seconds_count")))
    check("main daemon exits 0 on SIGTERM", D.stop() == 0)
    err = D.stderr()
    check("no sanitizer report", not re.search(r"AddressSanitizer|runtime error:|LeakSanitizer", err), err[-800:])
    finish()


if __name__ == "__main__":
    main()
