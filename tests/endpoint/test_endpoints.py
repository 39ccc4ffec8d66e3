#!/usr/bin/env python3
"""test_endpoints.py — the acceptance tests of tocherd's HTTP endpoints, against real
daemons started from BUILD_DIR (build, or build/san under `make check`):

    /usr/bin/python3 tests/endpoint/test_endpoints.py BUILD_DIR

What it establishes, one "ok"/"FAIL" line per check, then "N passed, N failed" (exit 1
on any failure):
  1. the happy path of every endpoint; a Server-Timing header with the five phases on
     every response; JSON answers ending with their "timings"; /metrics counting what
     was asked (route/status counters, the latency histogram, triangles, pixels);
  2. rendered tiles, in every format (png, png16, exr, exr-half, tiff, raw; by "format"
     and by Accept), decode (OpenImageIO) to the reconstruction /v1/evaluate gives at
     the pixel centres of api/openapi.yaml: float formats to float32 of a value within 1e-12 of
     the data scale of it (the fast cubic), half to half
     precision, PNG exactly as the contract's quantization, alpha and background
     outside the mesh, and a tile whose centres fall on vertices and edges;
  3. /v1/ordinates (and /v1/evaluate, /v1/render) equal build/tocher byte for byte,
     the "timings" member aside;
  4. render bytes (and ordinates, warnings, errors) do not depend on --render-threads;
  5. a catalogue of bad requests gets the right status and problem document and the
     daemon keeps answering (body, pixel, triangle limits, stalled clients, timeouts);
  6. 8 concurrent clients x 200 mixed requests all get the reference answers, and the
     daemon's VmRSS stays within 10% (not asserted under sanitizers);
  7. SIGTERM lets the request in flight finish, refuses new connections, exits 0;
  8. what real front-ends print: values that must agree within value_tolerance are
     averaged (beyond it refused naming the edge), degenerate triangles dropped on request
     with the request's numbering kept.
Every daemon started here is killed when the script ends, however it ends.
"""
import atexit
import http.client
import json
import math
import os
import random
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
from tochertest import LOCK, SAN_RE, Tocherd, check, daemon_env, finish, say, tally  # noqa: E402
BUILD = sys.argv[1] if len(sys.argv) > 1 else "build"
if not os.path.isabs(BUILD) and not os.path.isdir(BUILD):
    BUILD = os.path.join(ROOT, BUILD)
BUILD = os.path.abspath(BUILD)
TOCHERD = os.path.join(BUILD, "tocherd")
TOCHER = os.path.join(BUILD, "tocher")
SAN = os.path.basename(os.path.normpath(BUILD)).endswith("san")
EX = os.path.join(ROOT, "api", "examples")
TMP = tempfile.mkdtemp(prefix="tocher-endpoints.")
T_START = time.time()

try:
    import numpy as np
    import OpenImageIO as oiio
except ImportError as e:  # the image checks cannot run without them
    check("imports", False, "%s (apt-get install -y python3-openimageio python3-numpy)" % e)
    finish()

# ---- daemons --------------------------------------------------------------------------

DAEMONS = []
LOG_RE = re.compile(r"^\S+ \S+ (\d{3}|-) \d+ [0-9.]+ms( \(.*\))?$")


class Daemon(Tocherd):
    """One tocherd on 127.0.0.1:0; its stderr goes to a file in TMP."""

    def __init__(self, name, *flags):
        self.name, self.flags = name, flags
        self.sent = 0  # requests this script sent it (for the log-line count)
        super().__init__(TOCHERD, os.path.join(TMP, name + ".stderr"), flags)
        DAEMONS.append(self)

    def rss_kb(self):
        return self.status("VmRSS")


def _kill_all():
    for d in DAEMONS:
        if d.proc.poll() is None:
            d.proc.kill()
            try:
                d.proc.wait(5)
            except subprocess.TimeoutExpired:
                pass
    shutil.rmtree(TMP, ignore_errors=True)


atexit.register(_kill_all)
for _sig in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
    signal.signal(_sig, lambda s, f: sys.exit(1))


def _watchdog():
    check("watchdog", False, "the suite ran past its time limit; killing the daemons")
    say(tally())
    _kill_all()
    os._exit(1)


_wd = threading.Timer(900 if SAN else 300, _watchdog)
_wd.daemon = True
_wd.start()

# ---- HTTP -----------------------------------------------------------------------------

PHASES = ("parse", "validate", "build", "evaluate", "encode")
JSON_H = {"Content-Type": "application/json"}
AUDIT = {"n": 0, "server_timing": [], "timings": []}


class Resp:
    def __init__(self, status, headers, body, elapsed):
        self.status, self.headers, self.body, self.elapsed = status, headers, body, elapsed

    def header(self, name):
        return self.headers.get(name)

    def ctype(self):
        return (self.header("Content-Type") or "").split(";")[0].strip().lower()

    def json(self):
        return json.loads(self.body)

    def brief(self):
        return "%d %s %r" % (self.status, self.header("Content-Type"), self.body[:300])


def server_timing(resp):
    """{phase: ms} from the Server-Timing header ({} if absent or unreadable)."""
    out = {}
    for part in (resp.header("Server-Timing") or "").split(","):
        m = re.fullmatch(r"\s*([A-Za-z]+);dur=([0-9]+(?:\.[0-9]+)?)\s*", part)
        if m:
            out[m.group(1)] = m.group(2)
    return out


TIMINGS_RE = re.compile(rb',"timings":\{"parse":([0-9.]+),"validate":([0-9.]+),"build":([0-9.]+),'
                        rb'"evaluate":([0-9.]+),"encode":([0-9.]+),"total":([0-9.]+)\}\}\n$')
STRIP_RE = re.compile(rb',"timings":\{[^{}]*\}')


def strip_timings(body):
    """The body without its one `,"timings":{...}` member; None if it has not exactly one."""
    new, n = STRIP_RE.subn(b"", body)
    return new if n == 1 else None


def audit(label, resp, api_json=False):
    """Every response: Server-Timing with the five phases. JSON answers of the API: a last
    "timings" member with the same phase figures and their total."""
    st = server_timing(resp)
    problems = []
    missing = [p for p in PHASES if p not in st]
    if missing:
        problems.append("%s: Server-Timing %r lacks %s" % (label, resp.header("Server-Timing"), missing))
    tproblem = None
    if api_json and resp.status == 200:
        m = TIMINGS_RE.search(resp.body)
        if not m:
            tproblem = "%s: body does not end with a timings object: ...%r" % (label, resp.body[-160:])
        else:
            vals = [m.group(i + 1).decode() for i in range(6)]
            if not missing and [st[p] for p in PHASES] != vals[:5]:
                tproblem = "%s: timings %s differ from Server-Timing %s" % (label, vals[:5], [st[p] for p in PHASES])
            elif abs(sum(float(v) for v in vals[:5]) - float(vals[5])) > 0.004:
                tproblem = "%s: timings total %s is not the sum of %s" % (label, vals[5], vals[:5])
    with LOCK:
        AUDIT["n"] += 1
        AUDIT["server_timing"] += problems
        if api_json:
            AUDIT["timings"].append(tproblem)


def is_api_json(method, path):
    return method == "POST" and path in ("/v1/ordinates", "/v1/evaluate")


def request(d, method, path, body=None, headers=None, timeout=120):
    conn = http.client.HTTPConnection("127.0.0.1", d.port, timeout=timeout)
    t0 = time.time()
    try:
        with LOCK:
            d.sent += 1
        conn.request(method, path, body=body, headers=headers or {})
        r = conn.getresponse()
        data = r.read()
        resp = Resp(r.status, r.headers, data, time.time() - t0)
    finally:
        conn.close()
    audit("%s %s" % (method, path), resp, is_api_json(method, path))
    return resp


def get(d, path, **kw):
    return request(d, "GET", path, **kw)


def post(d, path, doc, headers=None, **kw):
    body = doc if isinstance(doc, (bytes, bytearray)) else json.dumps(doc).encode()
    return request(d, "POST", path, body=body, headers=JSON_H if headers is None else headers, **kw)


def raw_exchange(d, data, method="POST", timeout=10):
    """Sends bytes as they are on a new connection and reads one response."""
    s = socket.create_connection(("127.0.0.1", d.port), timeout=timeout)
    t0 = time.time()
    with LOCK:
        d.sent += 1
    try:
        try:
            s.sendall(data)
        except OSError:
            pass  # refused mid-upload: the answer may still be there to read
        r = http.client.HTTPResponse(s, method=method)
        r.begin()
        body = r.read()
        resp = Resp(r.status, r.headers, body, time.time() - t0)
    finally:
        s.close()
    audit("raw %s" % data[:40], resp)
    return resp


def healthz_ok(d):
    try:
        r = get(d, "/healthz", timeout=10)
        return r.status == 200 and healthy(r.json())
    except Exception:
        return False


def section(title):
    say("# %s (at %.1f s)" % (title, time.time() - T_START))


# ---- meshes and viewports ---------------------------------------------------------------

def load(name):
    with open(os.path.join(EX, name), "rb") as f:
        return f.read()


SQUARE_BYTES = load("square-light.json")
SHADOW_BYTES = load("shadow-edges.json")
RENDER_BYTES = load("render.json")
POINTS_BYTES = load("points.json")
SQUARE = json.loads(SQUARE_BYTES)
SHADOW = json.loads(SHADOW_BYTES)


def rgb_of(v):
    return [v, 1.5 * v * v, v - 0.5]  # the second channel passes 1, the third 0: PNG clamps both ways


def rgb_mesh():
    """shadow-edges with 3 channels: the same C0 and C-1 lines, corner values mapped alike."""
    m = json.loads(SHADOW_BYTES)
    m["values"] = [rgb_of(v) for v in SHADOW["values"]]
    m["corner_values"] = [{"triangle": c["triangle"], "values": [rgb_of(v) for v in c["values"]]}
                          for c in SHADOW["corner_values"]]
    return m


RGB = rgb_mesh()
SMALL = {"vertices": [[0, 0], [1, 0], [1, 1], [0, 1]], "triangles": [[0, 1, 2], [0, 2, 3]], "values": [0, 1, 2, 3]}

# Larger than the mesh (the unit square), non-dyadic steps.
VA = {"x0": -0.3, "y0": -0.2, "x1": 1.3, "y1": 1.15, "width": 48, "height": 40}
# Pixel centres at x = (i - 8)/16, y = (24 - j)/16 exactly: on every vertex, on the
# horizontal, vertical and diagonal edges, on the C0 line x = 1/2, the C-1 line y = 3/4,
# and on the mesh boundary.
VB = {"x0": -0.53125, "y0": -0.46875, "x1": 1.46875, "y1": 1.53125, "width": 32, "height": 32}


def with_(base, **kw):
    d = dict(base)
    d.update(kw)
    return d


def centres(vp):
    """Pixel centres, row 0 (top) first, exactly as the contract computes them."""
    x0, y0, x1, y1, w, h = vp["x0"], vp["y0"], vp["x1"], vp["y1"], vp["width"], vp["height"]
    xs = [x0 + (x1 - x0) * ((i + 0.5) / w) for i in range(w)]
    ys = [y1 - (y1 - y0) * ((j + 0.5) / h) for j in range(h)]
    return [(x, y) for y in ys for x in xs]


def in_unit_square(p):
    return 0.0 <= p[0] <= 1.0 and 0.0 <= p[1] <= 1.0


def evaluate_points(d, mesh, pts):
    """(values as an array [n][C] with NaN outside, outside as a set) from /v1/evaluate."""
    r = post(d, "/v1/evaluate", with_(mesh, points=[list(p) for p in pts]))
    if r.status != 200:
        raise RuntimeError("evaluate: " + r.brief())
    doc = r.json()
    vals = [v if isinstance(v, list) or v is None else [v] for v in doc["values"]]
    nc = len(next(v for v in vals if v is not None))
    arr = np.array([v if v is not None else [math.nan] * nc for v in vals], dtype=np.float64)
    return arr, set(doc["outside"])


# ---- images -----------------------------------------------------------------------------

MIME = {"png": "image/png", "png16": "image/png", "exr": "image/x-exr", "exr-half": "image/x-exr",
        "tiff": "image/tiff", "raw": "application/octet-stream"}
STORED = {"png": "uint8", "png16": "uint16", "exr": "float", "exr-half": "half", "tiff": "float"}
MAGIC = {"png": b"\x89PNG\r\n\x1a\n", "png16": b"\x89PNG\r\n\x1a\n", "exr": b"\x76\x2f\x31\x01",
         "exr-half": b"\x76\x2f\x31\x01", "tiff": (b"II*\x00", b"MM\x00*")}
FORMATS = ("png", "png16", "exr", "exr-half", "tiff", "raw")
_seq = [0]


class Decoded:
    def __init__(self, px, names, alpha, stored):
        self.px, self.names, self.alpha, self.stored = px, names, alpha, stored


def decode(data, fmt, w=None, h=None, nc=None):
    """Pixels [h][w][channels] in the stored type (raw: float32, no alpha)."""
    if fmt == "raw":
        return Decoded(np.frombuffer(data, dtype="<f4").reshape(h, w, nc), None, -1, "float")
    with LOCK:
        _seq[0] += 1
        n = _seq[0]
    ext = {"png": "png", "png16": "png", "exr": "exr", "exr-half": "exr", "tiff": "tif"}[fmt]
    path = os.path.join(TMP, "tile%d.%s" % (n, ext))  # the 2.4 bindings read files, not memory
    with open(path, "wb") as f:
        f.write(data)
    try:
        cfg = oiio.ImageSpec()
        cfg.attribute("oiio:UnassociatedAlpha", 1)  # alpha as written, nothing premultiplied
        inp = oiio.ImageInput.open(path, cfg)
        if inp is None:
            raise RuntimeError("OpenImageIO cannot open the %s: %s" % (fmt, oiio.geterror()))
        spec = inp.spec()
        px = inp.read_image(spec.format)
        inp.close()
        if px is None:
            raise RuntimeError("OpenImageIO cannot read the %s" % fmt)
        px = np.asarray(px).reshape(spec.height, spec.width, spec.nchannels)
        return Decoded(px, list(spec.channelnames), spec.alpha_channel, str(spec.format))
    finally:
        os.unlink(path)


def srgb(x):
    return 12.92 * x if x <= 0.0031308 else 1.055 * math.pow(x, 1.0 / 2.4) - 0.055


def png_level(v32, exposure, linear, maxval):
    """The contract's PNG sample of a float32 value: v * 2^exposure, sRGB, clamp, round."""
    x = float(v32) * (2.0 ** exposure)
    if not linear:
        x = srgb(x)
    if not x > 0.0:
        x = 0.0
    if x > 1.0:
        x = 1.0
    return math.floor(x * maxval + 0.5)


def tile_errors(resp, fmt, vp, ref, outside, background, exposure=0, linear=False):
    """Everything wrong with a rendered tile against the evaluation at its pixel centres
    (ref [n][C], outside: indices of points outside the mesh). [] if it is right."""
    errs = []
    w, h = vp["width"], vp["height"]
    nc = ref.shape[1]
    if resp.status != 200:
        return ["status " + resp.brief()]
    if resp.ctype() != MIME[fmt]:
        errs.append("Content-Type %r, expected %s" % (resp.header("Content-Type"), MIME[fmt]))
    if fmt == "raw":
        if len(resp.body) != w * h * nc * 4:
            return errs + ["raw has %d bytes, expected %d" % (len(resp.body), w * h * nc * 4)]
    else:
        magic = MAGIC[fmt] if isinstance(MAGIC[fmt], tuple) else (MAGIC[fmt],)
        if not any(resp.body.startswith(m) for m in magic):
            return errs + ["bytes do not start with the %s signature: %r" % (fmt, resp.body[:8])]
    img = decode(resp.body, fmt, w, h, nc)
    inside = np.ones(w * h, dtype=bool)
    inside[list(outside)] = False
    inside = inside.reshape(h, w)
    bg = np.array(background if isinstance(background, list) else [background] * nc, dtype=np.float64)
    expect = np.where(np.isnan(ref), bg[None, :], ref).reshape(h, w, nc)
    expect[~inside] = bg
    exp32 = expect.astype(np.float32)  # the contract: the double rounded once to float ...
    # ... give or take 1e-12 of the data's scale (the fast cubic: README, docs/design-notes.md): the
    # float32 of any double within that distance of /v1/evaluate's value is right.
    finite = np.abs(ref[np.isfinite(ref)])
    slack = 1e-12 * (finite.max() if finite.size else 0.0)
    lo32, hi32 = (expect - slack).astype(np.float32), (expect + slack).astype(np.float32)
    names = ["Y"] if nc == 1 else ["R", "G", "B"] if nc == 3 else ["ch%d" % c for c in range(nc)]
    if fmt == "raw":
        data, alpha = img.px, None
    else:
        if img.px.shape != (h, w, nc + 1):
            return errs + ["decoded shape %s, expected %s" % (img.px.shape, (h, w, nc + 1))]
        if sorted(img.names) != sorted(names + ["A"]) or img.alpha < 0 or img.names[img.alpha] != "A":
            errs.append("channels %s (alpha %d), expected %s + A" % (img.names, img.alpha, names))
            return errs
        if img.stored != STORED[fmt]:
            errs.append("stored as %s, expected %s" % (img.stored, STORED[fmt]))
        data = np.stack([img.px[:, :, img.names.index(n)] for n in names], axis=2)
        alpha = img.px[:, :, img.alpha]
    # the values
    if fmt in ("raw", "exr", "tiff"):
        bad = (data < lo32) | (data > hi32)
        what = "not float32(value within 1e-12 of the scale)"
    elif fmt == "exr-half":
        got = data.astype(np.float64)
        e = exp32.astype(np.float64)
        bad = np.abs(got - e) > np.maximum(np.abs(e) * 2.0 ** -11, 2.0 ** -25)
        what = "beyond half precision of the value"
    else:
        maxval = 255 if fmt == "png" else 65535
        q = np.empty((h, w, nc), dtype=np.int64)
        qlo, qhi = np.empty_like(q), np.empty_like(q)
        for j in range(h):
            for i in range(w):
                for c in range(nc):
                    q[j, i, c] = png_level(exp32[j, i, c], exposure, linear, maxval)
                    qlo[j, i, c] = png_level(lo32[j, i, c], exposure, linear, maxval)
                    qhi[j, i, c] = png_level(hi32[j, i, c], exposure, linear, maxval)
        got = data.astype(np.int64)
        bad = (got < qlo) | (got > qhi)
        what = "not the contract's quantization"
        off = np.abs(data.astype(np.int64) - q)
        if off.max() > 1:
            what += " (off by up to %d steps)" % off.max()
    if bad.any():
        j, i, c = [int(k) for k in np.argwhere(bad)[0]]
        errs.append("%d samples %s; first at pixel (%d,%d) channel %d: got %r, expected %r (value %r, %s)" % (
            int(bad.sum()), what, i, j, c, data[j, i, c].item(), exp32[j, i, c].item(), expect[j, i, c],
            "inside" if inside[j, i] else "outside"))
    # alpha: 1 inside, 0 outside
    if alpha is not None:
        one = {"png": 255, "png16": 65535}.get(fmt, 1.0)
        abad = alpha != np.where(inside, one, 0)
        if abad.any():
            j, i = [int(k) for k in np.argwhere(abad)[0]]
            errs.append("%d alpha samples wrong; first at (%d,%d): %r (%s)" % (
                int(abad.sum()), i, j, alpha[j, i].item(), "inside" if inside[j, i] else "outside"))
    return errs


# ---- problem documents ------------------------------------------------------------------

def contract():
    """The problem types and metric names api/openapi.yaml promises, read from the file."""
    import re
    import yaml
    with open(os.path.join(ROOT, "api", "openapi.yaml")) as fh:
        spec = yaml.safe_load(fh)
    types = set(spec["components"]["schemas"]["Problem"]["properties"]["type"]["enum"])
    text = spec["paths"]["/metrics"]["get"]["description"]
    metrics = re.findall(r"`(tocher_[a-z_]+)", text)
    return types, metrics


PROBLEM_TYPES, CONTRACT_METRICS = contract()


def healthy(doc):
    """A /healthz answer: {"status": "ok"}, the (memory) store up, and the timings every JSON
    answer carries."""
    return isinstance(doc, dict) and doc.get("status") == "ok" and set(doc) <= {"status", "store", "timings"} and \
        doc.get("store") == {"backend": "memory", "state": "up"}
TYPE_OF = {400: "/problems/malformed-request", 404: "/problems/not-found", 405: "/problems/method-not-allowed",
           413: "/problems/too-large", 415: "/problems/unsupported-media-type", 422: "/problems/invalid-mesh",
           503: "/problems/timeout", 500: "/problems/internal"}


def problem_errors(resp, status, detail=(), path=None, any_error=None):
    """What is wrong with a problem answer: status, Content-Type, the members, the type for
    the status, substrings of the detail, the exact path, a substring of some error."""
    errs = []
    if resp.status != status:
        errs.append("status %d, expected %d" % (resp.status, status))
    if resp.ctype() != "application/problem+json":
        errs.append("Content-Type %r" % resp.header("Content-Type"))
    try:
        doc = resp.json()
    except ValueError:
        return errs + ["body is not JSON: %r" % resp.body[:200]]
    if not isinstance(doc, dict):
        return errs + ["body is not an object: %r" % resp.body[:200]]
    missing = [k for k in ("type", "title", "status", "detail", "path") if k not in doc]
    if missing:
        errs.append("members %s missing" % missing)
    if doc.get("status") != resp.status:
        errs.append("body status %r vs HTTP %d" % (doc.get("status"), resp.status))
    if doc.get("type") != TYPE_OF.get(status):
        errs.append("type %r, expected %s" % (doc.get("type"), TYPE_OF.get(status)))
    if not isinstance(doc.get("title"), str) or not doc.get("title"):
        errs.append("empty title")
    for s in detail:
        if s not in str(doc.get("detail", "")):
            errs.append("detail %r lacks %r" % (doc.get("detail"), s))
    if path is not None and doc.get("path") != path:
        errs.append("path %r, expected %r" % (doc.get("path"), path))
    if any_error is not None:
        msgs = [e.get("path", "") + ": " + e.get("message", "") for e in doc.get("errors", [])]
        if not any(any_error in m for m in msgs):
            errs.append("no error mentions %r: %s" % (any_error, msgs))
    if errs:
        errs.append("body: %r" % resp.body[:300])
    return errs


# ---- metrics -----------------------------------------------------------------------------

def parse_metrics(text):
    samples = {}
    for line in text.splitlines():
        if not line or line.startswith("#"):
            continue
        m = re.match(r"^([a-zA-Z_:][a-zA-Z0-9_:]*)(?:\{(.*)\})?\s+(\S+)$", line)
        if not m:
            continue
        labels = tuple(sorted(re.findall(r'(\w+)="((?:[^"\\]|\\.)*)"', m.group(2) or "")))
        samples[(m.group(1), labels)] = float(m.group(3))
    return samples


def metric(samples, name, **labels):
    return samples.get((name, tuple(sorted(labels.items()))), 0.0)


IN_FLIGHT = ("tocher_requests_in_flight", "tocher_http_requests_in_flight")


def settled_metrics(d, timeout=5.0):
    """/metrics once every earlier request is accounted for. The daemon counts a request
    in libmicrohttpd's completion callback, which runs just after the client has the whole
    answer, so a scrape right after an answer may not count it yet: wait until the
    in-flight gauge shows only the scrape itself. Returns (samples, text)."""
    end = time.time() + timeout
    while True:
        text = get(d, "/metrics").body.decode()
        samples = parse_metrics(text)
        infl = next((v for k, v in samples.items() if k[0] in IN_FLIGHT), None)
        if infl == 1 or infl is None or time.time() > end:
            return samples, text
        time.sleep(0.02)


# =========================================================================================
# 1. happy path of every endpoint, Server-Timing, timings, metrics
# =========================================================================================

def section_basics(D):
    section("1. endpoints, Server-Timing, metrics")
    check("startup line names version and port", D.port > 0, D.line)
    r = get(D, "/healthz")
    check("GET /healthz", r.status == 200 and r.ctype() == "application/json" and healthy(r.json()),
          r.brief())
    r = get(D, "/v1/version")
    vout = subprocess.run([TOCHERD, "--version"], capture_output=True, text=True).stdout.strip()
    ok = r.status == 200 and r.ctype() == "application/json"
    doc = r.json() if ok else {}
    check("GET /v1/version", ok and doc.get("api") == "v1" and doc.get("version") == D.version and
          vout == "tocherd " + D.version, "%s; --version says %r" % (r.brief(), vout))

    m0, _ = settled_metrics(D)
    r = post(D, "/v1/ordinates", SQUARE_BYTES)
    ok = r.status == 200 and r.ctype() == "application/json"
    doc = r.json() if ok else {}
    shape_ok = ok and doc.get("channels") == 1 and len(doc.get("labels", [])) == 19 and \
        len(doc.get("ordinates", [])) == 4 and all(len(t) == 1 and len(t[0]) == 19 for t in doc["ordinates"])
    # The cubic interpolates: uuu/vvv/www are the vertex values (u = each triangle's first vertex).
    interp = shape_ok and all(doc["ordinates"][t][0][:3] == [SQUARE["values"][k] for k in SQUARE["triangles"][t]]
                              for t in range(4))
    check("POST /v1/ordinates (square-light: 4 x 19 ordinates, vertex values interpolated)",
          shape_ok and interp and list(doc)[-1] == "timings", r.brief())

    ev = with_(SQUARE, **json.loads(POINTS_BYTES))
    r = post(D, "/v1/evaluate", ev)
    ok = r.status == 200 and r.ctype() == "application/json"
    doc = r.json() if ok else {}
    check("POST /v1/evaluate (values, gradients, outside)",
          ok and len(doc["values"]) == 5 and doc["values"][0] == SQUARE["values"][4] and doc["values"][4] is None
          and doc["outside"] == [4] and len(doc["gradients"]) == 5 and doc["gradients"][4] is None
          and all(isinstance(g, list) and len(g) == 2 for g in doc["gradients"][:4]), r.brief())

    r = post(D, "/v1/render", RENDER_BYTES)
    ok = r.status == 200 and r.ctype() == "image/png" and r.body.startswith(MAGIC["png"])
    if ok:
        img = decode(r.body, "png")
        ok = img.px.shape == (256, 256, 2) and img.stored == "uint8"
    check("POST /v1/render (render.json: 256x256 grey+alpha PNG)", ok, r.brief()[:120])

    m1, text = settled_metrics(D)
    text_r = get(D, "/metrics")
    check("GET /metrics is Prometheus text", text_r.status == 200 and text_r.ctype() == "text/plain" and
          "version=0.0.4" in (text_r.header("Content-Type") or ""), text_r.brief()[:200])
    names = {k[0] for k in m1}
    listed = [n + "_bucket" if n.endswith("_seconds") else n for n in CONTRACT_METRICS]
    check("metric names as api/openapi.yaml lists them", len(listed) >= 5 and all(n in names for n in listed),
          "missing %s; the daemon exposes %s" % ([n for n in listed if n not in names],
                                                  sorted(n for n in names if not n.endswith(("_bucket", "_sum")))))

    def pick(*cands):
        return next((c for c in cands if c in names or c + "_count" in names), cands[0])
    req = pick("tocher_requests_total", "tocher_http_requests_total")
    hist = pick("tocher_request_duration_seconds", "tocher_http_request_duration_seconds")
    tris = pick("tocher_triangles_total", "tocher_triangles_processed_total")
    pix = pick("tocher_pixels_total", "tocher_pixels_processed_total")
    infl = pick("tocher_requests_in_flight", "tocher_http_requests_in_flight")
    deltas = {route: metric(m1, req, route=route, status="200") - metric(m0, req, route=route, status="200")
              for route in ("/v1/ordinates", "/v1/evaluate", "/v1/render", "/healthz")}
    check("metrics: route/status counters count each request once",
          deltas == {"/v1/ordinates": 1, "/v1/evaluate": 1, "/v1/render": 1, "/healthz": 0}, str(deltas))
    errs = []
    for route in ("/v1/ordinates", "/v1/render"):
        les = sorted(((float(dict(k[1])["le"]), v) for k, v in m1.items()
                      if k[0] == hist + "_bucket" and dict(k[1]).get("route") == route), key=lambda t: t[0])
        cnt, cnt0 = metric(m1, hist + "_count", route=route), metric(m0, hist + "_count", route=route)
        s, s0 = metric(m1, hist + "_sum", route=route), metric(m0, hist + "_sum", route=route)
        if len(les) < 2 or les[-1][0] != math.inf:
            errs.append("%s: buckets %s" % (route, les))
            continue
        if any(les[k][1] > les[k + 1][1] for k in range(len(les) - 1)):
            errs.append("%s: buckets not cumulative %s" % (route, les))
        if les[-1][1] != cnt or cnt - cnt0 != 1 or not s > s0:
            errs.append("%s: +Inf %s, count %s -> %s, sum %s -> %s" % (route, les[-1][1], cnt0, cnt, s0, s))
    if "# TYPE %s histogram" % hist not in text:
        errs.append("no '# TYPE %s histogram'" % hist)
    check("metrics: latency histogram has _bucket (cumulative, +Inf), _sum, _count", not errs, "; ".join(errs))
    dt, dp = metric(m1, tris) - metric(m0, tris), metric(m1, pix) - metric(m0, pix)
    check("metrics: triangles and pixels totals grow by what was processed",
          dt == 4 + 4 + 32 and dp == 256 * 256, "triangles +%s (expected 40), pixels +%s (expected 65536)" % (dt, dp))
    check("metrics: in-flight gauge settles to 1 (the scrape itself) once the answers are in",
          metric(m1, infl) == 1, str(metric(m1, infl)))
    r = request(D, "HEAD", "/healthz")
    check("HEAD /healthz", r.status == 200 and r.body == b"", r.brief())


def audit_report(label):
    with LOCK:
        st, tm, n = list(AUDIT["server_timing"]), [t for t in AUDIT["timings"]], AUDIT["n"]
    check("%s: every response (%d) has Server-Timing with the five phases" % (label, n), not st,
          "%d without: %s" % (len(st), st[:3]))
    bad = [t for t in tm if t]
    check("%s: every JSON answer of the API (%d) ends with timings equal to Server-Timing" % (label, len(tm)),
          not bad and tm, "%d wrong: %s" % (len(bad), bad[:3]))


# =========================================================================================
# 2. images against the evaluation at the pixel centres
# =========================================================================================

def section_images(D):
    section("2. rendered tiles against /v1/evaluate")
    pts_b = centres(VB)
    on = {(v[0], v[1]) for v in SHADOW["vertices"]}
    check("dyadic tile: pixel centres fall exactly on all 25 vertices",
          on <= set(pts_b), "missing %s" % sorted(on - set(pts_b))[:5])
    meshes = [("shadow-edges (1 channel)", SHADOW, 0.0), ("RGB variant (3 channels)", RGB, [0.125, -0.25, 0.5])]
    for vp_name, vp in (("viewport larger than the mesh", VA), ("dyadic tile on vertices and edges", VB)):
        pts = centres(vp)
        geo_out = {k for k, p in enumerate(pts) if not in_unit_square(p)}
        for mesh_name, mesh, bg in meshes:
            ref, outside = evaluate_points(D, mesh, pts)
            check("evaluate: outside == centres outside the closed unit square (%s, %s)" % (mesh_name, vp_name),
                  outside == geo_out and not np.isnan(np.delete(ref, list(outside), axis=0)).any(),
                  "outside-only %s, inside-only %s" % (sorted(outside - geo_out)[:5], sorted(geo_out - outside)[:5]))
            for fmt in FORMATS:
                doc = with_(mesh, viewport=vp, format=fmt)
                if bg != 0.0:
                    doc["background"] = bg
                try:
                    errs = tile_errors(post(D, "/v1/render", doc), fmt, vp, ref, outside, bg)
                except Exception as e:
                    errs = ["%r" % e]
                check("render %s, %s, %s" % (fmt, mesh_name, vp_name), not errs, "; ".join(errs))
    # exposure, linear, a scalar background, and formats chosen by Accept
    ref, outside = evaluate_points(D, SHADOW, centres(VA))
    ref3, outside3 = evaluate_points(D, RGB, centres(VA))
    variants = [
        ("png, exposure 2", SHADOW, {"format": "png", "exposure": 2}, None, "png", (ref, outside), 0.0, 2, False),
        ("png16, linear, exposure -1, RGB", RGB, {"format": "png16", "linear": True, "exposure": -1}, None, "png16",
         (ref3, outside3), 0.0, -1, True),
        ("raw, background 0.75", SHADOW, {"format": "raw", "background": 0.75}, None, "raw", (ref, outside), 0.75,
         0, False),
        ("png, background 0.75", SHADOW, {"format": "png", "background": 0.75}, None, "png", (ref, outside), 0.75,
         0, False),
        ("no format, no Accept -> png", SHADOW, {}, None, "png", (ref, outside), 0.0, 0, False),
        ("Accept: image/png", SHADOW, {}, "image/png", "png", (ref, outside), 0.0, 0, False),
        ("Accept: image/x-exr", SHADOW, {}, "image/x-exr", "exr", (ref, outside), 0.0, 0, False),
        ("Accept: image/tiff", RGB, {}, "image/tiff", "tiff", (ref3, outside3), 0.0, 0, False),
        ("Accept: application/octet-stream", RGB, {}, "application/octet-stream", "raw", (ref3, outside3), 0.0, 0,
         False),
        ("Accept: image/x-exr;q=0.5, image/tiff", SHADOW, {}, "image/x-exr;q=0.5, image/tiff", "tiff",
         (ref, outside), 0.0, 0, False),
        ("format raw wins over Accept: image/png", SHADOW, {"format": "raw"}, "image/png", "raw", (ref, outside), 0.0,
         0, False),
    ]
    # values beyond what a format's samples hold: written as its largest value, with a warning header
    square = {"vertices": [[0, 0], [1, 0], [1, 1], [0, 1]], "triangles": [[0, 1, 2], [0, 2, 3]], "method": "linear",
              "viewport": {"x0": 0, "y0": 0, "x1": 1, "y1": 1, "width": 8, "height": 8}}
    for fmt, big, bound in (("exr-half", 1e6, 65504.0), ("exr", 1e300, 3.4028234663852886e38),
                            ("tiff", -1e300, 3.4028234663852886e38)):
        r = post(D, "/v1/render", dict(square, values=[big, big / 5, big, big / 5], format=fmt))
        errs = []
        try:
            data = np.asarray(decode(r.body, fmt).px[..., 0], dtype=np.float64)
            if not np.isfinite(data).all():
                errs.append("infinite samples")
            if abs(abs(float(data.flat[0])) - bound) > bound * 1e-6:
                errs.append("corner sample %r, not +-%g" % (float(data.flat[0]), bound))
        except Exception as e:
            errs.append("%r" % e)
        warn = r.headers.get("Tocher-Warning", "")
        if "largest value %s holds" % fmt not in warn:
            errs.append("no warning header (%r)" % warn[:120])
        check("render %s of values beyond its range: +-%g, finite, with a warning" % (fmt, bound),
              r.status == 200 and not errs, "; ".join(errs) or r.brief())
    for name, mesh, extra, accept, fmt, (rf, out), bg, exposure, linear in variants:
        doc = with_(mesh, viewport=VA, **extra)
        headers = dict(JSON_H)
        if accept:
            headers["Accept"] = accept
        try:
            errs = tile_errors(post(D, "/v1/render", doc, headers=headers), fmt, VA, rf, out, bg, exposure, linear)
        except Exception as e:
            errs = ["%r" % e]
        check("render %s" % name, not errs, "; ".join(errs))


# =========================================================================================
# 3. the daemon and the CLI give the same bytes
# =========================================================================================

def run_cli(*args):
    p = subprocess.run([TOCHER, *args], capture_output=True, env=daemon_env(), timeout=120)
    return p.returncode, p.stdout, p.stderr


def options_agree_with_contract():
    """The request options as `tocher help` lists them (from the options and method tables)
    against MeshRequest in api/openapi.yaml: the same names, values and defaults."""
    import yaml
    with open(os.path.join(ROOT, "api", "openapi.yaml")) as fh:
        props = yaml.safe_load(fh)["components"]["schemas"]["MeshRequest"]["properties"]
    rc, out, _ = run_cli("help")
    text = out.decode().split("request options")[-1].splitlines()[1:]
    errs = []
    for line in text:
        m = re.match(r"^  (\S+)\s+(.*?)(?: \[.*\])?$", line)
        if not m:
            continue
        name, accepts = m.group(1), m.group(2)
        spec = props.get(name)
        if spec is None:
            errs.append("%s not in the contract" % name)
        elif accepts.startswith("a number"):
            lo, hi, dflt = re.match(r"a number from (\S+) to (\S+), default (\S+)", accepts).groups()
            if (float(lo), float(hi), float(dflt)) != (spec.get("minimum"), spec.get("maximum"), spec.get("default")):
                errs.append("%s: %s vs %s" % (name, accepts, spec))
        else:
            values = accepts.split(", ")
            if values != spec.get("enum") or values[0] != spec.get("default"):
                errs.append("%s: %s vs enum %s default %s" % (name, values, spec.get("enum"), spec.get("default")))
    return rc == 0 and len(text) >= 9 and not errs, "; ".join(errs) or "%d options" % len(text)


def section_cli(D):
    section("3. /v1/ordinates == tocher ordinates")
    ok, detail = options_agree_with_contract()
    check("every request option of `tocher help` (the options table) is in api/openapi.yaml with the same values "
          "and default", ok, detail)
    files = [("square-light.json", os.path.join(EX, "square-light.json")),
             ("shadow-edges.json", os.path.join(EX, "shadow-edges.json")),
             ("render.json", os.path.join(EX, "render.json"))]
    for name, doc in (("rgb-variant.json", RGB), ("shadow-edges linear4", with_(SHADOW, method="linear4")),
                      ("shadow-edges salesin, literal", with_(SHADOW, cross_boundary="salesin", wedges="literal"))):
        path = os.path.join(TMP, re.sub(r"[^a-z0-9.-]+", "_", name) + ".json")
        with open(path, "w") as f:
            json.dump(doc, f)
        files.append((name, path))
    for name, path in files:
        with open(path, "rb") as f:
            body = f.read()
        r = post(D, "/v1/ordinates", body)
        rc_t, cli_t, err_t = run_cli("ordinates", "--timings", path)
        rc, cli, err = run_cli("ordinates", path)
        http_s, cli_s = strip_timings(r.body), strip_timings(cli_t)
        check("ordinates %s: HTTP == tocher ordinates --timings, timings aside" % name,
              r.status == 200 and rc_t == 0 and http_s is not None and http_s == cli_s,
              "HTTP %s; CLI rc %d %r" % (r.brief()[:100], rc_t, (cli_t or err_t)[:100]))
        check("ordinates %s: HTTP without timings == tocher ordinates" % name,
              rc == 0 and http_s is not None and http_s == cli, "CLI rc %d, %d vs %d bytes" % (
                  rc, len(cli), len(http_s or b"")))
    # evaluate: one body over HTTP, mesh + points files for the CLI
    r = post(D, "/v1/evaluate", with_(SQUARE, **json.loads(POINTS_BYTES)))
    rc, cli, err = run_cli("eval", "--timings", os.path.join(EX, "square-light.json"), os.path.join(EX, "points.json"))
    check("evaluate square-light + points.json: HTTP == tocher eval, timings aside",
          r.status == 200 and rc == 0 and strip_timings(r.body) is not None and
          strip_timings(r.body) == strip_timings(cli), "%s vs %r" % (r.brief()[:150], cli[:150]))
    out = os.path.join(TMP, "cli-render.png")
    r = post(D, "/v1/render", RENDER_BYTES)
    rc, _, err = run_cli("render", os.path.join(EX, "render.json"), "-o", out)
    cli_png = open(out, "rb").read() if rc == 0 else b""
    check("render render.json (overlay): HTTP bytes == tocher render", r.status == 200 and r.body == cli_png,
          "rc %d %r; %d vs %d bytes" % (rc, err[:100], len(r.body), len(cli_png)))


# =========================================================================================
# 4. the same bytes whatever the number of render threads
# =========================================================================================

def section_threads(D):
    section("4. --render-threads 1, 2, 7")
    vp = {"x0": -0.2, "y0": -0.15, "x1": 1.2, "y1": 1.1, "width": 700, "height": 500}
    ds = [Daemon("rt%d" % n, "--render-threads", str(n), "--threads", "2") for n in (1, 2, 7)]
    raws = None
    for mesh_name, mesh in (("shadow-edges", SHADOW), ("RGB", RGB)):
        for fmt in ("raw", "exr", "tiff", "png16"):
            rs = [post(d, "/v1/render", with_(mesh, viewport=vp, format=fmt)) for d in ds]
            ok = all(r.status == 200 for r in rs) and len({r.body for r in rs}) == 1
            check("render 700x500 %s %s: identical bytes with 1, 2 and 7 render threads" % (mesh_name, fmt), ok,
                  "statuses %s, sizes %s, equal pairs %s" % ([r.status for r in rs], [len(r.body) for r in rs],
                                                            [rs[0].body == r.body for r in rs]))
            if fmt == "raw" and mesh_name == "RGB":
                raws = rs[0].body
    # the validation and build run on the render threads too: the same ordinates, warnings and errors
    big = grid_mesh(90)  # 16 200 triangles: every loop in several parts on 2 and 7 threads
    big["values"] = [math.sin(3 * x + 1) * math.cos(2 * y) for x, y in big["vertices"]]
    big["discontinuities"] = {"c0": [[45 * 91 + i for i in range(91)]], "c-1": [[i * 91 + 30 for i in range(91)]]}
    bad = dict(big, triangles=big["triangles"] + [big["triangles"][-1], big["triangles"][7]])
    for what, doc, want in (("a 16 200-triangle mesh", big, 200), ("it with two repeated triangles", bad, 422)):
        rs = [post(d, "/v1/ordinates", doc) for d in ds]
        docs = [json.loads(r.body) for r in rs]
        for x in docs:
            x.pop("timings", None)
        check("ordinates of %s: the same answer with 1, 2 and 7 render threads" % what,
              all(r.status == want for r in rs) and all(x == docs[0] for x in docs),
              "statuses %s, equal %s" % ([r.status for r in rs], [x == docs[0] for x in docs]))
    for d in ds:
        rc = d.stop()
        check("daemon %s: SIGTERM -> exit 0, no sanitizer report" % d.name,
              rc == 0 and not SAN_RE.search(d.stderr()), "rc %s; %s" % (rc, d.stderr()[-400:]))
    # and a sample of the large tile against the evaluation
    if raws is not None:
        rng = random.Random(7)
        pts = centres(vp)
        idx = sorted(rng.sample(range(len(pts)), 1500))
        ref, outside = evaluate_points(D, RGB, [pts[k] for k in idx])
        tile = np.frombuffer(raws, dtype="<f4").reshape(-1, 3)
        bg = np.zeros(3)
        exp64 = np.array([bg if n in outside else ref[n] for n in range(len(idx))])
        exp = exp64.astype(np.float32)
        slack = 1e-12 * np.abs(exp64).max()  # the fast cubic's contract (README, docs/design-notes.md)
        lo, hi = (exp64 - slack).astype(np.float32), (exp64 + slack).astype(np.float32)
        bad = np.nonzero(((tile[idx] < lo) | (tile[idx] > hi)).any(axis=1))[0]
        check("render 700x500 RGB raw: 1500 sampled pixels == float32(evaluate within 1e-12 of the scale)",
              len(bad) == 0,
              "%d differ, e.g. pixel %d: %s vs %s" % (len(bad), idx[bad[0]], tile[idx[bad[0]]], exp[bad[0]])
              if len(bad) else "")


# =========================================================================================
# 5. bad input
# =========================================================================================

MAX_BODY = 1 << 20


# ---- 8. what real front-ends print: value_tolerance, degenerate ----------------------------

def edge_ordinates(doc, t, a, b):
    """The 4 cubic ordinates of triangle t along its edge from corner a to corner b (0..2), by label."""
    names = "uvw"
    labels = doc["labels"]
    want = [names[a] * 3, "".join(sorted(names[a] * 2 + names[b], key=names.index)),
            "".join(sorted(names[a] + names[b] * 2, key=names.index)), names[b] * 3]
    return [doc["ordinates"][t][0][labels.index(x)] for x in want]


def warning_at(doc, path, text):
    return any(w["path"] == path and text in w["message"] for w in doc.get("warnings", []))


def section_frontend(D):
    section("8. what real front-ends print")
    # Triangle 1 = (0, 2, 3) says vertex 2 is 2.000004 where triangle 0 says 2: 1.3e-6 of the
    # scale 3, printing noise. Accepted, both corners averaged: the shared edge [0, 2] has the
    # same ordinates on both sides, bit for bit.
    noisy = with_(SMALL, corner_values=[{"triangle": 1, "values": [0, 2.000004, 3]}])
    r = post(D, "/v1/ordinates", noisy)
    doc = r.json() if r.status == 200 else {}
    ok = r.status == 200 and edge_ordinates(doc, 0, 0, 2) == edge_ordinates(doc, 1, 0, 1)
    check("value_tolerance (default 1e-4): corner values 1.3e-6 apart across a C1 edge are averaged, the edge "
          "exactly continuous", ok and abs(edge_ordinates(doc, 0, 0, 2)[3] - 2.000002) < 1e-15, r.brief())
    check("... and a warning names the vertex and the largest difference",
          warning_at(doc, "vertices[2]", "differed at 1 vertices, by up to 1.3e-06"), str(doc.get("warnings")))
    check("... the answer does not echo the mesh option", "value_tolerance" not in doc, str(list(doc)))
    r = post(D, "/v1/ordinates", with_(noisy, value_tolerance=0))
    check("value_tolerance 0: the same request refused (strict), naming the edge and both values",
          not problem_errors(r, 422, ["C1 edge [2, 0]", "vertex 2", "2 (triangle 0)", "2.000004", "(triangle 1)"],
                             "corner_values[0]"), r.brief())
    r = post(D, "/v1/ordinates", with_(noisy, corner_values=[{"triangle": 1, "values": [0, 2.001, 3]}]))
    check("beyond the tolerance (3.3e-4 of the scale): refused, the tolerance in the message",
          not problem_errors(r, 422, ["C1 edge [2, 0]", "value_tolerance 0.0001", "flag the edge c-1"],
                             "corner_values[0]"), r.brief())
    r = post(D, "/v1/ordinates", with_(noisy, corner_values=[{"triangle": 1, "values": [0, 2.001, 3]}],
                                       value_tolerance=1e-3))
    check("a larger value_tolerance accepts it", r.status == 200, r.brief())
    r = post(D, "/v1/compare", with_(noisy, reference={"points": [[0.5, 0.25]], "values": [0.75]},
                                     methods=[{"method": "linear", "value_tolerance": 0}]))
    doc = r.json() if r.status == 200 else {}
    check("value_tolerance inside /v1/compare's methods: ignored with a warning at its path",
          r.status == 200 and warning_at(doc, "methods[0].value_tolerance", "applies to the mesh"), r.brief())

    # degenerate "drop": triangle 1 has zero area (vertex 4 on the bottom edge), triangle 3 repeats
    # a vertex. The answer keeps the request's numbering; points and pixels fall in the others.
    clean = with_(SMALL, vertices=SMALL["vertices"] + [[0.5, 0]], values=[0, 1, 2, 3, 0.5])
    dirty = with_(clean, triangles=[[0, 1, 2], [0, 4, 1], [0, 2, 3], [2, 2, 3]], degenerate="drop")
    r = post(D, "/v1/ordinates", with_(dirty, degenerate="refuse"))
    check("degenerate \"refuse\" (the default): the zero-area triangle refused at its path",
          not problem_errors(r, 422, ["zero-area"], "triangles[1]"), r.brief())
    r, rc = post(D, "/v1/ordinates", dirty), post(D, "/v1/ordinates", clean)
    doc, ref = (r.json(), rc.json()) if r.status == rc.status == 200 else ({}, {})
    ords = doc.get("ordinates", [])
    check("degenerate \"drop\": /v1/ordinates has 4 entries, null for the dropped triangles 1 and 3, the others as "
          "without them", len(ords) == 4 and ords[1] is None and ords[3] is None and ords[0] == ref["ordinates"][0]
          and ords[2] == ref["ordinates"][1], r.brief())
    check("... one warning lists them at the first one's path",
          warning_at(doc, "triangles[1]", "2 degenerate triangles") and warning_at(doc, "triangles[1]", ": 1, 3;"),
          str(doc.get("warnings")))
    check("... the vertex only they used is reported unused", warning_at(doc, "vertices[4]", "used by no triangle"),
          str(doc.get("warnings")))
    pts = [[0.25, 0.1], [0.9, 0.5], [0.1, 0.8], [0.5, 0.0], [1.5, 0.5]]
    r, rc = post(D, "/v1/evaluate", with_(dirty, points=pts)), post(D, "/v1/evaluate", with_(clean, points=pts))
    check("... /v1/evaluate locates points in the remaining triangles (values as without them)",
          r.status == rc.status == 200 and r.json()["values"] == rc.json()["values"] and r.json()["outside"] == [4],
          r.brief())
    vp = {"x0": -0.1, "y0": -0.1, "x1": 1.1, "y1": 1.1, "width": 24, "height": 24}
    r = post(D, "/v1/render", with_(dirty, viewport=vp, format="raw"))
    rc = post(D, "/v1/render", with_(clean, viewport=vp, format="raw"))
    check("... /v1/render gives the tile of the mesh without them", r.status == rc.status == 200 and r.body == rc.body,
          r.brief())
    r = post(D, "/v1/ordinates", with_(dirty, corner_values=[{"triangle": 2, "values": [0, 2.5, 3]}]))
    check("... an error about another triangle names its index in the request",
          not problem_errors(r, 422, ["(triangle 0)", "(triangle 2)", "C1 edge [2, 0]"], "corner_values[0]"), r.brief())
    r = post(D, "/v1/ordinates", with_(dirty, corner_values=[{"triangle": 3, "values": [9, 9, 9]}],
                                       midpoints=[{"edge": [0, 4], "value": 1}]))
    doc = r.json() if r.status == 200 else {}
    check("... entries naming a dropped triangle or its edges are ignored with a warning",
          r.status == 200 and warning_at(doc, "corner_values[0].triangle", "triangle 3 was dropped")
          and warning_at(doc, "midpoints[0].edge", "edge only of triangles dropped"), r.brief())


def grid_mesh(n):
    verts = [[i / n, j / n] for j in range(n + 1) for i in range(n + 1)]
    tris = []
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            tris += [[a, a + 1, a + n + 2], [a, a + n + 2, a + n + 1]]
    return {"vertices": verts, "triangles": tris, "values": [0.5] * len(verts)}


def catalogue(D):
    """(name, send() -> Resp, status, detail substrings, path, any_error, extra check(resp) -> error or None)."""
    S = lambda **kw: with_(SMALL, **kw)  # noqa: E731
    VP4 = {"x0": 0, "y0": 0, "x1": 1, "y1": 1, "width": 4, "height": 4}
    P = lambda doc, route="/v1/ordinates", **kw: (lambda: post(D, route, doc, **kw))  # noqa: E731
    good = json.dumps(SMALL).encode()
    fan = {"vertices": [[0, 0], [1, 0], [0, 1], [1, 1], [-1, 1], [1, -1]],
           "triangles": [[0, 1, 2], [1, 3, 2], [0, 2, 4], [0, 5, 1], [1, 2, 5]], "values": [0] * 6}
    allow = lambda want: (lambda r: None if r.header("Allow") == want else "Allow %r, expected %r" % (  # noqa: E731
        r.header("Allow"), want))
    many_verts = S(vertices=SMALL["vertices"] + [[5 + k, 5] for k in range(3001 - 4)], values=[0] * 3001)
    return [
        ("truncated JSON", P(SHADOW_BYTES[:len(SHADOW_BYTES) // 2]), 400, ["not valid JSON"], "", None, None),
        ("not JSON", P(b"hello, world"), 400, ["not valid JSON", "line 1, column 1"], "", None, None),
        ("empty body", P(b""), 400, ["empty"], "", None, None),
        ("text after the JSON value", P(good + b" {}"), 400, ["unexpected text"], "", None, None),
        ("top-level array", P(b"[1, 2, 3]"), 400, ["JSON object", "array"], "", None, None),
        ("vertices as a string", P(S(vertices="0,0 1,0 1,1 0,1")), 400, ["got a string"], "vertices", None, None),
        ("a triangle with 2 indices", P(S(triangles=[[0, 1, 2], [0, 2]])), 400, ["3 vertex indices", "array of 2"],
         "triangles[1]", None, None),
        ("values with a string inside", P(S(values=[0, 1, "2", 3])), 400, ["got a string"], "values[2]", None, None),
        ("method as a number", P(S(method=3)), 400, ["expected a string", "got a number"], "method", None, None),
        ("NaN in the JSON text", P(good.replace(b"[1, 1]", b"[1, NaN]")), 400, ["not valid JSON", "NaN"], "", None,
         None),
        ("1e999", P(good.replace(b"[1, 0]", b"[1e999, 0]")), 422, ["not finite"], "vertices[1][0]", None, None),
        ("a fractional index", P(S(triangles=[[0, 1, 2.5], [0, 2, 3]])), 400, ["integer", "2.5"], "triangles[0][2]",
         None, None),
        ("an index out of range", P(S(triangles=[[0, 1, 2], [0, 2, 7]])), 422, ["out of range", "7"],
         "triangles[1][2]", None, None),
        ("a negative index", P(S(triangles=[[0, 1, 2], [-1, 2, 3]])), 422, ["out of range"], "triangles[1][0]", None,
         None),
        ("a zero-area triangle", P(S(vertices=[[0, 0], [1, 0], [2, 0], [0, 1]])), 422, ["zero-area"], "triangles[0]",
         None, None),
        ("a repeated triangle", P(S(triangles=[[0, 1, 2], [2, 1, 0]])), 422, ["repeats triangles[0]"], "triangles[1]",
         None, None),
        ("a non-manifold edge", P(fan), 422, ["non-manifold edge [1, 2]"], "triangles[4]", None, None),
        ("an edge flagged both c0 and c-1", P(S(discontinuities={"c0": [[0, 2]], "c-1": [[2, 0]]})), 422,
         ["edge [2, 0]", "both c0 and c-1"], "discontinuities.c-1[0][0]", None, None),
        ("a discontinuity segment that is not an edge", P(S(discontinuities={"c0": [[0, 1, 3]]})), 422,
         ["[1, 3] is not an edge"], "discontinuities.c0[0][1]", None, None),
        ("corner values disagreeing across a C1 edge", P(S(corner_values=[{"triangle": 0, "values": [0, 1, 5]}])), 422,
         ["disagree", "C1 edge"], "corner_values[0]", None, None),
        ("value_tolerance above 1", P(S(value_tolerance=2)), 422, ["value_tolerance must be a number from 0 to 1"],
         "value_tolerance", None, None),
        ("value_tolerance as a string", P(S(value_tolerance="1e-4")), 400, ["expected a number"], "value_tolerance",
         None, None),
        ("an unknown degenerate mode", P(S(degenerate="skip")), 422, ["unknown degenerate 'skip'", "refuse, drop"],
         "degenerate", None, None),
        ("a non-manifold edge with degenerate drop", P(with_(fan, degenerate="drop")), 422,
         ["non-manifold edge [1, 2]"], "triangles[4]", None, None),
        ("an unknown range", P(S(range="clamped")), 422, ["unknown range 'clamped'", "local, positive, free"], "range",
         None, None),
        ("normal with N.z = 0", P(S(normals=[[0, 0, 1], [0, 0, 1], [0, 0.5, 0], [0, 0, 1]])), 422, ["N.z"],
         "normals[2]", None, None),
        ("normal with N.z < 0", P(S(normals=[[0, 0, 1], [0.1, 0, -1], [0, 0, 1], [0, 0, 1]])), 422, ["N.z"],
         "normals[1]", None, None),
        ("gradients and normals both", P(S(gradients=[[0, 0]] * 4, normals=[[0, 0, 1]] * 4)), 422, ["not both"],
         "normals", None, None),
        ("a vertex with 2 channels among 1-channel values", P(S(values=[0, [1, 2], 2, 3])), 422,
         ["2 channels, expected 1"], "values[1]", None, None),
        ("17 channels", P(S(values=[[0] * 17] * 4)), 422, ["17 channels"], "values[0]", None, None),
        ("3 values for 4 vertices", P(S(values=[0, 1, 2])), 422, ["one per vertex"], "values", None, None),
        ("1-channel gradients on a 2-channel mesh", P(S(values=[[0, 0]] * 4, gradients=[[0, 0]] * 4)), 422,
         ["expected 2"], "gradients[0]", None, None),
        ("an unknown method name", P(S(method="bicubic")), 422, ["unknown method 'bicubic'"], "method", None, None),
        ("a field given twice", P(good[:-1] + b', "values": [0, 1, 2, 3]}'), 400, ["more than once"], "values", None,
         None),
        ("evaluate without points", P(SMALL, "/v1/evaluate"), 400, ["missing required field 'points'"], "points",
         None, None),
        ("a point with one coordinate", P(S(points=[[0.5, 0.5], [0.5]]), "/v1/evaluate"), 400, ["2 numbers"],
         "points[1]", None, None),
        ("render without viewport", P(SMALL, "/v1/render"), 400, ["missing required field 'viewport'"], "viewport",
         None, None),
        ("render viewport with x1 <= x0", P(S(viewport=with_(VP4, x1=-0.5)), "/v1/render"), 422, ["greater than"],
         "viewport.x1", None, None),
        ("render viewport with y1 == y0", P(S(viewport=with_(VP4, y1=0)), "/v1/render"), 422, ["greater than"],
         "viewport.y1", None, None),
        ("render width 0", P(S(viewport=with_(VP4, width=0)), "/v1/render"), 422, ["width"], "viewport.width", None,
         None),
        ("render an unknown format", P(S(viewport=VP4, format="jpeg"), "/v1/render"), 422, ["unknown format 'jpeg'"],
         "format", None, None),
        ("render png with 2 channels", P(S(values=[[0, 1]] * 4, viewport=VP4, format="png"), "/v1/render"), 422,
         ["1 or 3 channels", "has 2"], "format", None, None),
        ("render png16 with 2 channels", P(S(values=[[0, 1]] * 4, viewport=VP4, format="png16"), "/v1/render"), 422,
         ["1 or 3 channels"], "format", None, None),
        ("render exposure 100 stops", P(S(viewport=VP4, exposure=100), "/v1/render"), 422, ["out of range"],
         "exposure", None, None),
        ("render 2 background values for 1 channel", P(S(viewport=VP4, background=[0, 1]), "/v1/render"), 400,
         ["one per channel"], "background", None, None),
        ("a body not in UTF-8", P(good.replace(b'"values"', b'"v\xffalues"')), 400, ["not UTF-8"], "", None, None),
        ("a body over --max-body (sent in full)", lambda: raw_exchange(D, b"POST /v1/ordinates HTTP/1.1\r\nHost: t\r\n"
         b"Content-Type: application/json\r\nContent-Length: %d\r\n\r\n" % (MAX_BODY + 1) + b" " * (MAX_BODY + 1)),
         413, ["%d" % MAX_BODY], "", None, None),
        ("a chunked body past --max-body",
         lambda: raw_exchange(D, b"POST /v1/ordinates HTTP/1.1\r\nHost: t\r\nContent-Type: application/json\r\n"
                                 b"Transfer-Encoding: chunked\r\n\r\n" + (b"%x\r\n" % (600 << 10) + b" " * (600 << 10) +
                                                                          b"\r\n") * 2 + b"0\r\n\r\n"),
         413, ["larger than"], "", None, None),
        ("an image over --max-pixels", P(S(viewport=with_(VP4, width=1000, height=401)), "/v1/render"), 413,
         ["401000 pixels", "at most 400000"], "viewport", None, None),
        ("too many triangles", P(grid_mesh(32)), 413, ["2048 triangles", "at most 2000"], "triangles", None, None),
        ("too many vertices", P(many_verts), 413, ["3001 vertices", "at most 3000"], "vertices", None, None),
        ("too many points", P(S(points=[[0.5, 0.5]] * 20001), "/v1/evaluate"), 413, ["20001 points"], "points", None,
         None),
        ("Content-Type text/plain", P(good, headers={"Content-Type": "text/plain"}), 415, ["text/plain"], "", None,
         None),
        ("no Content-Type", P(good, headers={}), 415, ["without Content-Type"], "", None, None),
        ("charset other than UTF-8", P(good, headers={"Content-Type": "application/json; charset=iso-8859-1"}), 415,
         ["iso-8859-1"], "", None, None),
        ("Content-Encoding gzip", P(good, headers={"Content-Type": "application/json", "Content-Encoding": "gzip"}),
         415, ["gzip"], "", None, None),
        ("unknown route", lambda: get(D, "/v1/nothing-here"), 404, ["/v1/nothing-here"], "", None, None),
        ("unknown route (POST, almost a route)", P(good, "/v1/ordinate"), 404, ["/v1/ordinate"], "", None, None),
        ("GET /v1/ordinates", lambda: get(D, "/v1/ordinates"), 405, ["POST", "GET"], "", None, allow("POST")),
        ("POST /healthz", P(good, "/healthz"), 405, ["POST"], "", None, allow("GET, HEAD")),
        ("DELETE /v1/render", lambda: request(D, "DELETE", "/v1/render"), 405, ["DELETE"], "", None, allow("POST")),
        ("PUT /metrics", lambda: request(D, "PUT", "/metrics", body=b"x"), 405, ["PUT"], "", None,
         allow("GET, HEAD")),
    ]


def section_bad_input(D, S):
    section("5. bad input")
    cases = catalogue(D)
    check("the catalogue has at least 30 bad requests", len(cases) >= 30, str(len(cases)))
    for name, send, status, detail, path, any_error, extra in cases:
        try:
            r = send()
            errs = problem_errors(r, status, detail, path, any_error)
            if extra:
                e = extra(r)
                if e:
                    errs.insert(0, e)
        except Exception as e:
            errs = ["%r" % e]
        if not healthz_ok(D):
            errs.insert(0, "/healthz does not answer afterwards")
        check("%d for %s" % (status, name), not errs, "; ".join(errs))

    # Viewports narrower than a double's step per pixel (x1 - x0 subnormal): valid requests
    # that crashed the daemon before (pixels per unit overflow to infinity, 0 * infinity is
    # NaN, and a NaN became a column index). A fuzzer's find.
    for vp in ({"x0": 0, "y0": 0, "x1": 2.1e-319, "y1": 1, "width": 64, "height": 64},
               {"x0": 0, "y0": 0, "x1": 1, "y1": 3e-320, "width": 16, "height": 16},
               {"x0": 0, "y0": 0, "x1": 1e-310, "y1": 1e-310, "width": 9, "height": 9}):
        r = post(D, "/v1/render", with_(SMALL, viewport=vp, format="raw"))
        check("a viewport %g wide and %g high renders (200, the whole tile) and the daemon lives"
              % (vp["x1"], vp["y1"]), r.status == 200 and len(r.body) == 4 * vp["width"] * vp["height"]
              and healthz_ok(D), r.brief())

    # Only the headers, with a huge Content-Length: the 413 must come without the body.
    hdr = (b"POST /v1/render HTTP/1.1\r\nHost: t\r\nContent-Type: application/json\r\n"
           b"Content-Length: 10000000000000\r\n\r\n")
    try:
        s = socket.create_connection(("127.0.0.1", D.port), timeout=5)
        D.sent += 1
        t0 = time.time()
        s.sendall(hdr)
        r = http.client.HTTPResponse(s, method="POST")
        r.begin()
        body = r.read()
        resp = Resp(r.status, r.headers, body, time.time() - t0)
        s.close()
        audit("headers only", resp)
        errs = problem_errors(resp, 413, ["10000000000000", "%d" % MAX_BODY], "")
        if resp.elapsed > 2:
            errs.insert(0, "answered after %.2f s" % resp.elapsed)
    except Exception as e:
        errs = ["no answer without the body: %r" % e]
    check("413 from Content-Length alone (headers sent, body never): answered without reading it", not errs,
          "; ".join(errs))

    # A client that sends half its body and stalls, on the --connection-timeout 1, --threads 1 daemon.
    body = json.dumps(SMALL).encode()
    errs = []
    s = socket.create_connection(("127.0.0.1", S.port), timeout=10)
    t0 = time.time()
    s.sendall(b"POST /v1/ordinates HTTP/1.1\r\nHost: t\r\nContent-Type: application/json\r\nContent-Length: %d\r\n\r\n"
              % len(body) + body[:len(body) // 2])
    time.sleep(0.2)
    h0 = time.time()
    ok_h = healthz_ok(S)
    h_s = time.time() - h0
    if not ok_h or h_s > 1.0:
        errs.append("/healthz meanwhile: ok=%s in %.2f s" % (ok_h, h_s))
    got, how = b"", "open"
    s.settimeout(8)
    try:
        while True:
            chunk = s.recv(4096)
            if not chunk:
                how = "closed"
                break
            got += chunk
    except socket.timeout:
        how = "still open after %.1f s" % (time.time() - t0)
    except OSError as e:
        how = "reset (%s)" % e.__class__.__name__
    s.close()
    closed_after = time.time() - t0
    if how.startswith("still open") or closed_after > 5:
        errs.append("connection %s (%.2f s)" % (how, closed_after))
    if re.match(rb"HTTP/1\.[01] 2", got):
        errs.append("answered 2xx: %r" % got[:100])
    check("a half-sent body is cut off by --connection-timeout 1 (%s after %.2f s; /healthz meanwhile %.3f s)" % (
        how, closed_after, h_s), not errs, "; ".join(errs))

    # Past --request-timeout (0.02 s) while rendering: 503 /problems/timeout. 4000^2 (under the
    # default --max-pixels): 2000^2 took 31 ms here in all, too close to 0.02 s for a faster
    # machine; this takes 92-153 ms here (the cubic alone 67 ms), and the raster stops at the
    # deadline, not at the end.
    big = with_(SHADOW, viewport={"x0": -0.1, "y0": -0.1, "x1": 1.1, "y1": 1.1, "width": 4000, "height": 4000},
                format="raw")
    try:
        r = post(S, "/v1/render", big)
        errs = problem_errors(r, 503, ["time limit"], None)
    except Exception as e:
        errs = ["%r" % e]
    if not healthz_ok(S):
        errs.insert(0, "/healthz does not answer afterwards")
    check("503 /problems/timeout for a render past --request-timeout", not errs, "; ".join(errs))

    check("after the catalogue: both daemons alive and /healthz answers",
          D.alive() and S.alive() and healthz_ok(D) and healthz_ok(S), "alive %s %s" % (D.alive(), S.alive()))


# =========================================================================================
# 6. concurrency and memory
# =========================================================================================

class Item:
    def __init__(self, label, method, path, body=None, headers=None, kind="json", fmt=None):
        self.label, self.method, self.path, self.body, self.headers = label, method, path, body, headers or {}
        self.kind, self.fmt = kind, fmt
        self.ref = None  # (status, content type, normalized body)


def normalize(item, status, body):
    if item.kind == "json" and status == 200:
        return strip_timings(body)
    return body


def mixed_items():
    rng = random.Random(3)
    pts = [[rng.uniform(-0.1, 1.1), rng.uniform(-0.1, 1.1)] for _ in range(60)] + [[0.5, 0.75], [0.25, 0.5]]
    J = lambda d: json.dumps(d).encode()  # noqa: E731
    tile = {"x0": -0.05, "y0": 0.1, "x1": 1.05, "y1": 0.9, "width": 16, "height": 12}
    items = [
        Item("ordinates square", "POST", "/v1/ordinates", SQUARE_BYTES, JSON_H),
        Item("ordinates shadow", "POST", "/v1/ordinates", SHADOW_BYTES, JSON_H),
        Item("ordinates rgb", "POST", "/v1/ordinates", J(RGB), JSON_H),
        Item("evaluate shadow", "POST", "/v1/evaluate", J(with_(SHADOW, points=pts, with_gradients=True)), JSON_H),
        Item("evaluate rgb", "POST", "/v1/evaluate", J(with_(RGB, points=pts)), JSON_H),
        Item("evaluate square linear", "POST", "/v1/evaluate", J(with_(SQUARE, points=pts, method="linear")), JSON_H),
        Item("healthz", "GET", "/healthz", kind="plain"),
        Item("version", "GET", "/v1/version", kind="plain"),
        Item("400 not JSON", "POST", "/v1/evaluate", b"{nope", JSON_H, kind="problem"),
        Item("422 zero-area", "POST", "/v1/ordinates", J(with_(SMALL, vertices=[[0, 0], [1, 0], [2, 0], [0, 1]])),
             JSON_H, kind="problem"),
        Item("422 out of range", "POST", "/v1/render", J(with_(SMALL, triangles=[[0, 1, 9], [0, 2, 3]], viewport=tile)),
             JSON_H, kind="problem"),
        Item("422 png 2 channels", "POST", "/v1/render", J(with_(SMALL, values=[[0, 1]] * 4, viewport=tile,
                                                                   format="png")), JSON_H, kind="problem"),
        Item("404", "GET", "/v1/nope", kind="problem"),
        Item("405", "GET", "/v1/render", kind="problem"),
    ]
    for fmt in FORMATS:
        items.append(Item("render shadow %s" % fmt, "POST", "/v1/render", J(with_(SHADOW, viewport=tile, format=fmt)),
                          JSON_H, kind="image", fmt=fmt))
    for fmt in ("png", "exr-half", "tiff", "raw"):
        items.append(Item("render rgb %s" % fmt, "POST", "/v1/render",
                          J(with_(RGB, viewport=tile, format=fmt, background=[0.5, 0.25, 1])), JSON_H, kind="image",
                          fmt=fmt))
    items.append(Item("render accept exr", "POST", "/v1/render", J(with_(SHADOW, viewport=tile)),
                      dict(JSON_H, Accept="image/x-exr"), kind="image", fmt="exr"))
    return items, tile


def same_answer(item, status, ctype, body, tile):
    """None if (status, ctype, body) is the reference answer of item, else what differs."""
    rs, rc, rb = item.ref
    if status != rs or ctype != rc:
        return "%s: %d %s, expected %d %s" % (item.label, status, ctype, rs, rc)
    nb = normalize(item, status, body)
    if nb == rb:
        return None
    if item.kind == "image" and status == 200:
        nc = 3 if "rgb" in item.label else 1
        a = decode(body, item.fmt, tile["width"], tile["height"], nc)
        b = decode(rb, item.fmt, tile["width"], tile["height"], nc)
        if a.px.shape == b.px.shape and np.array_equal(a.px, b.px):
            return None
        return "%s: decoded pixels differ from the reference" % item.label
    return "%s: body differs: %r vs %r" % (item.label, (nb or body)[:120], rb[:120])


def load_worker(D, items, tile, k, n, out):
    rng = random.Random(100 + k)
    persistent = k % 2 == 1  # half the clients keep their connection alive
    conn, fails, kinds = None, [], {}
    order = [items[(k * 5 + i) % len(items)] for i in range(len(items))]  # every item at least once
    order += [rng.choice(items) for _ in range(n - len(order))]
    for item in order[:n]:
        try:
            if conn is None or not persistent:
                conn = http.client.HTTPConnection("127.0.0.1", D.port, timeout=60)
            with LOCK:
                D.sent += 1
            conn.request(item.method, item.path, body=item.body, headers=item.headers)
            r = conn.getresponse()
            body = r.read()
            resp = Resp(r.status, r.headers, body, 0)
            if r.will_close or not persistent:
                conn.close()
                conn = None
            audit(item.label, resp, is_api_json(item.method, item.path))
            err = same_answer(item, resp.status, resp.ctype(), body, tile)
        except Exception as e:
            err = "%s: %r" % (item.label, e)
            if conn is not None:
                conn.close()
            conn = None
        kinds[item.kind] = kinds.get(item.kind, 0) + 1
        if err:
            fails.append(err)
    if conn is not None:
        conn.close()
    out[k] = (fails, kinds)


def run_load(D, items, tile, nthreads, n):
    out = {}
    ths = [threading.Thread(target=load_worker, args=(D, items, tile, k, n, out)) for k in range(nthreads)]
    t0 = time.time()
    for t in ths:
        t.start()
    for t in ths:
        t.join(600)
    return out, time.time() - t0, sum(t.is_alive() for t in ths)


def section_concurrency(D):
    section("6. 8 clients x 200 mixed requests")
    items, tile = mixed_items()
    errs = []
    for it in items:  # the reference answers, one at a time
        r = request(D, it.method, it.path, body=it.body, headers=it.headers)
        it.ref = (r.status, r.ctype(), normalize(it, r.status, r.body))
        want = 200 if it.kind != "problem" else None
        if (want and r.status != want) or (it.kind == "problem" and r.status < 400) or it.ref[2] is None:
            errs.append("%s: %s" % (it.label, r.brief()))
    check("reference answers for %d kinds of request" % len(items), not errs, "; ".join(errs))
    warm, _, _ = run_load(D, items, tile, 8, 30)  # warm-up: every image format loaded, thread arenas made
    time.sleep(0.3)
    rss0 = D.rss_kb()
    out, secs, stuck = run_load(D, items, tile, 8, 200)
    time.sleep(0.3)
    rss1 = D.rss_kb()
    fails = [f for k in sorted(out) for f in out[k][0]]
    kinds = {}
    for k in out:
        for kind, c in out[k][1].items():
            kinds[kind] = kinds.get(kind, 0) + c
    total = sum(kinds.values())
    check("8 x 200 concurrent mixed requests (%d in %.1f s: %s) all answered as the reference" % (
        total, secs, ", ".join("%d %s" % (c, k) for k, c in sorted(kinds.items()))),
        not fails and not stuck and total == 1600 and len(out) == 8,
        "%d wrong, %d threads stuck: %s" % (len(fails), stuck, fails[:4]))
    wfails = [f for k in warm for f in warm[k][0]]
    check("warm-up round (8 x 30) answered as the reference", not wfails, str(wfails[:4]))
    if SAN:
        say("# skip memory assertion under sanitizers (ASan's quarantine inflates RSS): VmRSS %d kB after warm-up, "
            "%d kB after the load" % (rss0, rss1))
    else:
        check("VmRSS after the load within 10%% of after the warm-up (%d kB -> %d kB)" % (rss0, rss1),
              rss0 > 0 and abs(rss1 - rss0) <= 0.10 * rss0, "%+.1f%%" % (100.0 * (rss1 - rss0) / max(rss0, 1)))
    m, _ = settled_metrics(D)
    infl = next((m[k] for k in m if k[0] in IN_FLIGHT), None)
    check("in-flight gauge back to 1 (this request) after the load", infl == 1, str(infl))
    check("daemon alive and /healthz answers after the load", D.alive() and healthz_ok(D), "")


# =========================================================================================
# 7. graceful shutdown
# =========================================================================================

def section_shutdown():
    section("7. SIGTERM while a render is in flight")
    G = Daemon("graceful", "--shutdown-grace", "30", "--render-threads", "1", "--threads", "4")
    # 4000^2 (under the default --max-pixels): the render must still run ~0.3 s after it was
    # sent; the request takes ~0.8 s here (2500^2 took 0.56 s), and a much faster machine fails
    # loudly below ("proves nothing") rather than passing by luck
    vp = {"x0": -0.1, "y0": -0.1, "x1": 1.1, "y1": 1.1, "width": 4000, "height": 4000}
    path = os.path.join(TMP, "big.json")
    with open(path, "w") as f:
        json.dump(with_(SHADOW, viewport=vp, format="raw"), f)
    out = os.path.join(TMP, "big.raw")
    rc, _, err = run_cli("render", path, "-o", out)
    ref = np.fromfile(out, dtype="<f4").reshape(vp["height"], vp["width"]) if rc == 0 else None
    check("reference %dx%d raw from tocher render" % (vp["width"], vp["height"]), rc == 0, err[:200])
    # a keep-alive connection opened before the signal
    ka = http.client.HTTPConnection("127.0.0.1", G.port, timeout=120)
    ka.request("GET", "/healthz")
    r = ka.getresponse()
    r.read()
    ka_ok = r.status == 200 and not r.will_close
    res = {}
    sent = threading.Event()

    def slow():
        conn = http.client.HTTPConnection("127.0.0.1", G.port, timeout=120)
        try:
            with LOCK:
                G.sent += 1
            conn.request("POST", "/v1/render", json.dumps(with_(SHADOW, viewport=vp, format="exr")).encode(), JSON_H)
            sent.set()
            r = conn.getresponse()
            res["r"] = Resp(r.status, r.headers, r.read(), 0)
        except Exception as e:
            res["e"] = e
        finally:
            sent.set()
            conn.close()
        res["t"] = time.time()

    th = threading.Thread(target=slow)
    th.start()
    # Not by polling /metrics: a connection the busy pool thread accepted waits for the render.
    sent.wait(30)
    time.sleep(0.1)
    t_sig = time.time()
    G.proc.send_signal(signal.SIGTERM)

    def waiter():
        G.proc.wait()
        res["exit"] = time.time()

    wt = threading.Thread(target=waiter)
    wt.start()
    time.sleep(0.15)
    in_flight_then = th.is_alive()
    # a request on the connection opened before the signal (its answer is read below: if
    # this connection's pool thread is the one rendering, it comes after the render)
    ka_err = None
    try:
        ka.request("GET", "/healthz")
    except Exception as e:
        ka_err = e
    # a new connection: refused
    how, refused = "", False
    alive_at_connect = th.is_alive()
    try:
        s = socket.create_connection(("127.0.0.1", G.port), timeout=2)
    except ConnectionRefusedError:
        refused, how = True, "refused"
    except OSError as e:
        how = "connect failed: %r" % e
    else:
        try:
            s.settimeout(0.3)
            s.sendall(b"GET /healthz HTTP/1.1\r\nHost: t\r\n\r\n")
            got = s.recv(200)
            how = "connect() succeeded, then %s" % ("closed" if not got else "answered %r" % got[:40])
        except socket.timeout:
            how = "connect() succeeded and the request hangs unanswered (0.3 s)"
        except OSError as e:
            how = "connect() succeeded, then %r" % e
        s.close()
    check("after SIGTERM, a new connection is refused while a render is in flight", refused and alive_at_connect,
          how + (" while the render was still running" if alive_at_connect else "") if not refused else
          "the render had finished before the signal took effect; the check proves nothing")
    # ... gets 503 and Connection: close
    try:
        if ka_err:
            raise ka_err
        r = ka.getresponse()
        resp = Resp(r.status, r.headers, r.read(), 0)
        errs = [] if ka_ok else ["keep-alive not kept before the signal"]
        if resp.status != 503 or (resp.header("Connection") or "").lower() != "close" or \
                resp.ctype() != "application/problem+json":
            errs.append(resp.brief() + " Connection: %r" % resp.header("Connection"))
        check("after SIGTERM, a request on an open keep-alive connection gets 503 + Connection: close", not errs,
              "; ".join(errs))
        ptype = resp.json().get("type") if resp.ctype() == "application/problem+json" else None
        check("that 503's problem type is one api/openapi.yaml lists", ptype in PROBLEM_TYPES,
              "type %r is not in the contract's Problem.type enum %s" % (ptype, sorted(PROBLEM_TYPES)))
    except Exception as e:
        check("after SIGTERM, a request on an open keep-alive connection gets 503 + Connection: close", False, repr(e))
    ka.close()
    th.join(120)
    r = res.get("r")
    errs = []
    if r is None:
        errs.append("no answer: %r" % res.get("e"))
    elif r.status != 200:
        errs.append(r.brief())
    elif ref is not None:
        img = decode(r.body, "exr")
        y = img.px[:, :, img.names.index("Y")]
        a = img.px[:, :, img.names.index("A")]
        xs = np.array([vp["x0"] + (vp["x1"] - vp["x0"]) * ((i + 0.5) / vp["width"]) for i in range(vp["width"])])
        ys = np.array([vp["y1"] - (vp["y1"] - vp["y0"]) * ((j + 0.5) / vp["height"]) for j in range(vp["height"])])
        pts_in = ((ys >= 0) & (ys <= 1))[:, None] & ((xs >= 0) & (xs <= 1))[None, :]
        if not np.array_equal(y, ref):
            errs.append("%d pixels differ from tocher render" % int((y != ref).sum()))
        if not np.array_equal(a, np.where(pts_in, 1.0, 0.0).astype(np.float32)):
            errs.append("alpha differs from the closed unit square in %d pixels" % int((a != pts_in).sum()))
    check("the render in flight at SIGTERM completes: 200, exr == tocher render, alpha on the mesh (%.2f s after)" % (
        res.get("t", t_sig) - t_sig), not errs and in_flight_then, "; ".join(errs) if errs else
        "the render had finished before the signal took effect; the check proves nothing")
    wt.join(35)
    rc = G.proc.poll()
    t_exit = res.get("exit", time.time()) - t_sig
    log = G.stderr()
    check("daemon exits 0 within the grace period (%.2f s after SIGTERM), no sanitizer report" % t_exit,
          rc == 0 and t_exit < 30 and not SAN_RE.search(log), "rc %s; %s" % (rc, log[-500:]))
    check("its log says SIGTERM, the render, stopped",
          "SIGTERM" in log and "POST /v1/render 200" in log and log.rstrip().endswith("stopped"), log[-400:])


# =========================================================================================

def teardown(D, S):
    section("teardown")
    for d in (D, S):
        rc = d.stop()
        log = d.stderr()
        check("daemon %s: SIGTERM -> exit 0, no sanitizer report" % d.name, rc == 0 and not SAN_RE.search(log),
              "rc %s; %s" % (rc, "\n".join(log.splitlines()[-8:])))
    log = D.stderr().splitlines()
    reqs = [line for line in log if LOG_RE.match(line)]
    other = [line for line in log if not LOG_RE.match(line) and not line.startswith("tocherd: ")]
    check("main daemon logged one line per request (%d sent, %d lines)" % (D.sent, len(reqs)),
          len(reqs) == D.sent and not other, "unexpected lines %s" % other[:3])


def main():
    say("# %s against %s%s" % (os.path.basename(__file__), BUILD, " (sanitizers)" if SAN else ""))
    for exe in (TOCHERD, TOCHER):
        if not os.access(exe, os.X_OK):
            check("built", False, "%s is missing: make all" % exe)
            finish()
    D = Daemon("main", "--threads", "4", "--render-threads", "2", "--max-body", str(MAX_BODY),
               "--max-vertices", "3000", "--max-triangles", "2000", "--max-points", "20000",
               "--max-pixels", "400000")
    S = Daemon("strict", "--threads", "1", "--render-threads", "1", "--connection-timeout", "1",
               "--request-timeout", "0.02")
    steps = [("endpoints", lambda: section_basics(D)), ("images", lambda: section_images(D)),
             ("cli", lambda: section_cli(D)), ("threads", lambda: section_threads(D)),
             ("bad input", lambda: section_bad_input(D, S)), ("front-ends", lambda: section_frontend(D)),
             ("concurrency", lambda: section_concurrency(D)),
             ("shutdown", section_shutdown)]
    for name, fn in steps:
        t0 = time.time()
        try:
            fn()
        except Exception as e:
            import traceback
            check("section %s ran to its end" % name, False, "%r\n%s" % (e, traceback.format_exc()[-1500:]))
        if name == "endpoints":
            audit_report("section 1")
        say("# %s: %.1f s" % (name, time.time() - t0))
    audit_report("all sections")
    try:
        teardown(D, S)
    except Exception as e:
        check("teardown", False, repr(e))
    say("# total %.1f s" % (time.time() - T_START))
    finish()


if __name__ == "__main__":
    main()
