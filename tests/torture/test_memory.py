#!/usr/bin/env python3
"""test_memory.py — full size (issue 14, 2.3): the 367-byte request of the issue (one triangle,
16 channels, a 4096^2 raw tile: a 1 GiB answer) with the samples limit lifted grows the daemon
by at most 1.3 x its answer + 64 MB (it was +3.2 GB: tile, raw copy, response copy), and so do
4096^2 PNG, EXR and TIFF renders; two 1 GiB renders at once under a 1.5 GiB --max-memory: one
waits its turn (503 Retry-After), peak growth within the budget.

    /usr/bin/python3 tests/torture/test_memory.py BUILD_DIR
"""
import os
import shutil
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tests", "pylib"))
import memkit  # noqa: E402
from hostile import Daemon  # noqa: E402
from tochertest import check, finish, say  # noqa: E402

BUILD = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build"))
TMP = tempfile.mkdtemp(prefix="tocher-memory.")


def main():
    say("# %s against %s" % (os.path.basename(__file__), BUILD))
    d = Daemon(BUILD, TMP, "memory", max_samples=0, max_pixels=0, max_memory="8G")
    try:
        memkit.warm_up(d)
        memkit.growth(d, "the issue's request", 16, 4096, "raw")
        memkit.growth(d, "png", 3, 4096, "png")
        memkit.growth(d, "png16", 3, 4096, "png16")
        memkit.growth(d, "exr", 16, 4096, "exr")
        memkit.growth(d, "tiff", 4, 4096, "tiff")
        check("the daemon is alive", d.alive(), d.stderr()[-400:])
    finally:
        d.kill()
    d = Daemon(BUILD, TMP, "budget", max_samples=0, max_pixels=0, max_memory="1536M")
    try:
        memkit.budget(d, 1536, 16, 4096)
        check("the daemon is alive", d.alive(), d.stderr()[-400:])
    finally:
        d.kill()
        shutil.rmtree(TMP, ignore_errors=True)
    finish()


if __name__ == "__main__":
    main()
