#!/usr/bin/env python3
"""redis.py — the Redis mesh store in `make bench` (issue 16): what a stored mesh costs in Redis
(canonical bytes, stored bytes after zstd, MEMORY USAGE of the key) for grids of 10k, 131k and
524k triangles, and what a cache miss adds when the bytes come from Redis (fetch, decompress,
build) for 10k and 131k, against a cached tile and the in-memory store; and the per-request
existence check (EXPIRE, which renews the TTL) a cached tile pays. A redis-server without
persistence and the daemons are started here on loopback. Prints one JSON object, and the figures
on stderr.

    /usr/bin/python3 bench/perf/redis.py BUILD_DIR [--splice docs/performance.md]

--splice writes the section "Stored meshes in Redis" (report.py's section_redis) into that page
in place, for a run of this script alone.
"""
import http.client
import json
import os
import re
import socket
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "bench", "perf"))
import meshes  # noqa: E402  (the data and triangulations of the other benchmarks)
from stored import grid_request  # noqa: E402

BUILD = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 and not sys.argv[1].startswith("-") else "build")
TILE = "/v1/meshes/%s/tiles/1/0/1.raw?size=64"  # a small render: the build dominates a miss
PROCS = []


def free_port():
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port


def resp(port, *args):
    """One Redis command over a raw socket (RESP); bulk strings as bytes."""
    with socket.create_connection(("127.0.0.1", port), timeout=30) as s:
        out = b"*%d\r\n" % len(args)
        for a in args:
            a = str(a).encode()
            out += b"$%d\r\n%s\r\n" % (len(a), a)
        s.sendall(out)
        f = s.makefile("rb")
        line = f.readline()
        if line[:1] == b":":
            return int(line[1:-2])
        if line[:1] == b"$":
            n = int(line[1:-2])
            return None if n < 0 else f.read(n + 2)[:-2]
        if line[:1] == b"-":
            raise RuntimeError(line.decode())
        return line[1:-2].decode()


def zstd_content_size(v):
    """The decompressed size a zstd frame header states (RFC 8878 3.1.1.1), or len(v) if not zstd."""
    if v[:4] != b"\x28\xb5\x2f\xfd":
        return len(v)
    d = v[4]
    fcs_flag, single, did_flag = d >> 6, (d >> 5) & 1, d & 3
    pos = 5 + (0 if single else 1) + (0, 1, 2, 4)[did_flag]
    size = ((1 if single else 0), 2, 4, 8)[fcs_flag]
    n = int.from_bytes(v[pos:pos + size], "little")
    return n + 256 if size == 2 else n


def start_redis():
    port = free_port()
    p = subprocess.Popen(["redis-server", "--port", str(port), "--bind", "127.0.0.1", "--save", "", "--appendonly",
                          "no"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    PROCS.append(p)
    for _ in range(200):
        try:
            if resp(port, "PING") == "PONG":
                return port
        except OSError:
            time.sleep(0.05)
    raise SystemExit("redis-server did not start")


def start_daemon(*flags):
    p = subprocess.Popen([os.path.join(BUILD, "tocherd"), "--listen", "127.0.0.1:0", *flags],
                         stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
    PROCS.append(p)
    m = re.search(r"127\.0\.0\.1:(\d+)", p.stdout.readline().decode())
    if not m:
        raise SystemExit("tocherd did not start")
    return int(m.group(1))


def call(port, method, path, body=None, conn=None):
    c = conn or http.client.HTTPConnection("127.0.0.1", port, timeout=600)
    t0 = time.perf_counter()
    c.request(method, path, body=body, headers={"Content-Type": "application/json"} if body else {})
    r = c.getresponse()
    data = r.read()
    dt = time.perf_counter() - t0
    if r.status not in (200, 201):
        raise SystemExit("%s %s: %d %r" % (method, path, r.status, data[:200]))
    return dt, data, outside_phases(r.headers.get("Server-Timing", ""))


def outside_phases(timing):
    """Seconds of a request's total (Server-Timing) outside its phases (parse, validate, build,
    evaluate, encode): for a stored-mesh tile, the store's calls (the existence check, and on a
    miss the fetch and decompression) and the routing around them."""
    d = {k: float(v) for k, v in re.findall(r"(\w+);dur=([0-9.]+)", timing)}
    return (d.get("total", 0) - sum(v for k, v in d.items() if k != "total")) * 1e-3


def interleaved_medians(ports, mids, rounds):
    """Median tile latency on each daemon, one GET each per round in a rotating order: the load
    of a shared machine falls on all of them alike."""
    conns = [http.client.HTTPConnection("127.0.0.1", p, timeout=600) for p in ports]
    for c, p, mid in zip(conns, ports, mids):
        call(p, "GET", TILE % mid, conn=c)  # the first use: connection, image library, cache warm or not
    times, outside = [[] for _ in ports], [[] for _ in ports]
    for r in range(rounds):
        for k in range(len(ports)):
            i = (k + r) % len(ports)
            dt, _, out = call(ports[i], "GET", TILE % mids[i], conn=conns[i])
            times[i].append(dt), outside[i].append(out)
    for c in conns:
        c.close()
    return [(statistics.median(t), statistics.median(o)) for t, o in zip(times, outside)]


def cost_in_redis(rport, dport, n):
    body = grid_request(n)
    post_s, desc, _ = call(dport, "POST", "/v1/meshes", body)
    desc = json.loads(desc)
    key = "tocher:mesh:" + desc["id"]
    value = resp(rport, "GET", key)
    return {"triangles": desc["triangles"], "body_bytes": len(body), "canonical_bytes": zstd_content_size(value),
            "stored_bytes": len(value), "compressed": value[:4] == b"\x28\xb5\x2f\xfd",
            "memory_usage": resp(rport, "MEMORY", "USAGE", key), "post_s": post_s, "id": desc["id"], "body": body}


def miss_cost(rport, n, runs):
    """Median tile latency: miss via Redis (--cache-memory 1: every use fetches and builds), miss via
    the memory store, interleaved; then hit with each store, interleaved (300 rounds)."""
    body = grid_request(n)
    out = {"runs": runs}
    redis = ("--store", "redis://127.0.0.1:%d" % rport)
    for names, flags, rounds in ((("redis_miss", "memory_miss"), (redis + ("--cache-memory", "1"),
                                                                  ("--cache-memory", "1")), runs),
                                 (("redis_hit", "memory_hit"), (redis, ()), 300)):
        ports = [start_daemon(*f) for f in flags]
        descs = [json.loads(call(p, "POST", "/v1/meshes", body)[1]) for p in ports]
        for name, (t, o) in zip(names, interleaved_medians(ports, [d["id"] for d in descs], rounds)):
            out[name], out[name + "_outside"] = t, o
        out["triangles"] = descs[0]["triangles"]
        for p in PROCS[-2:]:
            p.terminate()
            p.wait(30)
    out["miss_added_s"] = out["redis_miss"] - out["redis_hit"]
    # The store's own share, from Server-Timing (total minus the phases): not the difference of two
    # noisy totals on a shared machine, where a build's variance dwarfs a fetch.
    out["redis_part_s"] = out["redis_miss_outside"] - out["memory_miss_outside"]
    out["check_per_hit_s"] = out["redis_hit_outside"] - out["memory_hit_outside"]
    return out


def main():
    rport = start_redis()
    try:
        dport = start_daemon("--store", "redis://127.0.0.1:%d" % rport, "--cache-memory", "1")
        sizes = []
        for n in (71, 256, 512):
            s = cost_in_redis(rport, dport, n)
            s.pop("body"), s.pop("id")
            sizes.append(s)
        used = resp(rport, "INFO", "memory").decode()
        m = re.search(r"used_memory:(\d+)", used)
        res = {"date": time.strftime("%Y-%m-%d", time.gmtime()), "cores": os.cpu_count(),
               "loadavg": os.getloadavg()[0],
               "redis_version": re.search(r"redis_version:(\S+)", resp(rport, "INFO", "server").decode()).group(1),
               "sizes": sizes, "used_memory_after": int(m.group(1)) if m else None,
               "miss": [miss_cost(rport, 71, 21), miss_cost(rport, 256, 7)]}
    finally:
        for p in PROCS:
            if p.poll() is None:
                p.terminate()
            p.wait(30)
    for s in res["sizes"]:
        print("redis: %d triangles: body %.2f MB, canonical %.2f MB, stored %.2f MB (%s, %.1f×), MEMORY USAGE %.2f MB, "
              "POST %.2f s" % (s["triangles"], s["body_bytes"] / 1e6, s["canonical_bytes"] / 1e6, s["stored_bytes"] / 1e6,
                               "zstd" if s["compressed"] else "as is", s["canonical_bytes"] / s["stored_bytes"],
                               s["memory_usage"] / 1e6, s["post_s"]), file=sys.stderr)
    for m in res["miss"]:
        print("redis: %d triangles, 64² raw tile: miss via Redis %.1f ms, via memory %.1f ms, hit %.2f ms (memory "
              "store %.2f ms): a miss adds %.1f ms, of which Redis (fetch + decompress) %.1f ms; the check per hit "
              "%.3f ms" % (m["triangles"], m["redis_miss"] * 1e3, m["memory_miss"] * 1e3, m["redis_hit"] * 1e3,
                           m["memory_hit"] * 1e3, m["miss_added_s"] * 1e3, m["redis_part_s"] * 1e3,
                           m["check_per_hit_s"] * 1e3), file=sys.stderr)
    print(json.dumps(res, indent=1))
    if "--splice" in sys.argv:
        splice(sys.argv[sys.argv.index("--splice") + 1], res)


def splice(page, res):
    """Replaces (or appends before "## Work only what a scene needs") the Redis section of page."""
    import report  # noqa: E402  (bench/perf/report.py)
    with open(page) as f:
        doc = f.read()
    head = "## Stored meshes in Redis"
    section = "%s\n\n%s\n\n" % (head, report.section_redis(res))
    if head in doc:
        a = doc.index(head)
        b = doc.find("\n## ", a + len(head))
        doc = doc[:a] + section + (doc[b + 1:] if b >= 0 else "")
    else:
        at = doc.find("## Work only what a scene needs")
        doc = doc[:at] + section + doc[at:] if at >= 0 else doc + "\n" + section
    with open(page, "w") as f:
        f.write(doc)


if __name__ == "__main__":
    main()
