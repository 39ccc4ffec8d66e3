"""analysis.py — numbers derived from the measurements for the tables and the prose: sample-count
matches, convergence slopes, which meshes to compare, the range limiter's error ratios."""
import math

from .data import run_ms

# The scanline profile also shows linear on the uniform mesh whose sample count is nearest (in
# log) to this many times clough-tocher's on the disc mesh: Bastos & Oliveira's ratio.
SCAN_UNIFORM_FACTOR = 15.0


def _interp(t, a, b):
    """Log-log interpolation between a and b at t in [0, 1]."""
    return math.exp(math.log(a) + t * (math.log(b) - math.log(a)))


def match_uniform(run, scene, method, target):
    """How many samples method needs on the uniform meshes to reach a mean relative error of
    target: interpolated log-log between the last density above it (lo) and the first at or
    below it (hi); lo is None when the coarsest already reaches it (an upper bound). Also the
    uniform mesh with the lowest error (best). None when method never ran on a uniform mesh."""
    m = {"found": False, "lo": None, "hi": None, "best": None}
    prev = None
    for label in run.labels("uniform"):
        r = run.get(scene, label, method)
        if not r:
            continue
        if m["best"] is None or r["mean_rel"] < m["best"]["mean_rel"]:
            m["best"] = r
        if m["found"]:
            continue
        if r["mean_rel"] > target:
            prev = r
            continue
        m.update(found=True, hi=r, lo=prev)
        if prev is None:
            m.update(samples=r["samples"], N=r["density"], run_ms=run_ms(r))
            continue
        t = (math.log(target) - math.log(prev["mean_rel"])) / (math.log(r["mean_rel"]) - math.log(prev["mean_rel"]))
        m.update(samples=_interp(t, prev["samples"], r["samples"]), N=_interp(t, prev["density"], r["density"]),
                 run_ms=_interp(t, run_ms(prev), run_ms(r)))
    return m if m["best"] else None


def slope(run, scene, kind, method, min_density):
    """Least-squares slope of log(mean relative error) against log(samples) over the meshes of
    kind with density >= min_density; None with fewer than 2 points."""
    pts = []
    for label in run.labels(kind):
        r = run.get(scene, label, method)
        if r and r["density"] >= min_density and r["mean_rel"] > 0:
            pts.append((math.log(r["samples"]), math.log(r["mean_rel"])))
    n = len(pts)
    sx, sy = sum(p[0] for p in pts), sum(p[1] for p in pts)
    sxx, sxy = sum(p[0] ** 2 for p in pts), sum(p[0] * p[1] for p in pts)
    den = n * sxx - sx * sx
    return (n * sxy - sx * sy) / den if n >= 2 and den > 0 else None


def scan_uniform(run, scene, ct):
    """The linear row on the uniform mesh whose samples are nearest in log to
    SCAN_UNIFORM_FACTOR times ct's."""
    if not ct:
        return None
    want = math.log(SCAN_UNIFORM_FACTOR * ct["samples"])
    rows = [r for r in (run.get(scene, l, "linear") for l in run.labels("uniform")) if r]
    return min(rows, key=lambda r: abs(math.log(r["samples"]) - want), default=None)


def best(run, scene, label):
    """The row with the lowest mean relative error on the mesh."""
    rows = [r for r in (run.get(scene, label, m) for m in run.methods) if r]
    return min(rows, key=lambda r: r["mean_rel"], default=None)


def ct_loses(run, scene):
    """Meshes where clough-tocher's mean relative error is above linear's."""
    out = []
    for label in run.labels():
        lin, ct = run.get(scene, label, "linear"), run.get(scene, label, "clough-tocher")
        if lin and ct and ct["mean_rel"] > lin["mean_rel"]:
            out.append(label)
    return out


def ct_loses_max(run, scene):
    """Disc densities where clough-tocher's largest error is above linear's."""
    out = []
    for label in run.labels("disc"):
        lin, ct = run.get(scene, label, "linear"), run.get(scene, label, "clough-tocher")
        if lin and ct and ct["max_abs"] > lin["max_abs"]:
            out.append("N=%d" % ct["density"])
    return out


# The range limiter against the free cubic: (limited, free) pairs with the same samples.
RANGE_PAIRS = [("clough-tocher", "ct-free"), ("ct-estimate", "ct-estimate-free")]
RANGE_TARGET = 1.1  # issue 12: the default's error at most 1.1x the free cubic's


def range_ratios(run):
    """Every (scene, mesh, pair) where both ran: the limited method's mean relative and RMS
    error over the free one's, and their overshoot."""
    out = []
    for scene in run.scenes:
        for label in run.labels():
            for lim, free in RANGE_PAIRS:
                a, b = run.get(scene, label, lim), run.get(scene, label, free)
                if a and b and b["mean_rel"] > 0 and b["rms"] > 0:
                    out.append({"scene": scene, "label": label, "kind": a["mesh"], "limited": a, "free": b,
                                "mrel": a["mean_rel"] / b["mean_rel"], "rms": a["rms"] / b["rms"]})
    return out
