"""loses.py — where the cubic loses, and why: the stiff scene's slivers, the box's footprint
corners, and the uniform meshes that a jump or a thin penumbra crosses."""
from . import analysis as an
from .fmt import g3, listing, ratio


def _slope(run, scene, kind, method, n):
    s = an.slope(run, scene, kind, method, n)
    return "%.2f" % s if s is not None else "n/a"


def stiff(run):
    losses = an.ct_loses(run, "stiff") if "stiff" in run.scenes else []
    fig = run.disc(run.c["fig_N"])
    ct, lin, c1, given, est = (run.get("stiff", fig, m) for m in
                               ("clough-tocher", "linear", "clough-tocher-c1", "ct-given", "ct-estimate"))
    if not (losses and ct and lin and c1):
        return ""
    rep = run.any_on("stiff", run.disc(run.c["rep_N"]))
    scale = run.scene_info["stiff"]["scale"]
    text = (f"**stiff**: clough-tocher's mean relative error is above linear's on {listing(losses)}; on the disc "
            f"mesh N = {run.c['fig_N']} it is {g3(ct['mean_rel'])} against linear's {g3(lin['mean_rel'])}, and "
            f"clough-tocher-c1's is {g3(c1['mean_rel'])}. The penumbrae are 3e-5 wide, so the disc mesh carries "
            f"slivers (worst aspect ratio {g3(rep['worst_aspect']) if rep else 'n/a'} at N = {run.c['rep_N']}) on "
            f"which B drops by the whole light across 3e-5. ")
    if ct["tangent_impact"] is not None:
        text += (f"The worst tangent plane of clough-tocher on N = {run.c['fig_N']} is at ({ct['tangent_x']:.6f}, "
                 f"{ct['tangent_y']:.6f}), with slope {g3(ct['tangent_used'])} where B's (one-sided, in that "
                 f"triangle) is {g3(ct['tangent_scene'])}; it moves a Bézier ordinate by "
                 f"{g3(100 * ct['tangent_impact'] / scale)}% of full scale. ")
    if given:
        text += f"With the scene's own corner gradients (`ct-given`) the mean relative error is {g3(given['mean_rel'])}. "
    if est:
        text += f"Estimated tangents (`ct-estimate`): {g3(est['mean_rel'])}."
    return text + "\n"


def box(run):
    if "box" not in run.scenes:
        return ""
    rep = run.disc(run.c["rep_N"])
    ct, lin, given = (run.get("box", rep, m) for m in ("clough-tocher", "linear", "ct-given"))
    if not (ct and lin):
        return ""

    def maxes(m):
        return ", ".join("%s (N=%d)" % (g3(r["max_abs"]), r["density"])
                         for r in (run.get("box", l, m) for l in run.labels("disc")) if r)

    text = (f"**box**: clough-tocher against linear on the disc mesh N = {run.c['rep_N']}: "
            f"{ratio(lin['rms'] / ct['rms'])}× lower RMS, and every method converges slowly there (disc slopes: "
            f"linear {_slope(run, 'box', 'disc', 'linear', 4)}, clough-tocher "
            f"{_slope(run, 'box', 'disc', 'clough-tocher', 4)}). The largest error hardly moves with N — "
            f"clough-tocher {maxes('clough-tocher')}; linear {maxes('linear')} — because it sits at the corners of "
            f"the box's footprint, where the limit of B from outside depends on the direction of approach "
            f"(`scene.h`) and one value per corner cannot fit it")
    d32 = [run.get("box", run.disc(32), m) for m in ("clough-tocher", "linear")] if run.disc(32) else [None, None]
    if all(d32) and d32[0]["corner_share"] is not None:
        text += (f": on the disc mesh N = 32, {100 * d32[0]['corner_share']:.0f}% of clough-tocher's summed pixel "
                 f"error (and {100 * d32[1]['corner_share']:.0f}% of linear's) lies within {run.c['corner_radius']:g} "
                 f"of those four corners")
    text += "."
    if given:
        text += f" Exact corner gradients do not change that (`ct-given` RMS {g3(given['rms'])} against {g3(ct['rms'])})."
    losses = an.ct_loses(run, "box")
    if losses:
        text += " Clough-tocher's mean relative error is above linear's on %s." % listing(losses)
    return text + "\n"


def uniform(run):
    jumps = [s for s in ("point-shadow", "box", "stiff") if s in run.scenes]
    text = ""
    for s in jumps:
        losses = an.ct_loses(run, s)
        if losses and s not in ("stiff", "box"):  # those two have their own paragraphs
            text += "**%s**: clough-tocher's mean relative error is above linear's on %s.\n" % (s, listing(losses))
    if not jumps:
        return text
    W = run.c["W"]
    slopes = ", ".join("%s %s" % (s, _slope(run, s, "uniform", "linear", 16)) for s in jumps)
    return text + (f"On uniform meshes with a jump or a 3e-5 penumbra crossing the cells ({', '.join(jumps)}), no "
                   f"method does much better than linear: the error is the smeared step in the cells it crosses, "
                   f"which every continuous interpolant makes alike, and its mean shrinks roughly like h (slopes of "
                   f"linear on uniform meshes N ≥ 16: {slopes}; −0.5 is order 1 in h). At N = 256 a cell is {W} / 256 "
                   f"= {W // 256} pixels wide, so the image average no longer resolves that strip and the curves "
                   f"flatten at N = 128–256 for every method: a limit of measuring at W = {W}, not of the methods. "
                   f"The adaptive meshes on these scenes split to their depth limit along the step for every "
                   f"threshold, hence the clusters of points at one error.\n")


def write(run):
    parts = [p for p in (stiff(run), box(run), uniform(run)) if p]
    return "### Where the cubic loses, and why\n\n" + "\n".join(parts) if parts else ""
