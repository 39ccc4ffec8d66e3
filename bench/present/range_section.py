"""range_section.py — issue 12's "do not spoil what works": the default (range local) against
the free cubic on every scene and mesh, as error ratios, and the overshoot each leaves."""
import os

from . import analysis as an
from . import plots
from .fmt import g3, pct, ratio, table

KINDS = ("disc", "uniform", "adaptive")
T = an.RANGE_TARGET


def _above(r):
    return r["mrel"] > T or r["rms"] > T


def headline(ratios):
    """One sentence for the top of the report."""
    if not ratios:
        return ""
    worst = max(ratios, key=lambda r: r["mrel"])
    worst_rms = max(ratios, key=lambda r: r["rms"])
    n = sum(_above(r) for r in ratios)
    return ("**Range limiting (issue 12):** against the free cubic with the same samples, the default "
            "(`range: local`) has at worst %s× the mean relative error (%s, %s, %s) and %s× the RMS (%s, %s, "
            "%s); %d of %d (scene, mesh, pair) cases are above the %g× target. "
            "[Range](#range-the-default-against-the-free-cubic), [realistic surfaces](#realistic-surfaces).\n"
            % (ratio(worst["mrel"]), worst["scene"], worst["label"], worst["limited"]["method"],
               ratio(worst_rms["rms"]), worst_rms["scene"], worst_rms["label"], worst_rms["limited"]["method"], n,
               len(ratios), T))


def _worst_cell(rs, key):
    if not rs:
        return "–"
    w = max(rs, key=lambda r: r[key])
    return "%s (%s)" % (ratio(w[key]), w["label"].split(" ", 1)[1])


def worst_table(run, ratios):
    head = ["scene", "mesh kind"]
    for lim, free in an.RANGE_PAIRS:
        head += ["%s / %s: mean rel." % (lim, free), "RMS", "above %g×" % T]
    rows = []
    for scene in run.scenes:
        for kind in KINDS:
            row = [scene, kind]
            for lim, _ in an.RANGE_PAIRS:
                rs = [r for r in ratios if r["scene"] == scene and r["kind"] == kind
                      and r["limited"]["method"] == lim]
                row += [_worst_cell(rs, "mrel"), _worst_cell(rs, "rms"),
                        "%d of %d" % (sum(_above(r) for r in rs), len(rs)) if rs else "–"]
            if any(c != "–" for c in row[2:]):
                rows.append(row)
    return table(head, rows, ["l", "l"] + ["r"] * (len(head) - 2))


def above_table(ratios):
    head = ["scene", "mesh", "limited", "mean rel. ratio", "RMS ratio", "limited mean rel.", "free mean rel.",
            "exact B: beyond 5 % R", "exact B: worst (R)", "free: beyond", "free: worst", "limited: beyond",
            "limited: worst"]
    rows = []
    for r in ratios:
        if not _above(r):
            continue
        a, b = r["limited"], r["free"]
        rows.append([r["scene"], r["label"], a["method"], "**%s**" % ratio(r["mrel"]) if r["mrel"] > T
                     else ratio(r["mrel"]), "**%s**" % ratio(r["rms"]) if r["rms"] > T else ratio(r["rms"]),
                     g3(a["mean_rel"]), g3(b["mean_rel"]), pct(a["exact_over_beyond"]), g3(a["exact_over_worst"]),
                     pct(b["over_beyond"]), g3(b["over_worst"]), pct(a["over_beyond"]), g3(a["over_worst"])])
    return table(head, rows, ["l", "l", "l"] + ["r"] * 10) if rows else ""


def why(ratios):
    """How many cases above the target are meshes where the exact B itself leaves its
    triangles' corner values, i.e. where a bound from the corner values must cut into it."""
    above = [r for r in ratios if _above(r)]
    if not above:
        return ""
    thr = 0.05
    leaves = [r for r in above if r["limited"]["exact_over_worst"] > thr]
    mags = sorted(r["limited"]["exact_over_worst"] for r in leaves)
    text = ("In %d of the %d cases above the target the exact B itself leaves its triangles' corner values by "
            "more than %g R somewhere" % (len(leaves), len(above), thr))
    if mags:
        text += " (by %s to %s R)" % (g3(mags[0]), g3(mags[-1]))
    return text + (": the mesh does not resolve a peak or a bend of the light, and the local bound, which widens "
                   "only as far as the samples show a hump, cuts into what the free cubic gets right. Where the "
                   "exact B stays within its corner values the limiter costs little.\n")


OVER_METHODS = ["exact", "linear", "clough-tocher", "ct-free", "ct-estimate", "ct-estimate-free", "clough-tocher-c1",
                "powell-sabin", "hermite"]


def overshoot_table(run):
    """Per scene and method, over every mesh: the largest share beyond 5 % R, the worst
    excursion, and the meshes with negative pixels."""
    methods = [m for m in OVER_METHODS if m in run.methods or m == "exact"]
    rows = []
    for scene in run.scenes:
        row = [scene]
        for m in methods:
            rs = [r for r in (run.get(scene, l, m) for l in run.labels()) if r]
            if m == "exact":  # the exact B's own: the same on every row of a mesh
                ex = [a for a in (run.any_on(scene, l) for l in run.labels()) if a and a["status"] == "ok"]
                rs = [{"over_beyond": a["exact_over_beyond"], "over_worst": a["exact_over_worst"], "over_negative": 0}
                      for a in ex]
            if not rs:
                row.append("–")
                continue
            neg = sum(r["over_negative"] > 0 for r in rs)
            row.append("%s · %s%s" % (pct(max(r["over_beyond"] for r in rs)), g3(max(r["over_worst"] for r in rs)),
                                      " · %d neg." % neg if neg else ""))
        rows.append(row)
    return table(["scene"] + methods, rows)


def write(run, figdir, rel):
    ratios = an.range_ratios(run)
    if not ratios:
        return ""
    plots.range_plot(run, ratios, os.path.join(figdir, "range-ratios.svg"))
    n, nm, nr = len(ratios), sum(r["mrel"] > T for r in ratios), sum(r["rms"] > T for r in ratios)
    above = above_table(ratios)
    return f"""## Range: the default against the free cubic

Every cubic and quadratic method is range-limited by default (`range: local`, `src/core/range.h`): each
triangle stays within its own corner values, widened by 5 % of their spread or by the hump or dip its data
show along an edge (a midpoint sample above both ends, corner planes that rise and fall along an edge;
estimated planes only as far as the values around the triangle go), and never below 0 where its corners are
≥ 0. The limiter projects the wedges' tangent planes and the edges' cross-boundary derivatives into that
bound, so continuity is kept. `range: free` is the paper's cubic (matplotlib's and scipy's).
Issue 12 asks that the default not spoil what works: on the reference scenes its error should be at most
{T:g}× the free cubic's. Two pairs are measured on every scene and mesh, each with the same samples:
clough-tocher against ct-free (tangents from the midpoint samples) and ct-estimate against ct-estimate-free
(tangents estimated from the vertex values).

**Result: {n - sum(_above(r) for r in ratios)} of {n} cases meet the target in both measures; {nm} are above it in
mean relative error and {nr} in RMS.** A ratio below 1 means the limiter lowered the error. The worst ratio per
scene and mesh kind (and the mesh where it occurs):

{worst_table(run, ratios)}
![range local against range free: error ratios]({rel}/range-ratios.svg)

{"Every case above the target (bold: the measure above it), with the overshoot the free cubic leaves there and what is left with the limiter:" if above else "No case is above the target."}

{above}
{why(ratios)}
**What the limiter buys on the reference scenes**: for each method, over all meshes of the scene, the largest
share of pixels beyond 5 % R · the worst excursion (R) · the number of meshes with negative pixels
(per-mesh figures in results.csv, columns `over_*`; the exact B's own in `exact_over_*`):

{overshoot_table(run)}"""
