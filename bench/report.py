#!/usr/bin/env python3
"""report.py — writes docs/report.md and its plots from what build/report measured (the
presentation half of `make report`; the measurement stays in C).

    /usr/bin/python3 bench/report.py DATADIR OUT.md

DATADIR holds build/report's results.csv, surfaces.csv, run.json, scanline CSVs and PNG rows;
the plots are written there too, and OUT.md links them relative to itself. Every number in
the page is computed here from those files: the prose around them only reads them.
"""
import os
import sys

from present import (every_scene, intro, loses, range_section, reading, scenes,
                     surfaces)
from present.analysis import range_ratios
from present.data import Run


def build(run, figdir, rel):
    parts = [
        intro.preamble(run, rel),
        intro.headline(run) + "\n" + range_section.headline(range_ratios(run)),
        intro.measured(run),
        intro.methods(run),
        range_section.write(run, figdir, rel),
        surfaces.write(run, figdir, rel),
        scenes.write(run, figdir, rel),
        "## Reading\n",
        reading.penumbra(run),
        reading.ps_hermite(run),
        loses.write(run),
        every_scene.write(run),
        intro.skipped(run),
    ]
    return "\n".join(p for p in parts if p)


def main(argv):
    if len(argv) != 3:
        sys.exit(__doc__)
    datadir, out = argv[1], argv[2]
    run = Run(datadir)
    rel = os.path.relpath(datadir, os.path.dirname(os.path.abspath(out)) or ".")
    text = build(run, datadir, rel)
    with open(out, "w") as f:
        f.write(text)
    print("report.py: wrote %s (%d scenes, %d rows, %d surface rows)" % (out, len(run.scenes), len(run.rows),
                                                                          len(run.surfaces)))


if __name__ == "__main__":
    main(sys.argv)
