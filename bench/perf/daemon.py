#!/usr/bin/env python3
"""daemon.py — the daemon's side of `make bench`: wrk on loopback against a fresh tocherd, and what
the process costs (memory, start-up) with and without the image stack. Prints one JSON object.

    /usr/bin/python3 bench/perf/daemon.py BUILD_DIR [SECONDS]
"""
import http.client
import json
import os
import re
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else "build")
SECONDS = int(sys.argv[2]) if len(sys.argv) > 2 else 10
LUA = os.path.join(ROOT, "bench", "perf", "post.lua")
SMALL = os.path.join(ROOT, "api", "examples", "square-light.json")  # the 4-triangle scene


def status_kb(pid, field):
    with open("/proc/%d/status" % pid) as f:
        for line in f:
            if line.startswith(field + ":"):
                return int(line.split()[1])
    return None


def start_daemon(extra=()):
    proc = subprocess.Popen([os.path.join(BUILD, "tocherd"), "--listen", "127.0.0.1:0", *extra],
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
    line = proc.stdout.readline().decode()
    m = re.search(r"127\.0\.0\.1:(\d+)", line)
    if not m:
        raise SystemExit("tocherd did not start: %r" % line)
    return proc, int(m.group(1))


def post(port, path, body):
    c = http.client.HTTPConnection("127.0.0.1", port, timeout=60)
    c.request("POST", path, body=body, headers={"Content-Type": "application/json"})
    r = c.getresponse()
    data = r.read()
    c.close()
    return r.status, data


def wrk(port, path, body_file, threads, conns, seconds):
    env = dict(os.environ, TOCHER_BODY=body_file)
    out = subprocess.run(["wrk", "-t%d" % threads, "-c%d" % conns, "-d%ds" % seconds, "-s", LUA,
                          "http://127.0.0.1:%d%s" % (port, path)], env=env, capture_output=True, text=True,
                         timeout=seconds + 60).stdout
    m = re.search(r"^WRKJSON (.*)$", out, re.M)
    res = json.loads(m.group(1)) if m else {"error": out[-400:]}
    if m:
        res["rps"] = res["requests"] / (res["duration_us"] * 1e-6)
    res.update(threads=threads, connections=conns, path=path)
    return res


def cli_cost(args):
    """Wall time and peak RSS (kB) of one CLI run."""
    t0 = time.perf_counter()
    proc = subprocess.Popen([os.path.join(BUILD, "tocher"), *args], stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    _, status, ru = os.wait4(proc.pid, 0)
    return {"s": time.perf_counter() - t0, "peak_rss_kb": ru.ru_maxrss, "exit": os.waitstatus_to_exitcode(status)}


def main():
    res = {"seconds": SECONDS}
    proc, port = start_daemon()
    try:
        small = open(SMALL, "rb").read()
        assert post(port, "/v1/ordinates", small)[0] == 200
        res["rss_start_kb"] = status_kb(proc.pid, "VmRSS")
        res["wrk"] = [wrk(port, "/v1/ordinates", SMALL, 2, 16, SECONDS),
                      wrk(port, "/v1/ordinates", SMALL, 1, 1, max(3, SECONDS // 2))]
        res["rss_after_json_kb"] = status_kb(proc.pid, "VmRSS")
        res["hwm_after_json_kb"] = status_kb(proc.pid, "VmHWM")
        render = json.loads(small)
        render.update(viewport={"x0": 0, "y0": 0, "x1": 1, "y1": 1, "width": 64, "height": 64}, format="png")
        t0 = time.perf_counter()
        st, _ = post(port, "/v1/render", json.dumps(render).encode())
        res["first_png_s"] = time.perf_counter() - t0
        t0 = time.perf_counter()
        post(port, "/v1/render", json.dumps(render).encode())
        res["second_png_s"] = time.perf_counter() - t0
        res["rss_after_png_kb"] = status_kb(proc.pid, "VmRSS")
    finally:
        proc.terminate()
        proc.wait(timeout=30)
    # The CLI: a command that writes no image never loads OpenImageIO.
    tmp = os.path.join(BUILD, "perf")
    os.makedirs(tmp, exist_ok=True)
    view = os.path.join(tmp, "small-render.json")
    with open(view, "w") as f:
        json.dump(render, f)
    res["cli_ordinates"] = min((cli_cost(["ordinates", SMALL]) for _ in range(5)), key=lambda r: r["s"])
    res["cli_render_png"] = min((cli_cost(["render", view, "-o", os.path.join(tmp, "small.png")])
                                 for _ in range(3)), key=lambda r: r["s"])
    view_raw = os.path.join(tmp, "small-render-raw.json")
    with open(view_raw, "w") as f:
        json.dump(dict(render, format="raw"), f)
    res["cli_render_raw"] = min((cli_cost(["render", view_raw, "-o", os.path.join(tmp, "small.raw")])
                                 for _ in range(3)), key=lambda r: r["s"])
    json.dump(res, sys.stdout, indent=1)
    print()


if __name__ == "__main__":
    main()
