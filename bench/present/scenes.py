"""scenes.py — one section per reference scene: every method on the representative disc mesh
(errors, times, overshoot), every method on every disc mesh, linear and clough-tocher on every
mesh, and the scene's figures."""
import os

from . import analysis as an
from . import plots
from .data import run_ms
from .fmt import g3, ms, pct, ratio, table

PROFILE = ["linear", "clough-tocher-c1", "clough-tocher", "ct-free"]  # the scanline's disc-mesh curves


def overshoot_cells(r):
    return [pct(r["over_beyond"]), g3(r["over_worst"]), str(r["over_negative"])]


def table_rep(run, scene, label):
    head = ["method", "samples", "gradient samples", "build ms", "render ms", "max abs", "RMS", "mean relative",
            "beyond 5 % R", "worst (R)", "negative px"]
    a = run.any_on(scene, label)
    rows = [["exact B (reference)", "", "", "", "", "", "", "", pct(a["exact_over_beyond"]), g3(a["exact_over_worst"]),
             "0"]] if a and a["exact_over_worst"] is not None else []
    for m in run.methods:
        r = run.get(scene, label, m, ok_only=False)
        if not r:
            continue
        cells = [m, r["samples"], r["gradient_samples"]]
        if r["status"] != "ok":
            rows.append(cells + ["skipped: " + r["note"]] + [""] * 7)
            continue
        rows.append(cells + [ms(r["build_ms"]), ms(r["render_ms"]), g3(r["max_abs"]), g3(r["rms"]),
                             g3(r["mean_rel"])] + overshoot_cells(r))
    return table(head, rows)


def table_disc_all(run, scene):
    rows = []
    for label in run.labels("disc"):
        a = run.any_on(scene, label)
        if a:
            rows.append([a["density"], a["vertices"]] +
                        [g3(r["mean_rel"]) if r else "skipped" for r in (run.get(scene, label, m) for m in run.methods)])
    return table(["disc N", "vertices"] + run.methods, rows, ["r"] * (2 + len(run.methods)))


def table_kinds(run, scene):
    head = ["mesh", "vertices", "triangles", "linear samples", "linear mean rel.", "linear run ms",
            "clough-tocher samples", "clough-tocher mean rel.", "clough-tocher run ms", "linear / clough-tocher error"]
    rows = []
    for label in run.labels():
        a = run.any_on(scene, label)
        if not a:
            continue
        row = [label, a["vertices"], a["triangles"]]
        lin, ct = run.get(scene, label, "linear"), run.get(scene, label, "clough-tocher")
        for r in (lin, ct):
            row += [r["samples"], g3(r["mean_rel"]), ms(run_ms(r))] if r else ["", "skipped", ""]
        row.append(ratio(lin["mean_rel"] / ct["mean_rel"]) if lin and ct else "")
        rows.append(row)
    return table(head, rows)


def profile_curves(run, scene):
    """(label, method, values, dashed) for the scanline plots."""
    data, rep = run.scanlines(scene), run.disc(run.c["rep_N"])
    out = []
    for m in PROFILE:
        r, col = run.get(scene, rep, m), "%s@%s" % (m, rep)
        if r and col in data:
            out.append(("%s, %s (%d)" % (m, rep, r["samples"]), m, data[col], m == "ct-free"))
    u = an.scan_uniform(run, scene, run.get(scene, rep, "clough-tocher"))
    if u and "linear@" + u["label"] in data:
        out.append(("linear, %s (%d)" % (u["label"], u["samples"]), "linear", data["linear@" + u["label"]], True))
    return out


def figures(run, scene, figdir, rel):
    """Writes the scene's plots; returns their markdown."""
    out = []
    for by_time, what in ((True, "time"), (False, "samples")):
        plots.error_plot(run, scene, by_time, os.path.join(figdir, "%s-%s.svg" % (scene, what)))
        out.append("![%s: mean relative error against %s](%s/%s-%s.svg)" %
                   (scene, "run time" if by_time else "samples", rel, scene, what))
    curves = profile_curves(run, scene)
    for ylog, suffix in ((False, ""), (True, "-log")) if curves else ():
        plots.scanline_plot(run, scene, curves, ylog, os.path.join(figdir, "%s-scanline%s.svg" % (scene, suffix)))
        out.append("![%s: relative error along x = %g%s](%s/%s-scanline%s.svg)" %
                   (scene, run.c["scan_x"], ", log scale" if ylog else "", rel, scene, suffix))
    if curves:
        out.append("Profile data (every method on the disc mesh N = %d, linear on every uniform mesh): "
                   "[`%s/%s-scanline.csv`](%s/%s-scanline.csv)." % (run.c["rep_N"], rel, scene, rel, scene))
    return "\n\n".join(out) + "\n"


def pictures(run, scene, figdir, rel):
    if not os.path.exists(os.path.join(figdir, "%s-images.png" % scene)):
        return ""
    fig = run.any_on(scene, run.disc(run.c["fig_N"]))
    return ("Disc mesh N = %d (%s triangles): reference | linear | clough-tocher-c1 | clough-tocher,\nthen the "
            "mesh | the three error maps (gain %g).\n\n![%s: reference, linear, clough-tocher-c1, clough-tocher]"
            "(%s/%s-images.png)\n\n![%s: mesh and error maps](%s/%s-errors.png)\n"
            % (run.c["fig_N"], fig["triangles"] if fig else "?", run.c["err_gain"], scene, rel, scene, scene, rel,
               scene))


def section(run, scene, figdir, rel):
    s = run.scene_info[scene]
    ev = s["events"]
    out = ["### %s\n\n%s. Full scale %s; %d C0 and %d C-1 discontinuity segments.\n" %
           (scene, s["summary"], g3(s["scale"]), sum(e["kind"] == "C0" for e in ev),
            sum(e["kind"] == "C-1" for e in ev))]
    rep = run.disc(run.c["rep_N"])
    a = run.any_on(scene, rep) if rep else None
    if a:
        out.append("**Disc mesh N = %d** (%d vertices, %d triangles, %d edges flagged C0, %d flagged C-1, worst "
                   "aspect ratio %s); overshoot as defined above, the exact B's own first:\n\n%s" %
                   (run.c["rep_N"], a["vertices"], a["triangles"], a["flagged_c0"], a["flagged_cm1"],
                    g3(a["worst_aspect"]), table_rep(run, scene, rep)))
    out.append("**Mean relative error of every method on the disc meshes:**\n\n" + table_disc_all(run, scene))
    out.append("**Linear and clough-tocher on every mesh:**\n\n" + table_kinds(run, scene))
    out.append(figures(run, scene, figdir, rel))
    out.append(pictures(run, scene, figdir, rel))
    return "\n".join(x for x in out if x)


def write(run, figdir, rel):
    return "## Per scene\n\n" + "\n".join(section(run, s, figdir, rel) for s in run.scenes)
