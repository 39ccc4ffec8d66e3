"""plots.py — the report's figures with matplotlib: mean relative error against run time and
against samples, the scanline error profiles, and the range limiter's error ratios."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from .analysis import RANGE_PAIRS, RANGE_TARGET  # noqa: E402
from .data import run_ms  # noqa: E402
from .style import style  # noqa: E402

# Text stays text and ids are fixed, so a rerun rewrites only what changed.
plt.rcParams.update({"svg.fonttype": "none", "svg.hashsalt": "tocher", "font.size": 9})
KIND_DASH = {"disc": "-", "uniform": "--", "adaptive": ":"}


def _save(fig, path):
    fig.savefig(path, metadata={"Date": None}, bbox_inches="tight")
    plt.close(fig)


def _curve(run, scene, method, kind, by_time):
    xs, ys = [], []
    for label in run.labels(kind):
        r = run.get(scene, label, method)
        if r:
            xs.append(run_ms(r) if by_time else r["samples"])
            ys.append(r["mean_rel"])
    return xs, ys


def error_plot(run, scene, by_time, path):
    """Every method on the disc meshes (solid); linear and clough-tocher also on the uniform
    (dashed) and adaptive (dotted) meshes."""
    fig, ax = plt.subplots(figsize=(9, 5.6))
    curves = [(m, "disc", m) for m in run.methods]
    curves += [(m, k, "%s, %s" % (m, k)) for m in ("linear", "clough-tocher") for k in ("uniform", "adaptive")]
    for i, (m, kind, label) in enumerate(curves):
        xs, ys = _curve(run, scene, m, kind, by_time)
        colour, marker = style(m, i)
        if xs:
            ax.plot(xs, ys, KIND_DASH[kind], color=colour, marker=marker, ms=4, lw=1.6 if kind == "disc" else 1.1,
                    label=label, fillstyle="none" if kind != "disc" else "full")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("run time: tc_recon_new + tc_render %dx%d, 1 thread (ms)" % (run.c["W"], run.c["W"]) if by_time
                  else "samples taken (scene evaluations; gradients not counted)")
    ax.set_ylabel("mean relative error |ref - rec| / scale")
    ax.set_title("%s: mean relative error against %s" % (scene, "run time" if by_time else "samples"))
    ax.grid(True, which="both", lw=0.3, alpha=0.5)
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1), fontsize=7.5, frameon=False)
    fig.text(0.01, -0.02, "Solid: discontinuity meshes. Dashed: uniform. Dotted: adaptive. One run; times are "
             "medians.", fontsize=7.5)
    _save(fig, path)


def scanline_plot(run, scene, curves, ylog, path):
    """curves: (label, method, ys, dashed) along x = scan_x, with the discontinuities crossed."""
    data = run.scanlines(scene)
    fig, ax = plt.subplots(figsize=(9, 4.2))
    for i, (label, method, ys, dashed) in enumerate(curves):
        ax.plot(data["y"], ys, "--" if dashed else "-", color=style(method, i)[0], lw=1.1, label=label)
    x = run.c["scan_x"]
    for e in run.scene_info[scene]["events"]:
        if e["axis"] == 1 and e["lo"] <= x <= e["hi"]:
            ax.axvline(e["at"], color="#888888", ls=":", lw=0.9)
            ax.annotate(e["kind"], (e["at"], 1), xycoords=("data", "axes fraction"), fontsize=7, ha="center",
                        va="bottom", color="#555555")
    dom = run.scene_info[scene]["domain"]
    ax.set_xlim(dom[1], dom[3])
    if ylog:
        ax.set_yscale("log")
        top = max(max(c[2]) for c in curves)
        if top > 0:
            ax.set_ylim(top * 1e-6, top * 1.5)
    ax.set_xlabel("y")
    ax.set_ylabel("|ref - rec| / scale")
    ax.set_title("%s: relative error along x = %g%s" % (scene, x, " (log scale)" if ylog else ""), pad=14)
    ax.grid(True, which="major", lw=0.3, alpha=0.5)
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1), fontsize=7.5, frameon=False)
    fig.text(0.01, -0.03, "Dotted verticals: discontinuities crossed (C0 kink, C-1 jump). Legend: method, mesh "
             "(samples).", fontsize=7.5)
    _save(fig, path)


def _grid(n):
    """Axes for n panels, three to a row, and a spare slot (or None) for the legend."""
    cols = min(3, n + 1)
    rows = -(-(n + 1) // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(3.2 * cols, 2.9 * rows), sharey=True, squeeze=False)
    flat = list(axes.flat)
    for ax in flat[n + 1:]:
        ax.set_visible(False)
    return fig, flat[:n], flat[n]


def range_plot(run, ratios, path):
    """Per scene: the limited method's mean relative error over the free one's, on every mesh."""
    scenes = run.scenes
    fig, axes, spare = _grid(len(scenes))
    lo = min([r["mrel"] for r in ratios] + [1]) * 0.95
    hi = max([r["mrel"] for r in ratios] + [RANGE_TARGET * 1.1]) * 1.05
    for ax, scene in zip(axes, scenes):
        for i, (lim, free) in enumerate(RANGE_PAIRS):
            for kind in ("disc", "uniform", "adaptive"):
                pts = [(r["limited"]["samples"], r["mrel"]) for r in ratios
                       if r["scene"] == scene and r["kind"] == kind and r["limited"]["method"] == lim]
                if pts:
                    ax.plot(*zip(*pts), KIND_DASH[kind], marker=style(lim, i)[1], ms=3.5, lw=1,
                            color=style(lim, i)[0], label="%s / %s, %s" % (lim, free, kind))
        ax.axhline(RANGE_TARGET, color="#444444", ls="-.", lw=0.8)
        ax.axhline(1, color="#999999", lw=0.6)
        ax.set_xscale("log")
        ax.set_ylim(lo, hi)
        ax.set_title(scene, fontsize=9)
        ax.set_xlabel("samples", fontsize=8)
        ax.grid(True, which="major", lw=0.3, alpha=0.5)
    axes[0].set_ylabel("mean relative error:\nlimited / free")
    handles, labels = axes[0].get_legend_handles_labels()
    spare.set_visible(True)
    spare.axis("off")
    spare.legend(handles, labels, loc="center", fontsize=7.5, frameon=False,
                 title="dash-dot: the target %g" % RANGE_TARGET, title_fontsize=8)
    fig.suptitle("Range local (the default) against range free, same samples", fontsize=10)
    fig.tight_layout()
    _save(fig, path)
