"""reading.py — the report's reading of the numbers: the penumbra against linear and
clough-tocher-c1, the samples linear needs, Powell-Sabin and Hermite, where the cubic loses, a
summary per scene, and run time. Every figure is computed here from the run."""
from . import analysis as an
from .data import run_ms
from .fmt import g3, ms, ratio

PEN = "penumbra"


def _x(a, b, key="mean_rel"):
    """a's key over b's, as a ratio string."""
    return ratio(a[key] / b[key]) if a and b and b[key] else "n/a"


def penumbra(run):
    rep = run.disc(run.c["rep_N"])
    ct, lin, c1 = (run.get(PEN, rep, m) for m in ("clough-tocher", "linear", "clough-tocher-c1"))
    if not (ct and lin and c1):
        return ""
    scale = run.scene_info[PEN]["scale"]
    text = (f"### Penumbra (scene b): flags against linear and against clough-tocher-c1\n\n"
            f"On the penumbra discontinuity mesh at N = {run.c['rep_N']} ({ct['vertices']} vertices, "
            f"{ct['triangles']} triangles, {ct['flagged_c0']} edges flagged C0), clough-tocher with the flags "
            f"({ct['samples']} samples: vertices and edge midpoints) has an RMS error of {g3(ct['rms'])}, "
            f"**{_x(lin, ct, 'rms')}× lower than linear's** {g3(lin['rms'])} on the same mesh ({lin['samples']} "
            f"samples: the vertices) and **{_x(c1, ct, 'rms')}× lower than clough-tocher-c1's** {g3(c1['rms'])} "
            f"(the same samples and the same cubic, flags ignored). In mean relative error: {g3(ct['mean_rel'])} "
            f"against {g3(lin['mean_rel'])} (linear, {_x(lin, ct)}×) and {g3(c1['mean_rel'])} (clough-tocher-c1, "
            f"{_x(c1, ct)}×); the largest errors are {g3(ct['max_abs'])}, {g3(lin['max_abs'])} and "
            f"{g3(c1['max_abs'])}, i.e. {g3(100 * ct['max_abs'] / scale)}%, {g3(100 * lin['max_abs'] / scale)}% "
            f"and {g3(100 * c1['max_abs'] / scale)}% of full scale.\n")
    if c1["mean_rel"] > lin["mean_rel"]:
        text += (f"Without the flags the cubic is worse than linear: clough-tocher-c1's mean relative error is "
                 f"{_x(c1, lin)}× linear's — it overshoots on both sides of every C0 line (see the scanline "
                 f"profile), as the C1 quadratic does in Salesin et al.'s Fig. 8b.\n")
    text += (f"Run time: clough-tocher {ms(run_ms(ct))} ms (build {ms(ct['build_ms'])} + render "
             f"{ms(ct['render_ms'])}), linear {ms(run_ms(lin))} ms (build {ms(lin['build_ms'])} + render "
             f"{ms(lin['render_ms'])}).\n")
    return text + samples_needed(run, ct) + literal(run, ct)


def samples_needed(run, ct):
    m = an.match_uniform(run, PEN, "linear", ct["mean_rel"])
    text = "\n**How many samples linear needs on uniform meshes.**\n"
    if m is None:
        return text + "No uniform mesh ran.\n"
    if m["found"] and m["lo"]:
        text += (f"Linear on uniform meshes reaches clough-tocher's mean relative error ({g3(ct['mean_rel'])}) "
                 f"between N = {m['lo']['density']} ({m['lo']['samples']} samples, {g3(m['lo']['mean_rel'])}) and "
                 f"N = {m['hi']['density']} ({m['hi']['samples']} samples, {g3(m['hi']['mean_rel'])}); "
                 f"interpolating log-log between the two, it needs about **{round(m['samples'])} samples** (N ≈ "
                 f"{ratio(m['N'])}): **{ratio(m['samples'] / ct['samples'])}× the {ct['samples']} samples** "
                 f"clough-tocher took on the disc mesh, or {ratio(m['samples'] / ct['vertices'])}× its "
                 f"{ct['vertices']} vertices. Bastos & Oliveira saw about 15× (bilinear on 2217 vertices was still "
                 f"22.7% worse than bicubic on 149).\n")
    elif m["found"]:
        text += (f"Linear on the coarsest uniform mesh (N = {m['hi']['density']}, {m['hi']['samples']} samples) "
                 f"already reaches clough-tocher's mean relative error ({g3(ct['mean_rel'])}), so the match is at "
                 f"most that.\n")
    else:
        b = m["best"]
        text += (f"Linear on uniform meshes never reaches clough-tocher's mean relative error ({g3(ct['mean_rel'])}) "
                 f"up to N = {b['density']}: its best is {g3(b['mean_rel'])} with {b['samples']} samples, "
                 f"{ratio(b['samples'] / ct['samples'])}× clough-tocher's samples and still "
                 f"{ratio(b['mean_rel'] / ct['mean_rel'])}× its error. Bastos & Oliveira saw about 15×.\n")
    u = an.scan_uniform(run, PEN, ct)
    if u:
        pct = 100 * (1 - ct["mean_rel"] / u["mean_rel"])
        text += (f"At about Bastos & Oliveira's ratio, linear on the uniform N = {u['density']} mesh "
                 f"({u['samples']} samples, {ratio(u['samples'] / ct['samples'])}× clough-tocher's) has a mean "
                 f"relative error of {g3(u['mean_rel'])}; clough-tocher's is {abs(pct):.1f}% "
                 f"{'lower' if pct > 0 else 'higher'} (they report 22.7% lower).\n")
    return text + _vertex_only(run, ct)


def _vertex_only(run, ct):
    text = ""
    est = run.get(PEN, ct["label"], "ct-estimate")
    m = an.match_uniform(run, PEN, "linear", est["mean_rel"]) if est else None
    if m and m["found"]:
        text += (f"Counting vertex samples only: clough-tocher with tangents estimated from the neighbouring "
                 f"vertices (`ct-estimate`, no midpoint samples, {est['samples']} samples) has a mean relative "
                 f"error of {g3(est['mean_rel'])}, and linear on uniform meshes needs about {round(m['samples'])} "
                 f"samples ({ratio(m['samples'] / est['samples'])}×) to match it"
                 + (f" (interpolated log-log between N = {m['lo']['density']} and N = {m['hi']['density']})"
                    if m["lo"] else "") + ".\n")
    m = an.match_uniform(run, PEN, "clough-tocher", ct["mean_rel"])
    if m and m["found"]:
        text += (f"Clough-tocher itself on uniform meshes (no flags, kinks inside triangles) needs about "
                 f"{round(m['samples'])} samples ({ratio(m['samples'] / ct['samples'])}×) to match its own "
                 f"disc-mesh result: the flags, not the cubic alone, make the difference.\n")
    elif m:
        text += (f"Clough-tocher itself on uniform meshes (no flags, kinks inside triangles) never matches its own "
                 f"disc-mesh result up to N = {m['best']['density']} (best {g3(m['best']['mean_rel'])} with "
                 f"{m['best']['samples']} samples): the flags, not the cubic alone, make the difference.\n")
    return text


def literal(run, ct):
    lit = run.get(PEN, ct["label"], "ct-literal")
    if lit:
        return (f"\nFigure 6 taken literally (`ct-literal`) on the same mesh: largest error {g3(lit['max_abs'])} "
                f"against {g3(ct['max_abs'])} with the two defects fixed ({_x(lit, ct, 'max_abs')}×), RMS "
                f"{g3(lit['rms'])} against {g3(ct['rms'])}; its mean relative error converges like linear's (see "
                f"the table of every method on the disc meshes).\n")
    r = run.get(PEN, ct["label"], "ct-literal", ok_only=False)
    return "\nFigure 6 taken literally (`ct-literal`) could not run on this mesh: %s\n" % r["note"] if r else ""


def _vs(run, scene, method, base="clough-tocher"):
    """'0.00302 (0.99× clough-tocher's)' on the representative disc mesh: method's mean relative error."""
    rep = run.disc(run.c["rep_N"])
    a, b = run.get(scene, rep, method), run.get(scene, rep, base)
    return "%s (%s× %s's)" % (g3(a["mean_rel"]), _x(a, b), base) if a and b else "n/a"


def _lowest(run, scene, methods):
    rep = run.disc(run.c["rep_N"])
    rows = [r for r in (run.get(scene, rep, m) for m in methods) if r]
    return min(rows, key=lambda r: r["mean_rel"])["method"] if rows else "n/a"


def ps_hermite(run):
    rep = run.disc(run.c["rep_N"])
    if not rep or "powell-sabin" not in run.methods:
        return ""
    items = []
    if "square-light" in run.scenes:
        items.append(f"- **Smooth light (square-light):** clough-tocher {g3(run.get('square-light', rep, 'clough-tocher')['mean_rel'])}, "
                     f"powell-sabin {_vs(run, 'square-light', 'powell-sabin')}, hermite {_vs(run, 'square-light', 'hermite')}; "
                     f"the lowest of the three is {_lowest(run, 'square-light', ['clough-tocher', 'powell-sabin', 'hermite'])}'s. "
                     "Powell-Sabin is a quadratic, yet with exact-enough tangent planes it converges like the cubics "
                     "in value.")
    if PEN in run.scenes:
        pen_lin = run.get(PEN, rep, "linear")
        ps = run.get(PEN, rep, "powell-sabin")
        ct, c1 = run.get(PEN, rep, "clough-tocher"), run.get(PEN, rep, "clough-tocher-c1")
        items.append(f"- **Kinks (penumbra):** Powell-Sabin cannot keep a C0 edge — a C1 quadratic has nothing to "
                     f"relax (Salesin et al.'s point about their Fig. 8b) — so it smooths the penumbra boundaries as "
                     f"clough-tocher-c1 does: powell-sabin {g3(ps['mean_rel']) if ps else 'n/a'} and clough-tocher-c1 "
                     f"{g3(c1['mean_rel']) if c1 else 'n/a'} against clough-tocher's {g3(ct['mean_rel']) if ct else 'n/a'} "
                     f"({_x(ps, ct)}× and {_x(c1, ct)}×), and {_x(ps, pen_lin)}× linear's; the answer carries a "
                     f"warning saying the flags were smoothed. Hermite keeps the kinks: each wedge has its own tangent "
                     f"plane and a patch edge carries only its ends' slopes along it, so a C0 edge stays C0 with its "
                     f"kink: {_vs(run, PEN, 'hermite')}.")
    if "point-shadow" in run.scenes:
        items.append(f"- **Jumps (point-shadow):** a C-1 edge cuts both meshes, so both keep the hard shadow: "
                     f"powell-sabin {_vs(run, 'point-shadow', 'powell-sabin')}, hermite {_vs(run, 'point-shadow', 'hermite')}.")
    if "box" in run.scenes:
        items.append(f"- **Box** (C-1 contact and C0 shadow): powell-sabin {_vs(run, 'box', 'powell-sabin')}, the C0 "
                     f"lines smoothed; hermite {_vs(run, 'box', 'hermite')}.")
    if "stiff" in run.scenes:
        h, hz = run.get("stiff", rep, "hermite"), run.get("stiff", rep, "hermite-zero-twist")
        why = (" — lower: the estimated cross derivatives of the large cells borrow from the steep slivers beside "
               "them, and dropping them is safer" if h and hz and hz["mean_rel"] < h["mean_rel"] else "")
        items.append(f"- **Stiff** (slivers next to large cells): powell-sabin {_vs(run, 'stiff', 'powell-sabin')}, "
                     f"hermite {_vs(run, 'stiff', 'hermite')}. Hermite with zero twist has "
                     f"{_vs(run, 'stiff', 'hermite-zero-twist', 'hermite')}{why}.")
    if PEN in run.scenes:
        items.append(f"- **Twist, in general:** zero twist gives up an order of convergence (bicubic Hermite with zero "
                     f"twist reproduces only bilinear cross terms); on the penumbra hermite-zero-twist's mean "
                     f"relative error is {_vs(run, PEN, 'hermite-zero-twist', 'hermite')}. With exact second derivatives "
                     f"(`hessians`) the twist is exact — the unit tests reproduce bicubics with them.")
    items.append("- **Where Hermite cannot go:** meshes that are not quads (adaptive quadtrees with hanging vertices, "
                 "Delaunay meshes), and general quads, across whose edges it is only C0: C1 holds on parallelograms "
                 "(see `docs/design-notes.md` for the measured gradient jump on jittered quads).")
    cost = [run.get(PEN, rep, m) for m in ("powell-sabin", "hermite", "clough-tocher")]
    if all(cost):
        items.append(f"- **Cost:** on the penumbra disc mesh powell-sabin runs in {ms(run_ms(cost[0]))} ms and hermite "
                     f"in {ms(run_ms(cost[1]))} ms (build + render), clough-tocher in {ms(run_ms(cost[2]))} ms.")
    return ("### Powell-Sabin and Hermite: where each wins and loses\n\nBoth are C1 schemes from the same samples "
            "and the same tangent planes as clough-tocher (tangents from the midpoint samples); Hermite runs on the "
            "quad version of each disc and uniform mesh (the cells of the rectilinear grid), so it is absent from "
            "the adaptive meshes, whose hanging vertices make no quads. Mean relative errors on the disc meshes "
            f"N = {run.c['rep_N']}:\n\n" + "\n".join(items) + "\n")
