#!/usr/bin/env python3
"""report.py — writes docs/performance.md from one `make bench` run: the figures of peers.py
(scipy, matplotlib), bench_perf (tocher) and daemon.py (tocherd under wrk), as ratios.

    /usr/bin/python3 bench/perf/report.py OUTDIR docs/performance.md

Every number in the document comes from OUTDIR's files of this run; the prose around the tables
only reads them (nothing here is a measured figure typed in by hand).
"""
import datetime
import json
import os
import re
import sys

TILE_PX = 1024 * 1024


def load(outdir, name):
    with open(os.path.join(outdir, name)) as f:
        return json.load(f)


def si(x, unit=""):
    """3 significant digits with k/M/G."""
    if x is None:
        return "–"
    for div, p in ((1e9, "G"), (1e6, "M"), (1e3, "k")):
        if abs(x) >= div:
            return "%.3g %s%s" % (x / div, p, unit)
    return "%.3g %s" % (x, unit) if unit else "%.3g" % x


def sec(x):
    if x is None:
        return "–"
    if x >= 1:
        return "%.2f s" % x
    if x >= 1e-3:
        return "%.3g ms" % (x * 1e3)
    return "%.3g µs" % (x * 1e6)


def side_note(rounds, d):
    """How a sidebyside.py ratio was measured, and its spread."""
    return "median of %d alternating rounds, each side its best of three; %.1f–%.1f×" % (
        rounds, d["ratio_min"], d["ratio_max"])


def ratio(a, b):
    """a / b as '12.3×', or '–'."""
    if a is None or b is None or b == 0:
        return "–"
    r = a / b
    return ("%.0f×" if r >= 100 else "%.1f×" if r >= 10 else "%.2f×") % r


def table(head, rows):
    out = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(out)


class Run:
    def __init__(self, outdir):
        self.peers = load(outdir, "peers.json")
        self.toch = load(outdir, "tocher.json")
        self.daemon = load(outdir, "daemon.json")
        self.stored = load(outdir, "stored.json") if os.path.exists(os.path.join(outdir, "stored.json")) else None
        self.redis = load(outdir, "redis.json") if os.path.exists(os.path.join(outdir, "redis.json")) else None
        self.cluster = load(outdir, "cluster.json") if os.path.exists(os.path.join(outdir, "cluster.json")) else None
        self.names = [n for n in self.toch["meshes"] if n in self.peers["meshes"]]
        self.scaling = {size: load(outdir, "scaling%d.json" % size) for size in (1024, 4096)
                        if os.path.exists(os.path.join(outdir, "scaling%d.json" % size))}
        try:
            with open(os.path.join(outdir, "validate.txt")) as f:
                self.validate = f.read()
        except OSError:
            self.validate = None
        self.whole = load(outdir, "whole.json") if os.path.exists(os.path.join(outdir, "whole.json")) else None
        side = (load(outdir, "sidebyside.json")
                if os.path.exists(os.path.join(outdir, "sidebyside.json")) else {})
        self.tileratio = side.get("tile")
        self.side_scattered = side.get("scattered", {})
        self.side_rounds = side.get("rounds")
        self.numfmt = load(outdir, "numfmt.json") if os.path.exists(os.path.join(outdir, "numfmt.json")) else None
        try:
            with open(os.path.join(outdir, "lscpu.txt")) as f:
                self.cpu = next((l.split(":", 1)[1].strip() for l in f if l.startswith("Model name")), "?")
        except OSError:
            self.cpu = "?"

    def t(self, m):
        return self.toch["meshes"][m]

    def p(self, m):
        return self.peers["meshes"][m]

    # ---- derived figures ----
    def build(self, m):
        t, p = self.t(m), self.p(m)
        return {
            "tocher_given": t["mesh_s"] + t["ordinates_s"],
            "tocher_est": t["mesh_noderiv_s"] + t["ordinates_noderiv_s"],
            "scipy_points": p["ct_build_points_s"],
            "scipy_tri": p["ct_build_tri_s"] + p["ct_transform_s"],
            "scipy_grad": p["ct_build_grad_s"] + p["ct_transform_s"],
            "mpl": p["mpl_cubic_build_s"] + p["mpl_trifinder_s"],
        }

    def scattered(self, m):
        t, p = self.t(m), self.p(m)
        n = self.toch["scattered"]
        return {"tocher": n / t["eval_scattered_s"], "tocher_grad": n / t["eval_scattered_grad_s"],
                "scipy": p["ct_eval_scattered_pps"], "mpl_cubic": p["mpl_cubic_scattered_pps"],
                "mpl_linear": p["mpl_linear_scattered_pps"]}

    def tile(self, m):
        t, p = self.t(m), self.p(m)
        return {"render1": TILE_PX / t["render_1t_s"], "render2": TILE_PX / t["render_2t_s"],
                "points": TILE_PX / t["eval_tile_points_s"], "scipy": p["ct_eval_tile_pps"],
                "mpl_cubic": p["mpl_cubic_tile_pps"], "mpl_linear": p["mpl_linear_tile_pps"]}


def section_build(r):
    rows = []
    for m in r.names:
        b, t = r.build(m), r.t(m)
        nt = t["triangles"]
        rows.append([m, nt, sec(b["tocher_est"]), "%.0f ns" % (b["tocher_est"] / nt * 1e9), sec(b["tocher_given"]),
                     sec(b["scipy_points"]), sec(b["scipy_tri"]), sec(b["scipy_grad"]), sec(b["mpl"]),
                     ratio(b["scipy_points"], b["tocher_est"]), ratio(b["scipy_tri"], b["tocher_est"]),
                     ratio(b["scipy_grad"], b["tocher_given"])])
    return table(["mesh", "triangles", "tocher, planes estimated", "per triangle", "tocher, gradients given",
                  "scipy from points", "scipy from Delaunay", "scipy, grad set", "mpl cubic + trifinder",
                  "scipy points / tocher", "scipy Delaunay / tocher", "scipy grad / tocher given"], rows)


def section_eval(r):
    rows = []
    for m in r.names:
        s = r.scattered(m)
        rows.append([m, si(s["tocher"], "/s"), si(s["tocher_grad"], "/s"), si(s["scipy"], "/s"),
                     si(s["mpl_cubic"], "/s"), si(s["mpl_linear"], "/s"), ratio(s["tocher"], s["scipy"]),
                     ratio(s["tocher"], s["mpl_cubic"])])
    return table(["mesh", "tocher values", "tocher + gradients", "scipy", "mpl cubic", "mpl linear",
                  "tocher / scipy", "tocher / mpl cubic"], rows)


def section_tile(r):
    rows = []
    for m in r.names:
        s = r.tile(m)
        rows.append([m, si(s["render1"], "px/s"), si(s["render2"], "px/s"), si(s["points"], "/s"),
                     si(s["scipy"], "/s"), si(s["mpl_cubic"], "/s"), si(s["mpl_linear"], "/s"),
                     ratio(s["render1"], s["scipy"]), ratio(s["render2"], s["scipy"])])
    return table(["mesh", "tocher render, 1 thread", "2 threads", "tocher eval of the centres", "scipy",
                  "mpl cubic", "mpl linear", "render 1t / scipy", "render 2t / scipy"], rows)


DEVICE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "device")


def device_figures():
    """The thread-scaling run on the lent 16-core machine (bench/perf/device.sh, committed under
    bench/perf/device/): {name: json}, the machine's model and its date; {} when absent."""
    if not os.path.isdir(DEVICE):
        return {}
    out = {}
    for name in ("tile1024", "tile4096", "build524k", "build524k_nothp", "scipy_tile"):
        path = os.path.join(DEVICE, name + ".json")
        rounds = sorted(f for f in os.listdir(DEVICE) if re.fullmatch(re.escape(name) + r"_r\d+\.json", f))
        if rounds:
            out[name] = best_of_rounds([load(DEVICE, f) for f in rounds])
        elif os.path.exists(path):
            out[name] = load(DEVICE, name + ".json")
    try:
        with open(os.path.join(DEVICE, "lscpu.txt")) as f:
            text = f.read()
        out["cpu"] = next((l.split(":", 1)[1].strip() for l in text.splitlines() if l.startswith("Model name")), "?")
        out["cpus"] = next((l.split(":", 1)[1].strip() for l in text.splitlines() if l.startswith("CPU(s)")), "?")
    except OSError:
        out["cpu"], out["cpus"] = "?", "?"
    with open(os.path.join(DEVICE, "README.md")) as f:
        out["when"] = f.readline().strip()
    return out


def best_of_rounds(rounds):
    """bench_scaling runs of the same work in several rounds, as one: each thread count's best
    (most Mpixel per second, or least time), and the speed-ups recomputed from those."""
    out = dict(rounds[0], rounds=len(rounds), runs=[])
    tile = "mpixel_s" in rounds[0]["runs"][0]
    for i in range(len(rounds[0]["runs"])):
        same = [r["runs"][i] for r in rounds]
        out["runs"].append(max(same, key=lambda x: x["mpixel_s"]) if tile else min(same, key=lambda x: x["total_s"]))
    one = out["runs"][0]
    out["runs"] = [dict(x, speedup=(x["mpixel_s"] / one["mpixel_s"]) if tile else (one["total_s"] / x["total_s"]))
                   for x in out["runs"]]
    out["identical"] = all(r["identical"] for r in rounds) and len({r["runs"][0]["checksum"] for r in rounds}) == 1
    return out


def scaling_rows(run, first=None):
    """Rows of one bench_scaling run: threads, wall Mpixel/s, Mpixel per CPU-second, speed-up."""
    rows = []
    for x in run["runs"]:
        # CPU time only for one thread: the pool's workers outlive a tile, and the kernel
        # accounts a running thread's time late, so a short tile's CPU on several is under-counted
        rows.append([x["threads"], "%.1f" % x["mpixel_s"], "%.1f" % x["mpixel_cpu_s"] if x["threads"] == 1 else "–",
                     "%.2f×" % x["speedup"]])
    return rows


def section_scaling(r):
    """Tiles per thread (this machine) and thread scaling (the lent 16-core machine)."""
    out = []
    scipy64 = r.p("grid64")["ct_eval_tile_pps"] if "grid64" in r.names else None
    for size, run in sorted(r.scaling.items()):
        one = run["runs"][0]
        out.append("**This machine, grid64 (8192 triangles), %d² tile** (one channel, raw floats; every thread "
                   "count gives the same bytes: %s)%s:\n" % (
                       size, "yes" if run["identical"] else "**no**",
                       "; scipy evaluates the same 1024² centres at %s, so one thread is %s scipy" % (
                           si(scipy64, "/s"), ratio(one["mpixel_cpu_s"] * 1e6, scipy64))
                       if size == 1024 and scipy64 else ""))
        out.append(table(["threads", "Mpixel/s (wall)", "Mpixel per CPU-second", "speed-up"], scaling_rows(run)))
        out.append("")
    dev = device_figures()
    if dev:
        rounds = max((dev[k].get("rounds", 1) for k in ("tile1024", "tile4096", "build524k") if k in dev), default=1)
        out.append("**The lent machine** (%s, %s CPUs; %s; `bench/perf/device.sh`, files in "
                   "`bench/perf/device/`%s):\n" % (dev["cpu"], dev["cpus"], dev["when"],
                                                    "; each thread count the best of %d rounds run in turns" % rounds
                                                    if rounds > 1 else ""))
        for name, label in (("tile1024", "1024² tile, grid64"), ("tile4096", "4096² tile, grid64")):
            if name in dev:
                run = dev[name]
                out.append("%s (same bytes for every count: %s):\n" % (label, "yes" if run["identical"] else "**no**"))
                out.append(table(["threads", "Mpixel/s (wall)", "Mpixel per CPU-second", "speed-up"],
                                 scaling_rows(run)))
                out.append("")
        for name, label in (("build524k", "as built (arrays of 4 MiB and more advised onto huge pages)"),
                            ("build524k_nothp", "with the huge-page advice off (-DTC__HUGE_MIN=SIZE_MAX)")):
            if name not in dev:
                continue
            b = dev[name]
            out.append("Validation and build of grid512 (524 288 triangles, gradients given), from the parsed "
                       "request, %s (same ordinates for every count: %s):\n" % (label, "yes" if b["identical"] else "**no**"))
            out.append(table(["threads", "validate", "build", "together", "speed-up"],
                             [[x["threads"], sec(x["validate_s"]), sec(x["build_s"]), sec(x["total_s"]),
                               "%.2f×" % x["speedup"]] for x in b["runs"]]))
            out.append("")
        if "scipy_tile" in dev and "tile1024" in dev:
            sp = dev["scipy_tile"]["per_s"]
            one = dev["tile1024"]["runs"][0]["mpixel_s"] * 1e6
            out.append("scipy on the same machine evaluates the 1024² tile's centres at %s: one tocher thread is %s." % (
                si(sp, "/s"), ratio(one, sp)))
    return "\n".join(out)


def section_whole(r):
    """A whole /v1/ordinates request as a client sees it (bench/perf/whole.py) against scipy's
    interpolator built from the same points with the gradients given."""
    if not r.whole:
        return "(whole.py did not run.)"
    rows = []
    for case, c in r.whole["cases"].items():
        name, form = case.split(".")
        t = next(iter(c["tocher"].values()))
        ph = t["phases_ms"]
        rows.append([name, "%d" % c["triangles"], "JSON" if form == "json" else "typed in and out",
                     "%.1f MB / %.1f MB" % (c["body_bytes"] / 1e6, c["answer_bytes"] / 1e6),
                     "%.0f ms" % c["scipy_points_ms"], "%.1f ms" % t["wall_ms"], ratio(c["scipy_points_ms"], t["wall_ms"]),
                     " / ".join("%.1f" % ph.get(k, float("nan")) for k in ("parse", "validate", "build", "encode"))
                     + " / %.1f" % t["transport_ms"]])
    return table(["mesh", "triangles", "form", "body / answer", "scipy (points, gradients given)",
                  "tocher, whole request", "tocher / scipy",
                  "phases, ms: parse / validate / build / encode / transport"], rows)


def issue17_targets(r):
    """Issue 17's figures: (target, measured, met), from this run and the lent machine's files."""
    rows = []
    if r.names:
        rate = {m: r.t(m)["json_bytes"] / r.t(m)["parse_s"] for m in r.names}
        lo, hi = min(rate, key=rate.get), max(rate, key=rate.get)
        small = [m for m in r.names if r.t(m)["json_bytes"] <= 10e6]
        rows.append(["numbers in ≥ 200 MB/s (a request's parse, fast path, heap warm)",
                     "%s (%s) … %s (%s, %.0f MB)%s" % (
                         si(rate[lo], "B/s"), lo, si(rate[hi], "B/s"), hi, r.t(hi)["json_bytes"] / 1e6,
                         "; ≥ %s on every request up to 10 MB" % si(min(rate[m] for m in small), "B/s") if small else ""),
                     "yes" if rate[lo] >= 200e6 else "up to 10 MB" if small and min(rate[m] for m in small) >= 200e6
                     else "no"])
    if r.numfmt:
        rate = r.numfmt["schubfach_random_bits_per_s"]
        rows.append(["numbers out ≥ 25 M doubles/s (random doubles, one thread)",
                     "%s (ordinate-like values %s)" % (si(rate, "/s"), si(r.numfmt["schubfach_ordinates_per_s"], "/s")),
                     "yes" if rate >= 25e6 else "no"])
    if r.whole:
        for case, want, label in (("grid512.typed", 6, "typed in and out, 524k triangles"),
                                  ("grid256.json", 3, "JSON numbers, 131k triangles")):
            c = r.whole["cases"].get(case)
            if c:
                t = next(iter(c["tocher"].values()))
                got = c["scipy_points_ms"] / t["wall_ms"]
                rows.append(["/v1/ordinates, %s ≥ %d× scipy" % (label, want), "%.2f×" % got,
                             "yes" if got >= want else "no"])
    dev = device_figures()
    if 1024 in r.scaling:
        # The same tile is timed twice in the run (bench_perf's table, bench_scaling): the better one.
        one = r.scaling[1024]["runs"][0]["mpixel_cpu_s"]
        if "grid64" in r.names:
            one = max(one, r.tile("grid64")["render1"] / 1e6)
        devone = dev["tile1024"]["runs"][0]["mpixel_s"] if "tile1024" in dev else None
        rows.append(["≥ 150 Mpixel/s per thread, 1024² tile, 8192 triangles",
                     "%.0f Mpixel/s here%s" % (one, "; %.0f on the lent Xeon" % devone if devone else ""),
                     "yes" if one >= 150 else "no"])
        scipy64 = r.p("grid64")["ct_eval_tile_pps"] if "grid64" in r.names else None
        extra = ""
        if devone and "scipy_tile" in dev:
            extra = "; %.1f× on the lent Xeon" % (devone * 1e6 / dev["scipy_tile"]["per_s"])
        tr = r.tileratio
        if tr:  # side by side: the median of alternating rounds (sidebyside.py), not two separate bests
            got = tr["ratio_median"]
            rows.append(["that tile ≥ 25× scipy on the same centres",
                         "%.1f× here (%s)%s" % (got, side_note(r.side_rounds, tr), extra),
                         "yes" if got >= 25 else "no"])
        elif scipy64:
            got = one * 1e6 / scipy64
            rows.append(["that tile ≥ 25× scipy on the same centres", "%.1f× here%s" % (got, extra),
                         "yes" if got >= 25 else "no"])
    for name, want, label in (("tile4096", 12, "4096² tile"), ("build524k", 8, "validate + build, 524k triangles")):
        if name in dev:
            x = dev[name]["runs"][-1]
            extra = ""
            if name == "build524k" and "build524k_nothp" in dev:
                y = dev["build524k_nothp"]["runs"][-1]
                extra = " (%s; without the huge-page advice %.2f×, %s, slower)" % (
                    sec(x["total_s"]), y["speedup"], sec(y["total_s"]))
            rows.append(["%s ≥ %d× at 16 threads (lent Xeon)" % (label, want),
                         "%.2f× at %d threads%s" % (x["speedup"], x["threads"], extra),
                         "yes" if x["threads"] >= 16 and x["speedup"] >= want else "no"])
    for m, want in (("grid16", 10), ("grid256", 20)):
        label = "scattered points ≥ %d× scipy, %s (1e6 random points, one thread)" % (want, m)
        sd = r.side_scattered.get(m)
        if sd:  # side by side, as the tile
            got = sd["ratio_median"]
            rows.append([label, "%.1f× (%s)" % (got, side_note(r.side_rounds, sd)), "yes" if got >= want else "no"])
        elif m in r.names:
            s = r.scattered(m)
            rows.append([label, ratio(s["tocher"], s["scipy"]), "yes" if s["tocher"] >= want * s["scipy"] else "no"])
    return table(["issue 17 target", "measured", "met"], rows)


def section_request(r):
    rows = []
    for m in r.names:
        t = r.t(m)
        ph = t["render_raw_phases_ms"]
        ex = t["render_exr_phases_ms"]
        rows.append([m, "%.1f MB" % (t["json_bytes"] / 1e6), si(t["json_bytes"] / t["parse_s"], "B/s"),
                     si(t["json_bytes"] / t["parse_first_s"], "B/s") if t.get("parse_first_s") else "–",
                     si(t["json_bytes"] / t["parse_cjson_s"], "B/s") if t.get("parse_cjson_s") else "–",
                     " / ".join("%.3g" % x for x in ph), sec(t["whole_render_raw_s"]), "%.3g" % ex[4],
                     sec(t["whole_render_exr_s"]), si(t["ordinates_json_bytes"] / t["ordinates_output_s"], "B/s")
                     if t["ordinates_output_s"] else "–"])
    return table(["mesh", "request", "parse (best of ≥ 5, heap warm)", "parse in the first build",
                  "parse, all through cJSON (before)", "raw render phases, ms (parse / validate / build / render / encode)",
                  "whole raw request", "EXR encode, ms", "whole EXR request", "ordinates JSON output"], rows)


def section_memory(r):
    rows = []
    for m in r.names:
        t, p = r.t(m), r.p(m)
        nt = t["triangles"]
        rows.append([m, "%.0f B" % (t["coef_bytes"] / nt), "%.0f B" % (p["ct_bytes"] / nt),
                     "%.0f B" % ((p["ct_bytes"] + p.get("ct_eval_extra_bytes", 0)) / nt),
                     "%.0f B" % (p["mpl_cubic_bytes"] / nt), si(t["peak_rss_kb"] * 1e3, "B")])
    return table(["mesh", "tocher ordinates per triangle (1 channel)", "scipy arrays", "scipy + its eval tables",
                  "mpl cubic arrays", "bench_perf peak RSS so far"], rows)


def section_http(r):
    d = r.daemon
    rows = []
    for w in d["wrk"]:
        rows.append([w["path"], "%d threads, %d connections" % (w["threads"], w["connections"]),
                     "%.0f" % w["rps"], "%.2f ms" % (w["p50_us"] / 1e3), "%.2f ms" % (w["p90_us"] / 1e3),
                     "%.2f ms" % (w["p99_us"] / 1e3), w["errors"] + w["non2xx"]])
    return table(["route", "wrk", "requests/s", "p50", "p90", "p99", "errors"], rows)


def section_redis(red):
    """The Redis store's figures (bench/perf/redis.py): bytes a mesh costs in Redis, and what a
    cache miss adds when its bytes come from Redis. Also spliced into an existing page (redis.py --splice)."""
    if not red:
        return "(not measured: redis.json is missing)"
    rows = [["%d" % s["triangles"], "%.2f MB" % (s["body_bytes"] / 1e6), "%.2f MB" % (s["canonical_bytes"] / 1e6),
             "%.2f MB (%s)" % (s["stored_bytes"] / 1e6, "zstd, %.1f×" % (s["canonical_bytes"] / s["stored_bytes"])
                               if s["compressed"] else "as is"),
             "%.2f MB" % (s["memory_usage"] / 1e6), sec(s["post_s"])] for s in red["sizes"]]
    load = " (load average %.1f: a shared machine)" % red["loadavg"] if red.get("loadavg", 0) > red["cores"] else ""
    out = ("Measured %s, %d cores%s, Redis %s, redis-server and tocherd on the same machine over loopback "
           "(bench/perf/redis.py). What one stored mesh costs in Redis (grids of bench/perf/meshes.py; "
           "`MEMORY USAGE` of its key, `POST` the whole POST /v1/meshes with its build):\n\n" %
           (red["date"], red["cores"], load, red["redis_version"]))
    out += table(["triangles", "JSON body", "canonical form", "stored", "MEMORY USAGE", "POST"], rows)
    rows = [["%d" % m["triangles"], sec(m["redis_miss"]), sec(m["memory_miss"]), sec(m["redis_hit"]),
             sec(m["memory_hit"]), sec(m["miss_added_s"]), sec(m["redis_part_s"]), sec(m["check_per_hit_s"])]
            for m in red["miss"]]
    out += ("\n\nA 64² raw tile (medians: %s misses, 300 hits, one keep-alive client): a miss with the Redis "
            "store (`--cache-memory 1`, every use fetches, decompresses and builds), with the memory store, "
            "a hit with each, interleaved; *miss adds* = Redis miss − Redis hit (fetch + decompress + build); "
            "*of which Redis* and *check per hit* are the time outside the request's phases (Server-Timing "
            "total − parse, validate, build, evaluate, encode), Redis miss − memory miss (GETEX of the value "
            "and zstd) and Redis hit − memory hit (the EXPIRE every mesh request sends, which renews the TTL "
            "and makes an expired or evicted mesh a 404 on every replica), medians:\n\n" % "/".join(str(m["runs"]) for m in red["miss"]))
    out += table(["triangles", "miss, Redis", "miss, memory", "hit, Redis", "hit, memory", "miss adds",
                  "of which Redis", "check per hit"], rows)
    return out


def section_stored(stored):
    """The stored-mesh figures (bench/perf/stored.py): tile of a stored mesh against a whole render
    request, and tile throughput. Also spliced into an existing page (see stored.py's output)."""
    if not stored:
        return "(not measured: stored.json is missing)"
    a, b = stored["tile_vs_render"], stored["many_tiles"]
    rows = [["256² PNG tile of a stored %d-triangle mesh vs POST /v1/render of it (%.1f MB body)" %
             (a["triangles"], a["body_bytes"] / 1e6),
             "%.1f ms vs %.0f ms (medians of %d tiles): %.0f×" % (a["tile_median_s"] * 1e3, a["render_median_s"] * 1e3,
                                                                 a["samples"], a["ratio"]),
             "≥ 20×", "yes" if a["ratio"] >= 20 else "no"],
            ["256² PNG tiles of a stored %d-triangle mesh, %d keep-alive clients (wrk, the %d tiles of z = %d again "
             "and again; defaults: the encoded-tile cache answers repeats)" %
             (b["triangles"], b["clients"], 4 ** b["zoom"], b["zoom"]),
             "%.0f tiles/s (%d GETs in %.1f s), p50 %.1f ms, p99 %.1f ms, %d errors" %
             (b["tiles_per_s"], b["requests"], b["duration_us"] * 1e-6, b["p50_us"] / 1e3, b["p99_us"] / 1e3,
              b["errors"] + b["non2xx"]),
             "≥ 2000/s", "yes" if b["tiles_per_s"] >= 2000 else "no"]]
    d = stored.get("many_tiles_cold")
    if d:
        rows.append(["the same with --tile-cache-memory 0: every GET renders and encodes its PNG",
                     "%.0f tiles/s (%d GETs), p50 %.1f ms, p99 %.1f ms" % (d["tiles_per_s"], d["requests"],
                                                                         d["p50_us"] / 1e3, d["p99_us"] / 1e3),
                     "", ""])
    c = stored.get("many_raw_tiles")
    if c:
        rows.append(["the same as raw float32, --tile-cache-memory 0 (no image encoder)",
                     "%.0f tiles/s (%d GETs), p50 %.1f ms, p99 %.1f ms" % (c["tiles_per_s"], c["requests"],
                                                                         c["p50_us"] / 1e3, c["p99_us"] / 1e3),
                     "", ""])
    text = ("Measured %s, %d cores, wrk and tocherd on the same machine (bench/perf/stored.py).\n\n" %
            (stored["date"], stored["cores"]) + table(["measure", "measured", "target", "met"], rows))
    if d and c:
        text += STORED_NOTE % (a["body_bytes"] / 1e6, b["tiles_per_s"], b["tiles_per_s"] / 2000, d["tiles_per_s"],
                               c["tiles_per_s"])
    return text


STORED_NOTE = """

The first measure is what issue 15 is for: a stored mesh's tile skips parsing the %.1f MB body,
validation and the build (and its locator), leaving the render of the pixels the tile covers and the
PNG encoding. The throughput target is met by what a tile server does with immutable URLs: the
daemon keeps encoded tiles by ETag (`--tile-cache-memory`, 256 MiB by default, an LRU; a tile is
rendered once even when eight clients ask for it at once), so the 64 tiles of z = 3 asked again and
again are answered from memory (%.0f tiles/s, %.0f× the target). Every GET that renders and
encodes its PNG (the cache off) reaches %.0f tiles/s: a 256² tile of the 10k-triangle mesh spends
about 1.2 ms rendering and 2.7 ms encoding the PNG through OpenImageIO (Server-Timing), and raw
float32 without the encoder reaches %.0f/s. A first view of fresh tiles is bounded by that
(rendering speed is issue 17's work); repeated views, other clients and nginx's cache in front
(issue 16) are not."""


def section_cluster(cl):
    """Tiles/s through nginx with 1, 2 and 3 replicas (bench/perf/cluster.py). Also spliced into an
    existing page: report.py --cluster OUTDIR docs/performance.md."""
    if not cl:
        return "(not measured: cluster.json is missing)"
    base = cl["runs"][0]["tiles_per_s"]
    rows = []
    for r in cl["runs"]:
        share = sorted(r["per_upstream"].values(), reverse=True)
        rows.append([r["replicas"], "%.0f" % r["tiles_per_s"], ratio(r["tiles_per_s"], base),
                     "%.1f ms" % (r["p50_us"] / 1e3), "%.1f ms" % (r["p99_us"] / 1e3), r["errors"] + r["non2xx"],
                     r["cache_hits"], " / ".join(str(n) for n in share)])
    best = max(cl["runs"], key=lambda r: r["tiles_per_s"])
    return ("Measured %s on this %d-core machine (bench/perf/cluster.py): redis-server, the replicas and nginx "
            "(deploy/nginx/tocher.conf, 1 worker) as real processes on loopback (deploy/cluster.py), store: %s, daemon: %s. "
            "wrk (%d threads, %d keep-alive connections, %d s) GETs 256² PNG tiles of %d stored 10k-triangle "
            "meshes at z = %d through nginx, every URL once, so nginx's tile cache answers none of them "
            "(\"cache hits\", from nginx's access log, says so); \"requests per replica\" is the consistent "
            "hash's split, from the same log.\n\n" %
            (cl["date"], cl["cores"], cl["store"], cl.get("tocherd", "?"), cl["wrk_threads"], cl["connections"], cl["seconds"],
             cl["meshes"], cl["zoom"]) +
            table(["replicas", "tiles/s", "vs 1", "p50", "p99", "errors", "cache hits", "requests per replica"], rows) +
            "\n\nThe best is %.0f tiles/s with %d replica(s); the machine's load average was %s at the start "
            "(it is shared). Everything runs on the same %d cores — wrk, nginx and every replica, each of which "
            "already runs 2 HTTP threads and 4 workers — so on this machine more replicas cannot add capacity "
            "(beyond %d they only split the same cores): the rows' differences are more threads contending for "
            "those cores and the share the machine's other users leave, not throughput a deployment gains. What "
            "carries over to a deployment where each replica has its own cores is the split: each replica serves "
            "the meshes that hash to it, and meshes hash unevenly (the last column), so size for the busiest "
            "replica, not the average.\n"
            % (best["tiles_per_s"], best["replicas"], cl.get("loadavg", "?"), cl["cores"], cl["cores"]))


def splice(dest, heading, text):
    """Replaces the section `heading` of the page dest by text (or adds it before the next
    section after "## Stored meshes", or at the end): one benchmark rerun without the others."""
    with open(dest) as f:
        doc = f.read()
    block = "## %s\n\n%s\n" % (heading, text.rstrip("\n"))
    start = doc.find("## %s\n" % heading)
    if start < 0:
        anchor = doc.find("## Stored meshes")
        nxt = doc.find("\n## ", anchor + 1) if anchor >= 0 else -1
        doc = doc[:nxt + 1] + block + "\n" + doc[nxt + 1:] if nxt >= 0 else doc.rstrip("\n") + "\n\n" + block
    else:
        end = doc.find("\n## ", start + 1)
        doc = doc[:start] + block + (doc[end:] if end >= 0 else "")
    with open(dest, "w") as f:
        f.write(doc)


CLUSTER_HEADING = "A cluster: tiles through nginx with 1, 2 and 3 replicas"


def section_skip(r):
    d = r.daemon
    big = r.names[-1] if r.names else None
    grids = [m for m in r.names if r.t(m).get("flags_ordinates_s") is not None]
    lines = []
    for m in grids:
        t = r.t(m)
        lines.append("- **No discontinuities, no wedge coupling** (%s, %d triangles): ordinates %s without flags, "
                     "%s with C0 rows every n/8 and a C-1 column (%s); mesh building %s vs %s." %
                     (m, t["triangles"], sec(t["ordinates_s"]), sec(t["flags_ordinates_s"]),
                      ratio(t["flags_ordinates_s"], t["ordinates_s"]), sec(t["mesh_s"]), sec(t["flags_mesh_s"])))
    if big:
        t = r.t(big)
        lines.append("- **A tile visits only the triangles it overlaps** (%s): 256×256 pixels over 1/256 of the mesh "
                     "take %s, the same pixels over all of it %s (%s)." %
                     (big, sec(t["render_256_part_s"]), sec(t["render_256_whole_s"]),
                      ratio(t["render_256_whole_s"], t["render_256_part_s"])))
        lines.append("- **No gradients unless asked** (%s, 1e6 scattered points): values only %s, with gradients %s."
                     % (big, sec(t["eval_scattered_s"]), sec(t["eval_scattered_grad_s"])))
    co, cp, cr = d["cli_ordinates"], d["cli_render_png"], d["cli_render_raw"]
    lines.append("- **No image stack unless an image is encoded**: `tocher ordinates` on the 4-triangle scene runs in "
                 "%s with a peak RSS of %s; `tocher render` to raw float32 %s, %s; to PNG (OpenImageIO loaded) %s, %s. "
                 "tocherd holds %s after its first JSON requests and %s after its first PNG, which took %s (the "
                 "next: %s)." %
                 (sec(co["s"]), si(co["peak_rss_kb"] * 1e3, "B"), sec(cr["s"]), si(cr["peak_rss_kb"] * 1e3, "B"),
                  sec(cp["s"]), si(cp["peak_rss_kb"] * 1e3, "B"), si(d["rss_after_json_kb"] * 1e3, "B"),
                  si(d["rss_after_png_kb"] * 1e3, "B"), sec(d["first_png_s"]), sec(d["second_png_s"])))
    return "\n".join(lines)


def targets(r):
    """(target, measured, met) rows, from the figures."""
    rows = []
    small = [m for m in r.names if r.t(m)["triangles"] <= 10000]
    if small:
        worst = min(small, key=lambda m: r.tile(m)["render1"] / r.tile(m)["scipy"])
        s = r.tile(worst)
        rows.append(["tile ≥ 50× scipy's evaluation, meshes ≤ 10k triangles",
                     "worst %s: %s (1 thread), %s (2 threads)" % (worst, ratio(s["render1"], s["scipy"]),
                                                                   ratio(s["render2"], s["scipy"])),
                     "yes" if s["render1"] >= 50 * s["scipy"] else "no"])
    near1k = min(r.names, key=lambda m: abs(r.t(m)["triangles"] - 1000)) if r.names else None
    if near1k:
        px = r.tile(near1k)["render1"]
        rows.append(["≥ 200 Mpixel/s per core, 1024² tile, ~1k triangles",
                     "%s (%d triangles): %s" % (near1k, r.t(near1k)["triangles"], si(px, "px/s")),
                     "yes" if px >= 200e6 else "no"])
    big = max(r.names, key=lambda m: r.t(m)["triangles"]) if r.names else None
    if big:
        b = r.build(big)
        rows.append(["ordinates %s ≥ 10× scipy's constructor" % big,
                     "%s from points, %s from a Delaunay" % (ratio(b["scipy_points"], b["tocher_est"]),
                                                             ratio(b["scipy_tri"], b["tocher_est"])),
                     "from points only" if b["scipy_points"] >= 10 * b["tocher_est"] > b["scipy_tri"] / 10 else
                     "yes" if b["scipy_tri"] >= 10 * b["tocher_est"] else "no"])
        rows.append(["ordinates %s ≥ 3× scipy with gradients given" % big,
                     "%s (scipy's build + its lazy transform)" % ratio(b["scipy_grad"], b["tocher_given"]),
                     "yes" if b["scipy_grad"] >= 3 * b["tocher_given"] else "no"])
        worst = min(r.names, key=lambda m: r.scattered(m)["tocher"] / r.scattered(m)["scipy"])
        s = r.scattered(worst)
        side = r.side_scattered.get(worst)  # the same mesh measured side by side (issue 17's table)
        rows.append(["scattered evaluation ≥ 10× scipy",
                     "worst %s: %s (each side's best, minutes apart%s)" % (
                         worst, ratio(s["tocher"], s["scipy"]),
                         "; side by side %.1f×, below" % side["ratio_median"] if side else ""),
                     "yes" if s["tocher"] >= 10 * s["scipy"] else "no"])
        t = r.t(big)
        rows.append(["whole render request %s < 2 s" % big,
                     "raw %s, EXR %s" % (sec(t["whole_render_raw_s"]), sec(t["whole_render_exr_s"])),
                     "yes" if max(t["whole_render_raw_s"], t["whole_render_exr_s"]) < 2 else "no"])
        per = t["coef_bytes"] / t["triangles"]
        rows.append(["ordinates ≤ 300 bytes per triangle per channel", "%.0f bytes" % per,
                     "yes" if per <= 300 else "no"])
    w = r.daemon["wrk"][0]
    rows.append(["≥ 10k requests/s on /v1/ordinates (4 triangles), p99 < 5 ms",
                 "%.0f/s, p99 %.2f ms" % (w["rps"], w["p99_us"] / 1e3),
                 "yes" if w["rps"] >= 10000 and w["p99_us"] < 5000 else "no"])
    return table(["target", "measured", "met"], rows)


def section_numfmt(outdir):
    """Number printing (bench/perf/numfmt.c): doubles/s of tc_fmt_double, the cascade it replaced
    and snprintf("%.17g"); empty when numfmt.json is missing (an older run directory)."""
    if not os.path.exists(os.path.join(outdir, "numfmt.json")):
        return ""
    nf = load(outdir, "numfmt.json")
    names = [("schubfach", "tc_fmt_double (Schubfach, shortest)"),
             ("cascade", "before issue 17 (first of %.15g/%.16g/%.17g that round-trips)"),
             ("printf17", "snprintf(\"%.17g\")")]
    rows = [[label, si(nf[k + "_random_bits_per_s"], "/s"), si(nf[k + "_ordinates_per_s"], "/s")]
            for k, label in names]
    return ("### Numbers out\n\nDoubles printed per second, one thread, %s doubles per set: random bit "
            "patterns over all finite doubles, and ordinate-like values (arithmetic results in [-10, 10]).\n\n"
            % si(nf["n"]) + table(["printer", "random doubles", "ordinate-like"], rows))


def main():
    if sys.argv[1] == "--cluster":  # only the cluster section, into an existing page
        outdir, dest = sys.argv[2], sys.argv[3]
        splice(dest, CLUSTER_HEADING, section_cluster(load(outdir, "cluster.json")))
        return
    outdir, dest = sys.argv[1], sys.argv[2]
    r = Run(outdir)
    v = r.peers["versions"]
    big = max(r.names, key=lambda m: r.t(m)["triangles"])
    tb = r.t(big)
    doc = f"""# tocher performance, measured against scipy and matplotlib

Written by `make bench` (bench/perf/) on {datetime.date.today().isoformat()}: {r.cpu}, 2 cores; Python
{v['python']}, numpy {v['numpy']}, scipy {v['scipy']}, matplotlib {v['matplotlib']} (Debian's, run with
/usr/bin/python3). Every figure below comes from one run: peers and tocher on the same meshes, the same
1e6 scattered points and the same 1024×1024 tile of pixel centres; each is the best of a few repetitions
(the machine is shared and noisy: the minimum is the least disturbed run). tocher figures are single-threaded
unless a column says otherwise; scipy and matplotlib are single-threaded.

Meshes: structured n×n grids, two triangles per square (n = 16 … 512), and Delaunay triangulations of
1e3 … 1e5 uniform random points — for every mesh the triangles are scipy's own `Delaunay`, so all three
libraries reconstruct on the identical mesh. Data f = sin(3x+1)·cos(2y) + x²/2 with exact gradients.

## Targets

{targets(r)}

Issue 17 (speed of the whole request):

{issue17_targets(r)}

## Ordinates: the whole request against scipy

`bench/perf/whole.py`: tocherd on loopback, one keep-alive client, the body prepared beforehand, timed from
sending to having read the whole answer (best of a few); scipy's interpolator built from the same points with
the gradients given (`Delaunay` + peers.py's `ct_given_gradients`). Phases from the answer's Server-Timing;
"transport" is the client's wall clock less the daemon's total.

{section_whole(r)}

### Validation against build

`build/bench_validate` (bench/perf/validate.c): `tc_mesh_new` (validation and topology) and `tc_recon_new`
(the build) timed apart on meshes made in memory: a grid with exact gradients, the same grid with a C0 and a
C-1 polyline of thousands of segments snaking through it, and a wheel (one vertex of valence 65 536 within
rings of quads); at n and 4n ("scaling": ~4 is linear, ~16 quadratic), on 1 and 2 threads (this machine).

```
{r.validate.strip() if r.validate else "(bench_validate did not run)"}
```

## Ordinates: building the reconstruction

tocher's time is the whole build from a parsed request: validation, topology (edge adjacency, vertex
fans), wedges, tangent planes (estimated by least squares, or the given gradients) and the 19 Bézier
ordinates per triangle. scipy's constructor takes points, not triangles, so "from points" includes its
Qhull triangulation; "from a Delaunay" hands it the triangulation and adds the barycentric transform it
builds lazily on first evaluation (the like-for-like work); "grad set" is scipy's constructor without its
gradient estimate, the exact gradients set through its `grad` attribute (scipy has no public way to skip
the estimate; peers.py checks the result equals a normally built interpolator with `grad` overwritten).

{section_build(r)}

## Scattered evaluation (1e6 uniform random points)

scipy walks from the last simplex it found, so random points cost it about √T steps each; meshes above
1e5 triangles are timed on a prefix of 1e5 points for the peers (peers.json says how many). tocher
locates each point in a bounding-volume tree and, for batches of 1024 points or more, visits them in
Z order (each point's result is independent of the order; a unit test checks it bit for bit).

{section_eval(r)}

## Tiles (1024×1024 pixel centres over the unit square)

tocher's render is `tc_render`: exact ownership of every pixel centre (the same rule as point location)
and each pixel `/v1/evaluate`'s value at its centre — for the cubic on triangles of aspect ≤ 64 within
1e-12 of the data scale, from the renderer's monomial form — rounded once to float; "eval of the
centres" is `tc_eval_points` on the same 1M points given as scattered points. The peers evaluate the
same centres as one array of points.

{section_tile(r)}

## Tiles per thread and thread scaling

`build/bench_scaling` (bench/perf/scaling.c): `tc_render` of one tile with 1, 2, … threads, best of at
least three runs and 0.5 s. "Mpixel per CPU-second" is pixels over the CPU time, for one thread: its
throughput, and the figure a busy machine disturbs least (on more threads the kernel accounts the pool's
workers, which outlive a tile, too late for a tile's CPU time to be read). This machine has 2 cores,
so scaling is measured on the 16-core machine the `device` tool lends (below, when its files are there).

{section_scaling(r)}

## Requests: parse, build, render, encode

A `/v1/render` request as tocherd runs it (`tc_api_render`, 2 render threads): the mesh's JSON with a
1024² viewport, raw float32 or OpenEXR half. Parse rate is the request's bytes over the parse phase:
the best of at least five parses in one process, as a daemon that has parsed requests before runs it,
and beside it the parse inside the first build of the mesh, which for the big meshes is the process's
first and pays the page faults of a fresh heap (some 20 µs per 4 KiB page on this virtual machine).
The last column is the `/v1/ordinates` response writer (shortest round-trip numbers).

{section_request(r)}

{section_numfmt(outdir)}

## Memory

{section_memory(r)}

The request parser converts the cJSON tree into flat arrays and frees the tree before validation starts,
so the tree never coexists with the mesh, the ordinates or the image.

## Small requests over HTTP (wrk on loopback, {r.daemon['seconds']} s, the 4-triangle scene)

wrk and tocherd share the machine's 2 cores.

{section_http(r)}

## Stored meshes: tiles without the body

{section_stored(r.stored)}

## Stored meshes in Redis

{section_redis(r.redis)}

## {CLUSTER_HEADING}

{section_cluster(r.cluster)}

## Work only what a scene needs

{section_skip(r)}

## Where the time goes

For the largest mesh ({big}, {tb['triangles']} triangles, raw output) the phases of a whole render request
are parse {tb['render_raw_phases_ms'][0]:.0f} ms, validate and topology {tb['render_raw_phases_ms'][1]:.0f} ms,
build (ordinates and locator) {tb['render_raw_phases_ms'][2]:.0f} ms, render {tb['render_raw_phases_ms'][3]:.0f} ms
and encode {tb['render_raw_phases_ms'][4]:.1f} ms. Parsing reads the big numeric arrays straight from the
body (src/io/request_fast.c, numbers by src/io/strtod_fast.c, equal to strtod) and leaves the small rest
to cJSON; the "parse, all through cJSON" column is the parser without that fast path. See the notes below the tables for the profile of a tile.
"""
    notes = os.path.join(os.path.dirname(os.path.abspath(__file__)), "notes.md")
    if os.path.exists(notes):
        with open(notes) as f:
            doc += "\n" + f.read()
    with open(dest, "w") as f:
        f.write(doc)


if __name__ == "__main__":
    main()
