#!/usr/bin/env python3
"""test_viewer.py — the browser test of GET /viewer: real headless Chromium, driven over the
DevTools protocol (--remote-debugging-pipe: NUL-separated JSON on fds 3 and 4, stdlib only),
shows a mesh stored in a real tocherd from BUILD_DIR:

    /usr/bin/python3 tests/endpoint/test_viewer.py BUILD_DIR

The mesh is a grey-scale "shadow": value 0 in a block at the lower left of a 2 x 1 rectangle,
1 elsewhere, so a tile drawn in the wrong place, flipped or not at all shows in the pixels.
It checks that the page loads with no script error; that it asks for tiles of the mesh and
each is answered 200; that the screenshot is not blank and is dark where the reconstruction
(/v1/evaluate, and the tile the daemon serves) is dark and bright where it is bright, at the
places the page's own view transform puts those points; that the readout under a hovered
point reports that point and /v1/evaluate's value and gradient there; that overlay and exposure
ask for the tiles they should and change the image; that wheel zoom, drag pan and a two-finger
pinch move the view as far as they should; and that a file dropped on the page (or chosen) is
POSTed and the method switch stores and shows the same data with another method.
One "ok"/"FAIL" line per check, then "N passed, N failed" (exit 1 on any failure). Without
Chromium it installs Debian's package (as root or with sudo -n) and only if that fails says
"skip" and counts nothing.
"""
import atexit
import base64
import fcntl
import http.client
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import threading
import time
import zlib

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tests", "pylib"))
from tochertest import SAN_RE, Tocherd, check, finish, say, tally  # noqa: E402

BUILD = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build"))
TMP = tempfile.mkdtemp(prefix="tocher-viewer.")
atexit.register(shutil.rmtree, TMP, True)  # registered first: runs last, after the browser is gone
RUNNING = []  # kill functions of what this script started, for the watchdog
DEADLINE = time.time() + 60  # the whole script; each wait below has its own shorter one
W, H = 1000, 700             # the browser's viewport, device scale factor 1
DARK, BRIGHT = 48, 200       # 8-bit screenshot levels: v = 0 shows as 0, v = 1 as 255 (sRGB, exposure 0)


def _watchdog():
    check("watchdog", False, "the script ran past 120 s; killing the browser and the daemon")
    print(tally(), flush=True)
    for kill in RUNNING:
        kill()
    shutil.rmtree(TMP, True)
    os._exit(1)


def chromium_path():
    for name in ("chromium", "chromium-browser"):
        p = shutil.which(name)
        if p:
            return p
    return None


def ensure_chromium():
    """Chromium's path, installing Debian's package if it is missing (make deps does it too)."""
    p = chromium_path()
    if p:
        return p
    sudo = [] if os.geteuid() == 0 else ["sudo", "-n"]
    if sudo and not shutil.which("sudo"):
        return None
    say("# chromium is missing: installing Debian's package")
    env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
    install = ["apt-get", "install", "-y", "-qq", "--no-install-recommends", "chromium"]
    for cmd in (["apt-get", "update", "-qq"], install):
        if subprocess.run(sudo + cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL).returncode:
            return None
    return chromium_path()


# ---- the mesh: a 2 x 1 rectangle, 9 x 5 vertices; 0 where x <= 0.75 and y <= 0.5, else 1 ----

def shadow_mesh():
    vs = [[0.25 * i, 0.25 * j] for j in range(5) for i in range(9)]
    tris = []
    for j in range(4):
        for i in range(8):
            a, b, c, d = 9 * j + i, 9 * j + i + 1, 9 * (j + 1) + i + 1, 9 * (j + 1) + i
            tris += [[a, b, c], [a, c, d]]
    vals = [0.0 if x <= 0.75 and y <= 0.5 else 1.0 for x, y in vs]
    return {"vertices": vs, "triangles": tris, "values": vals, "method": "clough-tocher"}


DARK_PT, BRIGHT_PTS, HOVER_PT = (0.2, 0.15), [(0.2, 0.85), (1.7, 0.15)], (0.9, 0.3)

# ---- HTTP to the daemon ----


class Daemon:
    def __init__(self, port):
        self.port = port

    def request(self, method, path, body=None):
        c = http.client.HTTPConnection("127.0.0.1", self.port, timeout=30)
        headers = {"Content-Type": "application/json"} if body is not None else {}
        c.request(method, path, body=None if body is None else json.dumps(body), headers=headers)
        r = c.getresponse()
        data = r.read()
        c.close()
        return r.status, r.getheader("Content-Type") or "", data

    def json(self, method, path, body=None):
        status, _, data = self.request(method, path, body)
        try:
            return status, json.loads(data)
        except ValueError:
            return status, {"raw": data[:300].decode("utf-8", "replace")}


# ---- PNG decoding (8-bit grey, grey+alpha, RGB, RGBA; what Chromium and tocherd write) ----

def decode_png(data):
    """(width, height, channels, rows): rows[y] a bytes of width*channels samples."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    pos, idat, hdr = 8, b"", None
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        chunk = data[pos + 8:pos + 8 + n]
        pos += 12 + n
        if kind == b"IHDR":
            hdr = struct.unpack(">IIBBBBB", chunk)
        elif kind == b"IDAT":
            idat += chunk
        elif kind == b"IEND":
            break
    w, h, depth, ctype, _, _, interlace = hdr
    ch = {0: 1, 2: 3, 4: 2, 6: 4}[ctype]
    assert depth == 8 and interlace == 0, "PNG depth %d interlace %d" % (depth, interlace)
    raw, stride, rows, prev = zlib.decompress(idat), w * ch, [], bytearray(w * ch)
    for y in range(h):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - ch] if i >= ch else 0
            b, c = prev[i], prev[i - ch] if i >= ch else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(line))
        prev = line
    return w, h, ch, rows


def pixel(img, x, y):
    w, h, ch, rows = img
    return tuple(rows[y][x * ch:(x + 1) * ch])


# ---- Chromium over the DevTools pipe ----


class Browser:
    """One headless Chromium; call() sends a command and waits for its answer, events are kept."""

    def __init__(self, path):
        self.profile = os.path.join(TMP, "profile")
        to_child, self.out = os.pipe()   # the browser reads commands on its fd 3
        self.inp, from_child = os.pipe()  # and writes answers and events on its fd 4
        # Its ends moved above 9 first, so that the dup2 onto 3 and 4 below cannot overwrite one another.
        to_child, from_child = (self._high(fd) for fd in (to_child, from_child))
        args = [path, "--headless", "--remote-debugging-pipe", "--user-data-dir=" + self.profile,
                "--no-first-run", "--no-default-browser-check", "--disable-gpu", "--disable-extensions",
                "--disable-background-networking", "--disable-component-update", "--disable-sync",
                "--hide-scrollbars", "--mute-audio", "--disable-dev-shm-usage", "--window-size=%d,%d" % (W, H)]
        if os.geteuid() == 0:
            args.append("--no-sandbox")  # Chromium's sandbox refuses to run as root (containers, CI)
        # The pipe ends go to fds 3 and 4 of the browser, where --remote-debugging-pipe expects them
        # (a small Python launcher: dash cannot redirect from fds above 9).
        launch = ("import os, sys; os.dup2(int(sys.argv[1]), 3); os.dup2(int(sys.argv[2]), 4); "
                  "os.execv(sys.argv[3], sys.argv[3:])")
        self.log = open(os.path.join(TMP, "chromium.log"), "wb")
        argv = [sys.executable, "-c", launch, str(to_child), str(from_child)] + args + ["about:blank"]
        self.proc = subprocess.Popen(argv, pass_fds=(to_child, from_child), stdin=subprocess.DEVNULL, stdout=self.log,
                                     stderr=self.log)
        os.close(to_child)
        os.close(from_child)
        self.next_id, self.answers, self.events = 1, {}, []
        self.cond = threading.Condition()
        threading.Thread(target=self._read, daemon=True).start()

    @staticmethod
    def _high(fd):
        high = fcntl.fcntl(fd, fcntl.F_DUPFD_CLOEXEC, 10)
        os.close(fd)
        return high

    def _read(self):
        buf = b""
        while True:
            try:
                chunk = os.read(self.inp, 1 << 16)
            except OSError:
                chunk = b""
            if not chunk:
                with self.cond:
                    self.answers[None] = "closed"
                    self.cond.notify_all()
                return
            buf += chunk
            while b"\0" in buf:
                msg, buf = buf.split(b"\0", 1)
                m = json.loads(msg)
                with self.cond:
                    if "id" in m:
                        self.answers[m["id"]] = m
                    else:
                        self.events.append(m)
                    self.cond.notify_all()

    def call(self, method, params=None, session=None, timeout=15):
        with self.cond:
            i = self.next_id
            self.next_id += 1
        msg = {"id": i, "method": method, "params": params or {}}
        if session:
            msg["sessionId"] = session
        os.write(self.out, json.dumps(msg).encode() + b"\0")
        end = time.time() + timeout
        with self.cond:
            while i not in self.answers:
                if None in self.answers:
                    raise RuntimeError("chromium closed the pipe during %s (see %s)" % (method, self.log.name))
                if not self.cond.wait(max(0.0, end - time.time())) and time.time() >= end:
                    raise RuntimeError("no answer to %s in %g s" % (method, timeout))
            m = self.answers.pop(i)
        if "error" in m:
            raise RuntimeError("%s: %s" % (method, m["error"]))
        return m.get("result", {})

    def events_of(self, method):
        with self.cond:
            return [e["params"] for e in self.events if e.get("method") == method]

    def close(self):
        if self.proc.poll() is None:
            try:
                self.call("Browser.close", timeout=5)
                self.proc.wait(5)
            except (RuntimeError, OSError, subprocess.TimeoutExpired):
                pass
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait(5)
        for fd in (self.out, self.inp):
            try:
                os.close(fd)
            except OSError:
                pass


class Page:
    def __init__(self, browser):
        self.b = browser
        target = browser.call("Target.createTarget", {"url": "about:blank"})["targetId"]
        self.s = browser.call("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
        for domain in ("Page", "Runtime", "Network"):
            self.call(domain + ".enable")
        self.call("Emulation.setDeviceMetricsOverride",
                  {"width": W, "height": H, "deviceScaleFactor": 1, "mobile": False})

    def call(self, method, params=None, timeout=15):
        return self.b.call(method, params, self.s, timeout)

    def js(self, expr):
        r = self.call("Runtime.evaluate", {"expression": expr, "returnByValue": True, "awaitPromise": True})
        if "exceptionDetails" in r:
            raise RuntimeError("%s: %s" % (expr, r["exceptionDetails"].get("text")))
        return r["result"].get("value")

    def state(self):
        # None until the whole page is parsed: polled right after Page.navigate, the parser may have
        # made the canvas but not yet #info or #status (a CI run failed on that once).
        return self.js("(() => { if (document.readyState === 'loading') return null;"
                       " const c = document.getElementById('canvas'), i = document.getElementById('info'),"
                       " s = document.getElementById('status'); if (!c || !i || !s) return null; const d = c.dataset;"
                       " return {view: d.view ? JSON.parse(d.view) : null, pending: +d.pending, loaded: +d.loaded,"
                       " failed: +d.failed, tiles: +d.tiles, mesh: i.dataset.id || null,"
                       " status: s.textContent}; })()")

    def wait(self, what, ok, timeout=15):
        """Polls state() until ok(state) or the deadline: the last state, or None on time-out."""
        end = min(time.time() + timeout, DEADLINE)
        st = None
        while time.time() < end:
            st = self.state()  # None until the page is there
            if st is not None and ok(st):
                return st
            time.sleep(0.05)
        check(what, False, "not within %g s; last page state %s" % (timeout, st))
        return None

    def settled(self, what, ok=lambda st: True, timeout=15):
        """Waits until every tile on screen is drawn (none loading, none failed) and ok(state)."""
        return self.wait(what, lambda st: st["view"] is not None and st["tiles"] > 0 and st["pending"] == 0
                         and ok(st), timeout)

    def canvas_rect(self):
        return self.js("(() => { const r = document.getElementById('canvas').getBoundingClientRect();"
                       " return [r.left, r.top, r.width, r.height]; })()")

    def screenshot(self):
        return decode_png(base64.b64decode(self.call("Page.captureScreenshot", {"format": "png"})["data"]))


def to_screen(rect, view, wx, wy):
    """The page's transform (its data-view): the CSS pixel where world point (wx, wy) is drawn."""
    left, top, w, h = rect
    return left + w / 2 + (wx - view["cx"]) * view["scale"], top + h / 2 - (wy - view["cy"]) * view["scale"]


TILE_RE = re.compile(r"/v1/meshes/([A-Za-z0-9_-]+)/tiles/(\d+)/(\d+)/(\d+)\.png\?(.*)$")


def tile_requests(page):
    """{requestId: (url, mesh id, z, x, y, query, status or None)} of every tile the page asked for."""
    got = {}
    for e in page.b.events_of("Network.requestWillBeSent"):
        m = TILE_RE.search(e["request"]["url"])
        if m:
            got[e["requestId"]] = [e["request"]["url"], m.group(1), int(m.group(2)), int(m.group(3)), int(m.group(4)),
                                   m.group(5), None]
    for e in page.b.events_of("Network.responseReceived"):
        if e["requestId"] in got:
            got[e["requestId"]][6] = e["response"]["status"]
    return got


def tile_requests_once(page, ok, timeout=10):
    """tile_requests(page) once ok(it) holds, or the last one after timeout seconds. Chromium sends
    its Network events apart from the page's script: the page may have drawn a tile before its
    responseReceived reaches this client (a run failed on that), so a check of them waits."""
    end = min(time.time() + timeout, DEADLINE)
    while True:
        reqs = tile_requests(page)
        if ok(reqs) or time.time() >= end:
            return reqs
        time.sleep(0.05)


def close_to(a, b):
    if isinstance(a, list) or isinstance(b, list):
        return isinstance(a, list) and isinstance(b, list) and len(a) == len(b) and all(map(close_to, a, b))
    if a is None or b is None:
        return a is b
    return abs(a - b) <= 1e-12 * (1 + abs(b))


def main():
    path = ensure_chromium()
    if not path:
        say("skip test_viewer.py: Chromium is not installed and could not be (apt-get install chromium, "
            "as root or with sudo); nothing was tested")
        finish()
    wd = threading.Timer(120, _watchdog)  # after the install: apt-get may take longer
    wd.daemon = True
    wd.start()
    d = Tocherd(os.path.join(BUILD, "tocherd"), os.path.join(TMP, "tocherd.stderr"))
    atexit.register(d.kill)
    RUNNING.append(d.kill)
    api = Daemon(d.port)
    mesh = shadow_mesh()

    # The fixture's premise, from the stateless API: dark and bright where the checks expect.
    status, ref = api.json("POST", "/v1/evaluate", dict(mesh, points=[DARK_PT] + BRIGHT_PTS))
    check("the shadow mesh evaluates (/v1/evaluate)", status == 200, "%s %s" % (status, ref))
    if status != 200:
        finish()
    check("the reference is dark at %s, bright at %s" % (DARK_PT, BRIGHT_PTS),
          ref["values"][0] < 0.02 and all(v > 0.95 for v in ref["values"][1:]), ref["values"])

    status, page_html_type, html = api.request("GET", "/viewer")
    check("GET /viewer: 200 text/html", status == 200 and page_html_type == "text/html; charset=utf-8"
          and b"<canvas id=\"canvas\"" in html, "%s %s" % (status, page_html_type))
    c = http.client.HTTPConnection("127.0.0.1", d.port, timeout=30)
    c.request("HEAD", "/viewer")
    r = c.getresponse()
    check("HEAD /viewer: 200, the page's length, no body, Cache-Control no-cache",
          r.status == 200 and r.read() == b"" and r.getheader("Content-Length") == str(len(html))
          and r.getheader("Cache-Control") == "no-cache", "%s %s" % (r.status, r.getheaders()))
    c.close()
    check("the page names no other host (no CDN, no external fetch)",
          not re.search(rb"(?:src|href)\s*=\s*[\"']?(?:https?:)?//|fetch\(\s*[\"'`]https?:", html))

    status, info = api.json("POST", "/v1/meshes", mesh)
    if not check("POST /v1/meshes stores the mesh", status in (200, 201) and "id" in info, "%s %s" % (status, info)):
        say("# the viewer needs the /v1/meshes routes; nothing more can be checked")
        finish()
    mid = info["id"]

    browser = Browser(path)
    atexit.register(browser.close)
    RUNNING.insert(0, browser.proc.kill)
    page = Page(browser)
    base = "http://127.0.0.1:%d" % d.port
    page.call("Page.navigate", {"url": base + "/viewer?mesh=" + mid})

    st = page.settled("the page draws the mesh's tiles", lambda st: st["mesh"] == mid)
    if not st:
        finish()
    errors = browser.events_of("Runtime.exceptionThrown")
    check("no script error on the page", not errors, errors[:1])
    text = page.js("document.getElementById('info').textContent")
    check("#info shows the mesh's id, triangle count and bbox",
          mid in text and "triangles%d" % info["triangles"] in text
          and "[0, 0] – [2, 1]" in text, text)
    nwarn = page.js("document.getElementById('warnings').dataset.count")
    check("#warnings lists the mesh's %d warnings" % len(info.get("warnings", [])),
          nwarn == str(len(info.get("warnings", []))), "%s vs %s" % (nwarn, info))
    check("the method switch says it needs the JSON (opened by id)",
          page.js("document.getElementById('method').disabled") and
          "JSON file" in page.js("document.getElementById('method-note').textContent"))

    z = st["view"]["z"]
    # Answered ones only: a tile that left the screen before its answer is cancelled (no status).
    answered = lambda reqs: [r for r in reqs.values() if r[1] == mid and r[2] == z and r[6] is not None]
    reqs = tile_requests_once(page, lambda reqs: len(answered(reqs)) >= st["tiles"])
    mine = answered(reqs)
    check("the page asked for the tiles on screen (%d at zoom level %d), each answered 200" % (st["tiles"], z),
          len(mine) >= st["tiles"] and all(r[6] == 200 for r in mine) and all("size=256" in r[5] for r in mine),
          [(r[0], r[6]) for r in reqs.values()][:6])

    # The screenshot: where the page's transform puts the dark point, the canvas is dark; bright points bright.
    shot, rect = page.screenshot(), page.canvas_rect()
    left, top, cw, ch = (int(round(v)) for v in rect)
    grid = [pixel(shot, x, y)[:3] for y in range(top + 5, top + ch - 5, 7) for x in range(left + 5, left + cw - 5, 7)]
    dark = sum(max(p) < DARK for p in grid) / len(grid)
    bright = sum(min(p) > BRIGHT for p in grid) / len(grid)
    check("the screenshot is not blank: %.0f%% dark, %.0f%% bright pixels" % (100 * dark, 100 * bright),
          dark > 0.02 and bright > 0.2 and len(set(grid)) > 3, "%d distinct colours" % len(set(grid)))
    sx, sy = to_screen(rect, st["view"], *DARK_PT)
    p = pixel(shot, int(sx), int(sy))
    check("dark at the dark point %s (screen %.0f, %.0f): %s" % (DARK_PT, sx, sy, p[:3]), max(p[:3]) < DARK)
    for pt in BRIGHT_PTS:
        sx, sy = to_screen(rect, st["view"], *pt)
        p = pixel(shot, int(sx), int(sy))
        check("bright at %s (screen %.0f, %.0f): %s" % (pt, sx, sy, p[:3]), min(p[:3]) > BRIGHT)

    # The tile the daemon serves is dark there too (the pixel the screenshot is compared with).
    s, t = 2.0, 2.0 / 2 ** z
    tx, ty = int(DARK_PT[0] / t), int((s - DARK_PT[1]) / t)
    status, ctype, png = api.request("GET", "/v1/meshes/%s/tiles/%d/%d/%d.png?size=256" % (mid, z, tx, ty))
    if check("GET the tile under the dark point", status == 200 and ctype == "image/png", "%s %s" % (status, ctype)):
        tile = decode_png(png)
        px, py = int((DARK_PT[0] - tx * t) / t * 256), int(((s - DARK_PT[1]) - ty * t) / t * 256)
        check("the reference tile is dark there", max(pixel(tile, px, py)[:1]) < DARK, pixel(tile, px, py))

    # Hover: the readout names the point under the pointer and /v1/evaluate's value and gradient there.
    sx, sy = to_screen(rect, st["view"], *HOVER_PT)
    page.call("Input.dispatchMouseEvent", {"type": "mouseMoved", "x": sx, "y": sy})
    tol = 1.0 / st["view"]["scale"]  # one pixel: the browser may round the pointer's position

    def near(ro):
        return "x" in ro and max(abs(float(ro["x"]) - HOVER_PT[0]), abs(float(ro["y"]) - HOVER_PT[1])) <= tol

    end, ro = min(time.time() + 10, DEADLINE), None
    while time.time() < end:
        ro = page.js("Object.assign({text: document.getElementById('readout').textContent},"
                     " document.getElementById('readout').dataset)")
        if near(ro):
            break
        time.sleep(0.05)
    if check("the readout reports the point under the pointer, %s within one pixel (%g)" % (HOVER_PT, tol),
             ro is not None and near(ro), ro):
        hx, hy = float(ro["x"]), float(ro["y"])
        status, ev = api.json("POST", "/v1/evaluate", dict(mesh, points=[[hx, hy]], with_gradients=True))
        value, grad = json.loads(ro["value"]), json.loads(ro["gradient"])
        check("its value and gradient are /v1/evaluate's there: %s, %s" % (value, grad),
              status == 200 and close_to(value, ev["values"][0]) and close_to(grad, ev["gradients"][0]),
              "%s %s" % (status, ev))
        check("the readout text shows them", "value" in ro["text"] and "gradient" in ro["text"], ro["text"])
        ev_calls = [e for e in browser.events_of("Network.requestWillBeSent")
                    if e["request"]["url"].endswith("/v1/meshes/%s/evaluate" % mid)]
        check("through POST /v1/meshes/{id}/evaluate", ev_calls and ev_calls[0]["request"]["method"] == "POST",
              len(ev_calls))

    # Overlay and exposure: the tiles are asked again with those parameters, and the image changes.
    page.js("document.getElementById('overlay').click()")
    st2 = page.settled("overlay on: the tiles redrawn", lambda st2: st2["loaded"] >= st["loaded"] + st2["tiles"])
    if st2:
        overlaid = lambda reqs: [r for r in reqs.values() if "overlay=true" in r[5] and r[6] is not None]
        over = overlaid(tile_requests_once(page, overlaid))
        shot2 = page.screenshot()
        changed = sum(pixel(shot, x, y) != pixel(shot2, x, y) for y in range(top, top + ch, 3)
                      for x in range(left, left + cw, 3))
        check("overlay=true tiles answered 200 and drawn (%d pixels of 1 in 9 changed)" % changed,
              over and all(r[6] == 200 for r in over) and changed > 50, [(r[0], r[6]) for r in over][:3])
    page.js("(() => { const e = document.getElementById('exposure'); e.value = '-2';"
            " e.dispatchEvent(new Event('input')); })()")
    st3 = page.settled("exposure -2: the tiles redrawn", lambda st: any(
        "exposure=-2&" in r[5] and r[6] == 200 for r in tile_requests(page).values()))
    if st3:
        sx, sy = to_screen(rect, st3["view"], *BRIGHT_PTS[1])
        p = pixel(page.screenshot(), int(sx), int(sy))
        check("exposure -2 dims the bright point: %s" % (p[:3],), 100 < max(p[:3]) < 160)  # sRGB(0.25) = 137

    # Zoom (wheel) and pan (drag): a finer level is asked for, and the view moves with the pointer.
    cx, cy = left + cw / 2, top + ch / 2
    page.call("Input.dispatchMouseEvent", {"type": "mouseWheel", "x": cx, "y": cy, "deltaX": 0, "deltaY": -700})
    st4 = page.settled("wheel zoom: a finer level drawn", lambda st: st["view"]["z"] > z)
    if st4:
        z4 = st4["view"]["z"]
        finer = lambda reqs: any(r[2] == z4 and r[6] == 200 for r in reqs.values())
        check("wheel zoom asks for zoom level %d tiles" % z4, finer(tile_requests_once(page, finer)))
        drag = (("mousePressed", cx), ("mouseMoved", cx + 60), ("mouseMoved", cx + 120), ("mouseReleased", cx + 120))
        for kind, x in drag:
            page.call("Input.dispatchMouseEvent", {"type": kind, "x": x, "y": cy, "button": "left", "clickCount": 1,
                                                   "buttons": 0 if kind == "mouseReleased" else 1})
        st5 = page.settled("drag: the view pans", lambda st: st["view"]["cx"] != st4["view"]["cx"])
        if st5:
            moved = (st4["view"]["cx"] - st5["view"]["cx"]) * st5["view"]["scale"]
            check("a 120-pixel drag pans 120 pixels (%.1f)" % moved, abs(moved - 120) < 0.5)

    # Pinch: two fingers from 100 to 200 pixels apart zoom 2x about their midpoint.
    page.call("Emulation.setTouchEmulationEnabled", {"enabled": True, "maxTouchPoints": 2})
    before = page.state()["view"]
    touch = [("touchStart", 50)] + [("touchMove", 50 + 10 * k) for k in range(1, 6)]
    for kind, half in touch:
        page.call("Input.dispatchTouchEvent", {"type": kind, "touchPoints": [
            {"x": cx - half, "y": cy, "id": 1}, {"x": cx + half, "y": cy, "id": 2}]})
    page.call("Input.dispatchTouchEvent", {"type": "touchEnd", "touchPoints": []})
    st8 = page.settled("pinch: the view zooms", lambda st: st["view"]["scale"] > before["scale"] * 1.5)
    if st8:
        v = st8["view"]
        drift = max(abs(v["cx"] - before["cx"]), abs(v["cy"] - before["cy"])) * v["scale"]
        check("a pinch from 100 to 200 pixels zooms x%.3f, its midpoint kept (moved %.2f px)"
              % (v["scale"] / before["scale"], drift), abs(v["scale"] / before["scale"] - 2) < 1e-3 and drift < 1)
    page.call("Emulation.setTouchEmulationEnabled", {"enabled": False})

    # A file dropped on the page: POSTed (a render request's file as its mesh: same data, same id);
    # then the method switch stores "linear"; then a file chosen with the file input is POSTed too.
    dropped = os.path.join(TMP, "shadow-render.json")
    with open(dropped, "w") as f:
        json.dump(dict(mesh, viewport={"x0": 0, "y0": 0, "x1": 1, "y1": 1, "width": 8, "height": 8}), f)
    data = {"items": [], "files": [dropped], "dragOperationsMask": 1}
    for kind in ("dragEnter", "dragOver", "drop"):
        page.call("Input.dispatchDragEvent", {"type": kind, "x": cx, "y": cy, "data": data})
    st6 = page.wait("the dropped file is POSTed and shown",
                    lambda st: not page.js("document.getElementById('method').disabled"))
    if st6:
        check("a dropped render request opens as its mesh (same id)", st6["mesh"] == mid, st6)
        page.js("(() => { const m = document.getElementById('method'); m.value = 'linear';"
                " m.dispatchEvent(new Event('change')); })()")
        st7 = page.settled("the method switch shows another mesh", lambda st: st["mesh"] not in (None, st6["mesh"]))
        if st7:
            lid = st7["mesh"]
            status, linfo = api.json("GET", "/v1/meshes/" + lid)
            check("it is the same data with method linear", status == 200 and linfo.get("method") == "linear"
                  and linfo.get("triangles") == info["triangles"], "%s %s" % (status, linfo))
            of_lid = lambda reqs: any(r[1] == lid and r[6] == 200 for r in reqs.values())
            check("its tiles are asked and answered", of_lid(tile_requests_once(page, of_lid)))
            check("the address bar names it", page.js("location.search") == "?mesh=" + lid,
                  page.js("location.search"))
            chosen = os.path.join(TMP, "shadow-ps.json")
            with open(chosen, "w") as f:
                json.dump(dict(mesh, method="powell-sabin"), f)
            obj = page.call("Runtime.evaluate", {"expression": "document.getElementById('file')"})["result"]
            page.call("DOM.setFileInputFiles", {"files": [chosen], "objectId": obj["objectId"]})
            st8 = page.settled("the chosen file is POSTed and shown",
                               lambda st: st["mesh"] not in (None, mid, lid))
            if st8:
                check("it shows as powell-sabin", page.js("document.getElementById('method').value") == "powell-sabin"
                      and "powell-sabin" in page.js("document.getElementById('info').textContent"))
    errors = browser.events_of("Runtime.exceptionThrown")
    check("still no script error", not errors, errors[:1])
    browser.close()
    rc = d.stop()
    check("tocherd exits 0 on SIGTERM, no sanitizer report", rc == 0 and not SAN_RE.search(d.stderr()),
          "exit %s; %s" % (rc, d.stderr()[-400:]))
    finish()


if __name__ == "__main__":
    try:
        main()
    except (RuntimeError, OSError, KeyError, ValueError, TypeError) as e:  # counted, not a traceback without a tally
        check("the browser session", False, "%s: %s" % (type(e).__name__, e))
        finish()
