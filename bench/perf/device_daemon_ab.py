"""device_daemon_ab.py — a whole render request on the lent 16-core machine, two daemons side by side.

    python3 DIR/device_daemon_ab.py [ROUNDS]      (JSON lines on stdout)

DIR (the script's own folder, carried to the machine) holds tocherd and base/tocherd built on the
development machine, lib/ with the shared libraries they need there (libmicrohttpd and its TLS
stack, libcjson, libhiredis, libzstd: `ldd build/tocherd`), and bench/perf/meshes.py's grid64.json.
Each daemon runs with --render-threads 16 and 1 (THREADS=2,1 in the environment: other counts,
as on the 2-core development machine), grid64 POSTed to each once as a stored mesh;
each round renders /v1/meshes/{id}/render raw at 4096² and 1024² on every daemon in turn. A line:
the wall time as the client sees it (64 MiB through loopback for 4096²) and the daemon's
Server-Timing (evaluate: the raster with its band buffers; encode: the answer's bytes)."""
import http.client, json, os, socket, subprocess, sys, time
D = os.path.dirname(os.path.abspath(__file__))  # the carried folder
env = dict(os.environ, LD_LIBRARY_PATH=os.path.join(D, "lib"))
def port():
    s = socket.socket(); s.bind(("127.0.0.1", 0)); p = s.getsockname()[1]; s.close(); return p
def start(binary, threads):
    p = port()
    proc = subprocess.Popen([binary, "--listen", "127.0.0.1:%d" % p, "--render-threads", str(threads)],
                            env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    for _ in range(100):
        try:
            c = http.client.HTTPConnection("127.0.0.1", p); c.request("GET", "/healthz"); c.getresponse().read(); break
        except OSError:
            time.sleep(0.05)
    return proc, p
mesh = open(os.path.join(D, "grid64.json"), "rb").read()
daemons = {}
for name, b in (("base", os.path.join(D, "base", "tocherd")), ("new", os.path.join(D, "tocherd"))):
    for th in [int(t) for t in os.environ.get("THREADS", "16,1").split(",")]:
        proc, p = start(b, th)
        c = http.client.HTTPConnection("127.0.0.1", p)
        c.request("POST", "/v1/meshes", mesh, {"Content-Type": "application/json"})
        r = c.getresponse(); body = r.read()
        daemons[(name, th)] = (proc, p, json.loads(body)["id"])
out = []
for rnd in range(int(sys.argv[1]) if len(sys.argv) > 1 else 5):
    for size in (4096, 1024):
        for key, (proc, p, mid) in daemons.items():
            req = json.dumps({"viewport": {"x0": 0, "y0": 0, "x1": 1, "y1": 1, "width": size, "height": size},
                              "format": "raw"}).encode()
            c = http.client.HTTPConnection("127.0.0.1", p)
            t0 = time.perf_counter()
            c.request("POST", "/v1/meshes/%s/render" % mid, req, {"Content-Type": "application/json"})
            r = c.getresponse(); data = r.read()
            ms = (time.perf_counter() - t0) * 1e3
            rec = {"round": rnd, "build": key[0], "threads": key[1], "size": size, "status": r.status, "bytes": len(data),
                   "wall_ms": round(ms, 2), "server_timing": r.getheader("Server-Timing")}
            out.append(rec); print(json.dumps(rec), flush=True)
for proc, p, mid in daemons.values():
    proc.terminate(); proc.wait()
