#!/usr/bin/env python3
"""test_hol.py — head-of-line blocking at full size (issue 14, 2.1): long renders (2 s of
rendering each) on as many connections as there are HTTP threads, then as many as leave one
worker free, while 16 pre-opened keep-alive connections send small /v1/ordinates; the
slowest small answer must stay within 250 ms (500 ms with more renders than the
2 cores) and none may go unanswered, with the idle
timeout at its default (10 s) and shorter than the renders (2 s). Then a full worker queue.

    /usr/bin/python3 tests/torture/test_hol.py BUILD_DIR"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "pylib"))
import loadkit  # noqa: E402
from tochertest import finish  # noqa: E402

BUILD = loadkit.build_dir(sys.argv)
for run in range(3):
    loadkit.hol(BUILD, "hol-%d renders=threads" % run, renders=2, conns=16, render_s=2.0, limit_s=0.25,
                conn_timeout=10)
loadkit.hol(BUILD, "hol idle-timeout 2 s", renders=2, conns=16, render_s=2.0, limit_s=0.25, conn_timeout=2)
# More CPU-bound renders than cores: what is left is the CPU's share, not head-of-line blocking.
loadkit.hol(BUILD, "hol renders=workers-1", renders=3, conns=16, render_s=2.0, limit_s=0.5, conn_timeout=10)
loadkit.queue_full(BUILD, "queue", render_s=3.0)
finish()
