"""intro.py — the report's opening: the headline, what was measured and how, the table of
methods, and the triples that could not run."""
from . import analysis as an
from .fmt import ratio, table

HEAD_SCENE = "penumbra"  # the headline's scene (Salesin et al.'s scene b), if measured


def headline(run):
    scene = HEAD_SCENE if HEAD_SCENE in run.scenes else run.scenes[0]
    rep = run.disc(run.c["rep_N"])
    ct, lin, c1 = (run.get(scene, rep, m) for m in ("clough-tocher", "linear", "clough-tocher-c1"))
    if not (ct and lin and c1):
        return "**Headline:** the representative disc mesh of %s did not run for every method.\n" % scene
    text = ("**Headline (%s, disc mesh N = %d):** clough-tocher with the flags has %s× lower RMS error than "
            "linear and %s× lower than clough-tocher-c1 on the same mesh; "
            % (scene, run.c["rep_N"], ratio(lin["rms"] / ct["rms"]), ratio(c1["rms"] / ct["rms"])))
    m = an.match_uniform(run, scene, "linear", ct["mean_rel"])
    if m and m["found"]:
        text += ("linear on uniform meshes needs about %d samples, %s× clough-tocher's %d, to match its mean "
                 "relative error%s. " % (round(m["samples"]), ratio(m["samples"] / ct["samples"]), ct["samples"],
                                         " (interpolated log-log)" if m["lo"] else " (at most)"))
    elif m:
        text += ("linear on uniform meshes never matches its mean relative error up to N = %d. "
                 % m["best"]["density"])
    return text + "Bastos & Oliveira saw about 15×. Details under [Reading](#reading).\n"


def _densities(run, kind):
    return ", ".join(str(m["density"]) for m in run.meshes if m["kind"] == kind)


def _adaptive(run):
    ad = [m for m in run.meshes if m["kind"] == "adaptive"]
    if not ad:
        return "*adaptive* — none in this run"
    start, depth = ad[0]["density"], ad[0]["max_depth"]
    return ("*adaptive* — a posteriori quadtrees, no flags, from a %d × %d grid with at most %d splits (finest "
            "cell 1/%d), splitting while the spread of B at a cell's corners exceeds a threshold of %s times the "
            "scene's scale" % (start, start, depth, start << depth,
                               ", ".join("%g" % m["threshold"] for m in ad)))


def measured(run):
    c, info = run.c, run.info
    W, gain = c["W"], c["err_gain"]
    return f"""## What was measured and how

- **Machine**: {info['machine']}, {info['nproc']} cores (model name from `/proc/cpuinfo`, `nproc`). Everything
  timed runs on one thread, one measurement at a time; other work on the machine shows up as noise in
  the milliseconds only.
- **Scenes and meshes**: each scene is meshed by `tc_scene_mesh_new` three ways: *disc* — a priori
  discontinuity meshes whose C0 / C-1 edges carry the scene's flags (N = {_densities(run, 'disc')}: no cell side
  longer than 1/N); *uniform* — N × N grids, no flags (N = {_densities(run, 'uniform')}); {_adaptive(run)}.
- **Samples taken** are the scene evaluations behind the values a method is given: vertex values, the
  one-sided values at vertices on C-1 lines, and the edge-midpoint samples for the methods that use
  them (linear4 and the cubics with `tangents: midpoints`); on adaptive meshes also the evaluations
  the quadtree made to decide its splits. A method that does not use the midpoints is given the mesh
  without them and is charged only for its own samples. The corner gradients of `ct-given` (one-sided
  differences, 24 evaluations per triangle) are counted separately as *gradient samples*.
- **Build time** is `tc_recon_new` on the method's `tc_mesh` (`tc_recon_free` included): the median of
  {c['build_batches']} batches, each repeating the call until it has taken at least {c['build_batch_ms']:g} ms, the
  time per call; a call longer than {c['build_big_ms']:g} ms is timed alone, median of 3. Validation and
  topology (`tc_mesh_new`) and the point locator (`tc_locator_new`) are the same for every method on a mesh
  and are not included (they are in results.csv as `mesh_ms`).
- **Interleaved timing**: the methods of one mesh are timed in rounds — each round one build batch and
  one render of every method in turn — so that a burst of other load on the machine falls on all of
  them alike and the median drops it.
- **Render time** is `tc_render` of a {W} × {W} tile of [0,1]² on 1 thread, median of {c['render_reps']}.
  **Run time** = build + render.
- **Errors** are taken at the {W}² pixel centres (`tc_viewport_pixel_center`) against the exact radiosity
  `tc_scene_value`, with `tc_compare`, in double precision: the largest |ref − rec|, the RMS, and
  Bastos & Oliveira's *mean relative error* (§6): |ref − rec| divided by the largest value the image can
  take — here the scene's full scale `tc_scene.scale`, B at the light's centre without the occluder — and
  averaged over the image.
- **Overshoot** (issue 12's measure, `tc_overshoot`) of the same {W}² tile, rendered once more with its
  pixels' owning triangles, outside the timed renders: with R the range of all the mesh's corner values,
  the share of pixels that leave their own triangle's corner values by more than {100 * c['over_threshold']:g} % of R
  (*beyond*), the largest such excursion in units of R (*worst*), and the pixels below 0 where no data is
  (*negative*). Linear cannot leave its corners; the exact function can (a peak between samples).
- **Scanline profiles** (Bastos & Oliveira, Fig. 12/13): |ref − rec| / scale at {c['scan_n']} points along
  the vertical line x = {c['scan_x']:g} (at the pixel rows' y), for linear, clough-tocher-c1, clough-tocher and
  ct-free on the disc mesh N = {c['rep_N']}, and linear on the uniform mesh whose sample count is nearest (in log) to
  {an.SCAN_UNIFORM_FACTOR:g}× clough-tocher's — Bastos & Oliveira's ratio. Caution: x = {c['scan_x']:g} is a mesh line
  of every uniform mesh with even N, so their profiles run along triangle edges (where each interpolant
  depends on the edge's own samples only) rather than through triangle interiors.
- **Pictures** (Salesin et al., Fig. 7/8): disc mesh N = {c['fig_N']}, {c['fig_panel']} × {c['fig_panel']} pixels per
  panel, written by `tc_img_encode` (PNG). Top row: reference | linear | clough-tocher-c1 |
  clough-tocher, each shown as sRGB(clamp(B / scale, 0, 1)) — B as a fraction of the scene's full scale,
  with the standard sRGB transfer and nothing else. Bottom row: the mesh (C1 edges grey, C0 yellow,
  C-1 red, boundary white, on black) | the three error maps, written linearly as min(1, {gain:g} · |ref − rec| / scale)
  (no transfer curve): a gain of {gain:g}, so white is an error of 1/{gain:g} of full scale or more and
  mid-grey half that.
""" + ("" if info["images_ok"] else
       "- **Some PNG pictures could not be written** in this run (see the run's messages on stderr).\n")


def methods(run):
    rows = []
    for m in run.info["methods"]:
        o = m["options"]
        used = "vertices" + (" + midpoints" if m["midpoints"] else "") + (" + gradients" if m["gradients"] else "")
        rows.append([m["name"], o["method"], o["cross_boundary"] or "", o["wedges"] or "", o["tangents"] or "",
                     o["range"] or "", used, m["what"]])
    head = ["name", "method", "cross_boundary", "wedges", "tangents", "range", "samples used", "what"]
    text = ("### Methods\n\nOne table in `bench/plan.c` (a new method is one line there; an option a method "
            "does not read is left blank):\n\n" + table(head, rows, ["l"] * len(head)))
    n = len(run.skipped())
    if n:
        text += ("\n%d (scene, mesh, method) triples could not run; they are listed at the end and left out of "
                 "the plots and ratios.\n" % n)
    else:
        text += "\nEvery (scene, mesh, method) triple ran.\n"
    return text


def skipped(run):
    rows = [[r["scene"], r["label"], r["method"], r["note"]] for r in run.skipped()]
    return "## Skipped\n\n" + table(["scene", "mesh", "method", "why"], rows, ["l"] * 4) if rows else ""


def preamble(run, rel):
    info = run.info
    return f"""<!-- Generated by `make report` (build/report, then bench/report.py): edit those, not this file. -->
# Error against run time

How far each reconstruction of tocher is from the exact illumination, what it costs, and how far it
leaves the data it was given, on the reference scenes of `src/scenes` and on realistic
discontinuity-meshed surfaces. Generated by `make report` — `build/report` (C, `bench/*.c`) measures,
`bench/report.py` (Python, `bench/present/`) writes this page and its plots — from tree
`{info['commit']}`. **All numbers, tables and figures come from one run**; the measurement took
{info['total_s']:.0f} s. Everything but the timings is deterministic: a rerun changes only the milliseconds. The
raw data is [`{rel}/results.csv`]({rel}/results.csv), one row per scene × mesh × method ({len(run.rows)} rows),
and [`{rel}/surfaces.csv`]({rel}/surfaces.csv) for the realistic surfaces.
"""
