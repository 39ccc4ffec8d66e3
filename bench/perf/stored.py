#!/usr/bin/env python3
"""stored.py — the stored-mesh side of `make bench` (issue 15): on a 131k-triangle grid, a 256² PNG
tile of a stored mesh against POST /v1/render of the same viewport with the whole body (medians and
their ratio); then 1000 GETs of 256² PNG tiles of a stored 10k-triangle mesh by 8 keep-alive
clients (wrk, for SECONDS: at the 2000/s target that is several thousand GETs, at least 1000), with the
daemon's defaults (the encoded-tile cache answers a tile again without rendering it) and, for the
rendering itself, with --tile-cache-memory 0 (PNG and raw). Prints one JSON object, and the figures on stderr.

    /usr/bin/python3 bench/perf/stored.py BUILD_DIR
"""
import http.client
import json
import os
import re
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "bench", "perf"))
import meshes  # noqa: E402  (the data and triangulations of the other benchmarks)

BUILD = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else "build")
LUA = os.path.join(ROOT, "bench", "perf", "tiles.lua")


def grid_request(n):
    """meshes.py's n×n grid (2n² triangles) and data, as a request with values only."""
    pts = meshes.grid_points(n)
    tri = meshes.triangulate(pts, 2 * n * n)
    v, _, _ = meshes.f(pts[:, 0], pts[:, 1])
    return json.dumps({"vertices": pts.tolist(), "triangles": tri.tolist(), "values": v.tolist()}).encode()


def start(*flags):
    proc = subprocess.Popen([os.path.join(BUILD, "tocherd"), "--listen", "127.0.0.1:0", *flags], stdout=subprocess.PIPE,
                            stderr=subprocess.DEVNULL)
    m = re.search(r"127\.0\.0\.1:(\d+)", proc.stdout.readline().decode())
    if not m:
        raise SystemExit("tocherd did not start")
    return proc, int(m.group(1))


def timed(conn, method, path, body=None):
    h = {"Content-Type": "application/json"} if body is not None else {}
    t0 = time.perf_counter()
    conn.request(method, path, body=body, headers=h)
    r = conn.getresponse()
    data = r.read()
    dt = time.perf_counter() - t0
    if r.status not in (200, 201):
        raise SystemExit("%s %s: %d %r" % (method, path, r.status, data[:200]))
    return dt, data


def viewport(bbox, z, x, y, size):
    x0, y0, x1, y1 = bbox
    s = max(x1 - x0, y1 - y0)
    t = s / float(1 << z)
    return {"x0": x0 + x * t, "y0": y0 + s - (y + 1) * t, "x1": x0 + (x + 1) * t, "y1": y0 + s - y * t,
            "width": size, "height": size}


def tile_vs_render(port, n=256):
    body = grid_request(n)
    c = http.client.HTTPConnection("127.0.0.1", port, timeout=300)
    post_s, desc = timed(c, "POST", "/v1/meshes", body)
    desc = json.loads(desc)
    base = body[:-1]  # the request without its closing brace: the viewport is appended
    tiles, renders = [], []
    for k, (z, x, y) in enumerate([(0, 0, 0), (1, 0, 1), (1, 1, 0), (2, 1, 2), (2, 3, 3), (3, 2, 5), (3, 7, 0)]):
        ts, tile = timed(c, "GET", "/v1/meshes/%s/tiles/%d/%d/%d.png" % (desc["id"], z, x, y))
        extra = json.dumps({"viewport": viewport(desc["bbox"], z, x, y, 256), "format": "png"})[1:]
        rs, img = timed(c, "POST", "/v1/render", base + b"," + extra.encode())
        if img != tile:
            raise SystemExit("tile %d/%d/%d differs from /v1/render" % (z, x, y))
        if k:  # the first of each loads the image library
            tiles.append(ts), renders.append(rs)
    c.close()
    med_t, med_r = statistics.median(tiles), statistics.median(renders)
    return {"triangles": desc["triangles"], "body_bytes": len(body), "post_s": post_s, "tile_median_s": med_t,
            "render_median_s": med_r, "ratio": med_r / med_t, "samples": len(tiles)}


def many_tiles(port, n=71, clients=8, seconds=5, z=3, fmt="png"):
    body = grid_request(n)
    c = http.client.HTTPConnection("127.0.0.1", port, timeout=300)
    _, desc = timed(c, "POST", "/v1/meshes", body)
    desc = json.loads(desc)
    timed(c, "GET", "/v1/meshes/%s/tiles/0/0/0.png" % desc["id"])  # the image library loaded
    c.close()
    env = dict(os.environ, TOCHER_TILE_BASE="/v1/meshes/%s/tiles" % desc["id"], TOCHER_TILE_Z=str(z),
               TOCHER_TILE_FORMAT=fmt)
    out = subprocess.run(["wrk", "-t%d" % clients, "-c%d" % clients, "-d%ds" % seconds, "-s", LUA,
                          "http://127.0.0.1:%d/" % port], env=env, capture_output=True, text=True, timeout=120).stdout
    m = re.search(r"^WRKJSON (.*)$", out, re.M)
    if not m:
        raise SystemExit("wrk: %s" % out[-400:])
    res = json.loads(m.group(1))
    res.update(triangles=desc["triangles"], clients=clients, zoom=z, format=fmt,
               tiles_per_s=res["requests"] / (res["duration_us"] * 1e-6))
    return res


def main():
    res = {"date": time.strftime("%Y-%m-%d", time.gmtime()), "cores": os.cpu_count()}
    proc, port = start()  # defaults: the encoded-tile cache on (each tile below is rendered once, then kept)
    try:
        res.update(tile_vs_render=tile_vs_render(port), many_tiles=many_tiles(port))
    finally:
        proc.terminate()
        proc.wait(30)
    proc, port = start("--tile-cache-memory", "0")  # every GET renders and encodes its tile
    try:
        res.update(many_tiles_cold=many_tiles(port), many_raw_tiles=many_tiles(port, fmt="raw"))
    finally:
        proc.terminate()
        proc.wait(30)
    a, b = res["tile_vs_render"], res["many_tiles"]
    print("stored: %d triangles (%.1f MB body): 256² PNG tile of the stored mesh %.1f ms, POST /v1/render of it "
          "%.0f ms (medians of %d): %.0f× (target ≥ 20×)" % (a["triangles"], a["body_bytes"] / 1e6,
                                                             a["tile_median_s"] * 1e3, a["render_median_s"] * 1e3,
                                                             a["samples"], a["ratio"]), file=sys.stderr)
    print("stored: %d GETs in %.1f s of 256² PNG tiles, %d-triangle mesh, %d keep-alive clients: %.0f tiles/s, p50 %.1f ms, "
          "p99 %.1f ms, %d errors (target ≥ 2000/s on 2 cores)" %
          (b["requests"], b["duration_us"] * 1e-6, b["triangles"], b["clients"], b["tiles_per_s"], b["p50_us"] / 1e3, b["p99_us"] / 1e3,
           b["errors"] + b["non2xx"]), file=sys.stderr)
    c, d = res["many_raw_tiles"], res["many_tiles_cold"]
    print("stored: without the tile cache (every GET renders): PNG %.0f tiles/s, raw float32 %.0f tiles/s" %
          (d["tiles_per_s"], c["tiles_per_s"]), file=sys.stderr)
    print(json.dumps(res, indent=1))


if __name__ == "__main__":
    main()
