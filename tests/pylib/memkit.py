"""memkit.py — the render-memory scenarios of issue 14 (2.3), shared by the short form
(tests/endpoint/test_memory.py) and the full size (tests/torture/test_memory.py): a tiny
request asking for a large image, the daemon's peak RSS growth against the answer's size,
and the memory budget (--max-memory) between renders in flight."""
import json
import socket
import threading
import time

from tochertest import check

GROWTH_FACTOR, GROWTH_SLACK_MB = 1.3, 64.0  # the bound: peak growth <= 1.3 x answer + 64 MB


def tiny_request(nc, size, fmt):
    """One triangle covering the viewport, nc channels: a few hundred bytes asking for size^2 pixels."""
    vals = [[float(1 + c + v) for c in range(nc)] for v in range(3)] if nc > 1 else [1.0, 2.0, 3.0]
    return json.dumps({"vertices": [[0, 0], [2, 0], [0, 2]], "triangles": [[0, 1, 2]], "values": vals,
                       "viewport": {"x0": 0, "y0": 0, "x1": 1, "y1": 1, "width": size, "height": size},
                       "format": fmt}, separators=(",", ":")).encode()


def post(port, path, body, timeout=300):
    """One POST on its own connection: (status, headers dict, body bytes), the body read to its end."""
    s = socket.create_connection(("127.0.0.1", port), timeout=timeout)
    s.sendall(b"POST %s HTTP/1.1\r\nHost: t\r\nContent-Type: application/json\r\nConnection: close\r\n"
              b"Content-Length: %d\r\n\r\n" % (path.encode(), len(body)) + body)
    chunks = []
    while True:
        b = s.recv(1 << 20)
        if not b:
            break
        chunks.append(b)
    s.close()
    out = b"".join(chunks)
    head, _, payload = out.partition(b"\r\n\r\n")
    lines = head.decode("latin-1").split("\r\n")
    status = int(lines[0].split()[1]) if lines and len(lines[0].split()) > 1 else 0
    headers = {k.strip().lower(): v.strip() for k, _, v in (l.partition(":") for l in lines[1:])}
    return status, headers, payload


def reset_peak(d):
    """VmHWM back to the current RSS (Linux clear_refs 5); returns VmRSS in kB."""
    with open("/proc/%d/clear_refs" % d.pid, "w") as f:
        f.write("5")
    return d.status("VmRSS")


def warm_up(d):
    """One small render in every format: the image plugin (about 125 MB) and the worker
    threads' arenas are loaded before anything is measured."""
    for fmt, nc in (("png", 3), ("png16", 1), ("exr", 4), ("exr-half", 2), ("tiff", 4), ("raw", 16)):
        post(d.port, "/v1/render", tiny_request(nc, 256, fmt))


def growth(d, label, nc, size, fmt):
    """Renders once; checks 200 and peak RSS growth <= 1.3 x answer + 64 MB."""
    body = tiny_request(nc, size, fmt)
    rss0 = reset_peak(d)
    t0 = time.time()
    status, _, payload = post(d.port, "/v1/render", body)
    took = time.time() - t0
    grown = (d.status("VmHWM") - rss0) / 1024.0
    answer = len(payload) / 1048576.0
    bound = GROWTH_FACTOR * answer + GROWTH_SLACK_MB
    ok = check("%s: %d-byte request, %d channels %d^2 %s -> %d, %.1f MiB answer in %.1f s" %
               (label, len(body), nc, size, fmt, status, answer, took), status == 200, payload[:300])
    check("... peak RSS growth %.1f MiB <= 1.3 x answer + 64 = %.1f MiB" % (grown, bound), ok and grown <= bound,
          "the tile is held more than once (tile, encoded copy, response copy)")
    return grown, answer


def reserved(d):
    status, _, payload = get(d.port, "/metrics")
    for line in payload.decode().splitlines():
        if line.startswith("tocher_memory_reserved_bytes "):
            return int(float(line.split()[1]))
    return -1


def get(port, path):
    s = socket.create_connection(("127.0.0.1", port), timeout=30)
    s.sendall(b"GET %s HTTP/1.1\r\nHost: t\r\nConnection: close\r\n\r\n" % path.encode())
    out = b""
    while True:
        b = s.recv(1 << 16)
        if not b:
            break
        out += b
    s.close()
    head, _, payload = out.partition(b"\r\n\r\n")
    return int(head.split()[1]), head, payload


def budget(d, budget_mb, nc, size):
    """Two renders whose peaks each fit the budget but not together, sent at once: one 200,
    the other 200 (if the first was done) or 503 busy with Retry-After, never both in memory;
    peak RSS growth <= budget + 64 MB; one render larger than the budget alone: 413 naming the
    viewport; the reservation falls back to 0 once the answers are sent."""
    body = tiny_request(nc, size, "raw")
    rss0 = reset_peak(d)
    results = [None, None]

    def one(k):
        results[k] = post(d.port, "/v1/render", body)
    threads = [threading.Thread(target=one, args=(k,)) for k in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    grown = (d.status("VmHWM") - rss0) / 1024.0
    statuses = sorted(r[0] for r in results)
    busy = [r for r in results if r[0] == 503]
    answer = size * size * nc * 4 / 1048576.0
    check("budget %d MiB: two %.0f MiB renders at once -> %s" % (budget_mb, answer, statuses),
          statuses in ([200, 503], [200, 200]) and 200 in statuses, str([r[2][:200] for r in results]))
    if busy:
        doc = json.loads(busy[0][2])
        check("... the refused one: 503 busy with Retry-After, saying why",
              busy[0][1].get("retry-after") == "1" and doc.get("type") == "/problems/busy"
              and "retry" in doc.get("detail", ""), str(busy[0][1]) + str(doc))
    check("... peak RSS growth %.0f MiB <= budget + 64 MiB" % grown, grown <= budget_mb + 64,
          "two answers were held at once past the budget")
    big = tiny_request(nc, size * 2, "raw")
    status, _, payload = post(d.port, "/v1/render", big)
    doc = json.loads(payload) if status != 200 else {}
    check("... a render larger than the whole budget: 413 naming the viewport",
          status == 413 and doc.get("path") == "viewport" and "MiB" in doc.get("detail", ""), payload[:300])
    end = time.time() + 5
    while reserved(d) != 0 and time.time() < end:
        time.sleep(0.05)
    check("... reserved memory back to 0 once the answers are sent (%d)" % reserved(d), reserved(d) == 0)
