#!/usr/bin/env python3
"""test_memory.py — render memory in a short form for `make test` (issue 14, 2.3; the full size
is tests/torture/test_memory.py): a few-hundred-byte request asking for a large image makes the
daemon grow by at most 1.3 x its answer + 64 MB (the tile is rendered and encoded in bands, and
the encoded answer is handed to the response without a copy), in every format; and the memory
budget (--max-memory) refuses a render that does not fit beside the ones in flight.

    /usr/bin/python3 tests/endpoint/test_memory.py BUILD_DIR

RSS figures mean nothing under the sanitizers (shadow memory, quarantine): there only the
statuses are checked. Prints "ok"/"FAIL" lines, then "N passed, N failed"."""
import json
import os
import shutil
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tests", "pylib"))
import loadkit  # noqa: E402
import memkit  # noqa: E402
from hostile import Daemon  # noqa: E402
from tochertest import check, finish, say  # noqa: E402

BUILD = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build"))
SAN = os.path.basename(os.path.normpath(BUILD)).endswith("san")
TMP = tempfile.mkdtemp(prefix="tocher-memory.")


def lazy_free_kb(d):
    """LazyFree in /proc/PID/smaps_rollup, kB: pages given back with MADV_FREE and not yet reclaimed."""
    try:
        with open("/proc/%d/smaps_rollup" % d.pid) as f:
            for line in f:
                if line.startswith("LazyFree:"):
                    return int(line.split()[1])
    except OSError:
        pass
    return -1


def spare(d):
    """The spare answer (io/hugemem.h): a sent answer of 32 MiB or more is kept as the block the
    next big answer is written into (tests/unit/test_hugemem.c), its pages lazily free (reclaimable)."""
    body = json.dumps(loadkit.grid(256), separators=(",", ":")).encode()  # 131072 triangles: a 45 MiB answer
    for k in (1, 2):
        status, _, payload = memkit.post(d.port, "/v1/ordinates", body)
        answer = len(payload) / 1048576.0
        check("ordinates of 131072 triangles (%d) -> %d, %.1f MiB answer" % (k, status, answer),
              status == 200 and answer > 32, payload[:300])
        lazy = lazy_free_kb(d) / 1024.0
        if lazy < 0:
            say("skip the spare's LazyFree check: this kernel's smaps_rollup has no LazyFree line")
            continue
        check("... once sent, its pages are the spare, lazily free: LazyFree %.1f MiB >= 32" % lazy, lazy >= 32)


def main():
    say("# %s against %s%s" % (os.path.basename(__file__), BUILD, " (sanitizers: statuses only)" if SAN else ""))
    if SAN:
        memkit.GROWTH_FACTOR, memkit.GROWTH_SLACK_MB = 1e9, 1e9
    d = Daemon(BUILD, TMP, "memory", threads=2, max_samples=0, max_memory="2G")
    try:
        memkit.warm_up(d)
        memkit.growth(d, "raw", 16, 1024, "raw")        # 64 MiB answer: was +192 MiB (3 copies)
        memkit.growth(d, "png", 3, 2048, "png")         # a small answer from 48 MiB of samples
        memkit.growth(d, "exr", 16, 1024, "exr")
        memkit.growth(d, "exr-half", 4, 2048, "exr-half")
        memkit.growth(d, "tiff", 4, 1024, "tiff")
        if not SAN:  # RSS means nothing under the sanitizers, and the build is slow there
            spare(d)
        check("the daemon is alive", d.alive(), d.stderr()[-400:])
    finally:
        d.kill()
    d = Daemon(BUILD, TMP, "budget", threads=2, max_samples=0, max_memory="100M")
    try:
        memkit.budget(d, 100 if not SAN else 1e9, 16, 1024)  # two 64 MiB answers in a 100 MiB budget
        check("the daemon is alive", d.alive(), d.stderr()[-400:])
    finally:
        d.kill()
        shutil.rmtree(TMP, ignore_errors=True)
    finish()


if __name__ == "__main__":
    main()
