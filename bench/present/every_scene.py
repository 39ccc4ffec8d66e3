"""every_scene.py — a paragraph per scene (the best method, clough-tocher against linear and
clough-tocher-c1, tangents given or estimated, convergence, matches, losses, cost), and run time."""
from . import analysis as an
from .data import run_ms
from .fmt import g3, listing, ms, ratio


def _slope(run, scene, kind, method, n):
    s = an.slope(run, scene, kind, method, n)
    return ("%.2f" % s, "%.2f" % (-2 * s)) if s is not None else ("n/a", "n/a")


def _errors(run, scene, rep):
    ct, lin, c1 = (run.get(scene, rep, m) for m in ("clough-tocher", "linear", "clough-tocher-c1"))
    if not (ct and lin and c1):
        return ""
    text = (f"Clough-tocher: RMS {g3(ct['rms'])}, mean relative {g3(ct['mean_rel'])}, max {g3(ct['max_abs'])} "
            f"({ct['samples']} samples); linear: {g3(lin['rms'])}, {g3(lin['mean_rel'])}, {g3(lin['max_abs'])} "
            f"({lin['samples']} samples); clough-tocher-c1: {g3(c1['rms'])}, {g3(c1['mean_rel'])}, "
            f"{g3(c1['max_abs'])}.\n")
    if lin["rms"] <= ct["rms"]:
        return text + "Here linear's RMS is the lower, by %s×.\n" % ratio(ct["rms"] / lin["rms"])
    text += "Clough-tocher's RMS is %s× lower than linear's" % ratio(lin["rms"] / ct["rms"])
    if c1["rms"] > ct["rms"]:
        text += " and %s× lower than clough-tocher-c1's" % ratio(c1["rms"] / ct["rms"])
    return text + ".\n"


def _tangents(run, scene, rep):
    text = ""
    given, est = run.get(scene, rep, "ct-given"), run.get(scene, rep, "ct-estimate")
    if given:
        text += (f"With the scene's corner gradients instead of the midpoint parabolas (`ct-given`, "
                 f"{given['samples']} value samples + {given['gradient_samples']} gradient samples): RMS "
                 f"{g3(given['rms'])}, mean relative {g3(given['mean_rel'])}.\n")
    if est:
        text += (f"With tangents estimated from the vertex values alone (`ct-estimate`, {est['samples']} samples): "
                 f"RMS {g3(est['rms'])}, mean relative {g3(est['mean_rel'])}.\n")
    return text


def _convergence(run, scene):
    lu, cu, gu = (_slope(run, scene, "uniform", m, 16) for m in ("linear", "clough-tocher", "ct-given"))
    ld, cd, c1d = (_slope(run, scene, "disc", m, 4) for m in ("linear", "clough-tocher", "clough-tocher-c1"))
    return (f"Convergence, as the slope of log mean relative error against log samples (order in h = −2 × slope): "
            f"uniform N ≥ 16: linear {lu[0]} (order {lu[1]}), clough-tocher {cu[0]} (order {cu[1]}), ct-given "
            f"{gu[0]} (order {gu[1]}); disc N ≥ 4: linear {ld[0]} ({ld[1]}), clough-tocher {cd[0]} ({cd[1]}), "
            f"clough-tocher-c1 {c1d[0]} ({c1d[1]}).\n")


def _match(run, scene, ct):
    m = an.match_uniform(run, scene, "linear", ct["mean_rel"]) if ct else None
    if not m:
        return ""
    if m["found"]:
        how = ("; interpolated log-log between N = %d and N = %d" % (m["lo"]["density"], m["hi"]["density"])
               if m["lo"] else "; an upper bound: the coarsest uniform mesh already matches")
        return ("Linear on uniform meshes needs about %d samples (%s× clough-tocher's on the disc mesh%s) to match "
                "its mean relative error.\n" % (round(m["samples"]), ratio(m["samples"] / ct["samples"]), how))
    b = m["best"]
    return ("Linear on uniform meshes never matches clough-tocher's mean relative error on the disc mesh up to "
            "N = %d (best %s with %d samples, still %s× higher).\n"
            % (b["density"], g3(b["mean_rel"]), b["samples"], ratio(b["mean_rel"] / ct["mean_rel"])))


def _fine(run, scene):
    fine = run.labels("uniform")[-1:] or [None]
    ct, lin = run.get(scene, fine[0], "clough-tocher"), run.get(scene, fine[0], "linear")
    if not (ct and lin):
        return ""
    return (f"Cost on the finest uniform mesh measured ({fine[0]}, {ct['triangles']} triangles): clough-tocher builds "
            f"in {ms(ct['build_ms'])} ms ({g3(1e3 * ct['build_ms'] / ct['triangles'])} µs per triangle) and renders in "
            f"{ms(ct['render_ms'])} ms; linear in {ms(lin['build_ms'])} ms and {ms(lin['render_ms'])} ms.\n")


def paragraph(run, scene):
    rep = run.disc(run.c["rep_N"])
    b = an.best(run, scene, rep)
    text = "**%s** — %s.\n" % (scene, run.scene_info[scene]["summary"])
    if b:
        text += "On the disc mesh N = %d the lowest mean relative error is %s's (%s).\n" % (
            run.c["rep_N"], b["method"], g3(b["mean_rel"]))
    text += _errors(run, scene, rep) + _tangents(run, scene, rep) + _convergence(run, scene)
    text += _match(run, scene, run.get(scene, rep, "clough-tocher"))
    loses = an.ct_loses(run, scene)
    text += ("Clough-tocher's mean relative error is above linear's on: %s.\n" % listing(loses) if loses else
             "Clough-tocher's mean relative error is below linear's on every mesh.\n")
    lm = an.ct_loses_max(run, scene)
    if lm:
        text += "Its largest error is above linear's on the disc meshes %s.\n" % listing(lm)
    return text + _fine(run, scene)


def run_time(run):
    rep = run.disc(run.c["rep_N"])
    ct, lin = run.get("penumbra", rep, "clough-tocher"), run.get("penumbra", rep, "linear")
    if not (ct and lin):
        return ""
    text = (f"### Run time\n\nAt W = {run.c['W']} the render dominates the run time: on the penumbra disc mesh "
            f"N = {run.c['rep_N']}, clough-tocher builds in {ms(ct['build_ms'])} ms and renders in "
            f"{ms(ct['render_ms'])} ms, linear in {ms(lin['build_ms'])} ms and {ms(lin['render_ms'])} ms, so the "
            f"cubic's run time is {ratio(run_ms(ct) / run_ms(lin))}× linear's. So in the time plots the disc-mesh "
            f"curves are nearly vertical: more samples on a discontinuity mesh cost almost no time.\n")
    m = an.match_uniform(run, "penumbra", "linear", ct["mean_rel"])
    if m and m["found"]:
        text += (f"Matching clough-tocher's penumbra result with linear on a uniform mesh takes about "
                 f"{ms(m['run_ms'])} ms (interpolated like the samples), {ratio(m['run_ms'] / run_ms(ct))}× "
                 f"clough-tocher's {ms(run_ms(ct))} ms, mostly in rendering the many more triangles.\n")
    return text + ("(The cost of taking the samples — here, evaluating the scene — is not in the run time; the "
                   "samples plot shows it.)\n")


def write(run):
    return "### Every scene\n\n" + "\n".join(paragraph(run, s) for s in run.scenes) + "\n" + run_time(run)
