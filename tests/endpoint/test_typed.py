#!/usr/bin/env python3
"""test_typed.py — typed arrays in and out (issue 17 §1) against a real tocherd from BUILD_DIR:

    /usr/bin/python3 tests/endpoint/test_typed.py BUILD_DIR

What it establishes, one "ok"/"FAIL" line per check, then "N passed, N failed":
  1. every numeric field given as {"dtype", "shape", "data"} (vertices, triangles, quads,
     values, gradients, normals, hessians, corner_values, corner_gradients, midpoints' edge
     and value, discontinuity polylines, points, compare's reference points and values), in
     every dtype a field takes, gets the answer the JSON form gets, byte for byte (timings
     aside);
  2. "encoding": "base64" answers the same doubles bit for bit (ordinates [T, C, K] per
     method, evaluate values and gradients, NaN where the JSON form has null);
  3. a stored mesh POSTed with typed arrays gets the id of the same mesh in JSON numbers;
  4. each refusal with its status and path: bad base64, wrong length, unknown or wrong dtype,
     wrong shape, NaN / infinity, an index above int32, a negative index (the core's check);
  5. the pre-scan: typed points over --max-points get 413 from their shape, data undecoded;
  6. (a figure, not a check) parse time from Server-Timing for a 131k-triangle
     /v1/ordinates request in JSON numbers and in typed arrays.
"""
import base64
import http.client
import json
import math
import os
import shutil
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tests", "pylib"))
from tochertest import Tocherd, check, finish, say  # noqa: E402

BUILD = sys.argv[1] if len(sys.argv) > 1 else "build"
if not os.path.isabs(BUILD) and not os.path.isdir(BUILD):
    BUILD = os.path.join(ROOT, BUILD)
TOCHERD = os.path.join(os.path.abspath(BUILD), "tocherd")
TMP = tempfile.mkdtemp(prefix="tocher-typed.")


def typed(a, dtype="float64"):
    """A NumPy array as the request's typed array: little-endian bytes, C order."""
    a = np.ascontiguousarray(np.asarray(a), dtype=np.dtype(dtype).newbyteorder("<"))
    return {"dtype": dtype, "shape": list(a.shape), "data": base64.b64encode(a.tobytes()).decode()}


def untyped(t):
    """A typed answer member as a NumPy float64 array of its shape."""
    assert t["dtype"] == "float64", t["dtype"]
    return np.frombuffer(base64.b64decode(t["data"], validate=True), dtype="<f8").reshape(t["shape"])


class Conn:
    def __init__(self, d):
        self.d = d

    def post(self, path, doc, raw=None):
        c = http.client.HTTPConnection("127.0.0.1", self.d.port, timeout=300)
        body = raw if raw is not None else json.dumps(doc).encode()
        c.request("POST", path, body=body, headers={"Content-Type": "application/json"})
        r = c.getresponse()
        data = r.read()
        hdr = {k.lower(): v for k, v in r.getheaders()}
        c.close()
        return r.status, hdr, data


def answer(status, data):
    """The JSON answer without its timings (which differ run to run)."""
    try:
        doc = json.loads(data)
    except ValueError:
        return None
    doc.pop("timings", None)
    return doc


def parse_ms(hdr):
    for part in hdr.get("server-timing", "").split(","):
        name, _, dur = part.strip().partition(";dur=")
        if name == "parse":
            return float(dur)
    return float("nan")


# ---- meshes ---------------------------------------------------------------------------

def grid(k, channels=2, seed=1):
    """A jittered k x k grid of vertices, 2 (k-1)^2 triangles, C channels of smooth values."""
    rng = np.random.default_rng(seed)
    u = np.linspace(0.0, 1.0, k)
    x, y = np.meshgrid(u, u)
    h = 0.1 / (k - 1)  # small enough that no triangle folds
    xy = np.stack([x.ravel(), y.ravel()], axis=1)
    inner = (xy[:, 0] > 0) & (xy[:, 0] < 1) & (xy[:, 1] > 0) & (xy[:, 1] < 1)
    xy[inner] += rng.uniform(-h, h, size=(int(inner.sum()), 2))
    i = np.arange(k - 1)
    a = (i[:, None] * k + i[None, :]).ravel()
    tris = np.concatenate([np.stack([a, a + 1, a + k + 1], 1), np.stack([a, a + k + 1, a + k], 1)])
    vals = np.stack([np.sin(3 * xy[:, 0] + c) * np.cos(2 * xy[:, 1]) + 1.5 for c in range(channels)], axis=1)
    grads = np.stack([np.stack([3 * np.cos(3 * xy[:, 0] + c) * np.cos(2 * xy[:, 1]),
                                -2 * np.sin(3 * xy[:, 0] + c) * np.sin(2 * xy[:, 1])], axis=1)
                      for c in range(channels)], axis=1)
    return xy, tris.astype(np.int64), vals, grads


def json_mesh(xy, tris, vals, **extra):
    doc = {"vertices": xy.tolist(), "triangles": tris.tolist(),
           "values": vals[:, 0].tolist() if vals.shape[1] == 1 else vals.tolist()}
    doc.update(extra)
    return doc


def typify(doc, fdt="float64", idt="int32"):
    """The request doc with every numeric array it knows as a typed array (dtypes fdt for
    numbers, idt for indices), nulls left in JSON (a typed array cannot say null)."""
    out = dict(doc)
    for k in ("vertices", "points"):
        if k in doc:
            out[k] = typed(doc[k], fdt)
    for k in ("triangles", "quads"):
        if k in doc:
            out[k] = typed(doc[k], idt)
    if "values" in doc:
        out["values"] = typed(doc["values"], fdt)
    for k in ("gradients", "normals", "hessians"):
        if k in doc and all(g is not None for g in doc[k]):
            out[k] = typed(doc[k], fdt)
    if "corner_values" in doc:
        out["corner_values"] = [dict(e, values=typed(e["values"], fdt)) for e in doc["corner_values"]]
    if "corner_gradients" in doc:
        out["corner_gradients"] = [dict(e, gradients=typed(e["gradients"], fdt))
                                   if all(g is not None for g in e["gradients"]) else e
                                   for e in doc["corner_gradients"]]
    if "midpoints" in doc:
        out["midpoints"] = [dict(e, edge=typed(e["edge"], idt),
                                 value=typed(e["value"], fdt) if isinstance(e["value"], list) else e["value"])
                            for e in doc["midpoints"]]
    if "discontinuities" in doc:
        dc = {}
        for kind, lines in doc["discontinuities"].items():  # one polyline typed, the rest JSON;
            if len({len(p) for p in lines}) == 1 and len(lines) > 1:  # equal lengths: all as one [m, k]
                dc[kind] = typed(lines, idt)
            else:
                dc[kind] = [typed(lines[0], idt)] + lines[1:]
        out["discontinuities"] = dc
    if "reference" in doc:
        ref = doc["reference"]
        out["reference"] = dict(ref, points=typed(ref["points"], fdt), values=typed(ref["values"], fdt))
    return out


def same_bits(a, b):
    """Equal doubles bit for bit, NaN (the JSON null) matching NaN."""
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    return a.shape == b.shape and bool(np.all((a.view(np.uint64) == b.view(np.uint64)) | (np.isnan(a) & np.isnan(b))))


def nulls_to_nan(x, width):
    """A JSON answer array (entries null for missing) as float64, null -> NaN rows of width."""
    if x is None:
        return [math.nan] * width if width > 1 else math.nan
    if isinstance(x, list):
        return [nulls_to_nan(e, width) for e in x]
    return x


# ---- 1 + 2: every field both ways ------------------------------------------------------

def shadow_doc(channels):
    with open(os.path.join(ROOT, "api", "examples", "shadow-edges.json")) as f:
        doc = json.load(f)
    if channels > 1:
        def ch(v):
            return [v, v * 0.5, 1 - v][:channels]
        doc["values"] = [ch(v) for v in doc["values"]]
        doc["corner_values"] = [dict(e, values=[ch(v) for v in e["values"]]) for e in doc["corner_values"]]
    doc["midpoints"] = [{"edge": [0, 1], "value": doc["values"][0]}, {"edge": [1, 2], "value": doc["values"][2]}]
    return doc


def field_cases():
    """(label, route, JSON doc) covering every numeric field."""
    xy, tris, vals, grads = grid(9, channels=2)
    one = json_mesh(xy, tris, vals[:, :1])
    cases = [
        ("grid 2 channels + gradients", "/v1/ordinates", json_mesh(xy, tris, vals, gradients=grads.tolist())),
        ("grid 1 channel + gradients [n, 2]", "/v1/ordinates",
         dict(one, gradients=grads[:, 0, :].tolist(), tangents="given")),
        ("grid normals", "/v1/ordinates",
         dict(one, normals=np.concatenate([-grads[:, 0, :], np.ones((len(xy), 1))], 1).tolist())),
        ("shadow edges 1 channel", "/v1/ordinates", shadow_doc(1)),
        ("shadow edges 3 channels", "/v1/ordinates", shadow_doc(3)),
        ("shadow edges powell-sabin", "/v1/ordinates", dict(shadow_doc(2), method="powell-sabin")),
        ("corner gradients", "/v1/ordinates",
         dict(one, tangents="given", gradients=grads[:, 0, :].tolist(),
              corner_gradients=[{"triangle": 3, "gradients": [[0.5, 1], [0.25, -1], [0, 0]]}])),
    ]
    # quads + hessians, hermite
    k = 5
    u = np.linspace(0, 1, k)
    qx, qy = np.meshgrid(u, u)
    qxy = np.stack([qx.ravel(), qy.ravel()], 1)
    a = np.array([j * k + i for j in range(k - 1) for i in range(k - 1)])
    quads = np.stack([a, a + 1, a + k + 1, a + k], 1)
    qv = np.sin(qxy[:, 0] * 2) + qxy[:, 1] ** 2
    hess = np.stack([-4 * np.sin(qxy[:, 0] * 2), 0 * qxy[:, 0], 2 + 0 * qxy[:, 0]], 1)
    cases.append(("quads + hessians, hermite", "/v1/ordinates",
                  {"vertices": qxy.tolist(), "quads": quads.tolist(), "values": qv.tolist(),
                   "hessians": hess.tolist(), "method": "hermite"}))
    pts = np.array([[0.5, 0.25], [0.1, 0.7], [5.0, 5.0], [0.999, 0.001], [1 / 3, 2 / 3]])
    cases.append(("evaluate 2 channels", "/v1/evaluate",
                  json_mesh(xy, tris, vals, points=pts.tolist(), with_gradients=True)))
    cases.append(("evaluate plain", "/v1/evaluate", dict(one, points=pts.tolist(), with_gradients=True)))
    cases.append(("compare reference", "/v1/compare",
                  dict(one, reference={"points": pts.tolist(), "values": [0.1, 0.2, 0.3, 0.4, 0.5]},
                       methods=["linear", "clough-tocher"])))
    return cases


def every_field_both_ways(c):
    for label, route, doc in field_cases():
        sj, _, bj = c.post(route, doc)
        aj = answer(sj, bj)
        check("%s: JSON form answers 200" % label, sj == 200, bj[:300])
        for fdt, idt in (("float64", "int32"), ("float64", "uint32")):
            st, _, bt = c.post(route, typify(doc, fdt, idt))
            at = answer(st, bt)
            if route == "/v1/compare":  # build and evaluate times differ run to run
                for e in (aj or {}).get("results", []) + (at or {}).get("results", []):
                    e.pop("build_ms", None), e.pop("evaluate_ms", None)
            check("%s: typed %s/%s gives the JSON form's answer" % (label, fdt, idt), st == sj and at == aj,
                  "%d %s" % (st, bt[:300]))
        if route == "/v1/compare":
            continue
        st, _, bt = c.post(route, dict(typify(doc), encoding="base64"))
        check_typed_answer(label, route, aj, answer(st, bt), st)


def check_typed_answer(label, route, aj, at, st):
    """The base64 answer holds the JSON answer's doubles bit for bit, in its shape."""
    if st != 200 or not at or not aj:
        check("%s: encoding base64 answers 200" % label, False, "%d %s" % (st, str(at)[:300]))
        return
    if route == "/v1/ordinates":
        x = untyped(at["ordinates"])
        want = nulls_to_nan(aj["ordinates"], len(aj["labels"]) * aj["channels"])
        want = np.array([np.reshape(w, (aj["channels"], len(aj["labels"]))) for w in want])
        ok = x.shape == (len(aj["ordinates"]), aj["channels"], len(aj["labels"])) and same_bits(x, want)
        check("%s: typed ordinates %s equal the JSON numbers bit for bit" % (label, list(x.shape)), ok)
        rest = {k: v for k, v in at.items() if k != "ordinates"}
        check("%s: the other members as in JSON" % label, rest == {k: v for k, v in aj.items() if k != "ordinates"})
        return
    for name in ("values", "gradients"):
        x = untyped(at[name])
        proto = np.asarray(next(v for v in aj[name] if v is not None), dtype=np.float64)
        want = np.array([np.full(proto.shape, np.nan) if v is None else v for v in aj[name]], dtype=np.float64)
        check("%s: typed %s %s equal the JSON numbers bit for bit" % (label, name, list(x.shape)),
              same_bits(x.reshape(want.shape), want) and x.shape == want.shape,
              "%s vs %s" % (x.shape, want.shape))
    check("%s: outside as in JSON" % label, at["outside"] == aj["outside"])


def dtypes_widen_exactly(c):
    """float32 / int32 / uint32 numbers are the doubles their JSON spelling gives."""
    xy, tris, vals, _ = grid(6, channels=1)
    v32 = vals.astype(np.float32).astype(np.float64)
    doc = json_mesh(xy.astype(np.float32).astype(np.float64), tris, v32)
    sj, _, bj = c.post("/v1/ordinates", doc)
    for fdt in ("float32",):
        st, _, bt = c.post("/v1/ordinates", typify(doc, fdt))
        check("float32 vertices and values: the JSON form's answer", st == sj == 200 and answer(st, bt) == answer(sj, bj),
              bt[:200])
    ints = json_mesh(np.round(xy * 1000), tris, np.round(vals * 100))
    sj, _, bj = c.post("/v1/ordinates", ints)
    for fdt in ("int32", "uint32"):
        st, _, bt = c.post("/v1/ordinates", typify(ints, fdt))
        check("%s vertices and values: the JSON form's answer" % fdt,
              st == sj == 200 and answer(st, bt) == answer(sj, bj), bt[:200])


# ---- 3: stored meshes ----------------------------------------------------------------

def stored_ids(c):
    for label, _, doc in field_cases()[:6]:
        sj, _, bj = c.post("/v1/meshes", doc)
        st, _, bt = c.post("/v1/meshes", typify(doc, "float64", "uint32"))
        idj, idt = (json.loads(bj).get("id") if s in (200, 201) else None for s, b in ((sj, bj), (st, bt)))
        check("%s: stored-mesh id of the typed mesh = the JSON mesh's (%s)" % (label, idj),
              sj == 201 and st == 200 and idj and idj == idt, "%d %d %s %s" % (sj, st, bj[:120], bt[:120]))
    xy, tris, vals, _ = grid(9)
    sj, _, bj = c.post("/v1/meshes", json_mesh(xy, tris, vals))
    mid = json.loads(bj)["id"]
    pts = np.array([[0.3, 0.3], [0.6, 0.1], [2.0, 2.0]])
    s1, _, b1 = c.post("/v1/meshes/%s/evaluate" % mid, {"points": pts.tolist(), "with_gradients": True})
    s2, _, b2 = c.post("/v1/meshes/%s/evaluate" % mid,
                       {"points": typed(pts), "with_gradients": True, "encoding": "base64"})
    check_typed_answer("stored evaluate", "/v1/evaluate", answer(s1, b1), answer(s2, b2), s2)


# ---- 4: refusals -----------------------------------------------------------------------

def refusals(c):
    xy, tris, vals, _ = grid(4, channels=1)
    base = json_mesh(xy, tris, vals)
    n = len(xy)
    bad_b64 = typed(xy)
    bad_b64["data"] = bad_b64["data"][:10] + "*" + bad_b64["data"][11:]
    nan_xy = xy.copy()
    nan_xy[3, 1] = np.nan
    inf_v = vals[:, 0].copy()
    inf_v[5] = np.inf
    big = tris.astype(np.uint32)
    big[3, 1] = 0xFFFFFFFF
    neg = tris.astype(np.int32)
    neg[3, 1] = -1
    cases = [
        ("bad base64", {"vertices": bad_b64}, 400, "vertices", "data: bad base64 at character 10"),
        ("wrong length", {"vertices": dict(typed(xy), shape=[n + 1, 2])}, 400, "vertices",
         "data: %d bytes, expected %d" % (16 * n, 16 * (n + 1))),
        ("unknown dtype", {"values": dict(typed(vals[:, 0]), dtype="float16")}, 400, "values", "dtype 'float16' unknown"),
        ("float triangles", {"triangles": typed(tris, "float64")}, 400, "triangles",
         "dtype float64: expected int32 or uint32"),
        ("vertices shape", {"vertices": typed(np.zeros((n, 3)))}, 400, "vertices", "shape [%d, 3]: expected [n, 2]" % n),
        ("NaN", {"vertices": typed(nan_xy)}, 422, "vertices[3][1]", "NaN in a typed array"),
        ("infinity (float32)", {"values": typed(inf_v, "float32")}, 422, "values[5]", "infinity in a typed array"),
        ("uint32 index above int32", {"triangles": typed(big, "uint32")}, 400, "triangles[3][1]",
         "must be an integer (a 32-bit index), got 4294967295"),
        ("negative index (the core's check)", {"triangles": typed(neg, "int32")}, 422, "triangles[3][1]", ""),
        ("midpoint edge as float", {"midpoints": [{"edge": typed([0, 1], "float64"), "value": 1}]}, 400,
         "midpoints[0].edge", "dtype float64: expected int32 or uint32"),
        ("bad encoding", {"encoding": "hex"}, 422, "encoding", "unknown encoding 'hex'"),
    ]
    for label, change, status, path, msg in cases:
        st, hdr, body = c.post("/v1/ordinates", dict(base, **change))
        p = answer(st, body) or {}
        check("refused: %s -> %d at %s" % (label, status, path),
              st == status and p.get("path") == path and msg in p.get("detail", "")
              and hdr.get("content-type", "").startswith("application/problem+json"),
              "%d %s" % (st, body[:300]))


# ---- 5: the pre-scan ---------------------------------------------------------------------

def prescan(c_small):
    """5.5 M typed float32 points (11 M numbers, 44 MB of data) over --max-points 5000000:
    413 from the shape; the same text with its last character broken gets the same 413
    (the data is never decoded) while a small one with that break gets 400."""
    xy, tris, vals, _ = grid(4, channels=1)
    base = json_mesh(xy, tris, vals)
    pts = np.random.default_rng(3).uniform(0, 1, size=(5_500_000, 2))
    doc = dict(base, points=typed(pts, "float32"))
    text = json.dumps(doc)
    broken = text.replace('=="', '!="', 1) if '=="' in text else text.replace('"}', '!"}', 1)
    for label, body in (("typed points", text), ("typed points with broken base64", broken)):
        t0 = time.time()
        st, _, b = c_small.post("/v1/evaluate", None, raw=body.encode())
        ms = (time.time() - t0) * 1000
        p = answer(st, b) or {}
        check("%s [5500000, 2] over --max-points 5000000: 413 at points (%.0f ms, %.0f MB body)"
              % (label, ms, len(body) / 1e6),
              st == 413 and p.get("path") == "points" and "5500000 points" in p.get("detail", ""), b[:300])
    small = dict(base, points=typed(pts[:3], "float32"))
    small["points"]["data"] = small["points"]["data"][:-1] + "!"
    st, _, b = c_small.post("/v1/evaluate", small)
    check("the same break under the limit: 400 (it is decoded)", st == 400, b[:200])


# ---- 6: a figure --------------------------------------------------------------------------

def parse_figure(c):
    xy, tris, vals, grads = grid(257, channels=1)
    doc = json_mesh(xy, tris, vals)
    tdoc = typify(doc)
    for label, d, enc in (("JSON numbers in and out", doc, None), ("typed in, JSON out", tdoc, None),
                          ("typed in and out", tdoc, "base64")):
        body = json.dumps(dict(d, encoding=enc) if enc else d).encode()
        best = None
        for _ in range(3):
            t0 = time.time()
            st, hdr, out = c.post("/v1/ordinates", None, raw=body)
            wall = (time.time() - t0) * 1000
            if best is None or parse_ms(hdr) < best[0]:
                best = (parse_ms(hdr), hdr.get("server-timing", ""), wall, len(out))
        say("figure: %d triangles, %s: body %.1f MB, answer %.1f MB, parse %.1f ms (best of 3; %s; wall %.0f ms)"
            % (len(tris), label, len(body) / 1e6, best[3] / 1e6, best[0], best[1], best[2]))
        check("131k triangles, %s: 200" % label, st == 200)


def main():
    d = Tocherd(TOCHERD, os.path.join(TMP, "main.stderr"))
    small = Tocherd(TOCHERD, os.path.join(TMP, "small.stderr"), ["--max-points", "5000000"])
    try:
        c = Conn(d)
        every_field_both_ways(c)
        dtypes_widen_exactly(c)
        stored_ids(c)
        refusals(c)
        prescan(Conn(small))
        if os.environ.get("TOCHER_TYPED_FIGURE", "1") != "0":
            parse_figure(c)
    finally:
        d.kill()
        small.kill()
        shutil.rmtree(TMP, ignore_errors=True)
    finish()


if __name__ == "__main__":
    main()
