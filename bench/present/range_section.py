"""range_section.py — issue 12's "do not spoil what works": the default (range local) against
the free cubic on every scene and mesh, as error ratios, and the overshoot each leaves."""
import os

from . import analysis as an
from . import plots
from .fmt import g3, listing, pct, ratio, table

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
    met = ["%s on the %s meshes (worst %s× mean relative, %s× RMS)" % (lim, kind, ratio(max(r["mrel"] for r in rs)),
                                                                      ratio(max(r["rms"] for r in rs)))
           for (lim, kind), rs in _groups(ratios).items() if rs and not any(_above(r) for r in rs)]
    return ("**Range limiting (issue 12):** against the free cubic with the same samples, the default "
            "(`range: local`) has at worst %s× the mean relative error (%s, %s, %s) and %s× the RMS (%s, %s, "
            "%s); %d of %d (scene, mesh, pair) cases are above the %g× target%s. "
            "[Range](#range-the-default-against-the-free-cubic), [realistic surfaces](#realistic-surfaces).\n"
            % (ratio(worst["mrel"]), worst["scene"], worst["label"], worst["limited"]["method"],
               ratio(worst_rms["rms"]), worst_rms["scene"], worst_rms["label"], worst_rms["limited"]["method"], n,
               len(ratios), T, "; it is met by " + listing(met) + " on every scene" if met else ""))


def _groups(ratios):
    """{(limited method, mesh kind): cases over every scene}, in plan order."""
    out = {}
    for lim, _ in an.RANGE_PAIRS:
        for kind in KINDS:
            out[(lim, kind)] = [r for r in ratios if r["limited"]["method"] == lim and r["kind"] == kind]
    return out


def _where(r):
    return "%s, %s" % (r["scene"], r["label"])


def summary_table(ratios):
    """Over every scene, per pair and mesh kind: cases, how many are above the target, the worst ratios."""
    head = ["limited / free", "mesh kind", "cases", "above in mean rel.", "above in RMS", "worst mean rel.",
            "worst RMS", "worst max abs"]
    rows = []
    for (lim, kind), rs in _groups(ratios).items():
        if not rs:
            continue
        free = rs[0]["free"]["method"]
        w = {k: max(rs, key=lambda r: r[k]) for k in ("mrel", "rms")}
        wm = max(rs, key=lambda r: r["limited"]["max_abs"] / r["free"]["max_abs"] if r["free"]["max_abs"] else 0)
        rows.append(["%s / %s" % (lim, free), kind, len(rs), sum(r["mrel"] > T for r in rs),
                     sum(r["rms"] > T for r in rs), "%s (%s)" % (ratio(w["mrel"]["mrel"]), _where(w["mrel"])),
                     "%s (%s)" % (ratio(w["rms"]["rms"]), _where(w["rms"])),
                     "%s (%s)" % (ratio(wm["limited"]["max_abs"] / wm["free"]["max_abs"]), _where(wm))])
    return table(head, rows, ["l", "l"] + ["r"] * 6)


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


def flat_share(r):
    """The share of the limiter's extra squared error (limited minus free) that lies in triangles touching a
    flat one (bench/results.h, sq_err_by_flat); None when the limiter added none."""
    a, b = r["limited"], r["free"]
    if a.get("sq_err") is None or b.get("sq_err") is None:
        return None
    extra = a["sq_err"] - b["sq_err"]
    return (a["sq_err_by_flat"] - b["sq_err_by_flat"]) / extra if extra > 0 else None


def above_table(ratios):
    head = ["scene", "mesh", "limited", "mean rel. ratio", "RMS ratio", "max abs ratio", "limited mean rel.",
            "free mean rel.",
            "exact B: beyond 5 % R", "exact B: worst (R)", "free: beyond", "free: worst", "limited: beyond",
            "limited: worst", "extra error by flat triangles"]
    rows = []
    for r in ratios:
        if not _above(r):
            continue
        a, b = r["limited"], r["free"]
        rows.append([r["scene"], r["label"], a["method"], "**%s**" % ratio(r["mrel"]) if r["mrel"] > T
                     else ratio(r["mrel"]), "**%s**" % ratio(r["rms"]) if r["rms"] > T else ratio(r["rms"]),
                     ratio(a["max_abs"] / b["max_abs"]) if b["max_abs"] else "n/a", g3(a["mean_rel"]), g3(b["mean_rel"]), pct(a["exact_over_beyond"]), g3(a["exact_over_worst"]),
                     pct(b["over_beyond"]), g3(b["over_worst"]), pct(a["over_beyond"]), g3(a["over_worst"]),
                     "–" if flat_share(r) is None else "%.0f %%" % (100 * flat_share(r))])
    return table(head, rows, ["l", "l", "l"] + ["r"] * 12) if rows else ""


def why(ratios):
    """What the cases above the target have in common, counted."""
    above = [r for r in ratios if _above(r)]
    if not above:
        return ""
    rms_only = [r for r in above if r["mrel"] <= T]
    lowered = [r for r in rms_only if r["mrel"] < 1]
    est_disc = [r for r in above if r["limited"]["method"] == "ct-estimate" and r["kind"] == "disc"]
    leaves = [r for r in above if r["limited"]["exact_over_worst"] > 0.05]
    by_flat = [r for r in above if (flat_share(r) or 0) >= 0.9]
    out = ["Of the %d cases above the target:" % len(above)]
    if rms_only:
        out.append("%d are above it in RMS only (mean relative error within %g×, and below 1× in %d of them): the "
                   "limiter lowers or keeps the average error and concentrates larger errors in fewer pixels, on "
                   "uniform and adaptive meshes, whose cells the discontinuities cross (%s)." % (len(rms_only), T, len(lowered),
                                                                  listing(dict.fromkeys("%s %s" % (r["scene"], r["kind"])
                                                                                        for r in rms_only))))
    if est_disc:
        w = max(est_disc, key=lambda r: r["limited"]["max_abs"] / r["free"]["max_abs"])
        out.append("%d %s ct-estimate on the discontinuity meshes (estimated planes count as data on well-shaped "
                   "triangles, aspect ≤ 8, and only as far as the values around go on longer ones): the largest "
                   "error grows by up to %s× (%s: %s against %s)." % (
                       len(est_disc), "is" if len(est_disc) == 1 else "are",
                       ratio(w["limited"]["max_abs"] / w["free"]["max_abs"]), _where(w),
                       g3(w["limited"]["max_abs"]), g3(w["free"]["max_abs"])))
    if by_flat:
        out.append("In %d of them at least 90 %% of the extra squared error lies in triangles that share a vertex "
                   "with a flat one (all corner values equal; %s): next to flat data the bound keeps a flat "
                   "triangle flat, so the planes at its vertices must be flat, and a step that crosses the next "
                   "cells unflagged is followed by a smooth rise instead of the free cubic's steep one — which "
                   "rings into the flat triangles (the free cubic's overshoot columns above). No bound that keeps "
                   "flat data flat can follow such a step; with the steps flagged (the disc meshes), clough-tocher is "
                   "within 1.1× of ct-free on every scene." % (len(by_flat), listing(dict.fromkeys(r["scene"] for r in by_flat))))
    if leaves:
        out.append("On %d the exact B itself leaves its triangles' corner values by more than 0.05 R somewhere "
                   "(by %s to %s R): the mesh does not resolve a peak or a bend, and a bound from the corner values "
                   "must cut into it." % (len(leaves), g3(min(r["limited"]["exact_over_worst"] for r in leaves)),
                                          g3(max(r["limited"]["exact_over_worst"] for r in leaves))))
    return " ".join(out) + "\n"


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
estimated planes only as far as the values around the triangle go where it is long or obtuse, aspect > 8),
and never below 0 where its corners are
≥ 0. The limiter projects the wedges' tangent planes and the edges' cross-boundary derivatives into that
bound, so continuity is kept. `range: free` is the paper's cubic (matplotlib's and scipy's).
Issue 12 asks that the default not spoil what works: on the reference scenes its error should be at most
{T:g}× the free cubic's. Two pairs are measured on every scene and mesh, each with the same samples:
clough-tocher against ct-free (tangents from the midpoint samples) and ct-estimate against ct-estimate-free
(tangents estimated from the vertex values).

**Result: {n - sum(_above(r) for r in ratios)} of {n} cases meet the target in both measures; {nm} are above it in
mean relative error and {nr} in RMS.** A ratio below 1 means the limiter lowered the error. Over every scene, per
pair and mesh kind (worst max abs: the largest error's ratio, for where the limiter cuts):

{summary_table(ratios)}
The worst ratio per scene and mesh kind (and the mesh where it occurs):

{worst_table(run, ratios)}
![range local against range free: error ratios]({rel}/range-ratios.svg)

{"Every case above the target (bold: the measure above it), with the overshoot the free cubic leaves there and what is left with the limiter:" if above else "No case is above the target."}

{above}
{why(ratios)}
**What the limiter buys on the reference scenes**: for each method, over all meshes of the scene, the largest
share of pixels beyond 5 % R · the worst excursion (R) · the number of meshes with negative pixels
(per-mesh figures in results.csv, columns `over_*`; the exact B's own in `exact_over_*`):

{overshoot_table(run)}"""
